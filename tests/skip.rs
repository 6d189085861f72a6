//! The fast-forward over polling loops changes nothing but speed: runs of the
//! robust build (also under faults that reset the MCU and corrupt the link),
//! the thesis port, the thesis sketch and an Uno robot's sketch give the same
//! results, traces, motions and UART bytes, to the cycle, skipping (the
//! default) as with `--no-skip`; and on the busy ones the skip did skip.

#[path = "support/mod.rs"]
mod support;

#[path = "support/identity.rs"]
mod identity;

use hil::bench::BenchOptions;
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{run_test, Test, TestOptions};
use identity::{assert_same, described, fault_case};

/// Runs `firmware` with `opts` twice, without and with the skip, and fails
/// naming the first line where the two part; returns the share of the
/// run's cycles the skip fast-forwarded.
fn same_with_and_without_skip(
    what: &str,
    firmware: &Firmware,
    test: Test,
    opts: &TestOptions,
) -> f64 {
    let robot = support::robot("henrytwo");
    let run = |skip: bool| {
        let opts = TestOptions {
            bench: BenchOptions { skip, ..opts.bench },
            ..opts.clone()
        };
        run_test(firmware.clone(), &robot, test, &opts).expect("the bench runs it")
    };
    let stepped = run(false);
    let free = run(true);
    assert_eq!(
        stepped.skipped_cycles, 0,
        "{what}: skipped with the skip off"
    );
    assert_same(what, ("--no-skip", &stepped), ("skip     ", &free));
    // The Mega's 16 MHz: the builds these tests run.
    free.skipped_cycles as f64 / (free.robot_time_s * 16e6)
}

#[test]
fn the_robust_build_runs_the_same_with_and_without_skip() {
    let robust = support::firmware("robust");
    let opts = TestOptions {
        leg_mm: 500.0,
        record: true,
        ..Default::default()
    };
    same_with_and_without_skip("robust, UMBmark CW", &robust, Test::UmbmarkCw, &opts);
    for name in ["reset-mid-test", "link-corruption"] {
        let (test, opts) = fault_case(name);
        same_with_and_without_skip(name, &robust, test, &opts);
    }
}

#[test]
fn the_thesis_port_runs_the_same_with_and_without_skip() {
    let opts = TestOptions {
        leg_mm: 100.0,
        record: true,
        ..Default::default()
    };
    same_with_and_without_skip(
        "thesis port, line",
        &support::firmware("thesis"),
        Test::Line,
        &opts,
    );
}

/// The thesis sketch polls (its `loop()` never sleeps, `analogRead` waits
/// for the ADC): the waits are skipped, with the same results.
#[test]
fn the_thesis_sketch_runs_the_same_with_and_without_skip() {
    let (d, fw) = described("firmware/arduino/henrytwo-thesis/tests.toml");
    let opts = TestOptions {
        // The sketch's leg is fixed in its code.
        leg_mm: d.leg_mm(None, 0.0).expect("a fixed leg"),
        record: true,
        description: Some(d),
        ..Default::default()
    };
    let share = same_with_and_without_skip("thesis sketch, line", &fw, Test::Line, &opts);
    // Its waits for the ADC; most of its time is in `delay()`, which
    // polls `micros()` (TCNT0): never skipped.
    assert!(share > 0.0, "thesis sketch: nothing skipped");
}

/// An Uno robot's sketch, through the command line: the report of
/// `hil run` is the same with `--no-skip` as without.
#[test]
fn an_uno_sketch_reports_the_same_with_no_skip() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            "leg-and-spin",
            "--tests",
            "fixtures/arduino/uno-l298n/tests.toml",
            "--board",
            "fixtures/boards/uno-l298n.toml",
            "--robot",
            "fixtures/robots/uno-l298n.toml",
            "--json",
        ];
        args.extend_from_slice(extra);
        let out = support::hil_at_root(&args);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mut report: serde_json::Value =
            serde_json::from_slice(&out.stdout).expect("a JSON report");
        // The host's real-time factor, the one number meant to change.
        report
            .as_object_mut()
            .expect("an object")
            .remove("rtf")
            .expect("the report has its rtf");
        report
    };
    let (skipping, not) = (run(&[]), run(&["--no-skip"]));
    assert_eq!(skipping["completed"], true, "{skipping}");
    assert_eq!(
        skipping, not,
        "the Uno sketch's report changed with --no-skip"
    );
}
