//! Text renderings of results, for people.

use std::fmt::Write;

use crate::experiment::TestRun;

/// A test run: one line per leg and turn, the end error.
pub fn render_run(run: &TestRun) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} ({}, seed {}): {}",
        run.test.name(),
        run.firmware,
        run.seed,
        if run.completed {
            "completed"
        } else {
            "DID NOT COMPLETE"
        }
    );
    if let Some(f) = &run.finding {
        let _ = writeln!(s, "  finding: {f}");
    }
    let mut turns = run.turns.iter().enumerate().peekable();
    for (i, leg) in run.legs.iter().enumerate() {
        let _ = writeln!(
            s,
            "  leg  {}   {:8.1} mm, heading {:+6.2} deg, counts L {:6} R {:6}",
            i + 1,
            leg.plant_distance_mm,
            leg.plant_heading_change_deg,
            leg.firmware_count_left,
            leg.firmware_count_right
        );
        while let Some((k, t)) = turns.next_if(|(_, t)| {
            t.start_cycle < run.legs.get(i + 1).map_or(u64::MAX, |l| l.start_cycle)
        }) {
            let c = |v: Option<i32>| v.map_or("   never".to_string(), |v| format!("{v:8}"));
            let _ = writeln!(
                s,
                "  turn {}   {:+8.2} deg, counts at cut-off L {} R {}",
                k + 1,
                t.plant_angle_deg,
                c(t.count_left_at_cutoff),
                c(t.count_right_at_cutoff)
            );
        }
    }
    let _ = writeln!(
        s,
        "  end          x {:+.2} cm, y {:+.2} cm (error vs the ideal end), heading {:+.2} deg",
        run.x_cm, run.y_cm, run.final_pose.theta_deg
    );
    let _ = writeln!(
        s,
        "  robot time   {:.3} s, CPU awake {:.2} %",
        run.robot_time_s,
        run.awake_fraction * 100.0
    );
    s
}
