//! simavr's free run between cycle timers changes nothing but speed: runs of
//! the robust build, the thesis port and an Arduino sketch (our own, and the
//! thesis sketch), with faults that reset the MCU and corrupt the link, give
//! the same results, traces, motions, UART bytes and SRAM, to the cycle,
//! with the core running free as with it stepped one instruction at a time
//! (as simavr runs by default).

#[path = "support/mod.rs"]
mod support;

#[path = "support/identity.rs"]
mod identity;

use hil::bench::BenchOptions;
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{run_test, Test, TestOptions, TestRun};
use identity::{assert_same, described, fault_case};

/// Runs `firmware` with `opts` twice, free and stepped, and fails naming
/// the first line where the two part; returns the stepped run.
fn same_free_and_stepped(
    what: &str,
    firmware: &Firmware,
    test: Test,
    opts: &TestOptions,
) -> TestRun {
    let robot = support::robot("henrytwo");
    let run = |free_run: bool| {
        let opts = TestOptions {
            bench: BenchOptions {
                free_run,
                ..opts.bench
            },
            ..opts.clone()
        };
        run_test(firmware.clone(), &robot, test, &opts).expect("the bench runs it")
    };
    let stepped = run(false);
    let free = run(true);
    assert_same(what, ("stepped", &stepped), ("free   ", &free));
    stepped
}

#[test]
fn the_robust_build_runs_the_same_free_and_stepped() {
    let opts = TestOptions {
        leg_mm: 500.0,
        record: true,
        ..Default::default()
    };
    same_free_and_stepped(
        "robust, UMBmark CW",
        &support::firmware("robust"),
        Test::UmbmarkCw,
        &opts,
    );
}

/// The faults that reset the MCU (a brown-out holds it in reset, then
/// lets it boot) and that corrupt its link, on the robust build.
#[test]
fn the_robust_build_under_faults_runs_the_same_free_and_stepped() {
    let robust = support::firmware("robust");
    for name in [
        "battery-brownout-reset",
        "reset-mid-test",
        "link-corruption",
    ] {
        let (test, opts) = fault_case(name);
        same_free_and_stepped(name, &robust, test, &opts);
    }
}

#[test]
fn the_thesis_port_runs_the_same_free_and_stepped() {
    let opts = TestOptions {
        leg_mm: 100.0,
        record: true,
        ..Default::default()
    };
    same_free_and_stepped(
        "thesis port, line",
        &support::firmware("thesis"),
        Test::Line,
        &opts,
    );
}

/// Sketches built with the Arduino core: busy loops polling `micros()`,
/// never asleep. Our own sketch's square is cut after 30 s of its 109
/// (its first leg, its first turn and the start of the next leg: what the
/// other three sides would add is more of the same, at a minute of CI
/// each way); the thesis sketch's line runs whole.
#[test]
fn arduino_sketches_run_the_same_free_and_stepped() {
    for (file, test, limit_s) in [
        (
            "fixtures/arduino/square-demo/tests.toml",
            Test::UmbmarkCcw,
            Some(30.0),
        ),
        (
            "firmware/arduino/henrytwo-thesis/tests.toml",
            Test::Line,
            None,
        ),
    ] {
        let (d, fw) = described(file);
        let opts = TestOptions {
            // The sketches' legs are fixed in their code.
            leg_mm: d.leg_mm(None, 0.0).expect("a fixed leg"),
            record: true,
            description: Some(d),
            limit_s,
            ..Default::default()
        };
        let run = same_free_and_stepped(file, &fw, test, &opts);
        assert!(
            !run.legs.is_empty() && (test == Test::Line || !run.turns.is_empty()),
            "{file}: {} legs, {} turns",
            run.legs.len(),
            run.turns.len()
        );
        assert_eq!(run.completed, limit_s.is_none(), "{file}");
    }
}
