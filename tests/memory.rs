//! A bench that runs for days keeps nothing of its past: what it retains is
//! counted (items in each record) after so many robot seconds, not timed
//! or read from the process's memory. `hil serve` runs the bench this way;
//! a test run keeps its records, each under a cap (see `bench/log.rs`).

#[path = "support/mod.rs"]
mod support;

use henrytwo_protocol::Test;
use hil::bench::{Bench, BenchOptions, Retained};

/// A booted bench driving a 2 m line (the motors' PWM changing, the trace
/// sampled), its records kept as `hil serve` keeps them or not.
fn driving_bench(served: bool) -> Bench {
    let robot = support::robot("henrytwo");
    let mut bench =
        Bench::new(support::firmware("robust"), &robot, BenchOptions::default()).unwrap();
    if served {
        bench.keep_latest_records();
    }
    hil::runs::start::wait_ready(&mut bench, None).unwrap();
    hil::runs::start::start_test(&mut bench, &[], true, Test::Line);
    bench
}

/// Run `seconds` of robot time in slices, taking the firmware's bytes as
/// `hil serve` does; what the bench retains then.
fn run(bench: &mut Bench, seconds: f64) -> Retained {
    for _ in 0..(seconds / 0.5) as usize {
        bench.run_for(0.5).unwrap();
        for n in 0..4 {
            bench.take_uart_output(n);
        }
    }
    bench.core().retained()
}

#[test]
fn a_served_bench_retains_the_same_few_items_however_long_it_runs() {
    let mut served = driving_bench(true);
    let after_2_s = run(&mut served, 2.0);
    let after_20_s = run(&mut served, 18.0);
    assert!(served.core().motion_changes() > 2, "the robot drove");
    // One item per record at most: the latest.
    assert!(after_20_s.total() <= 10, "{after_20_s:?}");
    assert!(
        after_20_s.total() <= after_2_s.total().max(10),
        "{after_2_s:?} -> {after_20_s:?}"
    );

    // The same run with its records kept, as a test run keeps them: what
    // the count above would see if a record grew again (100 trace samples
    // and some 100 drive events a robot second).
    let mut kept = driving_bench(false);
    let kept_20_s = run(&mut kept, 20.0);
    assert!(
        kept_20_s.trace >= 1900 && kept_20_s.drive > 500,
        "{kept_20_s:?}"
    );
}
