//! The walking skeleton end to end: the robust firmware's straight-line test
//! on the emulated robot, checked against the plant.

#[path = "support/mod.rs"]
mod support;

use hil::bench::{Bench, BenchOptions};
use hil::firmware::link::{frame, replies, Command, Param};
use hil::runs::line::{run_line, LineOptions, LineRun};
use hil::runs::start::wait_ready;
use std::sync::OnceLock;

fn line_2m() -> &'static LineRun {
    static RUN: OnceLock<LineRun> = OnceLock::new();
    RUN.get_or_init(|| {
        let opts = LineOptions {
            length_mm: 2000.0,
            bench: BenchOptions::default(),
            tell: Default::default(),
            params: Vec::new(),
        };
        run_line(
            support::firmware("robust"),
            &support::robot("henrytwo-ideal"),
            &opts,
        )
        .expect("the line test runs to completion")
    })
}

/// Every edge the plant produced reached the firmware: its counters equal the
/// plant's net edge counts exactly, per wheel, and so do the edges the bench
/// raised on the pins.
#[test]
fn firmware_counts_equal_plant_edges() {
    let s = &line_2m().summary;
    for (name, w) in [("left", &s.wheels.left), ("right", &s.wheels.right)] {
        assert!(
            w.plant_edges > 11_000,
            "{name}: only {} edges",
            w.plant_edges
        );
        assert_eq!(w.raised_edges, w.plant_edges, "{name}: raised vs plant");
        assert_eq!(
            w.firmware_count as i64, w.plant_edges,
            "{name}: firmware vs plant"
        );
    }
}

/// The robust firmware's stop rule for a leg (`odometry::leg_target` with
/// c_L = c_R = 1): it ends when the sum of both wheels' counts reaches
/// `ceil(2 * length / mm_per_count)`, computed in `f32` as the firmware does
/// with its factory distance per count (Henrytwo's).
fn leg_target_count_sum(length_mm: f64) -> i64 {
    (2.0 * length_mm as f32 / Param::MmPerCountLeft.factory_default()).ceil() as i64
}

/// The firmware cuts the motors by its own odometry on the edge at which
/// the sum of both wheels' counts reaches the stop rule's target, or at most
/// two edges later, and the counts it records are those in SRAM at the cycle
/// the bridge inputs went to zero.
///
/// Two edges, not zero: a known lost wake-up. Near the end of a leg the main
/// loop re-arms each wheel's trip from the counts it took when the last trip
/// fired; the i64 arithmetic in between takes long enough for an edge to
/// come, and when that edge already reached the new trip point,
/// `Encoders::arm` marks the trip fired (TRIPPED) without setting the sleep
/// flag (WOKEN), so the main loop sleeps through it until the other wheel's
/// trip wakes it one edge later; by the cut one more edge has come. Whether
/// a run shows it depends on the cycles at which the edges fall: this run
/// stops at the target exactly (11 978 + 11 984 for 23 962), an earlier
/// firmware's at the target + 2 (11 979 + 11 985); with `arm` setting WOKEN
/// no run passes the target, and this bound becomes 0.
#[test]
fn stops_at_most_two_edges_past_the_stop_rule() {
    let run = line_2m();
    let s = &run.summary;
    let (left, right) = (s.wheels.left.stop_count, s.wheels.right.stop_count);
    let target = leg_target_count_sum(s.length_mm);
    let past = left as i64 + right as i64 - target;
    assert!(
        (0..=2).contains(&past),
        "stopped at {left} + {right} counts, {past} edges past the stop rule's target {target}"
    );
    let cut = run
        .cutoffs
        .iter()
        .find(|c| c.at.cycle > run.start_cycle)
        .expect("a motor cut-off after the command");
    assert_eq!(cut.at.left_count, Some(left));
    assert_eq!(cut.at.right_count, Some(right));
}

/// The wheel set-points the firmware runs with, read over the protocol
/// (GET_PARAM) from a freshly booted robust build: (left, right).
fn firmware_setpoints() -> (f64, f64) {
    let mut b = Bench::new(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    wait_ready(&mut b, None).unwrap();
    let mut get = |p: Param| {
        let before = b.uart_output(1).len();
        b.send(1, &frame(&Command::GetParam(p)));
        b.run_for(0.1).unwrap();
        let r = replies(&b.uart_output(1)[before..]);
        assert!(r.len() == 1 && r[0].ok, "GET_PARAM {p:?}: {r:?}");
        f32::from_le_bytes(r[0].data[1..5].try_into().unwrap()) as f64
    };
    (get(Param::SetpointLeft), get(Param::SetpointRight))
}

/// The PID holds each wheel at the set-point the firmware reports
/// (GET_PARAM; the robust build runs both wheels at the thesis' right-wheel
/// 14.47 "RPM", the wheel's true RPM / 6): after the first second, the mean
/// speed over every 1 s window is within 1 % of it. The bound is tighter
/// than the 3.7 % between 14.47 and the thesis' left set-point of 15, so a
/// wheel held at the other set-point fails it.
#[test]
fn pid_settles_on_the_setpoints() {
    let (set_left, set_right) = firmware_setpoints();
    let run = line_2m();
    let start_s = run.start_cycle as f64 / 16e6;
    let stop_s = run.summary.cutoff_cycle.expect("cut-off") as f64 / 16e6;
    let at = |t: f64| {
        run.trace
            .iter()
            .min_by(|a, b| (a.t_s - t).abs().total_cmp(&(b.t_s - t).abs()))
            .copied()
            .unwrap()
    };
    // counts per second -> thesis RPM: * 60 / 6 / 602.2
    let rpm = |counts: f64, dt: f64| counts / dt * 60.0 / 6.0 / 602.2;
    let mut t = start_s + 1.0;
    let mut windows = 0;
    while t + 1.0 <= stop_s {
        let (a, b) = (at(t), at(t + 1.0));
        let dt = b.t_s - a.t_s;
        let left = rpm((b.left_edges - a.left_edges) as f64, dt);
        let right = rpm((b.right_edges - a.right_edges) as f64, dt);
        assert!(
            (left / set_left - 1.0).abs() < 0.01,
            "left {left} at {t} s, set-point {set_left}"
        );
        assert!(
            (right / set_right - 1.0).abs() < 0.01,
            "right {right} at {t} s, set-point {set_right}"
        );
        windows += 1;
        t += 1.0;
    }
    assert!(windows >= 10, "only {windows} windows of steady driving");
}

/// Two runs with the same config and seed give identical results, bit for bit.
#[test]
fn runs_are_deterministic() {
    let opts = LineOptions {
        length_mm: 300.0,
        bench: BenchOptions::default(),
        tell: Default::default(),
        params: Vec::new(),
    };
    let robot = support::robot("henrytwo-ideal");
    let a = run_line(support::firmware("robust"), &robot, &opts).unwrap();
    let b = run_line(support::firmware("robust"), &robot, &opts).unwrap();
    assert_eq!(
        serde_json::to_string(&a.summary).unwrap(),
        serde_json::to_string(&b.summary).unwrap()
    );
    assert_eq!(a.trace, b.trace);
    assert_eq!(a.cutoffs, b.cutoffs);
}

fn round(v: f64, digits: i32) -> f64 {
    let k = 10f64.powi(digits);
    (v * k).round() / k
}

/// The line summary, with robot-time fields, counts and the pose rounded to
/// what a change of the firmware or plant would move.
#[test]
fn line_summary_snapshot() {
    let s = &line_2m().summary;
    let v = serde_json::json!({
        "completed": s.completed,
        "robot_time_s": round(s.robot_time_s, 3),
        "drive_time_s": round(s.drive_time_s, 3),
        "pwm_hz": round(s.pwm_hz, 2),
        "distance_firmware_mm": round(s.distance_firmware_mm, 1),
        "distance_plant_mm": round(s.distance_plant_mm, 1),
        "pose": {
            "x_mm": round(s.pose.x().0, 0),
            "y_mm": round(s.pose.y().0, 0),
            "theta_deg": round(s.pose.theta().0.to_degrees(), 1),
        },
        "left": {"edges": s.wheels.left.plant_edges, "count": s.wheels.left.firmware_count, "stop": s.wheels.left.stop_count},
        "right": {"edges": s.wheels.right.plant_edges, "count": s.wheels.right.firmware_count, "stop": s.wheels.right.stop_count},
        "firmware_log": s.firmware_log,
    });
    insta::assert_json_snapshot!("line_2m_summary", v);
}
