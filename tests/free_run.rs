//! simavr's free run between cycle timers changes nothing but speed: runs of
//! the robust build, the thesis port and an Arduino sketch (our own, and the
//! thesis sketch), with faults that reset the MCU and corrupt the link, give
//! the same results, traces, motions, UART bytes and SRAM, to the cycle,
//! with the core running free as with it stepped one instruction at a time
//! (as simavr runs by default).

#[path = "support/mod.rs"]
mod support;

use std::sync::Arc;

use hil::bench::BenchOptions;
use hil::firmware::description::Description;
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{run_test, Test, TestOptions, TestRun};
use hil::runs::faults::library;

/// Everything a run shows, as text: the report's JSON (results, the UARTs'
/// bytes, the applied faults, the awake fraction), the trace and the
/// motions with their cycles.
fn everything(r: &TestRun) -> String {
    format!(
        "{}\n{:?}\n{:?}\n{:?}",
        serde_json::to_string(r).expect("a run serialises"),
        r.trace,
        r.motions,
        r.bluetooth_out
    )
}

/// Runs `firmware` with `opts` twice, free and stepped, and fails naming
/// the first line where the two part.
fn same_free_and_stepped(what: &str, firmware: &Firmware, test: Test, opts: &TestOptions) {
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
    assert!(!stepped.trace.is_empty(), "{what}: no trace to compare");
    let (a, b) = (everything(&stepped), everything(&free));
    if a != b {
        let at = a
            .lines()
            .zip(b.lines())
            .position(|(x, y)| x != y)
            .unwrap_or(0);
        let cut = |s: &str| {
            s.lines()
                .nth(at)
                .unwrap_or("")
                .chars()
                .take(600)
                .collect::<String>()
        };
        panic!(
            "{what}: free run differs from stepping at line {at}\nstepped: {}\nfree:    {}",
            cut(&a),
            cut(&b)
        );
    }
}

fn described(file: &str) -> (Arc<Description>, Firmware) {
    let d = Description::load(hil::paths::workspace_root().join(file)).expect("description loads");
    let elf = d.elf.clone().expect("the description names its ELF");
    let fw = Firmware::load(&elf).unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"));
    (Arc::new(d), fw)
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
        let case = library()
            .into_iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no fault {name} in the library"));
        let opts = TestOptions {
            leg_mm: case.leg_mm,
            limit_s: Some(case.limit_s),
            faults: case.faults.clone(),
            framed: case.framed,
            record: true,
            ..Default::default()
        };
        same_free_and_stepped(name, &robust, case.test, &opts);
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
/// never asleep.
#[test]
fn arduino_sketches_run_the_same_free_and_stepped() {
    for (file, test) in [
        ("fixtures/arduino/square-demo/tests.toml", Test::UmbmarkCcw),
        ("firmware/arduino/henrytwo-thesis/tests.toml", Test::Line),
    ] {
        let (d, fw) = described(file);
        let opts = TestOptions {
            // The sketches' legs are fixed in their code.
            leg_mm: d.leg_mm(None, 0.0).expect("a fixed leg"),
            record: true,
            description: Some(d),
            ..Default::default()
        };
        same_free_and_stepped(file, &fw, test, &opts);
    }
}
