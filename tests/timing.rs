//! The PID loop's timing budgets, measured cycle-exactly on the robust
//! firmware over a straight line, and a breach reported as a failure.

#[path = "support/mod.rs"]
mod support;

use hil::bench::BenchOptions;
use hil::experiment::{run_test_observed, Test, TestOptions};
use hil::timing::{Budgets, TimingProbe, TimingReport};
use std::process::Command;
use std::sync::OnceLock;

fn report() -> &'static TimingReport {
    static R: OnceLock<TimingReport> = OnceLock::new();
    R.get_or_init(|| {
        let fw = support::firmware("robust");
        let probe = TimingProbe::new(&fw, "ht_control_tick", 240_000).unwrap();
        let opts = TestOptions {
            leg_mm: 600.0,
            bench: BenchOptions::default(),
            limit_s: None,
            record: false,
            faults: Vec::new(),
            framed: false,
            params: Vec::new(),
            hang_after_s: None,
        };
        let (run, obs) = run_test_observed(
            fw.clone(),
            &support::robot("henrytwo-ideal"),
            Test::Line,
            &opts,
            Some(Box::new(probe)),
        )
        .unwrap();
        assert!(run.completed);
        let probe = obs.unwrap().into_any().downcast::<TimingProbe>().unwrap();
        probe.report(&fw, "ht_control_tick", 16_000_000)
    })
}

/// The control tick comes every 15 ms (a hardware CTC timer: jitter is only
/// the interrupt latency), and the PID runs once per tick.
#[test]
fn control_tick_is_15_ms() {
    let r = report();
    assert!(
        r.control_cycles.count > 30,
        "{} PID runs",
        r.control_cycles.count
    );
    let mean_ms = r.tick_period_cycles.mean / 16_000.0;
    assert!((mean_ms - 15.0).abs() < 0.01, "mean period {mean_ms} ms");
    assert!(
        r.tick_jitter_max_cycles < 1600,
        "jitter {} cycles",
        r.tick_jitter_max_cycles
    );
    // The PID takes real time: thousands of cycles of soft float.
    assert!(r.control_cycles.min > 1000 && r.control_cycles.max < 32_000);
}

/// Both encoder interrupts are seen, each run once per A edge, and their
/// latency includes at least the datasheet's response time.
#[test]
fn encoder_isrs_are_measured() {
    let r = report();
    for name in ["INT4", "INT5"] {
        let isr = r.isrs.iter().find(|i| i.name == name).expect(name);
        assert!(
            isr.duration.count > 3000,
            "{name}: {} runs",
            isr.duration.count
        );
        assert!(
            isr.latency.min >= 5,
            "{name}: latency {} cycles",
            isr.latency.min
        );
        assert!(
            isr.duration.max < 800,
            "{name}: {} cycles",
            isr.duration.max
        );
    }
    assert!(
        r.stack_margin_bytes > 1000,
        "stack margin {}",
        r.stack_margin_bytes
    );
    assert!(r.cpu_load > 0.0 && r.cpu_load < 0.5);
}

/// The default budgets hold; a budget tighter than the measurement fails,
/// and `hil timing` says which one and exits non-zero.
#[test]
fn budgets_pass_and_a_breach_fails() {
    let root = hil::paths::workspace_root();
    let budgets = Budgets::load(&root.join("fixtures/timing-budgets.toml")).unwrap();
    let rows = report().check(&budgets);
    assert!(rows.iter().all(|r| r.pass), "{rows:#?}");

    let dir = std::env::temp_dir().join(format!("hil-timing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tight = dir.join("tight.toml");
    let text = std::fs::read_to_string(root.join("fixtures/timing-budgets.toml"))
        .unwrap()
        .replace("control_max_us = 2000.0", "control_max_us = 10.0");
    std::fs::write(&tight, text).unwrap();
    let _ = support::firmware_path("robust");
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args([
            "timing",
            "--leg-mm",
            "300",
            "--budgets",
            tight.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stdout.contains("EXCEEDED"), "{stdout}");
    assert!(stderr.contains("ht_control_tick execution"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
