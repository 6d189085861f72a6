//! The thesis' printed figures (section 6.2-6.3, Tables 2 and 3, equations 121-126, the
//! firmware listing) and the checks of each against the data and against its own formulas.

use serde::Serialize;

use super::data::StepData;
use super::first_order::{DiscreteModel, FopdtFit, ReactionCurve};
use super::GainInterpretation;
use crate::side::Side;

/// A printed number and how many decimals it was printed with.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Printed {
    /// The value.
    pub value: f64,
    /// Decimals printed.
    pub decimals: u8,
}

impl Printed {
    const fn new(value: f64, decimals: u8) -> Printed {
        Printed { value, decimals }
    }

    /// One unit of the last printed digit.
    pub fn unit(&self) -> f64 {
        10f64.powi(-i32::from(self.decimals))
    }
}

/// What the thesis printed for one motor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ThesisFigures {
    /// Which motor.
    pub side: Side,
    /// First-order gain `K` (eq. 121 / 123), thesis RPM.
    pub k: Printed,
    /// First-order time constant `tau` (eq. 121 / 123), s.
    pub tau_s: Printed,
    /// Numerator of the discrete model (eq. 122 / 124).
    pub numerator: Printed,
    /// Pole of the discrete model (eq. 122 / 124).
    pub pole: Printed,
    /// `Kp` (section 6.3 table and firmware).
    pub kp: Printed,
    /// `Ti`, s (section 6.3 table).
    pub ti_s: Printed,
    /// `Td`, s (section 6.3 table).
    pub td_s: Printed,
    /// `Ki` in the firmware listing, 1/s.
    pub ki_firmware: Printed,
    /// `Kd` in the firmware listing, s.
    pub kd_firmware: Printed,
    /// The `s^2` coefficient of the printed controller (eq. 125 / 126).
    pub kd_equation: Printed,
    /// The dead time implied by `Kp = 1.2 T / L` and `Ti = 2 L`, s (not printed).
    pub dead_time_s: Printed,
}

impl ThesisFigures {
    /// The figures printed for `side`.
    pub const fn of(side: Side) -> ThesisFigures {
        match side {
            Side::Right => ThesisFigures {
                side,
                k: Printed::new(25.0, 0),
                tau_s: Printed::new(0.0685, 4),
                numerator: Printed::new(4.917, 3),
                pole: Printed::new(0.8033, 4),
                kp: Printed::new(2.74, 2),
                ti_s: Printed::new(0.06, 2),
                td_s: Printed::new(0.015, 3),
                ki_firmware: Printed::new(45.66, 2),
                kd_firmware: Printed::new(0.0411, 4),
                kd_equation: Printed::new(0.041, 3),
                dead_time_s: Printed::new(0.03, 2),
            },
            Side::Left => ThesisFigures {
                side,
                k: Printed::new(22.0, 0),
                tau_s: Printed::new(0.055, 3),
                numerator: Printed::new(0.5919, 4),
                pole: Printed::new(0.9731, 4),
                kp: Printed::new(2.20, 2),
                ti_s: Printed::new(0.06, 2),
                td_s: Printed::new(0.015, 3),
                ki_firmware: Printed::new(36.666, 3),
                kd_firmware: Printed::new(0.033, 3),
                kd_equation: Printed::new(0.33, 2),
                dead_time_s: Printed::new(0.03, 2),
            },
        }
    }
}

/// Whether our number agrees with the thesis'.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Within the tolerance.
    Reproduces,
    /// Outside it.
    Contradicts,
}

/// What a check compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckBasis {
    /// Our estimate from the step-response data against the thesis' figure. Tolerance: the
    /// resolution of the data (count quantisation and sampling), propagated.
    Data,
    /// The thesis' own inputs through the rule it states (ZOH, Ziegler-Nichols), against the
    /// figure it printed. Tolerance: one unit of the last printed digit.
    Arithmetic,
    /// The thesis' inputs through the textbook form of the rule, where the thesis used
    /// another form.
    Method,
}

/// One thesis figure, reproduced or contradicted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ThesisCheck {
    /// What is compared.
    pub quantity: String,
    /// Against what.
    pub basis: CheckBasis,
    /// The thesis' figure.
    pub thesis_value: f64,
    /// Ours.
    pub ours: f64,
    /// The largest difference still called [`Verdict::Reproduces`].
    pub tolerance: f64,
    /// Whether `|ours - thesis_value| <= tolerance`.
    pub verdict: Verdict,
    /// Why, and where the thesis' number comes from when it is not ours.
    pub note: String,
}

impl ThesisCheck {
    fn new(
        quantity: impl Into<String>,
        basis: CheckBasis,
        thesis_value: f64,
        ours: f64,
        tolerance: f64,
        note: impl Into<String>,
    ) -> ThesisCheck {
        let verdict = if (ours - thesis_value).abs() <= tolerance * (1.0 + 1e-9) {
            Verdict::Reproduces
        } else {
            Verdict::Contradicts
        };
        ThesisCheck {
            quantity: quantity.into(),
            basis,
            thesis_value,
            ours,
            tolerance,
            verdict,
            note: note.into(),
        }
    }
}

/// What the checks need from the identification of the mean column.
pub(crate) struct MeanResult<'a> {
    pub k: f64,
    pub tau_s: f64,
    pub tau_resolution_s: f64,
    pub fopdt: &'a FopdtFit,
    pub reaction: Option<&'a ReactionCurve>,
    pub gain: &'a GainInterpretation,
}

/// Linear interpolation of `values` at `t` between contiguous rows.
fn value_at(data: &StepData, values: &[f64], t: f64) -> Option<f64> {
    let i = (1..data.times_s.len()).find(|&i| data.times_s[i] >= t)?;
    if !data.contiguous(i) {
        return None;
    }
    let (t0, t1) = (data.times_s[i - 1], data.times_s[i]);
    Some(values[i - 1] + (values[i] - values[i - 1]) * (t - t0) / (t1 - t0))
}

/// The checks of the thesis' figures for `side` against `data` and `mean`.
pub(crate) fn checks(side: Side, data: &StepData, mean: &MeanResult<'_>) -> Vec<ThesisCheck> {
    use CheckBasis::{Arithmetic, Data, Method};
    let f = ThesisFigures::of(side);
    let period = data.sample_period_s;
    let l = f.dead_time_s.value;
    let mut out = Vec::new();

    // --- from the data ---
    out.push(ThesisCheck::new(
        "K: steady level of the mean curve (thesis RPM for the step to the mean PWM)",
        Data,
        f.k.value,
        mean.k,
        0.5,
        format!(
            "mean of the last printed rows of the mean column; the thesis rounded it to an \
             integer. It is the response to a step of the mean PWM {:.0}/255, not a gain per \
             PWM count ({:.4} thesis RPM per count).",
            mean.gain.step_pwm, mean.gain.k_per_pwm_count
        ),
    ));
    let at_thesis_tau = value_at(data, &data.mean.values, f.tau_s.value)
        .map(|v| {
            format!(
                " At the thesis' {} s the mean curve is at {:.1} % of K.",
                f.tau_s.value,
                100.0 * v / mean.k
            )
        })
        .unwrap_or_default();
    let tangent = mean
        .reaction
        .map(|r| {
            format!(
                " (The reaction-curve tangent's T, a different quantity, is {:.4} s.)",
                r.t_s
            )
        })
        .unwrap_or_default();
    out.push(ThesisCheck::new(
        "tau: 63.2 % time of the mean curve (s)",
        Data,
        f.tau_s.value,
        mean.tau_s,
        mean.tau_resolution_s,
        format!(
            "linear interpolation between the samples around 63.2 % of K; tolerance = one \
             count quantum of the mean column over its slope there.{at_thesis_tau}{tangent}"
        ),
    ));
    let first_count = data
        .levels
        .iter()
        .min_by_key(|c| c.pwm)
        .and_then(|c| {
            let i = c.values.iter().position(|&v| v > 0.0)?;
            Some(format!(
                " The slowest curve ({}) shows its first count at {:.3} s.",
                c.name, data.times_s[i]
            ))
        })
        .unwrap_or_default();
    out.push(ThesisCheck::new(
        "dead time L implied by Kp = 1.2 T/L, Ti = 2L (s)",
        Data,
        l,
        mean.fopdt.l_s,
        0.5 * period,
        format!(
            "ours: the FOPDT least-squares fit of the mean curve (window-averaged samples), \
             where the response starts relative to t = 0. The mean curve already reads {:.0} % \
             of K at the first sample, so the curve has no dead time of two samples: the \
             thesis' L = 0.03 s (two sample periods) is not read from it.{}",
            100.0 * data.mean.values.get(1).copied().unwrap_or(0.0) / mean.k,
            first_count
        ),
    ));
    let thesis_zoh = DiscreteModel::zoh(f.k.value, f.tau_s.value, 0.0, period);
    let typo = if (thesis_zoh.pole - f.pole.value).abs() > f.pole.unit() {
        " The printed model is not the ZOH of the thesis' own K and tau either (see the \
         arithmetic check)."
    } else {
        ""
    };
    let pole = (-period / mean.tau_s).exp();
    let pole_tol = pole * period / (mean.tau_s * mean.tau_s) * mean.tau_resolution_s;
    out.push(ThesisCheck::new(
        "discrete pole exp(-T/tau) from the data",
        Data,
        f.pole.value,
        pole,
        pole_tol,
        format!(
            "our tau through the ZOH rule; tolerance propagated from the tau resolution.{typo}"
        ),
    ));
    out.push(ThesisCheck::new(
        "discrete numerator K(1 - a) from the data",
        Data,
        f.numerator.value,
        mean.k * (1.0 - pole),
        mean.k * pole_tol,
        format!(
            "our K and tau through the ZOH rule; tolerance propagated from the tau \
             resolution.{typo}"
        ),
    ));
    out.push(ThesisCheck::new(
        "Kp = 1.2 T/L from the data (T = our tau, L = 0.03 s as in the thesis)",
        Data,
        f.kp.value,
        1.2 * mean.tau_s / l,
        1.2 * mean.tau_resolution_s / l,
        "the thesis' rule and dead time with our 63.2 % time constant",
    ));

    // --- the thesis' own arithmetic ---
    let pole_note = if side == Side::Left {
        format!(
            "{} = exp(-{period}/{:.3}): the thesis discretised tau = {:.2} s, ten times its own \
             {} s (typo); with {} s the model is {:.4}/(z - {:.4}), and the pole {} stands for \
             tau = {:.3} s.",
            f.pole.value,
            10.0 * f.tau_s.value,
            10.0 * f.tau_s.value,
            f.tau_s.value,
            f.tau_s.value,
            thesis_zoh.numerator,
            thesis_zoh.pole,
            f.pole.value,
            -period / f.pole.value.ln(),
        )
    } else {
        "ZOH of the thesis' K/(tau s + 1) at T = 15 ms".to_owned()
    };
    out.push(ThesisCheck::new(
        "discrete pole exp(-T/tau) from the thesis' tau",
        Arithmetic,
        f.pole.value,
        thesis_zoh.pole,
        f.pole.unit(),
        pole_note,
    ));
    let num_note = if side == Side::Left {
        format!(
            "{} = {} (1 - {}), the numerator of the tau = 0.55 s model; with tau = {} s it is \
             {:.4}.",
            f.numerator.value, f.k.value, f.pole.value, f.tau_s.value, thesis_zoh.numerator
        )
    } else {
        "ZOH of the thesis' K/(tau s + 1) at T = 15 ms".to_owned()
    };
    out.push(ThesisCheck::new(
        "discrete numerator K(1 - a) from the thesis' K and tau",
        Arithmetic,
        f.numerator.value,
        thesis_zoh.numerator,
        f.numerator.unit(),
        num_note,
    ));
    let kp = 1.2 * f.tau_s.value / l;
    out.push(ThesisCheck::new(
        "Kp = 1.2 T/L from the thesis' T = tau and L = 0.03 s",
        Arithmetic,
        f.kp.value,
        kp,
        f.kp.unit(),
        "Ziegler-Nichols first method as tabled by Ogata, with T the 63.2 % time constant \
         (not the tangent's T)",
    ));
    out.push(ThesisCheck::new(
        "Ti = 2L (s)",
        Arithmetic,
        f.ti_s.value,
        2.0 * l,
        f.ti_s.unit(),
        "L = 0.03 s",
    ));
    out.push(ThesisCheck::new(
        "Td = L/2 (s)",
        Arithmetic,
        f.td_s.value,
        0.5 * l,
        f.td_s.unit(),
        "L = 0.03 s",
    ));
    out.push(ThesisCheck::new(
        "Ki = Kp/Ti in the firmware (1/s)",
        Arithmetic,
        f.ki_firmware.value,
        f.kp.value / f.ti_s.value,
        f.ki_firmware.unit(),
        "the thesis' Kp and Ti; the firmware truncates rather than rounds",
    ));
    out.push(ThesisCheck::new(
        "Kd = Kp Td in the firmware (s)",
        Arithmetic,
        f.kd_firmware.value,
        f.kp.value * f.td_s.value,
        f.kd_firmware.unit(),
        "the thesis' Kp and Td",
    ));
    out.push(ThesisCheck::new(
        "s^2 coefficient Kp Td of the printed controller (eq. 125 / 126)",
        Arithmetic,
        f.kd_equation.value,
        f.kp.value * f.td_s.value,
        f.kd_equation.unit(),
        if side == Side::Left {
            "eq. (126) prints 0.33 s^2; Kp Td = 0.033, which is what the firmware uses: a \
             factor-10 slip in the printed equation"
        } else {
            "eq. (125)"
        },
    ));

    // --- the rule's textbook form ---
    if let Some(ku) = mean.gain.incremental_per_controller_unit {
        out.push(ThesisCheck::new(
            "Kp = 1.2 T/(K L) with the process gain (thesis T and L)",
            Method,
            f.kp.value,
            1.2 * f.tau_s.value / (ku * l),
            f.kp.unit(),
            format!(
                "Ziegler and Nichols divide by the process gain K; Ogata's table (and the \
                 thesis) leaves it out, which is right only for K = 1 in the controller's \
                 units. The firmware's controller output U drives PWM = map(U, 24, -24, 255, 0) \
                 = 127.5 + 5.3125 U, and the steady levels rise {:.3} thesis RPM per PWM count \
                 ({:.3} per unit of U), so the rule gives this Kp in units of U per thesis RPM.",
                mean.gain.incremental_per_pwm_count.unwrap_or(f64::NAN),
                ku
            ),
        ));
    }
    out
}
