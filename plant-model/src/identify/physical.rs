//! A physical DC-motor model fitted to all PWM levels of a step-response file at once, and
//! its held-out error. The model, its units and what can be identified are in the parent
//! module's docs ("Physical motor model").

use std::f64::consts::PI;
use std::fmt::Write as _;

use serde::Serialize;

use super::data::{IdentifyError, StepData};
use super::first_order::{lstsq, minimise_bounded, unit_response, Sampling};
use super::{THESIS_LEFT_CSV, THESIS_RIGHT_CSV};
use crate::side::Side;

/// The thesis robot's gearbox ratio (motor turns per wheel turn).
pub const GEAR_RATIO: f64 = 100.37;

/// Nominal voltage of the 2S LiPo, V.
pub const SUPPLY_V: f64 = 7.4;

/// Motor-shaft rad/s per thesis "RPM": `6` (true wheel RPM per thesis RPM) `* 2 pi / 60`
/// (wheel rad/s per wheel RPM) `* gear ratio`.
pub fn motor_rad_s_per_thesis_rpm(gear_ratio: f64) -> f64 {
    6.0 * 2.0 * PI / 60.0 * gear_ratio
}

/// How the speed-dependent loss is shared between the back-EMF and viscous friction, which
/// speed data cannot tell apart (only `k_eff = kt + b R / kt` is identifiable).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViscousSplit {
    /// `b = 0`, so `kt = ke = k_eff`: the largest torque constant the data allow.
    NoViscousFriction,
    /// `kt` given (e.g. from a datasheet's no-load speed); `b = (k_eff - kt) kt / R`.
    TorqueConstant {
        /// `kt = ke`, N m/A = V s/rad.
        kt: f64,
    },
}

/// What is fixed rather than fitted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PhysicalAssumptions {
    /// Armature resistance, ohm. Not identifiable from speed data (it only scales the
    /// torques). The default 10 ohm is an assumption: 6 V micro metal gear motors range from
    /// about 4 ohm (high-power) to about 17 ohm (low-power, 0.36 A stall at 6 V).
    pub r_ohm: f64,
    /// Supply voltage, V; duty `d` gives the average voltage `d V`.
    pub supply_v: f64,
    /// Gearbox ratio.
    pub gear_ratio: f64,
    /// How `k_eff` is split between `kt` and `b`.
    pub split: ViscousSplit,
}

impl Default for PhysicalAssumptions {
    /// 10 ohm, 7.4 V, 100.37:1, no viscous friction.
    fn default() -> Self {
        PhysicalAssumptions {
            r_ohm: 10.0,
            supply_v: SUPPLY_V,
            gear_ratio: GEAR_RATIO,
            split: ViscousSplit::NoViscousFriction,
        }
    }
}

/// Physical parameters, all at the motor shaft (load, wheel and robot reflected through the
/// gearbox).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MotorParams {
    /// Armature resistance `R`, ohm.
    pub r_ohm: f64,
    /// Torque constant `kt` = back-EMF constant `ke`, N m/A = V s/rad.
    pub kt: f64,
    /// Rotor + load inertia `J`, kg m^2.
    pub j_kg_m2: f64,
    /// Viscous friction `b`, N m s/rad.
    pub b_nm_s_per_rad: f64,
    /// Coulomb friction `tau_c`, N m.
    pub tau_c_nm: f64,
    /// Gearbox ratio.
    pub gear_ratio: f64,
    /// Supply voltage, V.
    pub supply_v: f64,
}

impl MotorParams {
    /// The combinations speed data can identify.
    pub fn identifiable(&self) -> Identifiable {
        Identifiable {
            k_eff_v_s_per_rad: self.kt + self.b_nm_s_per_rad * self.r_ohm / self.kt,
            dead_band_v: self.tau_c_nm * self.r_ohm / self.kt,
            tau_s: self.tau_s(),
        }
    }

    /// `tau = J / (b + kt ke / R)`, s.
    pub fn tau_s(&self) -> f64 {
        self.j_kg_m2 / (self.b_nm_s_per_rad + self.kt * self.kt / self.r_ohm)
    }

    /// Steady motor speed at `duty`, rad/s: the `w > 0` solution of
    /// `kt (d V - ke w) / R = b w + tau_c`, or 0 in the dead band `d V kt / R <= tau_c`.
    pub fn steady_motor_rad_s(&self, duty: f64) -> f64 {
        let drive = duty * self.supply_v * self.kt / self.r_ohm;
        if drive <= self.tau_c_nm {
            return 0.0;
        }
        (drive - self.tau_c_nm) / (self.b_nm_s_per_rad + self.kt * self.kt / self.r_ohm)
    }

    /// Steady wheel speed at `duty`, thesis RPM.
    pub fn steady_thesis_rpm(&self, duty: f64) -> f64 {
        self.steady_motor_rad_s(duty) / motor_rad_s_per_thesis_rpm(self.gear_ratio)
    }

    /// The speed a firmware sample shows at `t` after a step from rest to `duty` applied at
    /// `start_s`, thesis RPM.
    pub fn sample_thesis_rpm(&self, duty: f64, t: f64, start_s: f64, period_s: f64) -> f64 {
        self.steady_thesis_rpm(duty)
            * unit_response(t, self.tau_s(), start_s, period_s, Sampling::WindowAverage)
    }
}

/// What speed data identify: the motor equation divided by `kt / R` reads
/// `(J R / kt) w' = d V - k_eff w - V_c`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Identifiable {
    /// `k_eff = kt + b R / kt`, V s/rad (motor shaft).
    pub k_eff_v_s_per_rad: f64,
    /// `V_c = tau_c R / kt`: the average voltage needed to turn at all, V.
    pub dead_band_v: f64,
    /// `tau = J R / (kt k_eff)`, s.
    pub tau_s: f64,
}

impl Identifiable {
    /// The physical parameters these stand for under `assumptions`.
    pub fn params(&self, assumptions: &PhysicalAssumptions) -> MotorParams {
        let r = assumptions.r_ohm;
        let kt = match assumptions.split {
            ViscousSplit::NoViscousFriction => self.k_eff_v_s_per_rad,
            ViscousSplit::TorqueConstant { kt } => kt,
        };
        MotorParams {
            r_ohm: r,
            kt,
            j_kg_m2: self.tau_s * self.k_eff_v_s_per_rad * kt / r,
            b_nm_s_per_rad: (self.k_eff_v_s_per_rad - kt) * kt / r,
            tau_c_nm: self.dead_band_v * kt / r,
            gear_ratio: assumptions.gear_ratio,
            supply_v: assumptions.supply_v,
        }
    }
}

/// The model against one PWM level.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelError {
    /// The level's 8-bit PWM value.
    pub pwm: u16,
    /// Whether the fit did not see this level.
    pub held_out: bool,
    /// Measured steady level, thesis RPM.
    pub measured_steady_rpm: f64,
    /// Predicted steady level, thesis RPM.
    pub predicted_steady_rpm: f64,
    /// Predicted minus measured steady level, thesis RPM.
    pub steady_error_rpm: f64,
    /// `steady_error_rpm` in % of the measured level.
    pub steady_error_pct: f64,
    /// RMS of predicted minus measured over all rows of the level, thesis RPM.
    pub rms_error_rpm: f64,
    /// `rms_error_rpm` in % of the measured steady level.
    pub rms_error_pct: f64,
}

/// The physical model fitted to some PWM levels of one file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhysicalFit {
    /// What was fixed.
    pub assumptions: PhysicalAssumptions,
    /// The PWM levels fitted.
    pub trained_on: Vec<u16>,
    /// The fitted combinations.
    pub identifiable: Identifiable,
    /// `V_c / V`: the duty below which the wheel does not turn.
    pub dead_band_duty: f64,
    /// When the response starts relative to the logged `t = 0` (as `L` of
    /// [`super::FopdtFit`]; shared by all levels), s.
    pub start_s: f64,
    /// The physical parameters under `assumptions`.
    pub params: MotorParams,
    /// RMS residual over the fitted rows, thesis RPM.
    pub rms_residual_rpm: f64,
    /// One entry per PWM level of the file (fitted and held out).
    pub levels: Vec<LevelError>,
}

impl PhysicalFit {
    /// Predicted steady wheel speed at `duty`, thesis RPM.
    pub fn steady_thesis_rpm(&self, duty: f64) -> f64 {
        self.params.steady_thesis_rpm(duty)
    }
}

fn pwm_list(levels: &[u16]) -> String {
    levels
        .iter()
        .map(u16::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Fits the physical model to the PWM levels `train` of `data` (all at once: one `k_eff`,
/// `V_c`, `tau` and start time for every level) and evaluates it on every level of `data`.
///
/// Two stages, each over all trained levels at once:
///
/// 1. the steady-state equation, which is linear in the duty
///    (`w_ss(d) = (d V - V_c) / k_eff`), by linear least squares (nalgebra) on the steady
///    levels (the mean of each column's [`StepData::steady_rows`]);
/// 2. `tau` and the start time by a bounded search (grid and golden section, as in
///    [`super::fit_fopdt`]) minimising the squared error over all rows of the trained
///    levels, the samples modelled as the firmware's window averages of
///    `w_ss(d) (1 - exp(-(t - start)/tau))`.
///
/// A single least-squares fit of everything over the printed rows would let the eight
/// printed rows of each rise outweigh the three of each steady level; since the low levels
/// rise more slowly than one `tau` allows, it then lowers their steady speeds to follow the
/// rise (on the thesis data it put the dead band at PWM 147 and missed PWM 170's steady
/// level by 39 %).
pub fn fit_physical(
    data: &StepData,
    train: &[u16],
    assumptions: &PhysicalAssumptions,
) -> Result<PhysicalFit, IdentifyError> {
    let fail = |reason: String| IdentifyError::Fit {
        column: format!("pwm {}", pwm_list(train)),
        reason,
    };
    let columns: Vec<_> = train
        .iter()
        .map(|&p| {
            data.levels
                .iter()
                .find(|c| c.pwm == Some(p))
                .ok_or_else(|| fail(format!("the file has no column pwm{p}_rpm")))
        })
        .collect::<Result<_, _>>()?;
    if columns.len() < 2 {
        return Err(fail(
            "at least two PWM levels are needed to separate the gain from the dead band".into(),
        ));
    }
    let period = data.sample_period_s;
    let steady = data.steady_rows();
    let steady_level =
        |values: &[f64]| values[steady.clone()].iter().sum::<f64>() / steady.len() as f64;

    // Stage 1: the steady line w_ss(d) = p1 d + p0, thesis RPM.
    let (line, _) = lstsq(
        columns
            .iter()
            .map(|c| ([c.duty().unwrap_or(0.0), 1.0], steady_level(&c.values))),
    )
    .ok_or_else(|| fail("the steady levels do not determine a line".into()))?;
    let (p1, p0) = (line[0], line[1]);
    if p1.is_nan() || p1 <= 0.0 {
        return Err(fail(
            "the steady levels do not rise with the duty; no motor model fits".into(),
        ));
    }
    let w_ss = |d: f64| (p1 * d + p0).max(0.0);

    // Stage 2: tau and the start time on all rows.
    let sse = |tau: f64, start: f64| -> f64 {
        columns
            .iter()
            .map(|c| {
                let target = w_ss(c.duty().unwrap_or(0.0));
                data.times_s
                    .iter()
                    .zip(&c.values)
                    .map(|(&t, &v)| {
                        let model =
                            target * unit_response(t, tau, start, period, Sampling::WindowAverage);
                        (model - v).powi(2)
                    })
                    .sum::<f64>()
            })
            .sum()
    };
    let best_tau = |start: f64| {
        minimise_bounded(
            |tau| sse(tau, start),
            0.1 * period,
            100.0 * period,
            32,
            true,
        )
    };
    let (start, _) = minimise_bounded(|s| best_tau(s).1, -period, 6.0 * period, 141, false);
    let (tau, sse) = best_tau(start);
    let conv = motor_rad_s_per_thesis_rpm(assumptions.gear_ratio);
    let k_eff = assumptions.supply_v / (p1 * conv);
    let dead_band_duty = -p0 / p1;
    let identifiable = Identifiable {
        k_eff_v_s_per_rad: k_eff,
        dead_band_v: dead_band_duty * assumptions.supply_v,
        tau_s: tau,
    };
    let params = identifiable.params(assumptions);
    let levels = data
        .levels
        .iter()
        .filter_map(|c| {
            let pwm = c.pwm?;
            let duty = c.duty()?;
            let measured = steady_level(&c.values);
            let predicted = params.steady_thesis_rpm(duty);
            let sq: f64 = data
                .times_s
                .iter()
                .zip(&c.values)
                .map(|(&t, &v)| (params.sample_thesis_rpm(duty, t, start, period) - v).powi(2))
                .sum();
            let rms = (sq / c.values.len() as f64).sqrt();
            Some(LevelError {
                pwm,
                held_out: !train.contains(&pwm),
                measured_steady_rpm: measured,
                predicted_steady_rpm: predicted,
                steady_error_rpm: predicted - measured,
                steady_error_pct: 100.0 * (predicted - measured) / measured,
                rms_error_rpm: rms,
                rms_error_pct: 100.0 * rms / measured,
            })
        })
        .collect();
    let fitted_rows: usize = columns.iter().map(|c| c.values.len()).sum();
    Ok(PhysicalFit {
        assumptions: *assumptions,
        trained_on: train.to_vec(),
        identifiable,
        dead_band_duty,
        start_s: start,
        params,
        rms_residual_rpm: (sse / fitted_rows as f64).sqrt(),
        levels,
    })
}

/// One train/hold-out split.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoldoutSplit {
    /// What the split tests.
    pub name: String,
    /// Levels fitted.
    pub train: Vec<u16>,
    /// Levels predicted.
    pub held_out: Vec<u16>,
    /// The fit (its `levels` cover all five, `held_out` marked).
    pub fit: PhysicalFit,
}

/// The hold-out study of one side.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SideHoldout {
    /// Which motor.
    pub side: Side,
    /// The model fitted to all levels (per-level residuals of the full fit).
    pub all_levels: PhysicalFit,
    /// The splits.
    pub splits: Vec<HoldoutSplit>,
}

/// Physical-model fit on some levels, error on the others, for both thesis motors.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoldoutReport {
    /// What was fixed.
    pub assumptions: PhysicalAssumptions,
    /// Right, then left.
    pub sides: Vec<SideHoldout>,
}

/// The two splits: interpolation (train 170, 210, 250; predict 190, 230) and extrapolation
/// (train 190, 210, 230; predict 170, 250).
pub const HOLDOUT_SPLITS: [(&str, [u16; 3]); 2] = [
    ("interpolate", [170, 210, 250]),
    ("extrapolate", [190, 210, 230]),
];

impl HoldoutReport {
    /// Every held-out level of every split and side.
    pub fn held_out_levels(&self) -> impl Iterator<Item = (Side, &str, &LevelError)> + '_ {
        self.sides.iter().flat_map(|s| {
            s.splits.iter().flat_map(move |sp| {
                sp.fit
                    .levels
                    .iter()
                    .filter(|l| l.held_out)
                    .map(move |l| (s.side, sp.name.as_str(), l))
            })
        })
    }

    /// A plain-text table (what docs/results/calibration.md quotes).
    pub fn render(&self) -> String {
        let mut out = String::new();
        let a = &self.assumptions;
        let _ = writeln!(
            out,
            "Physical motor model (R = {} ohm fixed, {} V supply, {}:1, split: {:?})",
            a.r_ohm, a.supply_v, a.gear_ratio, a.split
        );
        for side in &self.sides {
            let f = &side.all_levels;
            let _ = writeln!(
                out,
                "\n{} motor, fitted to all levels: k_eff {:.4e} V s/rad, dead band {:.3} V \
                 (duty {:.3} = PWM {:.1}), tau {:.4} s, start {:+.4} s, rms {:.2} thesis RPM",
                side.side,
                f.identifiable.k_eff_v_s_per_rad,
                f.identifiable.dead_band_v,
                f.dead_band_duty,
                f.dead_band_duty * 255.0,
                f.identifiable.tau_s,
                f.start_s,
                f.rms_residual_rpm
            );
            render_levels(&mut out, "all levels", f);
            for sp in &side.splits {
                render_levels(
                    &mut out,
                    &format!(
                        "{}: train {}, hold out {}",
                        sp.name,
                        pwm_list(&sp.train),
                        pwm_list(&sp.held_out)
                    ),
                    &sp.fit,
                );
            }
        }
        out
    }
}

fn render_levels(out: &mut String, title: &str, fit: &PhysicalFit) {
    let _ = writeln!(out, "  {title}");
    let _ = writeln!(
        out,
        "    pwm  role       measured  predicted  steady err (RPM, %)   rms err (RPM, %)"
    );
    for l in &fit.levels {
        let _ = writeln!(
            out,
            "    {:>3}  {:<9}  {:>8.2}  {:>9.2}  {:>+8.2} {:>+7.1} %   {:>6.2} {:>6.1} %",
            l.pwm,
            if l.held_out { "held out" } else { "fitted" },
            l.measured_steady_rpm,
            l.predicted_steady_rpm,
            l.steady_error_rpm,
            l.steady_error_pct,
            l.rms_error_rpm,
            l.rms_error_pct
        );
    }
}

/// The hold-out study of `data` under `assumptions`, with [`HOLDOUT_SPLITS`].
pub fn holdout_for(
    data: &StepData,
    side: Side,
    assumptions: &PhysicalAssumptions,
) -> Result<SideHoldout, IdentifyError> {
    let all: Vec<u16> = data.levels.iter().filter_map(|c| c.pwm).collect();
    let all_levels = fit_physical(data, &all, assumptions)?;
    let splits = HOLDOUT_SPLITS
        .iter()
        .map(|(name, train)| {
            let fit = fit_physical(data, train, assumptions)?;
            Ok(HoldoutSplit {
                name: (*name).to_owned(),
                train: train.to_vec(),
                held_out: all.iter().copied().filter(|p| !train.contains(p)).collect(),
                fit,
            })
        })
        .collect::<Result<_, IdentifyError>>()?;
    Ok(SideHoldout {
        side,
        all_levels,
        splits,
    })
}

/// The hold-out study of both thesis motors (Tables 2 and 3) with the default
/// [`PhysicalAssumptions`].
pub fn holdout_report() -> HoldoutReport {
    let assumptions = PhysicalAssumptions::default();
    let sides = [
        (Side::Right, THESIS_RIGHT_CSV),
        (Side::Left, THESIS_LEFT_CSV),
    ]
    .into_iter()
    .map(|(side, csv)| {
        let data = StepData::parse(csv).expect("the vendored thesis CSVs parse");
        holdout_for(&data, side, &assumptions).expect("the thesis data fit")
    })
    .collect();
    HoldoutReport { assumptions, sides }
}
