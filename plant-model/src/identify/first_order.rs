//! First-order identification: the 63.2 % method, the FOPDT least-squares fit, the
//! reaction-curve tangent, Ziegler-Nichols' first method and the zero-order-hold discrete
//! model. The formulas are in the parent module's docs.

use nalgebra::{SMatrix, SVector};
use serde::Serialize;

/// `1 - 1/e`: the fraction of its final value a first-order step response reaches after one
/// time constant (the "63.2 %" of the method; the thesis writes 63.3 % in its text).
pub const FRACTION_AT_TAU: f64 = 1.0 - 1.0 / std::f64::consts::E;

/// How a sample relates to the speed: what the firmware reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// The mean speed over the window `(t - T, t]` (encoder counts in the window; what the
    /// thesis firmware computes). Used by every fit in this module.
    WindowAverage,
    /// The speed at the instant `t`.
    Instant,
}

/// The unit-gain first-order-plus-dead-time step response seen through `sampling`, at time `t`:
/// `1 - exp(-(t - L)/tau)` for `t > L` (instant), or its mean over `(t - T, t]`.
pub fn unit_response(t: f64, tau: f64, l: f64, period: f64, sampling: Sampling) -> f64 {
    match sampling {
        Sampling::Instant => {
            let s = t - l;
            if s > 0.0 {
                -(-s / tau).exp_m1()
            } else {
                0.0
            }
        }
        Sampling::WindowAverage => {
            (integral_of_unit_response(t, tau, l) - integral_of_unit_response(t - period, tau, l))
                / period
        }
    }
}

/// `integral_0^t (1 - exp(-(u - L)/tau)) du` over `u > L`.
fn integral_of_unit_response(t: f64, tau: f64, l: f64) -> f64 {
    let s = t - l;
    if s > 0.0 {
        s + tau * (-s / tau).exp_m1()
    } else {
        0.0
    }
}

/// Linear least squares `min |A x - b|` over the rows `(a, b)`, by the normal equations
/// (Cholesky; `N` is 1 or 2 here, so conditioning is no concern). Returns the solution and
/// the residual sum of squares; `None` when `A` has no full column rank.
pub(crate) fn lstsq<const N: usize>(
    rows: impl IntoIterator<Item = ([f64; N], f64)>,
) -> Option<(SVector<f64, N>, f64)> {
    let mut ata = SMatrix::<f64, N, N>::zeros();
    let mut atb = SVector::<f64, N>::zeros();
    let mut btb = 0.0;
    for (a, b) in rows {
        let a = SVector::<f64, N>::from(a);
        ata += a * a.transpose();
        atb += a * b;
        btb += b * b;
    }
    let x = ata.cholesky()?.solve(&atb);
    let sse = (btb - 2.0 * x.dot(&atb) + (x.transpose() * ata * x)[0]).max(0.0);
    x.iter().all(|v| v.is_finite()).then_some((x, sse))
}

/// Minimises `f` over `[lo, hi]`: `n` grid points (geometric when `log`), then a
/// golden-section search in the bracket around the best grid point (60 steps: the bracket
/// shrinks to 3e-13 of its size). Returns `(x, f(x))`. For one-parameter fits anywhere in
/// the workspace (the gap diagnosis uses it too).
pub fn minimise_bounded(
    mut f: impl FnMut(f64) -> f64,
    lo: f64,
    hi: f64,
    n: usize,
    log: bool,
) -> (f64, f64) {
    let n = n.max(3);
    let at = |i: usize| {
        let u = i as f64 / (n - 1) as f64;
        if log {
            lo * (hi / lo).powf(u)
        } else {
            lo + (hi - lo) * u
        }
    };
    let mut best = (0, f64::INFINITY);
    for i in 0..n {
        let v = f(at(i));
        if v < best.1 {
            best = (i, v);
        }
    }
    let (mut a, mut b) = (at(best.0.saturating_sub(1)), at((best.0 + 1).min(n - 1)));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..60 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let x = 0.5 * (a + b);
    let fx = f(x);
    if fx <= best.1 {
        (x, fx)
    } else {
        (at(best.0), best.1)
    }
}

/// The 63.2 % first-order fit of one column, the way the thesis did it: `K` is the steady
/// level, `tau` the time at which the curve first reaches `(1 - 1/e) K`, interpolated
/// linearly between the two samples around it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FirstOrder632 {
    /// `K`: the steady level (mean of [`crate::identify::StepData::steady_rows`]), thesis RPM.
    pub k: f64,
    /// `(1 - 1/e) K`, thesis RPM.
    pub level_632: f64,
    /// The interpolated crossing time, s; `None` when the crossing lies in a gap of the
    /// samples (then only [`Self::crossing_between_s`] is known).
    pub tau_s: Option<f64>,
    /// The times of the last sample below and the first at or above `level_632`, s.
    pub crossing_between_s: [f64; 2],
    /// How well the data fix the crossing time: one count quantum of this column divided by
    /// the slope there, s (`None` with `tau_s`).
    pub tau_resolution_s: Option<f64>,
}

/// The 63.2 % fit of `values` sampled at `times` (`contiguous(i)` says whether row `i`
/// directly follows row `i - 1`); `quantum` is this column's resolution in thesis RPM.
pub fn fit_632(
    times: &[f64],
    values: &[f64],
    contiguous: impl Fn(usize) -> bool,
    k: f64,
    quantum: f64,
) -> Option<FirstOrder632> {
    let level = FRACTION_AT_TAU * k;
    let i = (1..values.len()).find(|&i| values[i] >= level)?;
    let (t0, t1, y0, y1) = (times[i - 1], times[i], values[i - 1], values[i]);
    let (tau_s, tau_resolution_s) = if contiguous(i) && y1 > y0 {
        let slope = (y1 - y0) / (t1 - t0);
        (Some(t0 + (level - y0) / slope), Some(quantum / slope))
    } else {
        (None, None)
    };
    Some(FirstOrder632 {
        k,
        level_632: level,
        tau_s,
        crossing_between_s: [t0, t1],
        tau_resolution_s,
    })
}

/// Ziegler and Nichols' reaction curve: the tangent at the steepest point of the response.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReactionCurve {
    /// The steepest slope between two consecutive samples, thesis RPM/s.
    pub max_slope: f64,
    /// Where the tangent crosses 0: the apparent dead time `L`, s.
    pub l_s: f64,
    /// From there to where the tangent reaches `K`: `T = K / slope`, s.
    pub t_s: f64,
}

/// The tangent through the steepest pair of consecutive samples of the rise (pairs starting
/// below 63.2 % of `k`; pairs across a gap are skipped; the earliest of equal slopes wins, so
/// a one-count jitter of the steady level cannot be taken for the rise); `None` if the curve
/// never rises.
pub fn reaction_curve(
    times: &[f64],
    values: &[f64],
    contiguous: impl Fn(usize) -> bool,
    k: f64,
) -> Option<ReactionCurve> {
    let (i, slope) = (1..values.len())
        .filter(|&i| contiguous(i) && values[i - 1] < FRACTION_AT_TAU * k)
        .map(|i| (i, (values[i] - values[i - 1]) / (times[i] - times[i - 1])))
        .fold(None, |best: Option<(usize, f64)>, (i, s)| match best {
            Some((_, b)) if b >= s => best,
            _ => Some((i, s)),
        })?;
    if slope.is_nan() || slope <= 0.0 {
        return None;
    }
    Some(ReactionCurve {
        max_slope: slope,
        l_s: times[i] - values[i] / slope,
        t_s: k / slope,
    })
}

/// PID gains in the parallel form `Kp + Ki/s + Kd s` with `Ki = Kp/Ti`, `Kd = Kp Td`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PidGains {
    /// The time constant `T` used, s.
    pub t_s: f64,
    /// The dead time `L` used, s.
    pub l_s: f64,
    /// `Kp = 1.2 T / L` (Ogata's table: no process gain; see
    /// [`Self::kp_with_process_gain`]).
    pub kp: f64,
    /// `Ti = 2 L`, s.
    pub ti_s: f64,
    /// `Td = L / 2`, s.
    pub td_s: f64,
    /// `Kp / Ti`, 1/s.
    pub ki: f64,
    /// `Kp Td`, s.
    pub kd: f64,
    /// Ziegler and Nichols' own rule `1.2 T / (K L)`, with `K` the incremental process gain
    /// in thesis RPM per unit of the firmware's controller output (see
    /// [`crate::identify::GainInterpretation`]); `None` when that gain is unknown.
    pub kp_with_process_gain: Option<f64>,
}

/// Ziegler-Nichols first method (reaction curve), PID row: `Kp = 1.2 T/L`, `Ti = 2L`,
/// `Td = L/2`; `process_gain` (if known) gives [`PidGains::kp_with_process_gain`].
pub fn ziegler_nichols(t_s: f64, l_s: f64, process_gain: Option<f64>) -> Option<PidGains> {
    if !(l_s > 0.0 && t_s > 0.0) {
        return None;
    }
    let kp = 1.2 * t_s / l_s;
    let ti_s = 2.0 * l_s;
    let td_s = 0.5 * l_s;
    Some(PidGains {
        t_s,
        l_s,
        kp,
        ti_s,
        td_s,
        ki: kp / ti_s,
        kd: kp * td_s,
        kp_with_process_gain: process_gain
            .filter(|k| *k > 0.0)
            .map(|k| 1.2 * t_s / (k * l_s)),
    })
}

/// The zero-order-hold discretisation `K (1 - a) / (z - a) z^-d`, `a = exp(-T/tau)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscreteModel {
    /// The sample period `T`, s.
    pub sample_period_s: f64,
    /// `K (1 - a)`.
    pub numerator: f64,
    /// `a = exp(-T / tau)`.
    pub pole: f64,
    /// `d = round(L / T)` samples of dead time (0 without one).
    pub delay_samples: u32,
}

impl DiscreteModel {
    /// ZOH model of `K / (tau s + 1) e^(-L s)` at period `T` (`L` rounded to whole samples,
    /// negative `L` taken as 0).
    pub fn zoh(k: f64, tau_s: f64, l_s: f64, period_s: f64) -> DiscreteModel {
        let pole = (-period_s / tau_s).exp();
        DiscreteModel {
            sample_period_s: period_s,
            numerator: k * (1.0 - pole),
            pole,
            delay_samples: (l_s.max(0.0) / period_s).round() as u32,
        }
    }

    /// The continuous time constant this pole stands for: `-T / ln a`.
    pub fn tau_s(&self) -> f64 {
        -self.sample_period_s / self.pole.ln()
    }

    /// The steady gain `numerator / (1 - pole)`.
    pub fn gain(&self) -> f64 {
        self.numerator / (1.0 - self.pole)
    }
}

/// Search bounds of the FOPDT fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FopdtBounds {
    /// Smallest `L`, s. Negative values let the response start before the first counting
    /// window (the default `-T` allows a whole window).
    pub l_min_s: f64,
    /// Largest `L`, s.
    pub l_max_s: f64,
    /// Smallest `tau`, s.
    pub tau_min_s: f64,
    /// Largest `tau`, s.
    pub tau_max_s: f64,
}

impl FopdtBounds {
    /// `L` in `[-T, 6T]`, `tau` in `[T/10, 100 T]` (0.0015 to 1.5 s at the thesis' 15 ms).
    pub fn for_period(period_s: f64) -> FopdtBounds {
        FopdtBounds {
            l_min_s: -period_s,
            l_max_s: 6.0 * period_s,
            tau_min_s: 0.1 * period_s,
            tau_max_s: 100.0 * period_s,
        }
    }
}

/// A first-order-plus-dead-time fit `K e^(-L s) / (tau s + 1)` by least squares.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FopdtFit {
    /// `K`, thesis RPM.
    pub k: f64,
    /// `tau`, s.
    pub tau_s: f64,
    /// `L`, s: when the response starts, from the logged `t = 0`. Negative means it started
    /// before the first counting window opened (the time stamps lag the step by `-L`).
    pub l_s: f64,
    /// How the samples were modelled.
    pub sampling: Sampling,
    /// Measured minus fitted, thesis RPM, one per row.
    pub residuals: Vec<f64>,
    /// Root mean square of `residuals`, thesis RPM.
    pub rms_residual: f64,
    /// Whether `L` or `tau` ended on a bound of the search (the fit is then not a minimum).
    pub at_bound: bool,
}

/// Fits `K`, `tau`, `L` to `values` at `times` by least squares, `sampling` saying how a
/// sample relates to the speed.
///
/// Method: a bounded search over the dead time `L` (grid of `T/20`, then golden section),
/// for each `L` a bounded search over `tau` (geometric grid, then golden section), and for
/// each `(L, tau)` the gain `K` by linear least squares (nalgebra). This is variable
/// projection: the model is linear in `K`, so only `(L, tau)` are searched, and a bounded
/// search cannot wander off the way Gauss-Newton can on the kinks the dead time makes.
/// Rows may have gaps: the model is evaluated at each row's own time.
pub fn fit_fopdt(
    times: &[f64],
    values: &[f64],
    period_s: f64,
    bounds: &FopdtBounds,
    sampling: Sampling,
) -> Option<FopdtFit> {
    let gain_and_sse = |tau: f64, l: f64| -> (f64, f64) {
        let rows = times
            .iter()
            .zip(values)
            .map(|(&t, &v)| ([unit_response(t, tau, l, period_s, sampling)], v));
        lstsq(rows).map_or((0.0, f64::INFINITY), |(x, sse)| (x[0], sse))
    };
    let best_tau = |l: f64| {
        minimise_bounded(
            |tau| gain_and_sse(tau, l).1,
            bounds.tau_min_s,
            bounds.tau_max_s,
            32,
            true,
        )
    };
    let steps = (((bounds.l_max_s - bounds.l_min_s) / (period_s / 20.0)).round() as usize).max(2);
    let (l, _) = minimise_bounded(
        |l| best_tau(l).1,
        bounds.l_min_s,
        bounds.l_max_s,
        steps + 1,
        false,
    );
    let (tau, sse) = best_tau(l);
    if !sse.is_finite() || gain_and_sse(tau, l).0 <= 0.0 {
        return None;
    }
    let (k, _) = gain_and_sse(tau, l);
    let residuals: Vec<f64> = times
        .iter()
        .zip(values)
        .map(|(&t, &v)| v - k * unit_response(t, tau, l, period_s, sampling))
        .collect();
    let rms_residual = (residuals.iter().map(|r| r * r).sum::<f64>() / values.len() as f64).sqrt();
    let near = |x: f64, b: f64, scale: f64| (x - b).abs() <= 1e-6 * scale;
    Some(FopdtFit {
        k,
        tau_s: tau,
        l_s: l,
        sampling,
        residuals,
        rms_residual,
        at_bound: near(l, bounds.l_min_s, period_s)
            || near(l, bounds.l_max_s, period_s)
            || near(tau, bounds.tau_min_s, tau)
            || near(tau, bounds.tau_max_s, tau),
    })
}
