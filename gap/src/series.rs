//! Time series: the telemetry layout, its segments, the residual of a simulated series
//! against a measured one (per segment, whiteness, correlation with the input), and the
//! held-out check of the motor model on step responses.
//!
//! # Telemetry CSV
//!
//! `#` comments and blank lines anywhere; one header, then one row per control period:
//!
//! ```text
//! t_s,rpm_left,rpm_right,pwm_left,pwm_right[,x_mm,y_mm,theta_rad]
//! ```
//!
//! `rpm_*`: the wheel speed of the period, signed (forward positive), in the manifest's
//! `rpm_unit`; `pwm_*`: the 8-bit duty command, signed (−255..255, forward positive); the
//! pose columns (all three or none) track the robot in [`calib::Frame::Default`]. Rows must be
//! in time order.

use std::path::Path;

use plant_model::identify::{fit_physical, unit_response, PhysicalAssumptions, Sampling, StepData};
use plant_model::Side;
use serde::Serialize;

use crate::stats::{cross_correlation, ljung_box, minimise_1d, CrossCorrelation, LjungBox};
pub use crate::telemetry::{RpmUnit, Sample, Telemetry, TELEMETRY_HEADER, TELEMETRY_POSE};
use crate::GapError;

/// Reads the telemetry CSV (module docs). `path` names the file in errors.
pub fn read_telemetry(
    text: &str,
    path: &Path,
    period_s: f64,
    unit: RpmUnit,
) -> Result<Telemetry, GapError> {
    let err = |line: usize, message: String| GapError::Telemetry {
        path: path.to_path_buf(),
        line,
        message,
    };
    let to_thesis = match unit {
        RpmUnit::ThesisRpm => 1.0,
        RpmUnit::WheelRpm => 1.0 / 6.0,
    };
    let mut header: Option<bool> = None;
    let mut samples: Vec<Sample> = Vec::new();
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        last_line = line;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let Some(with_pose) = header else {
            let with_pose = if l == TELEMETRY_HEADER {
                false
            } else if l == format!("{TELEMETRY_HEADER},{TELEMETRY_POSE}") {
                true
            } else {
                return Err(err(
                    line,
                    format!(
                        "header is `{l}`, expected `{TELEMETRY_HEADER}` optionally followed by \
                         `,{TELEMETRY_POSE}`"
                    ),
                ));
            };
            header = Some(with_pose);
            continue;
        };
        let fields: Vec<&str> = l.split(',').map(str::trim).collect();
        let want = if with_pose { 8 } else { 5 };
        if fields.len() != want {
            return Err(err(
                line,
                format!("{} fields, the header has {want}", fields.len()),
            ));
        }
        let names = [
            "t_s",
            "rpm_left",
            "rpm_right",
            "pwm_left",
            "pwm_right",
            "x_mm",
            "y_mm",
            "theta_rad",
        ];
        let mut v = [0.0; 8];
        for (k, f) in fields.iter().enumerate() {
            v[k] = f
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    err(
                        line,
                        format!("`{}` = `{f}` is not a finite number", names[k]),
                    )
                })?;
        }
        for (k, name) in [(3, "pwm_left"), (4, "pwm_right")] {
            if v[k].abs() > 255.0 {
                return Err(err(
                    line,
                    format!("`{name}` = {} is outside −255..255", v[k]),
                ));
            }
        }
        if let Some(prev) = samples.last() {
            if v[0] <= prev.t_s {
                return Err(err(line, format!("t_s = {} does not increase", v[0])));
            }
        }
        samples.push(Sample {
            t_s: v[0],
            rpm_left: v[1] * to_thesis,
            rpm_right: v[2] * to_thesis,
            pwm_left: v[3],
            pwm_right: v[4],
            pose: with_pose.then_some((v[5], v[6], v[7])),
        });
    }
    if header.is_none() {
        return Err(err(
            last_line + 1,
            format!("no header; the first non-comment line must be `{TELEMETRY_HEADER}`"),
        ));
    }
    if samples.is_empty() {
        return Err(err(last_line + 1, "no data rows".into()));
    }
    Ok(Telemetry { period_s, samples })
}

/// What the robot was doing during a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SegmentKind {
    /// The first samples of a leg, until both wheels reach 90 % of the leg's steady speed.
    Startup,
    /// The rest of a leg.
    Steady,
    /// A spin (duties of opposite sign, or one wheel driven alone).
    Turn,
    /// Both duties zero: stopping or coasting.
    StopCoast,
}

impl SegmentKind {
    /// All, in report order.
    pub const ALL: [SegmentKind; 4] = [
        SegmentKind::Startup,
        SegmentKind::Steady,
        SegmentKind::Turn,
        SegmentKind::StopCoast,
    ];
}

/// The segment of every sample, from the duties (and the speeds, for the start-up).
pub fn segments(t: &Telemetry) -> Vec<SegmentKind> {
    #[derive(PartialEq, Clone, Copy)]
    enum Drive {
        Leg,
        Turn,
        Stop,
    }
    let drive: Vec<Drive> = t
        .samples
        .iter()
        .map(|s| {
            if s.pwm_left == 0.0 && s.pwm_right == 0.0 {
                Drive::Stop
            } else if s.pwm_left > 0.0 && s.pwm_right > 0.0 {
                Drive::Leg
            } else {
                Drive::Turn
            }
        })
        .collect();
    let mut out: Vec<SegmentKind> = drive
        .iter()
        .map(|d| match d {
            Drive::Leg => SegmentKind::Steady,
            Drive::Turn => SegmentKind::Turn,
            Drive::Stop => SegmentKind::StopCoast,
        })
        .collect();
    // Legs: mark the start-up transient.
    let mut i = 0;
    while i < drive.len() {
        if drive[i] != Drive::Leg {
            i += 1;
            continue;
        }
        let start = i;
        while i < drive.len() && drive[i] == Drive::Leg {
            i += 1;
        }
        let leg = &t.samples[start..i];
        let half = &leg[leg.len() / 2..];
        let median = |f: &dyn Fn(&Sample) -> f64| {
            let mut v: Vec<f64> = half.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (ml, mr) = (
            median(&|s| s.rpm_left.abs()),
            median(&|s| s.rpm_right.abs()),
        );
        let settled = leg
            .iter()
            .position(|s| s.rpm_left.abs() >= 0.9 * ml && s.rpm_right.abs() >= 0.9 * mr)
            .unwrap_or(leg.len())
            .max(1);
        for o in out.iter_mut().skip(start).take(settled) {
            *o = SegmentKind::Startup;
        }
    }
    out
}

/// The residual of one wheel over one segment kind.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentResidual {
    /// The segment kind.
    pub segment: SegmentKind,
    /// Samples.
    pub n: usize,
    /// Mean of real − sim, thesis RPM.
    pub bias_left: f64,
    /// Mean of real − sim, thesis RPM.
    pub bias_right: f64,
    /// RMS of real − sim, thesis RPM.
    pub rms_left: f64,
    /// RMS of real − sim, thesis RPM.
    pub rms_right: f64,
}

/// Whiteness and input correlation of one wheel's residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelResidualTests {
    /// Which wheel.
    pub side: Side,
    /// RMS of real − sim, thesis RPM.
    pub rms: f64,
    /// Ljung-Box on the residual (`None`: too short or constant).
    pub ljung_box: Option<LjungBox>,
    /// Cross-correlation of the residual with this wheel's duty (`None`: the duty is
    /// constant, as in a step response, so no correlation can be measured).
    pub input_correlation: Option<CrossCorrelation>,
    /// What the two tests say.
    pub verdict: String,
}

/// The gap between a measured and a simulated series.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeriesGap {
    /// What is compared.
    pub label: String,
    /// Samples compared.
    pub n: usize,
    /// Per segment kind.
    pub segments: Vec<SegmentResidual>,
    /// Per wheel.
    pub wheels: Vec<WheelResidualTests>,
    /// Remarks (e.g. lengths differ).
    pub notes: Vec<String>,
}

fn verdict(lb: &Option<LjungBox>, cc: &Option<CrossCorrelation>) -> String {
    let mut v = Vec::new();
    match lb {
        Some(l) if l.rejected => v.push(format!(
            "residual not white (Ljung-Box Q = {:.1}, p = {:.3}): dynamics the model lacks",
            l.q, l.p_value
        )),
        Some(l) => v.push(format!("residual white (p = {:.2})", l.p_value)),
        None => v.push("whiteness not testable (too few samples)".into()),
    }
    match cc {
        Some(c) if c.significant => v.push(format!(
            "correlated with the duty (r = {:+.2} at lag {}, band ±{:.2}): an input-dependent \
             effect is missing (gain, dead band, saturation)",
            c.peak, c.peak_lag, c.band
        )),
        Some(_) => v.push("uncorrelated with the duty".into()),
        None => v.push("input correlation not measurable (constant duty)".into()),
    }
    v.join("; ")
}

/// Residual tests of a real − sim series against an input, over a quarter of its samples'
/// lags (1 to 10).
pub fn residual_tests(side: Side, residual: &[f64], input: &[f64]) -> WheelResidualTests {
    let n = residual.len();
    let lags = (n / 4).clamp(1, 10);
    let lb = ljung_box(residual, lags);
    let cc = cross_correlation(residual, input, lags);
    let rms = (residual.iter().map(|e| e * e).sum::<f64>() / n.max(1) as f64).sqrt();
    WheelResidualTests {
        side,
        rms,
        verdict: verdict(&lb, &cc),
        ljung_box: lb,
        input_correlation: cc,
    }
}

/// Compares a measured series with a simulated one, sample by sample (the segments come
/// from the measured duties).
pub fn series_gap(label: &str, real: &Telemetry, sim: &Telemetry) -> Result<SeriesGap, GapError> {
    let mut notes = Vec::new();
    if (real.period_s - sim.period_s).abs() > 1e-9 {
        return Err(GapError::Series(format!(
            "periods differ: real {} s, sim {} s",
            real.period_s, sim.period_s
        )));
    }
    let n = real.samples.len().min(sim.samples.len());
    if n < 4 {
        return Err(GapError::Series("fewer than 4 common samples".into()));
    }
    if real.samples.len() != sim.samples.len() {
        notes.push(format!(
            "lengths differ (real {}, sim {}); compared the first {n}",
            real.samples.len(),
            sim.samples.len()
        ));
    }
    let seg = segments(real);
    let el: Vec<f64> = (0..n)
        .map(|i| real.samples[i].rpm_left - sim.samples[i].rpm_left)
        .collect();
    let er: Vec<f64> = (0..n)
        .map(|i| real.samples[i].rpm_right - sim.samples[i].rpm_right)
        .collect();
    let segments = SegmentKind::ALL
        .iter()
        .filter_map(|&k| {
            let idx: Vec<usize> = (0..n).filter(|&i| seg[i] == k).collect();
            if idx.is_empty() {
                return None;
            }
            let m = idx.len() as f64;
            let mean = |e: &[f64]| idx.iter().map(|&i| e[i]).sum::<f64>() / m;
            let rms = |e: &[f64]| (idx.iter().map(|&i| e[i] * e[i]).sum::<f64>() / m).sqrt();
            Some(SegmentResidual {
                segment: k,
                n: idx.len(),
                bias_left: mean(&el),
                bias_right: mean(&er),
                rms_left: rms(&el),
                rms_right: rms(&er),
            })
        })
        .collect();
    let ul: Vec<f64> = real.samples[..n].iter().map(|s| s.pwm_left).collect();
    let ur: Vec<f64> = real.samples[..n].iter().map(|s| s.pwm_right).collect();
    Ok(SeriesGap {
        label: label.to_owned(),
        n,
        segments,
        wheels: vec![
            residual_tests(Side::Left, &el, &ul),
            residual_tests(Side::Right, &er, &ur),
        ],
        notes,
    })
}

/// PWM levels split into disjoint training and held-out sets.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct LevelSplit {
    train: Vec<u16>,
    held_out: Vec<u16>,
}

impl LevelSplit {
    /// Train on `train` (each must be in `all`), hold out the rest of `all`.
    pub fn new(all: &[u16], train: &[u16]) -> Result<Self, GapError> {
        if let Some(t) = train.iter().find(|t| !all.contains(t)) {
            return Err(GapError::Split(format!(
                "PWM level {t} is not in the data (have {all:?})"
            )));
        }
        let held_out: Vec<u16> = all.iter().copied().filter(|p| !train.contains(p)).collect();
        if train.len() < 2 || held_out.is_empty() {
            return Err(GapError::Split(
                "need at least two training levels and one held out".into(),
            ));
        }
        Ok(LevelSplit {
            train: train.to_vec(),
            held_out,
        })
    }

    /// Training levels.
    pub fn train(&self) -> &[u16] {
        &self.train
    }

    /// Held-out levels.
    pub fn held_out(&self) -> &[u16] {
        &self.held_out
    }
}

/// One PWM level against both motor models.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelGap {
    /// PWM value.
    pub pwm: u16,
    /// Whether the fits did not see it.
    pub held_out: bool,
    /// Measured steady speed, thesis RPM.
    pub measured_steady_rpm: f64,
    /// The model without friction: steady speed.
    pub before_steady_rpm: f64,
    /// The model with Coulomb friction: steady speed.
    pub after_steady_rpm: f64,
    /// RMS over the rows, without friction.
    pub before_rms_rpm: f64,
    /// RMS over the rows, with friction.
    pub after_rms_rpm: f64,
    /// RMS with friction over the first contiguous block of rows (the start-up transient),
    /// thesis RPM.
    pub after_rise_rms_rpm: f64,
    /// RMS with friction over the steady rows, thesis RPM.
    pub after_steady_rms_rpm: f64,
    /// Residual tests of the model with friction on this level's first contiguous block of
    /// rows.
    pub after_tests: WheelResidualTests,
}

/// The motor model on held-out PWM levels, before and after adding friction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotorHoldout {
    /// Which motor.
    pub side: Side,
    /// Levels fitted.
    pub train: Vec<u16>,
    /// Levels predicted.
    pub held_out: Vec<u16>,
    /// Before: first order with the steady speed proportional to the duty (the thesis'
    /// structure), gain fitted on the training levels, thesis RPM per unit duty.
    pub before_gain_rpm_per_duty: f64,
    /// Before: time constant, s.
    pub before_tau_s: f64,
    /// After: `plant_model::identify::fit_physical` on the training levels (Coulomb
    /// friction, i.e. a dead band): the dead band as PWM.
    pub after_dead_band_pwm: f64,
    /// After: time constant, s.
    pub after_tau_s: f64,
    /// Per level.
    pub levels: Vec<LevelGap>,
    /// RMS over the held-out rows, before, thesis RPM.
    pub heldout_rms_before: f64,
    /// RMS over the held-out rows, after, thesis RPM.
    pub heldout_rms_after: f64,
    /// 1 − after/before.
    pub reduction: f64,
}

fn only_levels(data: &StepData, keep: &[u16]) -> StepData {
    let levels: Vec<_> = data
        .levels
        .iter()
        .filter(|c| c.pwm.is_some_and(|p| keep.contains(&p)))
        .cloned()
        .collect();
    let rows = data.times_s.len();
    let mean_values = (0..rows)
        .map(|i| levels.iter().map(|c| c.values[i]).sum::<f64>() / levels.len().max(1) as f64)
        .collect();
    StepData {
        mean: plant_model::identify::Column {
            name: "mean_rpm".into(),
            pwm: None,
            values: mean_values,
        },
        levels,
        ..data.clone()
    }
}

/// Fits the motor without and with friction on the training levels of `split` only (the fit
/// receives a copy of the data holding nothing else) and reports both on every level.
pub fn motor_holdout(
    data: &StepData,
    side: Side,
    split: &LevelSplit,
) -> Result<MotorHoldout, GapError> {
    let train = only_levels(data, &split.train);
    let period = data.sample_period_s;
    let steady = train.steady_rows();
    let level = |v: &[f64]| v[steady.clone()].iter().sum::<f64>() / steady.len() as f64;

    // Before: w = g d (1 - exp(-(t - start)/tau)), g by least squares through 0.
    let (sxy, sxx) = train.levels.iter().fold((0.0, 0.0), |(a, b), c| {
        let d = c.duty().unwrap_or(0.0);
        (a + d * level(&c.values), b + d * d)
    });
    let g = sxy / sxx;
    let sse = |tau: f64, start: f64| {
        train
            .levels
            .iter()
            .map(|c| {
                let target = g * c.duty().unwrap_or(0.0);
                train
                    .times_s
                    .iter()
                    .zip(&c.values)
                    .map(|(&t, &v)| {
                        (target * unit_response(t, tau, start, period, Sampling::WindowAverage) - v)
                            .powi(2)
                    })
                    .sum::<f64>()
            })
            .sum::<f64>()
    };
    let best_tau = |s: f64| minimise_1d(|tau| sse(tau, s), 0.1 * period, 100.0 * period, 32, true);
    let (start0, _) = minimise_1d(|s| best_tau(s).1, -period, 6.0 * period, 141, false);
    let (tau0, _) = best_tau(start0);
    let before =
        |d: f64, t: f64| g * d * unit_response(t, tau0, start0, period, Sampling::WindowAverage);

    // After: the physical model with Coulomb friction.
    let fit = fit_physical(&train, &split.train, &PhysicalAssumptions::default())
        .map_err(|e| GapError::Fit(e.to_string()))?;
    let after = |d: f64, t: f64| fit.params.sample_thesis_rpm(d, t, fit.start_s, period);

    let steady_all = data.steady_rows();
    let mut levels = Vec::new();
    let (mut sb, mut sa, mut nh) = (0.0, 0.0, 0usize);
    for c in &data.levels {
        let (Some(pwm), Some(d)) = (c.pwm, c.duty()) else {
            continue;
        };
        let held = split.held_out.contains(&pwm);
        let eb: Vec<f64> = data
            .times_s
            .iter()
            .zip(&c.values)
            .map(|(&t, &v)| v - before(d, t))
            .collect();
        let ea: Vec<f64> = data
            .times_s
            .iter()
            .zip(&c.values)
            .map(|(&t, &v)| v - after(d, t))
            .collect();
        let rms = |e: &[f64]| (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        if held {
            sb += eb.iter().map(|x| x * x).sum::<f64>();
            sa += ea.iter().map(|x| x * x).sum::<f64>();
            nh += eb.len();
        }
        // The first contiguous block of rows (the rise).
        let block = (1..data.samples.len())
            .find(|&i| !data.contiguous(i))
            .unwrap_or(data.samples.len());
        let input: Vec<f64> = vec![f64::from(pwm); block];
        let measured = c.values[steady_all.clone()].iter().sum::<f64>() / steady_all.len() as f64;
        levels.push(LevelGap {
            pwm,
            held_out: held,
            measured_steady_rpm: measured,
            before_steady_rpm: g * d,
            after_steady_rpm: fit.params.steady_thesis_rpm(d),
            before_rms_rpm: rms(&eb),
            after_rms_rpm: rms(&ea),
            after_rise_rms_rpm: rms(&ea[..block]),
            after_steady_rms_rpm: rms(&ea[steady_all.clone()]),
            after_tests: residual_tests(side, &ea[..block], &input),
        });
    }
    let hb = (sb / nh.max(1) as f64).sqrt();
    let ha = (sa / nh.max(1) as f64).sqrt();
    Ok(MotorHoldout {
        side,
        train: split.train.clone(),
        held_out: split.held_out.clone(),
        before_gain_rpm_per_duty: g,
        before_tau_s: tau0,
        after_dead_band_pwm: fit.dead_band_duty * 255.0,
        after_tau_s: fit.identifiable.tau_s,
        levels,
        heldout_rms_before: hb,
        heldout_rms_after: ha,
        reduction: crate::fit::reduction(hb, ha),
    })
}
