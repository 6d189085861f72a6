//! `Bench::run_until` checks its `done` on a fixed grid of robot time: at
//! the first step at or after each grid point, and at the first step at or
//! after the limit. The fast path (bursts inside the simulator module) and
//! the watched path (one step at a time, for observers and profiles) must
//! check at the same cycles, and so must a run split into several calls.

#[path = "support/mod.rs"]
mod support;

use std::cell::RefCell;
use std::rc::Rc;

use hil::bench::{Bench, BenchOptions, Observer, Step, CHECK_PERIOD_S};
use hil::runs::experiment::Test;
use hil::runs::line::ready_bench;

/// Keeps (cycle before, cycle after) of every step.
struct Steps(Rc<RefCell<Vec<(u64, u64)>>>);

impl Observer for Steps {
    fn step(&mut self, step: &Step) {
        self.0
            .borrow_mut()
            .push((step.cycle_before, step.cycle_after));
    }
    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any> {
        self
    }
}

/// A bench a moment into the robust firmware's first UMBmark leg: the CPU
/// sleeps, wakes for encoder edges and its 15 ms tick, and sleeps again.
fn moving_bench() -> Bench {
    let (mut bench, _, _) = ready_bench(
        support::firmware("robust"),
        &support::robot("henrytwo"),
        BenchOptions::default(),
        300.0,
    )
    .unwrap();
    bench.send(1, &[Test::UmbmarkCw.command_byte()]);
    bench.run_for(0.2).unwrap();
    bench
}

/// Run `bench` to cycle `end` in runs of at most `chunk_s`, noting the cycle
/// of every check of `done`.
fn checks_to(bench: &mut Bench, end: u64, chunk_s: f64) -> Vec<u64> {
    let hz = bench.clock().hz() as f64;
    let mut checks = Vec::new();
    while bench.cycle() < end {
        let left_s = (end - bench.cycle()) as f64 / hz;
        let done = bench
            .run_until(left_s.min(chunk_s), |b| {
                checks.push(b.cycle());
                false
            })
            .unwrap();
        assert!(!done);
    }
    assert_eq!(bench.cycle(), end, "the runs overshot their limit");
    checks
}

/// Fails naming the first check where `got` and `want` part (thousands of
/// cycles would tell nothing).
fn same_checks(what: &str, got: &[u64], want: &[u64]) {
    if let Some(i) = (0..got.len().min(want.len())).find(|&i| got[i] != want[i]) {
        panic!(
            "{what}: check {i} at cycle {}, expected at {} (the one before at {:?})",
            got[i],
            want[i],
            i.checked_sub(1).map(|j| want[j])
        );
    }
    assert_eq!(got.len(), want.len(), "{what}: number of checks");
}

fn sram(bench: &Bench) -> Vec<u8> {
    (0x200..0x2200).map(|a| bench.read_u8(a)).collect()
}

#[test]
fn done_is_checked_on_a_grid_of_robot_time_however_the_run_is_driven() {
    // The watched run: one step at a time, every step seen.
    let mut watched = moving_bench();
    let start = watched.cycle();
    let seen = Rc::new(RefCell::new(Vec::new()));
    watched.set_observer(Some(Box::new(Steps(seen.clone()))));
    let hz = watched.clock().hz() as f64;
    let watched_checks = {
        let mut checks = Vec::new();
        assert!(!watched
            .run_until(0.3, |b| {
                checks.push(b.cycle());
                false
            })
            .unwrap());
        checks
    };
    watched.set_observer(None);
    let end = watched.cycle();
    let steps = seen.borrow().clone();
    assert!(steps.len() > 1000, "too few steps seen: {}", steps.len());
    assert!(
        steps.iter().any(|&(b, a)| a - b > 1000),
        "the CPU never slept: the test would not see checks after a sleep"
    );

    // What the checks should be, from the steps alone: the first step, then
    // the first step at or after each grid point, and the limit's.
    let period = (CHECK_PERIOD_S * hz).round() as u64;
    let limit = start + (0.3 * hz).round() as u64;
    let mut expected = vec![steps[0].1];
    for &(_, after) in &steps[1..] {
        let last = *expected.last().unwrap();
        let due = ((last / period + 1) * period).min(limit);
        if after >= due {
            expected.push(after);
        }
    }
    same_checks("watched run", &watched_checks, &expected);
    assert_eq!(*expected.last().unwrap(), end);
    // The run ends after the first step that reaches the limit: an
    // instruction, or a sleep that simavr jumps over to its next event.
    let last = steps
        .iter()
        .find(|&&(before, after)| before < limit && after >= limit)
        .expect("a step reaches the limit");
    assert_eq!(end, last.1, "ended at {end}, limit {limit}, step {last:?}");
    // A check per period while awake; fewer, never more, across sleeps.
    let periods = (end - start) / period;
    assert!(
        (watched_checks.len() as u64) < periods + 3 && watched_checks.len() > 100,
        "{} checks in {periods} periods",
        watched_checks.len()
    );

    // The fast path in one run: the same checks, the same end.
    let mut fast = moving_bench();
    assert_eq!(fast.cycle(), start);
    same_checks("fast run", &checks_to(&mut fast, end, 1.0), &watched_checks);
    assert_eq!(sram(&fast), sram(&watched));

    // The fast path in runs of 7 ms: the same checks on the grid, plus each
    // run's first step and its limit's.
    let mut split = moving_bench();
    let split_checks = checks_to(&mut split, end, 0.007);
    assert_eq!(sram(&split), sram(&watched));
    let extra: Vec<u64> = split_checks
        .iter()
        .copied()
        .filter(|c| !watched_checks.contains(c))
        .collect();
    assert!(
        watched_checks.iter().all(|c| split_checks.contains(c)),
        "a grid check went missing in the split run"
    );
    let runs = (0.3f64 / 0.007).ceil() as usize;
    assert!(
        !extra.is_empty() && extra.len() <= 2 * runs,
        "{} checks beyond the grid for {runs} runs",
        extra.len()
    );
}
