//! The walking skeleton end to end: the robust firmware's straight-line test
//! on the emulated robot, checked against the plant.

#[path = "support/mod.rs"]
mod support;

use hil::bench::BenchOptions;
use hil::line::{run_line, LineOptions, LineRun, MM_PER_COUNT};
use std::sync::OnceLock;

fn line_2m() -> &'static LineRun {
    static RUN: OnceLock<LineRun> = OnceLock::new();
    RUN.get_or_init(|| {
        let opts = LineOptions {
            length_mm: 2000.0,
            bench: BenchOptions::default(),
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

/// The firmware cuts the motors by its own odometry within two encoder counts
/// of the configured length (the trip that ends the leg is served by the main
/// loop, which may be inside a PID computation of up to ~0.5 ms: about one
/// more edge per wheel at 145 mm/s), and the counts it records then are the
/// counts in SRAM at the cycle the bridge inputs went to zero.
#[test]
fn stops_within_one_count_of_the_length() {
    let run = line_2m();
    let s = &run.summary;
    let mean_counts = (s.wheels.left.stop_count + s.wheels.right.stop_count) as f64 / 2.0;
    let over_mm = mean_counts * MM_PER_COUNT - s.length_mm;
    assert!(
        (0.0..2.0 * MM_PER_COUNT).contains(&over_mm),
        "stopped {over_mm} mm past the length (one count is {MM_PER_COUNT} mm)"
    );
    let cut = run
        .cutoffs
        .iter()
        .find(|c| c.at.cycle > run.start_cycle)
        .expect("a motor cut-off after the command");
    assert_eq!(cut.at.left_count, s.wheels.left.stop_count);
    assert_eq!(cut.at.right_count, s.wheels.right.stop_count);
}

/// The PID holds each wheel at its setpoint: after the first second, the mean
/// speed over every 1 s window is within 5 % of the setpoint (thesis "RPM",
/// the wheel's true RPM / 6: right 14.47, left 15.0).
#[test]
fn pid_settles_on_the_setpoints() {
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
        assert!((left / 15.0 - 1.0).abs() < 0.05, "left {left} at {t} s");
        assert!((right / 14.47 - 1.0).abs() < 0.05, "right {right} at {t} s");
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
