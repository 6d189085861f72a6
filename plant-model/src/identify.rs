//! System identification from step responses: the thesis' first-order motor models and PID
//! gains recomputed from its Tables 2 and 3 (`fixtures/thesis-data/motor_step_*.csv`), which
//! of its printed figures they reproduce and which they contradict, and a physical DC-motor
//! model fitted to all PWM levels at once.
//!
//! Entry points: [`identify_csv`] (a file or CSV text, plus a side hint) returns an
//! [`Identification`] (serde `Serialize`, and [`Identification::render`] for text);
//! [`holdout_report`] fits the physical model on some PWM levels and reports its error on
//! the others.
//!
//! # Units
//!
//! - **thesis "RPM"** ([`crate::ThesisRpm`]): what the thesis firmware prints and tabulates,
//!   `counts / T * 60 / 6 / 602.2`, which is the *true wheel RPM / 6* (it divides by the 6
//!   counts per motor turn twice). Every speed in this module is in this unit unless its
//!   name says otherwise. One encoder count in one 15 ms window is
//!   `60 / (6 * 6 * 100.37 * 0.015)` = 1.107 thesis RPM ([`count_quantum_thesis_rpm`]): the
//!   resolution of each PWM column; the mean of five columns resolves 1.107 / 5.
//! - **true wheel RPM** = 6 x thesis RPM; **wheel rad/s** = thesis RPM x pi/5 (0.628);
//!   **motor-shaft rad/s** = wheel rad/s x 100.37 = 63.06 x thesis RPM
//!   ([`motor_rad_s_per_thesis_rpm`]), the unit of the physical model.
//! - **PWM**: the 8-bit compare value of `analogWrite`; duty `d = PWM / 255`.
//! - Times in seconds, `T` = 0.015 s the sample period.
//!
//! # The data and how a sample is modelled
//!
//! Each row `k` is the firmware's speed for the window `(t_k - T, t_k]`: encoder counts in the
//! window, so the *mean* speed over the window, quantised to whole counts. Every least-squares
//! fit here models a sample that way ([`Sampling::WindowAverage`]: the model's speed averaged
//! over the window, in closed form). The thesis printed rows 0-7 and 127-129 only: fits
//! evaluate the model at each row's own time and never interpolate across the gap; a 63.2 %
//! point that falls in the gap (PWM 170 and 190 right, 170 left) is reported as the interval
//! 0.105-1.905 s, not as a number.
//!
//! # What the thesis did (section 6.2-6.3)
//!
//! 1. It stepped each motor (robot on the floor, the other motor at the same PWM) from rest
//!    to PWM 170, 190, 210, 230 and 250 and logged the speed every 15 ms (Tables 2, 3).
//! 2. It averaged the five curves ("PROM") and fitted `K / (tau s + 1)` to the average by the
//!    63.2 % criterion: `K` its steady level (24.98 -> 25, 21.81 -> 22), `tau` the time it
//!    reaches 63.2 % of `K` (printed: 0.0685 s right, 0.055 s left). The average of five step
//!    responses is the response to the average step, so `K` is the steady speed after a step
//!    from 0 to PWM 210 (duty 210/255), which the thesis treats as a unit step. `K` is **not**
//!    a gain per PWM count: that would be 25/210 = 0.119 thesis RPM per count from rest, while
//!    the steady levels rise 0.31 (right) and 0.35 (left) per count around PWM 210
//!    ([`GainInterpretation`]).
//! 3. It discretised with a zero-order hold at 15 ms: right `4.917/(z - 0.8033)`, the ZOH of
//!    `25/(0.0685 s + 1)`; left printed `0.5919/(z - 0.9731)`, which is the ZOH of
//!    `22/(0.55 s + 1)`: tau entered ten times too large (with 0.055 s it is
//!    `5.2514/(z - 0.7613)`).
//! 4. It tuned a PID by Ziegler and Nichols' first method in Ogata's table form
//!    (`Kp = 1.2 T/L`, `Ti = 2L`, `Td = L/2`) with `T` = the 63.2 % time constant (not the
//!    reaction-curve tangent's `T`) and `L` = 0.03 s for both motors: `Kp` = 1.2 x 0.0685 /
//!    0.03 = 2.74 and 1.2 x 0.055 / 0.03 = 2.20, `Ti` = 0.06 s, `Td` = 0.015 s. The firmware
//!    uses `Ki = Kp/Ti` (45.66, 36.666; truncated) and `Kd = Kp Td` (0.0411, 0.033); the
//!    printed controller (126) has 0.33 s^2 for the left, a factor-10 slip. `L` is never
//!    stated; `Ti` and `Kp` fix it at 0.03 s = two sample periods. The curves do not show it:
//!    the mean curves already read 17 % (right) and 22 % (left) of `K` at the first sample,
//!    the FOPDT fits start them 7.6 ms *before* `t = 0` (below), and the tangent meets zero
//!    at 4.5 ms and 2.8 ms. Ogata's `1.2 T/L` also drops the process gain of Ziegler and
//!    Nichols' `1.2 T/(K L)`; in the firmware's own controller units (its output `U` drives
//!    `PWM = map(U, 24, -24, 255, 0) = 127.5 + 5.3125 U`, [`CONTROLLER_PWM_PER_UNIT`]) the
//!    incremental gain is 1.65 (right) and 1.88 (left) thesis RPM per unit, and the rule would
//!    give `Kp` = 1.67 and 1.17 ([`PidGains::kp_with_process_gain`]).
//!
//! # Methods
//!
//! - **63.2 %** ([`fit_632`]): `K` = mean of the steady rows ([`StepData::steady_rows`]: the
//!   last contiguous block, here rows 127-129); `tau` = first time the curve reaches
//!   `(1 - 1/e) K`, linearly interpolated between the two samples around it. Its resolution
//!   ([`FirstOrder632::tau_resolution_s`]) is one count quantum over the slope there.
//! - **FOPDT least squares** ([`fit_fopdt`]): `K e^(-L s) / (tau s + 1)`, samples as window
//!   means, minimising the squared error over all rows. Bounded search over the dead time `L`
//!   in `[-T, 6T]` (grid of `T/20`, then golden section), for each `L` a bounded search over
//!   `tau` in `[T/10, 100 T]` (geometric grid, then golden section), and for each `(L, tau)`
//!   the gain `K` by linear least squares (nalgebra): variable projection, no Gauss-Newton.
//!   A negative `L` means the response started before the first counting window opened (the
//!   logged time stamps lag the step); [`Identification::dead_time_s`] is `max(L, 0)`.
//! - **Reaction curve** ([`reaction_curve`]): the tangent through the steepest pair of
//!   consecutive samples of the rise; `L` where it meets 0, `T = K / slope`.
//! - **Ziegler-Nichols, first method** ([`ziegler_nichols`]): `Kp = 1.2 T/L`, `Ti = 2L`,
//!   `Td = L/2`, `Ki = Kp/Ti`, `Kd = Kp Td`. [`Identification`] applies it the thesis' way
//!   (`T` = the 63.2 % `tau`, `L` = two sample periods unless
//!   [`IdentifyOptions::zn_dead_time_s`] says otherwise) and, per column, also to the
//!   tangent's own `L` and `T` ([`LevelFit::zn_reaction_curve`]).
//! - **ZOH discrete model** ([`DiscreteModel::zoh`]): `y(z)/u(z) = K (1 - a)/(z - a) z^-d`,
//!   `a = exp(-T/tau)`, `d = round(L/T)` for the FOPDT's dead time (0 here).
//!
//! # Results on the thesis data (mean curves)
//!
//! | | right | left |
//! |---|---|---|
//! | `K` (63.2 %), thesis RPM | 24.98 (thesis 25) | 21.81 (thesis 22) |
//! | `tau` (63.2 %), s | 0.0672 +/- 0.0021 (thesis 0.0685) | 0.0490 +/- 0.0017 (thesis 0.055) |
//! | FOPDT `K`, `tau`, `L` | 24.80, 0.0671 s, -0.0076 s | 21.53, 0.0514 s, -0.0076 s |
//! | tangent `L`, `T`, s | 0.0045, 0.0627 | 0.0028, 0.0548 |
//! | ZN (`T` = tau, `L` = 0.03 s): `Kp`, `Ki`, `Kd` | 2.69, 44.8, 0.0403 | 1.96, 32.6, 0.0294 |
//! | ZOH model | 4.995/(z - 0.8000) | 5.756/(z - 0.7361) |
//!
//! The checks ([`ThesisCheck`], printed by [`Identification::render`]): right `K`, `tau`,
//! pole, numerator and `Kp` are reproduced from the data within their resolution (the
//! thesis' `tau` is 1.3 ms, 0.08 of a sample, above the 63.2 % point), and the thesis' chain
//! from its own `K`, `tau` and `L` gives exactly its 2.74, 0.06, 0.015, 0.8033 and 4.917.
//! Left: `K` and the PID arithmetic from `tau` = 0.055 s are reproduced; the discrete model
//! (tau 0.55 s) and eq. (126)'s 0.33 are contradicted, and so is `tau` itself: the data put
//! the 63.2 % point at 0.049 s (at 0.055 s the curve is at 66.9 %). For both motors the
//! dead time of 0.03 s is not in the data.
//!
//! # Physical motor model ([`fit_physical`], [`MotorParams`])
//!
//! All quantities at the motor shaft (wheel, load and robot reflected through the 100.37:1
//! gearbox), `w` in rad/s:
//!
//! ```text
//! J w' = kt (d V - ke w) / R - b w - tau_c      (w > 0), kt = ke
//! steady state: kt (d V - ke w) / R = b w + tau_c, and w = 0 when d V kt / R <= tau_c
//! tau = J / (b + kt ke / R)
//! ```
//!
//! - The duty acts as the average voltage `d V` with `V` = 7.4 V, the 2S pack's nominal
//!   voltage: the DRV8833 alternates drive and coast at 31.4 kHz, hundreds of times faster
//!   than the motor, and the current is taken as continuous. Neglected: the bridge's on
//!   resistance, the battery's state of charge (8.4 V full), and the inductance (the
//!   electrical time constant is far below the 40-70 ms mechanical one).
//! - **Identifiability**: dividing by `kt / R` gives `(J R / kt) w' = d V - k_eff w - V_c`
//!   with `k_eff = kt + b R / kt` and `V_c = tau_c R / kt`. Speed-only data determine exactly
//!   three combinations: `k_eff` (V s/rad), `V_c` (the dead-band voltage) and `tau`
//!   ([`Identifiable`]). The five parameters need two fixed: `R` (default 10 ohm, an
//!   assumption, not a measurement: 6 V micro metal gear motors range from about 4 ohm for
//!   the high-power versions to about 17 ohm for the low-power ones, 0.36 A stall at 6 V) and
//!   the split of `k_eff` between back-EMF and viscous friction (default `b = 0`, i.e.
//!   `kt = k_eff`, the largest `kt` the data allow; or give `kt` from a datasheet and get
//!   `b`: [`ViscousSplit`]). `J` and `tau_c` scale as `1/R`; predictions of speed do not
//!   depend on these choices at all.
//! - **Fit**, all levels at once, two stages: the steady line `w(d) = (d V - V_c) / k_eff`
//!   by linear least squares on the five steady levels, then `tau` and the start time by a
//!   bounded search over all rows (see [`fit_physical`] for why not one joint fit).
//! - **Result** (R = 10 ohm, b = 0): right `k_eff` = 1.487e-3 V s/rad, `V_c` = 3.75 V (PWM
//!   129), `tau` = 0.059 s, `J` = 1.31e-8 kg m^2, `tau_c` = 0.56 mN m; left 1.301e-3 V s/rad,
//!   4.30 V (PWM 148), 0.047 s, 7.9e-9 kg m^2, 0.56 mN m. The steady levels are not linear in
//!   the duty (they bend upwards), so a linear steady state misses PWM 170 by -12 % (right)
//!   and -20 % (left) and 210 by +8 % / +10 %; and the low levels rise more slowly than one
//!   `tau` allows (PWM 170 right: 0.2 s against 0.045 s at 250), so the rise of the low
//!   levels is off by about 20 % of their level (RMS). [`holdout_report`] gives the
//!   per-level residuals and the held-out errors (training on 170, 210, 250 and predicting
//!   190, 230; training on 190, 210, 230 and predicting 170, 250).

mod data;
mod first_order;
mod physical;
mod thesis;

use std::fmt::Write as _;

use serde::Serialize;

pub use data::{Column, CsvSource, IdentifyError, StepData};
pub use first_order::{
    fit_632, fit_fopdt, minimise_bounded, reaction_curve, unit_response, ziegler_nichols,
    DiscreteModel, FirstOrder632, FopdtBounds, FopdtFit, PidGains, ReactionCurve, Sampling,
    FRACTION_AT_TAU,
};
pub use physical::{
    fit_physical, holdout_for, holdout_report, motor_rad_s_per_thesis_rpm, HoldoutReport,
    HoldoutSplit, Identifiable, LevelError, MotorParams, PhysicalAssumptions, PhysicalFit,
    SideHoldout, ViscousSplit, GEAR_RATIO, HOLDOUT_SPLITS, SUPPLY_V,
};
pub use thesis::{CheckBasis, Printed, ThesisCheck, ThesisFigures, Verdict};

use crate::side::Side;

/// The thesis' Table 2 (right motor), as vendored in `fixtures/thesis-data`.
pub const THESIS_RIGHT_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fixtures/thesis-data/motor_step_right.csv"
));

/// The thesis' Table 3 (left motor), as vendored in `fixtures/thesis-data`.
pub const THESIS_LEFT_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../fixtures/thesis-data/motor_step_left.csv"
));

/// PWM counts per unit of the thesis firmware's controller output `U`:
/// `pwm = map(U, 24, -24, 255, 0) = 127.5 + U * 255/48`.
pub const CONTROLLER_PWM_PER_UNIT: f64 = 255.0 / 48.0;

/// One encoder count in one sample window, in thesis "RPM": the firmware's
/// `counts / T * 60 / 6 / 602.2` for one count, `60 / (6 * 6 * 100.37 * T)` (1.107 at 15 ms).
pub fn count_quantum_thesis_rpm(period_s: f64) -> f64 {
    60.0 / (6.0 * 6.0 * GEAR_RATIO * period_s)
}

/// What the gain `K` of the mean column means as a process gain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GainInterpretation {
    /// The step the mean column answers: the mean PWM of the columns (210 of 255).
    pub step_pwm: f64,
    /// `K / step_pwm`: the secant gain from rest, thesis RPM per PWM count.
    pub k_per_pwm_count: f64,
    /// The slope of the steady levels against PWM (least squares over the columns), thesis RPM
    /// per PWM count: the gain a speed controller works against near its operating point.
    pub incremental_per_pwm_count: Option<f64>,
    /// Where that line reaches 0: the dead band, PWM counts.
    pub dead_band_pwm: Option<f64>,
    /// `incremental_per_pwm_count * CONTROLLER_PWM_PER_UNIT`: thesis RPM per unit of the
    /// firmware's controller output.
    pub incremental_per_controller_unit: Option<f64>,
}

/// Options of [`identify`]; the default is the thesis' recipe (see the fields).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct IdentifyOptions {
    /// `L` for the Ziegler-Nichols gains, s; `None`: two sample periods, the thesis' 0.03 s.
    pub zn_dead_time_s: Option<f64>,
    /// Bounds of the FOPDT fits; `None`: [`FopdtBounds::for_period`].
    pub fopdt_bounds: Option<FopdtBounds>,
    /// Fixed values of the physical model.
    pub physical: PhysicalAssumptions,
}

/// How [`Identification::tau_s`] was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TauMethod {
    /// The 63.2 % crossing of the mean curve (the thesis' method).
    Crossing632,
    /// The FOPDT fit's `tau`, because the 63.2 % crossing lies in a gap of the samples.
    Fopdt,
}

/// Every fit of one column (a PWM level or the mean).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelFit {
    /// The column's header name.
    pub column: String,
    /// Its PWM value (`None` for the mean).
    pub pwm: Option<u16>,
    /// The 63.2 % fit (the thesis' method).
    pub first_order: FirstOrder632,
    /// The FOPDT least-squares fit.
    pub fopdt: FopdtFit,
    /// The reaction-curve tangent.
    pub reaction_curve: Option<ReactionCurve>,
    /// Ziegler-Nichols gains from `T` = the 63.2 % `tau` and the options' `L` (the thesis'
    /// recipe); `None` when `tau` is unknown.
    pub zn: Option<PidGains>,
    /// Ziegler-Nichols gains from the reaction curve's own `L` and `T` (the textbook recipe);
    /// `None` when its `L <= 0`.
    pub zn_reaction_curve: Option<PidGains>,
    /// ZOH model of the 63.2 % fit.
    pub discrete: Option<DiscreteModel>,
    /// ZOH model of the FOPDT fit (with its dead time in whole samples).
    pub fopdt_discrete: DiscreteModel,
}

/// The identification of one step-response file.
///
/// The top-level numbers describe the mean column, the way the thesis used it (see the module
/// docs): `k` and `tau_s` by the 63.2 % method, `dead_time_s` from the FOPDT fit, the
/// Ziegler-Nichols gains from `T = tau_s` and `L = zn_dead_time_s`, and the ZOH model
/// `numerator / (z - pole) z^-delay_samples`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    /// The motor, from the caller's hint or the file's comments.
    pub side: Option<Side>,
    /// `T`, s.
    pub sample_period_s: f64,
    /// Sample index of each row; residuals are listed in this order.
    pub samples: Vec<u64>,
    /// The PWM step the mean column answers (the mean of the PWM columns).
    pub step_pwm: f64,
    /// `K`: steady level of the mean column, thesis RPM.
    pub k: f64,
    /// `tau`: 63.2 % time of the mean column, s (see `tau_method`).
    pub tau_s: f64,
    /// How `tau_s` was found.
    pub tau_method: TauMethod,
    /// How well the data fix `tau`, s: one count quantum over the slope at the 63.2 % point,
    /// or half a sample period with [`TauMethod::Fopdt`].
    pub tau_resolution_s: f64,
    /// Dead time of the FOPDT fit of the mean column, s (its `L`, 0 when negative).
    pub dead_time_s: f64,
    /// The `L` used for the Ziegler-Nichols gains, s.
    pub zn_dead_time_s: f64,
    /// `1.2 T / L`.
    pub kp: f64,
    /// `2 L`, s.
    pub ti_s: f64,
    /// `L / 2`, s.
    pub td_s: f64,
    /// `Kp / Ti`, 1/s.
    pub ki: f64,
    /// `Kp Td`, s.
    pub kd: f64,
    /// `1.2 T / (K L)` with the incremental process gain per unit of the firmware's output.
    pub kp_with_process_gain: Option<f64>,
    /// `exp(-T / tau)`.
    pub pole: f64,
    /// `K (1 - pole)`.
    pub numerator: f64,
    /// `round(dead_time_s / T)`.
    pub delay_samples: u32,
    /// All fits of the mean column.
    pub mean: LevelFit,
    /// All fits of each PWM column.
    pub levels: Vec<LevelFit>,
    /// What `K` means as a process gain.
    pub gain: GainInterpretation,
    /// The physical motor model fitted to all PWM columns (`None` with fewer than two).
    pub physical: Option<PhysicalFit>,
    /// The thesis' figures for this side, reproduced or contradicted (empty when the side is
    /// unknown).
    pub checks: Vec<ThesisCheck>,
}

fn fit_column(
    data: &StepData,
    column: &data::Column,
    quantum: f64,
    zn_l: f64,
    bounds: &FopdtBounds,
    process_gain: Option<f64>,
) -> Result<LevelFit, IdentifyError> {
    let period = data.sample_period_s;
    let steady = data.steady_rows();
    let k = column.values[steady.clone()].iter().sum::<f64>() / steady.len() as f64;
    let fail = |reason: &str| IdentifyError::Fit {
        column: column.name.clone(),
        reason: reason.to_owned(),
    };
    if k.is_nan() || k <= 0.0 {
        return Err(fail(
            "the steady level is not above 0: the motor did not turn",
        ));
    }
    let contiguous = |i: usize| data.contiguous(i);
    let first_order = fit_632(&data.times_s, &column.values, contiguous, k, quantum)
        .ok_or_else(|| fail("the curve never reaches 63.2 % of its steady level"))?;
    let fopdt = fit_fopdt(
        &data.times_s,
        &column.values,
        period,
        bounds,
        Sampling::WindowAverage,
    )
    .ok_or_else(|| fail("the FOPDT least-squares fit failed"))?;
    let reaction = reaction_curve(&data.times_s, &column.values, contiguous, k);
    let zn = first_order
        .tau_s
        .and_then(|tau| ziegler_nichols(tau, zn_l, process_gain));
    let zn_reaction_curve = reaction
        .as_ref()
        .and_then(|r| ziegler_nichols(r.t_s, r.l_s, process_gain));
    let discrete = first_order
        .tau_s
        .map(|tau| DiscreteModel::zoh(k, tau, 0.0, period));
    let fopdt_discrete = DiscreteModel::zoh(fopdt.k, fopdt.tau_s, fopdt.l_s, period);
    Ok(LevelFit {
        column: column.name.clone(),
        pwm: column.pwm,
        first_order,
        fopdt,
        reaction_curve: reaction,
        zn,
        zn_reaction_curve,
        discrete,
        fopdt_discrete,
    })
}

fn gain_interpretation(data: &StepData, k: f64) -> GainInterpretation {
    let step_pwm = data.mean_pwm();
    let steady = data.steady_rows();
    let points: Vec<(f64, f64)> = data
        .levels
        .iter()
        .filter_map(|c| {
            let level = c.values[steady.clone()].iter().sum::<f64>() / steady.len() as f64;
            Some((f64::from(c.pwm?), level))
        })
        .collect();
    let line = first_order::lstsq(points.iter().map(|&(p, y)| ([p, 1.0], y)))
        .map(|(x, _)| (x[0], x[1]))
        .filter(|(slope, _)| *slope > 0.0 && points.len() >= 2);
    GainInterpretation {
        step_pwm,
        k_per_pwm_count: k / step_pwm,
        incremental_per_pwm_count: line.map(|(s, _)| s),
        dead_band_pwm: line.map(|(s, c)| -c / s),
        incremental_per_controller_unit: line.map(|(s, _)| s * CONTROLLER_PWM_PER_UNIT),
    }
}

/// Identifies `data` (see the module docs); `side` selects the thesis figures to check.
pub fn identify(
    data: &StepData,
    side: Option<Side>,
    options: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    let period = data.sample_period_s;
    let zn_l = options.zn_dead_time_s.unwrap_or(2.0 * period);
    let bounds = options
        .fopdt_bounds
        .clone()
        .unwrap_or_else(|| FopdtBounds::for_period(period));
    let quantum = count_quantum_thesis_rpm(period);
    let steady = data.steady_rows();
    let k_mean = data.mean.values[steady.clone()].iter().sum::<f64>() / steady.len() as f64;
    let gain = gain_interpretation(data, k_mean);
    let process_gain = gain.incremental_per_controller_unit;
    let mean = fit_column(
        data,
        &data.mean,
        quantum / data.levels.len() as f64,
        zn_l,
        &bounds,
        process_gain,
    )?;
    let levels = data
        .levels
        .iter()
        .map(|c| fit_column(data, c, quantum, zn_l, &bounds, process_gain))
        .collect::<Result<Vec<_>, _>>()?;
    let (tau, tau_resolution_s, tau_method) =
        match (mean.first_order.tau_s, mean.first_order.tau_resolution_s) {
            (Some(tau), Some(res)) => (tau, res, TauMethod::Crossing632),
            _ => (mean.fopdt.tau_s, 0.5 * period, TauMethod::Fopdt),
        };
    let zn = ziegler_nichols(tau, zn_l, process_gain).ok_or_else(|| IdentifyError::Fit {
        column: data.mean.name.clone(),
        reason: format!("Ziegler-Nichols needs L > 0 (got {zn_l} s)"),
    })?;
    let dead_time_s = mean.fopdt.l_s.max(0.0);
    let discrete = DiscreteModel::zoh(k_mean, tau, dead_time_s, period);
    let all_pwm: Vec<u16> = data.levels.iter().filter_map(|c| c.pwm).collect();
    let physical = if all_pwm.len() >= 2 {
        Some(fit_physical(data, &all_pwm, &options.physical)?)
    } else {
        None
    };
    let side = side.or(data.side_in_comments);
    let checks = side.map_or_else(Vec::new, |side| {
        thesis::checks(
            side,
            data,
            &thesis::MeanResult {
                k: k_mean,
                tau_s: tau,
                tau_resolution_s,
                fopdt: &mean.fopdt,
                reaction: mean.reaction_curve.as_ref(),
                gain: &gain,
            },
        )
    });
    Ok(Identification {
        side,
        sample_period_s: period,
        samples: data.samples.clone(),
        step_pwm: gain.step_pwm,
        k: k_mean,
        tau_s: tau,
        tau_method,
        tau_resolution_s,
        dead_time_s,
        zn_dead_time_s: zn_l,
        kp: zn.kp,
        ti_s: zn.ti_s,
        td_s: zn.td_s,
        ki: zn.ki,
        kd: zn.kd,
        kp_with_process_gain: zn.kp_with_process_gain,
        pole: discrete.pole,
        numerator: discrete.numerator,
        delay_samples: discrete.delay_samples,
        mean,
        levels,
        gain,
        physical,
        checks,
    })
}

/// Reads a step-response CSV (a path, or the text itself: see [`CsvSource`]) and identifies
/// it with the default options; `side_hint` overrides the side named in the file's comments.
pub fn identify_csv<'a>(
    source: impl Into<CsvSource<'a>>,
    side_hint: Option<Side>,
) -> Result<Identification, IdentifyError> {
    let data = StepData::load(source)?;
    identify(&data, side_hint, &IdentifyOptions::default())
}

fn opt(v: Option<f64>, decimals: usize) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.decimals$}"))
}

impl Identification {
    /// A plain-text report: the model, the per-column fits, the physical model and the
    /// thesis checks.
    pub fn render(&self) -> String {
        let mut o = String::new();
        let side = self
            .side
            .map_or("unknown side".to_owned(), |s| format!("{s} motor"));
        let _ = writeln!(
            o,
            "Step-response identification, {side}, T = {} s, {} rows (samples {})",
            self.sample_period_s,
            self.samples.len(),
            sample_ranges(&self.samples)
        );
        let _ = writeln!(
            o,
            "Speeds in thesis RPM (true wheel RPM / 6); the mean column is the response to a \
             step 0 -> PWM {:.0}/255.",
            self.step_pwm
        );
        let _ = writeln!(o, "\nMean curve (the thesis' model):");
        let _ = writeln!(
            o,
            "  63.2 % method      K = {:.3} thesis RPM, tau = {:.4} s (+/- {:.4} s){}",
            self.k,
            self.tau_s,
            self.tau_resolution_s,
            match self.tau_method {
                TauMethod::Crossing632 => "",
                TauMethod::Fopdt => " [63.2 % point in a gap: tau from the FOPDT fit]",
            }
        );
        let f = &self.mean.fopdt;
        let _ = writeln!(
            o,
            "  FOPDT (LS)         K = {:.3}, tau = {:.4} s, L = {:+.4} s, rms residual {:.3} \
             -> dead time {:.4} s",
            f.k, f.tau_s, f.l_s, f.rms_residual, self.dead_time_s
        );
        if let Some(r) = &self.mean.reaction_curve {
            let _ = writeln!(
                o,
                "  reaction curve     max slope {:.1} thesis RPM/s, L = {:.4} s, T = {:.4} s",
                r.max_slope, r.l_s, r.t_s
            );
        }
        let _ = writeln!(
            o,
            "  Ziegler-Nichols    T = tau, L = {} s: Kp = {:.3}, Ti = {:.4} s, Td = {:.4} s, \
             Ki = {:.3}, Kd = {:.5}",
            self.zn_dead_time_s, self.kp, self.ti_s, self.td_s, self.ki, self.kd
        );
        if let Some(kp) = self.kp_with_process_gain {
            let _ = writeln!(
                o,
                "                     with the process gain ({:.3} thesis RPM per unit of the \
                 firmware output): Kp = {:.3}",
                self.gain
                    .incremental_per_controller_unit
                    .unwrap_or(f64::NAN),
                kp
            );
        }
        if let Some(zn) = &self.mean.zn_reaction_curve {
            let _ = writeln!(
                o,
                "  ZN on the tangent  Kp = {:.2}, Ti = {:.4} s, Td = {:.4} s",
                zn.kp, zn.ti_s, zn.td_s
            );
        }
        let _ = writeln!(
            o,
            "  ZOH, T = {} s      {:.4} / (z - {:.4}){}",
            self.sample_period_s,
            self.numerator,
            self.pole,
            if self.delay_samples > 0 {
                format!(" z^-{}", self.delay_samples)
            } else {
                String::new()
            }
        );
        let _ = writeln!(
            o,
            "\nPer column (63.2 % | FOPDT least squares, * = on a search bound | tangent):"
        );
        let _ = writeln!(
            o,
            "  column        K      tau632     FOPDT K   tau      L        rms    tangent L  T"
        );
        for l in std::iter::once(&self.mean).chain(&self.levels) {
            let tau = match l.first_order.tau_s {
                Some(t) => format!("{t:.4}"),
                None => format!(
                    "gap {:.3}-{:.3}",
                    l.first_order.crossing_between_s[0], l.first_order.crossing_between_s[1]
                ),
            };
            let _ = writeln!(
                o,
                "  {:<12} {:>6.2}  {:<15} {:>6.2}  {:.4}  {:+.4}{} {:.3}  {:>8}  {}",
                l.column,
                l.first_order.k,
                tau,
                l.fopdt.k,
                l.fopdt.tau_s,
                l.fopdt.l_s,
                if l.fopdt.at_bound { "*" } else { " " },
                l.fopdt.rms_residual,
                opt(l.reaction_curve.as_ref().map(|r| r.l_s), 4),
                opt(l.reaction_curve.as_ref().map(|r| r.t_s), 4),
            );
        }
        if let (Some(s), Some(d)) = (self.gain.incremental_per_pwm_count, self.gain.dead_band_pwm) {
            let _ = writeln!(
                o,
                "  steady levels vs PWM: {:.4} thesis RPM per count, zero at PWM {:.1}; \
                 K / {:.0} = {:.4} per count",
                s, d, self.step_pwm, self.gain.k_per_pwm_count
            );
        }
        if let Some(p) = &self.physical {
            let a = &p.assumptions;
            let m = &p.params;
            let _ = writeln!(
                o,
                "\nPhysical model, all levels at once (R = {} ohm fixed, V = {} V, {}:1, {:?}):",
                a.r_ohm, a.supply_v, a.gear_ratio, a.split
            );
            let _ = writeln!(
                o,
                "  identifiable: k_eff = {:.4e} V s/rad, dead band {:.3} V (PWM {:.1}), tau = \
                 {:.4} s, start {:+.4} s, rms {:.3} thesis RPM",
                p.identifiable.k_eff_v_s_per_rad,
                p.identifiable.dead_band_v,
                p.dead_band_duty * 255.0,
                p.identifiable.tau_s,
                p.start_s,
                p.rms_residual_rpm
            );
            let _ = writeln!(
                o,
                "  physical: kt = ke = {:.4e} N m/A, J = {:.3e} kg m^2, b = {:.3e} N m s/rad, \
                 tau_c = {:.3e} N m (motor shaft)",
                m.kt, m.j_kg_m2, m.b_nm_s_per_rad, m.tau_c_nm
            );
            for l in &p.levels {
                let _ = writeln!(
                    o,
                    "  pwm {:>3}: steady {:>6.2} measured, {:>6.2} model ({:+.1} %), rms {:.2} \
                     ({:.1} %)",
                    l.pwm,
                    l.measured_steady_rpm,
                    l.predicted_steady_rpm,
                    l.steady_error_pct,
                    l.rms_error_rpm,
                    l.rms_error_pct
                );
            }
        }
        if !self.checks.is_empty() {
            let _ = writeln!(o, "\nThesis checks:");
            for c in &self.checks {
                let _ = writeln!(
                    o,
                    "  [{}] {:?}: {}: thesis {}, ours {:.5} (tolerance {:.2e})\n      {}",
                    match c.verdict {
                        Verdict::Reproduces => "reproduces ",
                        Verdict::Contradicts => "CONTRADICTS",
                    },
                    c.basis,
                    c.quantity,
                    c.thesis_value,
                    c.ours,
                    c.tolerance,
                    c.note
                );
            }
        }
        o
    }
}

/// `0-7, 127-129`.
fn sample_ranges(samples: &[u64]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < samples.len() {
        let mut j = i;
        while j + 1 < samples.len() && samples[j + 1] == samples[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            samples[i].to_string()
        } else {
            format!("{}-{}", samples[i], samples[j])
        });
        i = j + 1;
    }
    parts.join(", ")
}
