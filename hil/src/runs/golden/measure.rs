//! A run's quantities for a golden file: where each leg ended, how much it
//! turned, each turn's angle, each leg's mean duty per side, the control
//! loop's cycles.

use super::{Kind, Quantity};
use crate::mcu::clock::Clock;
use crate::runs::experiment::TestRun;
use crate::runs::timing::TimingReport;

/// The control function whose cycles and period a golden run records (the
/// bench's builds').
pub const CONTROL_FUNCTION: &str = "ht_control_tick";

/// The quantities of `run` (legs and turns from the bridge, positions from
/// the plant's trace at rest), and of `timing` when the control function
/// was timed. `clock` converts the run's cycles to its trace's seconds.
pub fn measure(run: &TestRun, timing: Option<&TimingReport>, clock: Clock) -> Vec<Quantity> {
    let mut out = Vec::new();
    let mut push = |name: String, kind: Kind, value: f64| {
        out.push(Quantity { name, kind, value });
    };
    let t = |cycle: u64| clock.seconds(cycle).0;
    // A leg is at rest when the next leg or turn starts, or at the end.
    let starts = run.segment_starts();
    for (k, leg) in run.legs.iter().enumerate() {
        let n = k + 1;
        let rest = starts.iter().find(|&&s| s > leg.start_cycle).copied();
        let (x, y) = match rest.and_then(|c| sample_at(run, t(c))) {
            Some(s) => (s.x_mm, s.y_mm),
            None => (run.final_pose.x_mm, run.final_pose.y_mm),
        };
        push(format!("leg {n} end x (mm)"), Kind::LegMm, x);
        push(format!("leg {n} end y (mm)"), Kind::LegMm, y);
        push(
            format!("leg {n} heading change (deg)"),
            Kind::TurnDeg,
            leg.plant_heading_change_deg,
        );
        let (left, right) = mean_duty(run, t(leg.start_cycle), t(leg.cutoff_cycle));
        push(format!("leg {n} duty left (mean)"), Kind::Duty, left);
        push(format!("leg {n} duty right (mean)"), Kind::Duty, right);
    }
    for (k, turn) in run.turns.iter().enumerate() {
        push(
            format!("turn {} angle (deg)", k + 1),
            Kind::TurnDeg,
            turn.plant_angle_deg,
        );
    }
    push("end x (mm)".into(), Kind::LegMm, run.final_pose.x_mm);
    push("end y (mm)".into(), Kind::LegMm, run.final_pose.y_mm);
    if let Some(r) = timing.filter(|r| r.control_cycles.count > 0) {
        let c = r.control_cycles;
        push(
            "control function, mean (cycles)".into(),
            Kind::Cycles,
            c.mean,
        );
        push(
            "control function, max (cycles)".into(),
            Kind::Cycles,
            c.max as f64,
        );
        let p = r.tick_period_cycles;
        if p.count > 0 {
            push(
                "control period, min (cycles)".into(),
                Kind::Cycles,
                p.min as f64,
            );
            push(
                "control period, max (cycles)".into(),
                Kind::Cycles,
                p.max as f64,
            );
        }
    }
    out
}

/// The last trace sample at or before `t_s`.
fn sample_at(run: &TestRun, t_s: f64) -> Option<&crate::bench::Sample> {
    run.trace.iter().take_while(|s| s.t_s <= t_s).last()
}

/// The mean signed duty of each motor over the trace samples in
/// `[from_s, to_s)` (0 when there are none: a leg shorter than a sample).
fn mean_duty(run: &TestRun, from_s: f64, to_s: f64) -> (f64, f64) {
    let samples: Vec<_> = run
        .trace
        .iter()
        .filter(|s| s.t_s >= from_s && s.t_s < to_s)
        .collect();
    if samples.is_empty() {
        return (0.0, 0.0);
    }
    let n = samples.len() as f64;
    (
        samples.iter().map(|s| s.left_duty).sum::<f64>() / n,
        samples.iter().map(|s| s.right_duty).sum::<f64>() / n,
    )
}
