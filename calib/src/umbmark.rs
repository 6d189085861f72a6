//! UMBmark (Borenstein & Feng 1996): the bi-directional square path test.
//!
//! The robot drives a square of side L, n times clockwise and n times counter-clockwise
//! (n = 5), and the end-position error of each run is measured. In [`Frame::Default`]
//! (origin at the start, x along the first leg, y to the left), to first order in the two
//! dominant systematic errors
//!
//! * α — the under-rotation of every 90° turn (rad), caused by the wheelbase error Eb, and
//! * β — the heading change over every straight leg (rad, positive = curving left), caused by
//!   the wheel-diameter ratio Ed,
//!
//! the end errors are (Borenstein & Feng's Type A and Type B errors added, thesis
//! eqs. 46-77):
//!
//! ```text
//! CW : x = −2L(α + β)   y = −2L(α + β)
//! CCW: x = −2L(α − β)   y = +2L(α − β)
//! ```
//!
//! hence, with the centroids (x_cw, y_cw), (x_ccw, y_ccw) of the runs,
//!
//! ```text
//! α = (x_cw + x_ccw)/(−4L)      β = (x_cw − x_ccw)/(−4L)       (Borenstein eqs. 7, 9)
//! α = (y_cw − y_ccw)/(−4L)      β = (y_cw + y_ccw)/(−4L)       (the same from y)
//! ```
//!
//! The x-based pair is the primary estimate; the y-based pair is computed as a check (see
//! [`Agreement`]). Then
//!
//! ```text
//! R  = (L/2)/sin(β/2)                        radius of the legs' curvature
//! Ed = (R + b'/2)/(R − b'/2)                 b' = b (Borenstein) or Eb·b (OptiOdom), see EdVariant
//! Eb = 90°/(90° − α)                         b_actual = Eb·b_nominal
//! cL = 2/(Ed + 1)    cR = 2/(1/Ed + 1)       so cR/cL = Ed and (cL + cR)/2 = 1
//! ```
//!
//! When a linear scale error Es = L_calc/L_actual was measured (and not yet corrected when
//! the squares were driven) it is applied first: the legs were actually L/Es long, every turn
//! was scaled by 1/Es through the wrong mean wheel diameter, so L/Es replaces L above and
//! Eb = 90°/((90° − α)·Es).

use serde::Serialize;

pub use crate::borenstein::correction_factors;
use crate::borenstein::{ed_from_curvature, radius};
use crate::exact::{self, Solution};
use crate::thesis_gui;
use crate::types::{
    centroid, Direction, EdVariant, Endpoint, Frame, Mode, ScaleError, UmbmarkRuns,
};

/// Parameters of a UMBmark analysis. `Default` gives the thesis robot's reduced UMBmark
/// (L = 2 m) on its design wheelbase, [`crate::HENRYTWO_WHEELBASE_MM`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UmbmarkParams {
    /// Side L of the square, cm (reduced UMBmark: 200; Borenstein's original: 400).
    pub side_cm: f64,
    /// The wheelbase b the robot's odometry used while driving the squares, mm.
    pub wheelbase_mm: f64,
    /// Frame the end points are recorded in.
    pub frame: Frame,
    /// Correct formulas or the thesis GUI's.
    pub mode: Mode,
    /// Wheelbase used in the Ed formula ([`Mode::Correct`] only; the GUI uses a constant).
    pub ed_variant: EdVariant,
    /// Linear scale error measured on a straight line before the squares, if any
    /// ([`Mode::Correct`] only; the GUI has no Es).
    pub scale: Option<ScaleError>,
    /// Largest accepted difference between the x- and y-based α (and β), degrees.
    pub agreement_tolerance_deg: f64,
    /// [`Mode::ThesisCompat`] only: the GUI's wheelbase constant in Ba = Eb·b, mm, when it is
    /// not `wheelbase_mm` (as printed in ANEXO C: 12.25 cm).
    pub compat_base_mm: Option<f64>,
    /// [`Mode::ThesisCompat`] only: the GUI's constant for b/2 in the Ed formula, mm, when it
    /// is not `wheelbase_mm / 2` (as printed in ANEXO C the GUI has b = 12.25 cm but
    /// b/2 = 6.15 cm).
    pub compat_half_wheelbase_mm: Option<f64>,
    /// First-order formulas (as published) or the same model solved exactly
    /// ([`Mode::Correct`] only; see [`crate::exact`]).
    pub solution: Solution,
}

impl Default for UmbmarkParams {
    fn default() -> Self {
        Self {
            side_cm: 200.0,
            wheelbase_mm: crate::HENRYTWO_WHEELBASE_MM,
            frame: Frame::Default,
            mode: Mode::Correct,
            ed_variant: EdVariant::Borenstein,
            scale: None,
            agreement_tolerance_deg: 1.0,
            compat_base_mm: None,
            compat_half_wheelbase_mm: None,
            solution: Solution::FirstOrder,
        }
    }
}

/// How well the x-based and y-based estimates of α and β agree.
///
/// Under the first-order model the CW centroid lies on the line y = x and the CCW centroid on
/// y = −x, so both pairs of formulas estimate the same α and β. A mirrored axis (x or y), an
/// axis rotated by ±90° or exchanged CW/CCW labels maps one diagonal onto the other: the
/// estimates then disagree by Δ_same = |(α_x − α_y, β_x − β_y)| while the "flipped"
/// combination Δ_flip = |(α_x + α_y, β_x + β_y)| is small. Exchanged x and y, the
/// anti-diagonal swap and a 180° rotation keep each diagonal in place: they cannot be seen
/// this way (they exchange α and β or flip both signs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Agreement {
    /// α_x − α_y, degrees.
    pub alpha_diff_deg: f64,
    /// β_x − β_y, degrees.
    pub beta_diff_deg: f64,
    /// The tolerance applied, degrees.
    pub tolerance_deg: f64,
    /// Both differences within the tolerance.
    pub consistent: bool,
    /// |(α_x − α_y, β_x − β_y)|, degrees.
    pub disagreement_deg: f64,
    /// |(α_x + α_y, β_x + β_y)|: the disagreement if one axis were mirrored, degrees.
    pub disagreement_if_mirrored_deg: f64,
    /// Axis changes that would at least halve the disagreement (empty when none would, or
    /// when the estimates agree).
    pub explained_by: Vec<String>,
}

/// The axis changes that exchange the two diagonals, hence turn Δ_same into Δ_flip.
const FLIPPING_CHANGES: [&str; 4] = [
    "x mirrored",
    "y mirrored",
    "axes rotated by 90° (either way)",
    "CW and CCW labels exchanged",
];

/// Everything a UMBmark analysis yields. Angles carry their unit in the name; lengths are in
/// cm except the wheelbases (mm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UmbmarkResult {
    /// Formulas used.
    pub mode: Mode,
    /// Which solution of the model gave α and β (always first order in compat mode).
    pub solution: Solution,
    /// Frame of the input (centroids below are reported in it).
    pub frame: Frame,
    /// Wheelbase used in the Ed formula (always `borenstein` in compat mode).
    pub ed_variant: EdVariant,
    /// Side L of the square as commanded, cm.
    pub side_cm: f64,
    /// Side actually driven, L/Es, cm (= `side_cm` without a scale error).
    pub side_actual_cm: f64,
    /// Wheelbase the odometry used during the runs, mm.
    pub wheelbase_nominal_mm: f64,
    /// Number of CW runs.
    pub runs_cw: usize,
    /// Number of CCW runs.
    pub runs_ccw: usize,
    /// Centroid of the CW end errors, input frame, cm.
    pub centroid_cw: Endpoint,
    /// Centroid of the CCW end errors, input frame, cm.
    pub centroid_ccw: Endpoint,
    /// Distance of the CW centroid from the origin, cm.
    pub r_cg_cw_cm: f64,
    /// Distance of the CCW centroid from the origin, cm.
    pub r_cg_ccw_cm: f64,
    /// E_max,syst = max(r_cg_cw, r_cg_ccw), Borenstein's measure of systematic error, cm.
    pub e_max_cm: f64,
    /// (r_cg_cw + r_cg_ccw)/2, the error the thesis reports in Table 10, cm.
    pub error_mean_cm: f64,
    /// α used for Eb (Correct: from x; ThesisCompat: the GUI's), degrees.
    pub alpha_deg: f64,
    /// The same α, radians.
    pub alpha_rad: f64,
    /// β used for R and Ed (Correct: from x; ThesisCompat: the GUI's), degrees.
    pub beta_deg: f64,
    /// The same β, radians.
    pub beta_rad: f64,
    /// α = (x_cw + x_ccw)/(−4L) in the default frame, degrees.
    pub alpha_x_deg: f64,
    /// The same, radians.
    pub alpha_x_rad: f64,
    /// α = (y_cw − y_ccw)/(−4L) in the default frame, degrees.
    pub alpha_y_deg: f64,
    /// The same, radians.
    pub alpha_y_rad: f64,
    /// β = (x_cw − x_ccw)/(−4L) in the default frame, degrees.
    pub beta_x_deg: f64,
    /// The same, radians.
    pub beta_x_rad: f64,
    /// β = (y_cw + y_ccw)/(−4L) in the default frame, degrees.
    pub beta_y_deg: f64,
    /// The same, radians.
    pub beta_y_rad: f64,
    /// Agreement of the x- and y-based estimates.
    pub agreement: Agreement,
    /// Radius of curvature of the legs, cm (positive = curving left; `None` when β = 0).
    pub radius_cm: Option<f64>,
    /// Diameter ratio error Ed = D_R/D_L.
    pub ed: f64,
    /// Wheelbase error Eb = b_actual/b_nominal.
    pub eb: f64,
    /// Correction factor for the left wheel's distance per count.
    pub cl: f64,
    /// Correction factor for the right wheel's distance per count.
    pub cr: f64,
    /// Corrected (actual) wheelbase Eb·b, mm.
    pub wheelbase_mm: f64,
    /// Linear scale error Es = L_calc/L_actual, when given.
    pub es: Option<f64>,
    /// Anything the reader of the numbers should know.
    pub warnings: Vec<String>,
}

/// The four first-order estimates, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Estimates {
    pub alpha_x: f64,
    pub beta_x: f64,
    pub alpha_y: f64,
    pub beta_y: f64,
}

/// α and β from x and from y, for centroids in the default frame and side `l`.
pub(crate) fn estimates(cw: Endpoint, ccw: Endpoint, l: f64) -> Estimates {
    let k = -4.0 * l;
    Estimates {
        alpha_x: (cw.x_cm + ccw.x_cm) / k,
        beta_x: (cw.x_cm - ccw.x_cm) / k,
        alpha_y: (cw.y_cm - ccw.y_cm) / k,
        beta_y: (cw.y_cm + ccw.y_cm) / k,
    }
}

pub(crate) fn agreement(e: &Estimates, tolerance_deg: f64) -> Agreement {
    let d = |v: f64| v.to_degrees();
    let alpha_diff_deg = d(e.alpha_x - e.alpha_y);
    let beta_diff_deg = d(e.beta_x - e.beta_y);
    let same = alpha_diff_deg.hypot(beta_diff_deg);
    let flip = d(e.alpha_x + e.alpha_y).hypot(d(e.beta_x + e.beta_y));
    let consistent = alpha_diff_deg.abs() <= tolerance_deg && beta_diff_deg.abs() <= tolerance_deg;
    let explained_by = if !consistent && flip <= 0.5 * same {
        FLIPPING_CHANGES.iter().map(|s| s.to_string()).collect()
    } else {
        Vec::new()
    };
    Agreement {
        alpha_diff_deg,
        beta_diff_deg,
        tolerance_deg,
        consistent,
        disagreement_deg: same,
        disagreement_if_mirrored_deg: flip,
        explained_by,
    }
}

pub(crate) fn agreement_warnings(a: &Agreement, e: &Estimates, frame: Frame) -> Vec<String> {
    let mut w = Vec::new();
    if !a.consistent {
        w.push(format!(
            "x- and y-based estimates disagree by more than {tol}°: alpha {ax:.3}° (x) vs {ay:.3}° (y), \
             beta {bx:.3}° (x) vs {by:.3}° (y); the end errors do not fit the two-error model \
             (non-systematic errors, an uncorrected scale or initial-heading error, or a frame \
             other than the declared `{frame:?}`)",
            tol = a.tolerance_deg,
            ax = e.alpha_x.to_degrees(),
            ay = e.alpha_y.to_degrees(),
            bx = e.beta_x.to_degrees(),
            by = e.beta_y.to_degrees(),
        ));
    }
    if !a.explained_by.is_empty() {
        w.push(format!(
            "the disagreement falls from {s:.2}° to {f:.2}° if one of these held: {list}; \
             check the frame (declared `{frame:?}`) and the CW/CCW labels",
            s = a.disagreement_deg,
            f = a.disagreement_if_mirrored_deg,
            list = a.explained_by.join(", "),
        ));
    }
    w
}

/// Analyse a UMBmark experiment.
///
/// Pure: the result depends on `runs` and `params` only. In [`Mode::ThesisCompat`] the
/// GUI's formulas decide α, β, R, Ed, Eb, cL, cR and the wheelbase (see
/// [`crate::thesis::gui_umbmark`]); the x/y estimates and the agreement check are always the
/// correct ones, computed in the default frame.
pub fn umbmark_correction(runs: &UmbmarkRuns, params: &UmbmarkParams) -> UmbmarkResult {
    let mut warnings = Vec::new();
    let cw_in = centroid(runs.cw());
    let ccw_in = centroid(runs.ccw());
    let cw = params.frame.to_default(cw_in);
    let ccw = params.frame.to_default(ccw_in);
    let r_cw = cw_in.norm();
    let r_ccw = ccw_in.norm();

    for d in [Direction::Cw, Direction::Ccw] {
        let n = runs.runs(d).len();
        if n != 5 {
            warnings.push(format!(
                "{n} {} runs; UMBmark asks for 5 per direction",
                d.as_str()
            ));
        }
    }

    let es = match params.mode {
        Mode::Correct => params.scale.map(|s| s.es()),
        Mode::ThesisCompat => None,
    };
    let side_actual = params.side_cm / es.unwrap_or(1.0);
    let est = estimates(cw, ccw, side_actual);
    let agreement = agreement(&est, params.agreement_tolerance_deg);
    warnings.extend(agreement_warnings(&agreement, &est, params.frame));

    let b_nom = params.wheelbase_mm;
    let (alpha_rad, beta_rad, radius_cm, ed, eb, wheelbase_mm, ed_variant);
    match params.mode {
        Mode::Correct => {
            if params.compat_base_mm.is_some() || params.compat_half_wheelbase_mm.is_some() {
                warnings.push("compat_* parameters are ignored in Mode::Correct".into());
            }
            (alpha_rad, beta_rad) = match params.solution {
                Solution::FirstOrder => (est.alpha_x, est.beta_x),
                Solution::Exact => match exact::umbmark_alpha_beta(cw, ccw, side_actual) {
                    Some(fit) => {
                        warnings.extend(exact::residual_warning(fit.rms_cm));
                        (fit.params[0], fit.params[1])
                    }
                    None => {
                        warnings.push(
                            "the exact solution did not converge (turn errors beyond 34° or legs bending beyond 69°): first-order α and β used"
                                .into(),
                        );
                        (est.alpha_x, est.beta_x)
                    }
                },
            };
            let alpha_deg = alpha_rad.to_degrees();
            eb = 90.0 / ((90.0 - alpha_deg) * es.unwrap_or(1.0));
            wheelbase_mm = eb * b_nom;
            let b_for_ed_cm = match params.ed_variant {
                EdVariant::Borenstein => b_nom,
                EdVariant::OptiOdom => wheelbase_mm,
            } / 10.0;
            let kappa = params.solution.curvature(beta_rad, side_actual);
            radius_cm = radius(kappa);
            ed = ed_from_curvature(kappa, b_for_ed_cm);
            if kappa.abs() * b_for_ed_cm / 2.0 >= 1.0 {
                warnings.push(
                    "the legs' radius of curvature is below half the wheelbase: Ed is meaningless"
                        .into(),
                );
            }
            ed_variant = params.ed_variant;
        }
        Mode::ThesisCompat => {
            if params.scale.is_some() {
                warnings.push("the thesis GUI has no scale error Es: `scale` ignored".into());
            }
            if params.ed_variant != EdVariant::Borenstein {
                warnings.push(
                    "the thesis GUI uses a constant b/2 in Ed: ed_variant ignored (borenstein)"
                        .into(),
                );
            }
            let half_mm = params
                .compat_half_wheelbase_mm
                .unwrap_or(params.wheelbase_mm / 2.0);
            let gui_cw = Frame::ThesisGui.from_default(cw);
            let gui_ccw = Frame::ThesisGui.from_default(ccw);
            let g = thesis_gui::gui_umbmark(
                gui_cw,
                gui_ccw,
                params.side_cm,
                params.compat_base_mm.unwrap_or(params.wheelbase_mm) / 10.0,
                half_mm / 10.0,
            );
            alpha_rad = g.alpha_deg.to_radians();
            beta_rad = g.beta_deg.to_radians();
            radius_cm = Some(g.radio_c_cm);
            ed = g.error_diametro;
            eb = g.error_base;
            wheelbase_mm = g.base_act_cm * 10.0;
            ed_variant = EdVariant::Borenstein;
            if !ed.is_finite() {
                warnings.push(
                    "the GUI's beta is 0: it divides by sin(0) and its Ed is not a number".into(),
                );
            }
            if runs.cw().len() != 5 || runs.ccw().len() != 5 {
                warnings.push(
                    "the thesis GUI accepts exactly 5 runs per direction; centroids here use all runs"
                        .into(),
                );
            }
            warnings.push(
                "Mode::ThesisCompat: the thesis GUI's formulas, bugs included (degrees passed to \
                 sin(), alpha from y, beta from the GUI's mirrored x); for reproducing the thesis only"
                    .into(),
            );
        }
    }
    let (cl, cr) = correction_factors(ed);

    UmbmarkResult {
        mode: params.mode,
        solution: match params.mode {
            Mode::Correct => params.solution,
            Mode::ThesisCompat => Solution::FirstOrder,
        },
        frame: params.frame,
        ed_variant,
        side_cm: params.side_cm,
        side_actual_cm: side_actual,
        wheelbase_nominal_mm: b_nom,
        runs_cw: runs.cw().len(),
        runs_ccw: runs.ccw().len(),
        centroid_cw: cw_in,
        centroid_ccw: ccw_in,
        r_cg_cw_cm: r_cw,
        r_cg_ccw_cm: r_ccw,
        e_max_cm: r_cw.max(r_ccw),
        error_mean_cm: (r_cw + r_ccw) / 2.0,
        alpha_deg: alpha_rad.to_degrees(),
        alpha_rad,
        beta_deg: beta_rad.to_degrees(),
        beta_rad,
        alpha_x_deg: est.alpha_x.to_degrees(),
        alpha_x_rad: est.alpha_x,
        alpha_y_deg: est.alpha_y.to_degrees(),
        alpha_y_rad: est.alpha_y,
        beta_x_deg: est.beta_x.to_degrees(),
        beta_x_rad: est.beta_x,
        beta_y_deg: est.beta_y.to_degrees(),
        beta_y_rad: est.beta_y,
        agreement,
        radius_cm,
        ed,
        eb,
        cl,
        cr,
        wheelbase_mm,
        es,
        warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without a wheelbase given, UMBmark takes Henrytwo's 130 mm design wheelbase as
    /// nominal, as the Triangular Path does.
    #[test]
    fn default_wheelbase_is_henrytwos_130_mm() {
        let runs = UmbmarkRuns::new(
            vec![Endpoint::new(-3.0, 4.0); 5],
            vec![Endpoint::new(2.0, 1.5); 5],
        )
        .unwrap();
        let r = umbmark_correction(&runs, &UmbmarkParams::default());
        assert_eq!(r.wheelbase_nominal_mm, 130.0);
        assert_eq!(r.wheelbase_mm, r.eb * 130.0);
    }
}
