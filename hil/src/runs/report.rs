//! Text renderings of results, for people.

use std::fmt::Write;
use std::time::Instant;

use serde::Serialize;

use crate::bench::Sample;
use crate::runs::experiment::TestRun;

/// The host's wall time over a command, for its real-time factor. An
/// untimed clock (`--deterministic`) reads nothing, so that the output
/// depends on the inputs alone.
#[derive(Debug, Clone, Copy)]
pub struct WallClock(Option<Instant>);

impl WallClock {
    /// A clock started now; `timed: false` never reads the host's time.
    pub fn start(timed: bool) -> Self {
        Self(timed.then(Instant::now))
    }

    /// Wall seconds since the start, or `None` when untimed.
    pub fn stop(&self) -> Option<f64> {
        self.0.map(|t| t.elapsed().as_secs_f64())
    }
}

/// Robot time against the host's wall time over the same work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pace {
    pub robot_s: f64,
    pub wall_s: f64,
}

impl Pace {
    /// The pace of `robot_s` of robot time, when the wall time was read.
    pub fn of(robot_s: f64, wall_s: Option<f64>) -> Option<Self> {
        wall_s.map(|wall_s| Self { robot_s, wall_s })
    }

    /// Robot seconds per wall second.
    pub fn rtf(&self) -> f64 {
        self.robot_s / self.wall_s
    }
}

/// Which host-timing fields a JSON result carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaceFields {
    /// `rtf` only.
    Rtf,
    /// `rtf` and `wall_s`.
    RtfAndWall,
}

/// `value` as JSON with its host timing added (`rtf`, and `wall_s` when
/// asked); without a pace (deterministic output) the fields are left out.
pub fn json_with_pace<T: Serialize>(
    value: &T,
    pace: Option<Pace>,
    fields: PaceFields,
) -> serde_json::Result<serde_json::Value> {
    let mut v = serde_json::to_value(value)?;
    if let (Some(p), Some(map)) = (pace, v.as_object_mut()) {
        map.insert("rtf".into(), p.rtf().into());
        if fields == PaceFields::RtfAndWall {
            map.insert("wall_s".into(), p.wall_s.into());
        }
    }
    Ok(v)
}

/// The plant trace as CSV, one row per sample.
pub fn trace_csv(samples: &[Sample]) -> String {
    let mut csv =
        String::from("t_s,x_mm,y_mm,theta_rad,left_edges,right_edges,left_duty,right_duty\n");
    for s in samples {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{}",
            s.t_s,
            s.x_mm,
            s.y_mm,
            s.theta_rad,
            s.left_edges,
            s.right_edges,
            s.left_duty,
            s.right_duty
        );
    }
    csv
}

/// A test run: one line per leg and turn, the end error.
pub fn render_run(run: &TestRun) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} ({}, seed {}): {}",
        run.test.name(),
        run.firmware,
        run.seed,
        match (run.completed, &run.fragments) {
            (true, _) => "completed",
            (false, Some(_)) => "FRAGMENTED: not a complete run of the test",
            (false, None) => "DID NOT COMPLETE",
        }
    );
    if let Some(f) = &run.finding {
        let _ = writeln!(s, "  finding: {f}");
    }
    for w in &run.warnings {
        let _ = writeln!(s, "  warning: {w}");
    }
    let mut turns = run.turns.iter().enumerate().peekable();
    // A firmware whose counters the bench does not know: no counts.
    let count = |v: Option<i32>| v.map_or("     -".to_string(), |v| format!("{v:6}"));
    for (i, leg) in run.legs.iter().enumerate() {
        let _ = writeln!(
            s,
            "  leg  {}   {:8.1} mm, heading {:+6.2} deg, counts L {} R {}",
            i + 1,
            leg.plant_distance_mm,
            leg.plant_heading_change_deg,
            count(leg.firmware_count_left),
            count(leg.firmware_count_right)
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
    s.push_str(&crate::runs::experiment::uarts::render(&run.uarts, "  "));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Summary {
        robot_time_s: f64,
    }

    /// Host timing joins a result only when the clock was read, `wall_s` only when asked.
    #[test]
    fn pace_fields_join_only_a_timed_result() {
        let r = Summary { robot_time_s: 8.0 };
        let pace = Pace::of(8.0, Some(2.0));
        let v = json_with_pace(&r, pace, PaceFields::RtfAndWall).unwrap();
        assert_eq!(v["rtf"], 4.0);
        assert_eq!(v["wall_s"], 2.0);
        let v = json_with_pace(&r, pace, PaceFields::Rtf).unwrap();
        assert_eq!(v["rtf"], 4.0);
        assert!(v.get("wall_s").is_none());
        let v = json_with_pace(&r, Pace::of(8.0, None), PaceFields::RtfAndWall).unwrap();
        assert_eq!(v, serde_json::json!({ "robot_time_s": 8.0 }));
        assert!(WallClock::start(false).stop().is_none());
        assert!(WallClock::start(true).stop().is_some());
    }

    /// One header, one row per sample, every field in the header's order.
    #[test]
    fn trace_csv_has_a_header_and_a_row_per_sample() {
        let s = Sample {
            t_s: 0.01,
            x_mm: 1.5,
            y_mm: -0.25,
            theta_rad: 0.125,
            left_edges: 3,
            right_edges: 4,
            left_duty: 0.5,
            right_duty: 0.75,
        };
        assert_eq!(
            trace_csv(&[s, s]),
            "t_s,x_mm,y_mm,theta_rad,left_edges,right_edges,left_duty,right_duty\n\
             0.01,1.5,-0.25,0.125,3,4,0.5,0.75\n\
             0.01,1.5,-0.25,0.125,3,4,0.5,0.75\n"
        );
    }
}
