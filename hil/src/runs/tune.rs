//! `hil tune`: the gains [`crate::firmware::tune::derive`] gives a robot,
//! checked on the bench: a straight line driven with them, its step
//! response read from the plant's trace (each wheel's speed over 50 ms
//! windows), the duty never at 0 while driving, the overshoot bounded, the
//! speed settled.

use plant_model::RobotConfig;

use crate::bench::{BenchError, Sample};
use crate::firmware::elf::Firmware;
use crate::firmware::params::Tell;
use crate::firmware::tune::{derive, TuneError, Tuning};
use crate::runs::line::{run_line, LineOptions};

/// Largest overshoot of a wheel's speed over its set-point at the start, as
/// a fraction. The output stage maps `U = 0` to duty 128, so a motor that
/// holds the set-point at a low duty overshoots at every start whatever its
/// gains: coarse65 (27 % duty) 50 % with its derived gains, 65-73 % with
/// gentler PI gains; Henrytwo (69 % duty) 10-15 % with the factory gains.
pub const MAX_OVERSHOOT: f64 = 0.6;
/// Latest time after the start by which a wheel's speed stays within
/// [`SETTLE_BAND`] of its set-point, s.
pub const MAX_SETTLING_S: f64 = 1.0;
/// How long the speed must be seen to stay settled before the cut-off, s: a
/// line too short to show it is no pass.
pub const SETTLED_FOR_S: f64 = 0.5;
/// The settling band, a fraction of the set-point.
pub const SETTLE_BAND: f64 = 0.10;
/// Speeds are measured over windows of this many trace samples (10 ms
/// each): several control periods, so one count's quantum is a few percent.
const WINDOW: usize = 5;

/// One check of the bench run.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Check {
    pub name: String,
    pub value: f64,
    pub limit: f64,
    pub pass: bool,
}

/// One wheel's step response on the bench.
#[derive(Debug, Clone, serde::Serialize)]
pub struct WheelResponse {
    /// Peak speed over the set-point, a fraction.
    pub overshoot: f64,
    /// From the start until the speed stays within the band, s; `None` when it never does,
    /// or not for [`SETTLED_FOR_S`] before the cut-off.
    pub settling_s: Option<f64>,
    /// Trace samples (10 ms) with the duty at 0 while driving.
    pub duty_zero_samples: usize,
}

/// The gains derived and their check on the bench.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TuneReport {
    pub tuning: Tuning,
    pub factory_chatters: bool,
    pub line_mm: f64,
    /// The line's end, by the plant after braking, mm.
    pub distance_mm: f64,
    pub drive_time_s: f64,
    pub left: WheelResponse,
    pub right: WheelResponse,
    pub checks: Vec<Check>,
    pub warnings: Vec<String>,
}

impl TuneReport {
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.pass)
    }
}

/// Why `hil tune` produced no report.
#[derive(Debug, thiserror::Error)]
pub enum TuneRunError {
    #[error(transparent)]
    Tune(#[from] TuneError),
    #[error(transparent)]
    Bench(#[from] BenchError),
}

/// Derive `robot`'s gains and drive a line of `line_mm` with them.
pub fn tune(
    firmware: Firmware,
    robot: &RobotConfig,
    bench: crate::bench::BenchOptions,
    line_mm: f64,
) -> Result<TuneReport, TuneRunError> {
    let tuning = derive(robot)?;
    let opts = LineOptions {
        length_mm: line_mm,
        bench,
        tell: Tell::Robot,
        params: tuning.params(),
    };
    let run = run_line(firmware, robot, &opts)?;
    let clock = bench.clock;
    let start = clock.seconds(run.start_cycle).0;
    let cut = run
        .summary
        .cutoff_cycle
        .map(|c| clock.seconds(c).0)
        .unwrap_or(f64::NAN);
    let counts = robot.encoder.gear_ratio * robot.encoder.a_edges_per_motor_rev as f64;
    // From the first sample a wheel is driven (the start duty) to the cut-off.
    let driving: Vec<&Sample> = run
        .trace
        .iter()
        .filter(|s| s.t_s > start && s.t_s < cut)
        .skip_while(|s| s.left_duty == 0.0 && s.right_duty == 0.0)
        .collect();
    let start = driving.first().map_or(start, |s| s.t_s);
    let wheel = |i: usize, setpoint: f64| -> WheelResponse {
        let edges = |s: &Sample| if i == 0 { s.left_edges } else { s.right_edges };
        let duty = |s: &Sample| if i == 0 { s.left_duty } else { s.right_duty };
        // Thesis RPM is wheel RPM / 6: counts per second * 10 / counts per turn.
        let speeds: Vec<(f64, f64)> = driving
            .windows(WINDOW + 1)
            .map(|w| {
                let (a, b) = (w[0], w[WINDOW]);
                let rpm = (edges(b) - edges(a)).abs() as f64 / (b.t_s - a.t_s) * 10.0 / counts;
                (b.t_s - start, rpm)
            })
            .collect();
        let peak = speeds.iter().map(|&(_, v)| v).fold(0.0, f64::max);
        let last_out = speeds
            .iter()
            .rposition(|&(_, v)| (v - setpoint).abs() > SETTLE_BAND * setpoint);
        // The start's first period runs at the start duty before the PID's first tick.
        let first_tick = start + 0.05;
        WheelResponse {
            overshoot: (peak - setpoint).max(0.0) / setpoint,
            settling_s: match last_out {
                Some(k) if k + 1 >= speeds.len() => None,
                Some(k) => Some(speeds[k + 1].0),
                None => speeds.first().map(|s| s.0),
            }
            .filter(|&t| speeds.last().is_some_and(|l| l.0 - t >= SETTLED_FOR_S)),
            duty_zero_samples: driving
                .iter()
                .filter(|s| s.t_s > first_tick && duty(s) == 0.0)
                .count(),
        }
    };
    let left = wheel(0, tuning.left.setpoint_rpm);
    let right = wheel(1, tuning.right.setpoint_rpm);
    let mut checks = Vec::new();
    for (side, w) in [("left", &left), ("right", &right)] {
        checks.push(Check {
            name: format!("{side} duty at 0 while driving (10 ms samples)"),
            value: w.duty_zero_samples as f64,
            limit: 0.0,
            pass: w.duty_zero_samples == 0,
        });
        checks.push(Check {
            name: format!("{side} overshoot"),
            value: w.overshoot,
            limit: MAX_OVERSHOOT,
            pass: w.overshoot <= MAX_OVERSHOOT,
        });
        let settling = w.settling_s.unwrap_or(f64::INFINITY);
        checks.push(Check {
            name: format!("{side} settling to within {:.0} % (s)", SETTLE_BAND * 100.0),
            value: settling,
            limit: MAX_SETTLING_S,
            pass: settling <= MAX_SETTLING_S,
        });
    }
    Ok(TuneReport {
        factory_chatters: tuning.factory_chatters(),
        tuning,
        line_mm,
        distance_mm: run.summary.distance_plant_final_mm,
        drive_time_s: run.summary.drive_time_s,
        left,
        right,
        checks,
        warnings: run.summary.warnings,
    })
}

impl TuneReport {
    /// The text report: the derivation per wheel, the gains, the checks.
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        for (side, w) in [("left", &self.tuning.left), ("right", &self.tuning.right)] {
            let zn = w.ziegler_nichols;
            let _ = writeln!(
                s,
                "{side:<5}  K {:.3} thesis RPM per unit of U, T {:.4} s, L {:.3} s; set-point {:.2} \
                 thesis RPM at {:.0}/255 duty, {:.1} counts per period",
                w.process_gain,
                w.tau_s,
                crate::firmware::tune::ZN_DEAD_TIME_S,
                w.setpoint_rpm,
                w.steady_duty,
                w.counts_per_period
            );
            let _ = writeln!(
                s,
                "       Ziegler-Nichols 1.2 T/(K L), Ti 2L, Td L/2: kp {:.4} ki {:.3} kd {:.5}",
                zn.kp, zn.ki, zn.kd
            );
            for a in &w.adjusted {
                let _ = writeln!(s, "       {a}");
            }
            let _ = writeln!(
                s,
                "       gains kp {} ki {} kd {}; factory gains on the loop model: {} period(s) at duty 0",
                w.gains.kp, w.gains.ki, w.gains.kd, w.factory_predicted.duty_zero_periods
            );
        }
        let _ = writeln!(
            s,
            "bench: a {:.0} mm line with these gains: {:.1} mm, {:.2} s driving",
            self.line_mm, self.distance_mm, self.drive_time_s
        );
        for c in &self.checks {
            let _ = writeln!(
                s,
                "  {} {:<40} {:.3} (limit {})",
                if c.pass { "pass" } else { "FAIL" },
                c.name,
                c.value,
                c.limit
            );
        }
        for w in &self.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        s
    }
}
