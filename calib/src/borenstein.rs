//! The formulas UMBmark and the Triangular Path share (Borenstein & Feng 1996): a leg's
//! curvature from its heading change β, Ed from that curvature, the radius, and the
//! correction factors cL, cR from Ed.
//!
//! A leaf: both methods and the thesis GUI's formulas ([`crate::thesis`]) call it, so none
//! of them has to reach into another for them.

/// Curvature κ = 2 sin(β/2)/L (1/cm) of a leg of chord L whose heading changed by β.
pub(crate) fn curvature(beta_rad: f64, l: f64) -> f64 {
    2.0 * (beta_rad / 2.0).sin() / l
}

/// Ed = (R + b/2)/(R − b/2), written with κ = 1/R so that β = 0 gives exactly 1.
pub(crate) fn ed_from_curvature(kappa: f64, b: f64) -> f64 {
    (1.0 + kappa * b / 2.0) / (1.0 - kappa * b / 2.0)
}

/// (cL, cR) = (2/(Ed + 1), 2/(1/Ed + 1)).
pub fn correction_factors(ed: f64) -> (f64, f64) {
    (2.0 / (ed + 1.0), 2.0 / (1.0 / ed + 1.0))
}

/// Radius from curvature, `None` for a straight leg.
pub(crate) fn radius(kappa: f64) -> Option<f64> {
    (kappa != 0.0).then(|| 1.0 / kappa)
}
