//! `hil bench` compares the bench with raw simavr replaying the bench run's
//! inputs; the comparison only means something if the replay executes the
//! same program path. These tests hold the replay to that.

#[path = "support/mod.rs"]
mod support;

use hil::experiment::Test;
use hil::perf::{bench_run, raw_replay};

#[test]
fn a_raw_replay_ends_in_the_bench_runs_firmware_state() {
    let fw = support::firmware("robust");
    let rec = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    assert!(rec.completed, "the line did not complete on the bench");
    assert!(
        rec.edges.len() > 100,
        "too few edges recorded: {}",
        rec.edges.len()
    );
    for simavr_pwm_timers in [false, true] {
        let replay = raw_replay(&fw, &rec, simavr_pwm_timers).unwrap();
        assert!(
            replay.faithful,
            "replay (simavr PWM timers {simavr_pwm_timers}) diverged"
        );
        assert_eq!(replay.measured.robot_s, rec.measured.robot_s);
    }
}

#[test]
fn a_replay_missing_an_input_is_caught() {
    let fw = support::firmware("robust");
    let mut rec = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    // Without the battery on A0 the firmware reads a flat battery.
    rec.analog.clear();
    assert!(!raw_replay(&fw, &rec, false).unwrap().faithful);
    // Without the last quarter of the encoder edges the counts fall short.
    let mut rec2 = bench_run(&fw, &support::robot("henrytwo"), Test::Line, 400.0, true).unwrap();
    let keep = rec2.edges.len() * 3 / 4;
    rec2.edges.truncate(keep);
    assert!(!raw_replay(&fw, &rec2, false).unwrap().faithful);
}
