//! Small numerical helpers: the χ² distribution, residual whiteness (Ljung-Box), cross-
//! correlation with an input, and a bounded 1-D minimiser.

use serde::Serialize;

/// ln Γ(x) for x > 0 (Lanczos, g = 7, n = 9; relative error below 1e-13).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let gln = ln_gamma(a);
    if x < a + 1.0 {
        // Series for P.
        let mut sum = 1.0 / a;
        let mut del = sum;
        let mut ap = a;
        for _ in 0..1000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - gln).exp()
    } else {
        // Continued fraction for Q (modified Lentz).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - gln).exp() * h
    }
}

/// P(χ²_k > q).
pub fn chi2_sf(q: f64, k: usize) -> f64 {
    gamma_q(k as f64 / 2.0, q / 2.0).clamp(0.0, 1.0)
}

/// Sample autocorrelation of `e` at lag `k` (biased estimator, as in Ljung-Box).
pub fn autocorrelation(e: &[f64], k: usize) -> f64 {
    let n = e.len();
    if k >= n {
        return 0.0;
    }
    let m = e.iter().sum::<f64>() / n as f64;
    let den: f64 = e.iter().map(|v| (v - m).powi(2)).sum();
    if den <= 0.0 {
        return 0.0;
    }
    let num: f64 = (k..n).map(|t| (e[t] - m) * (e[t - k] - m)).sum();
    num / den
}

/// The Ljung-Box test of a residual series.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LjungBox {
    /// Samples.
    pub n: usize,
    /// Lags summed (h).
    pub lags: usize,
    /// Q = n(n + 2) Σ ρ_k²/(n − k).
    pub q: f64,
    /// P(χ²_h > Q): small means the residual is not white.
    pub p_value: f64,
    /// Whether whiteness is rejected at 5 %.
    pub rejected: bool,
}

/// Ljung-Box on `e` with `h` lags (at least 1 and below n). `None` for fewer than 4 samples
/// or a constant series.
pub fn ljung_box(e: &[f64], h: usize) -> Option<LjungBox> {
    let n = e.len();
    if n < 4 {
        return None;
    }
    let h = h.clamp(1, n - 2);
    let m = e.iter().sum::<f64>() / n as f64;
    if e.iter().all(|v| (v - m).abs() < 1e-15) {
        return None;
    }
    let nf = n as f64;
    let q = nf
        * (nf + 2.0)
        * (1..=h)
            .map(|k| autocorrelation(e, k).powi(2) / (nf - k as f64))
            .sum::<f64>();
    let p = chi2_sf(q, h);
    Some(LjungBox {
        n,
        lags: h,
        q,
        p_value: p,
        rejected: p < 0.05,
    })
}

/// Cross-correlation of a residual with an input.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrossCorrelation {
    /// Samples.
    pub n: usize,
    /// r_k for lags k = 0..=max_lag: corr(e_t, u_{t−k}) (the input leading the residual).
    pub r: Vec<f64>,
    /// The lag of the largest |r|.
    pub peak_lag: usize,
    /// r at that lag.
    pub peak: f64,
    /// The 95 % band of a white residual, 1.96/√n.
    pub band: f64,
    /// Whether any |r_k| exceeds the band.
    pub significant: bool,
}

/// Cross-correlation of `e` with `u` for lags 0..=max_lag; `None` when either is constant
/// (e.g. a step input after the step) or shorter than 4 samples.
pub fn cross_correlation(e: &[f64], u: &[f64], max_lag: usize) -> Option<CrossCorrelation> {
    let n = e.len().min(u.len());
    if n < 4 {
        return None;
    }
    let (e, u) = (&e[..n], &u[..n]);
    let me = e.iter().sum::<f64>() / n as f64;
    let mu = u.iter().sum::<f64>() / n as f64;
    let se = (e.iter().map(|v| (v - me).powi(2)).sum::<f64>() / n as f64).sqrt();
    let su = (u.iter().map(|v| (v - mu).powi(2)).sum::<f64>() / n as f64).sqrt();
    if se < 1e-12 || su < 1e-12 {
        return None;
    }
    let max_lag = max_lag.min(n - 2);
    let r: Vec<f64> = (0..=max_lag)
        .map(|k| (k..n).map(|t| (e[t] - me) * (u[t - k] - mu)).sum::<f64>() / (n as f64 * se * su))
        .collect();
    let (peak_lag, peak) = r
        .iter()
        .copied()
        .enumerate()
        .fold(
            (0, 0.0f64),
            |a, (k, v)| if v.abs() > a.1.abs() { (k, v) } else { a },
        );
    let band = 1.96 / (n as f64).sqrt();
    Some(CrossCorrelation {
        n,
        r,
        peak_lag,
        peak,
        band,
        significant: peak.abs() > band,
    })
}

/// Minimises `f` on [lo, hi]: `n` grid points (geometric when `log`), then golden section in
/// the bracket around the best. Returns (x, f(x)). The identification's minimiser.
pub fn minimise_1d(f: impl Fn(f64) -> f64, lo: f64, hi: f64, n: usize, log: bool) -> (f64, f64) {
    plant_model::identify::minimise_bounded(f, lo, hi, n, log)
}
