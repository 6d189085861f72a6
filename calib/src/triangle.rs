//! The Triangular Path test (Ruan, Li, Zhu 2012), with the 120° turn form derived here.
//!
//! # Procedure
//!
//! 1. **Straight line**: the robot drives a straight line of length L, n times (n = 5). The
//!    diameter ratio error Ed makes the path an arc; the lateral end error y gives the heading
//!    change β over the line and from it Ed.
//! 2. **Equilateral triangle** of side L, n times in one direction (counter-clockwise in the
//!    thesis), after the line's correction was applied. The end error gives the turn error
//!    and from it the wheelbase error Eb.
//!
//! # The straight line
//!
//! A path of length L whose heading changes uniformly by β is an arc whose chord points at
//! β/2, so the end error is (x, y) ≈ (0, L·sin(β/2)) ≈ (0, Lβ/2) and (Ruan eq. 2, thesis
//! eq. 98)
//!
//! ```text
//! β = 2·ȳ_line / L,   R = (L/2)/sin(β/2),   Ed = (R + b'/2)/(R − b'/2),
//! cL = 2/(Ed + 1),    cR = 2/(1/Ed + 1)
//! ```
//!
//! with b' as in UMBmark ([`EdVariant`]). This is the same curvature-to-Ed step as UMBmark's
//! (see [`crate::umbmark`]): only the way β is measured differs.
//!
//! # The triangle: derivation of the 120° form (first order)
//!
//! Frame: [`Frame::Default`], start at the origin heading along +x, counter-clockwise, so
//! every corner is a left turn of nominally 120° (the exterior angle). Let
//!
//! * δ = under-rotation of each 120° turn (rad): the robot turns 120° − δ,
//! * β = heading change over each leg (rad, positive = left), as measured by the line test.
//!
//! Leg k (k = 0, 1, 2) starts with heading θ_k = k·(120° − δ + β): each earlier corner lost δ
//! and each earlier leg added β. Within the leg the heading grows uniformly by β, so the
//! chord of the leg points at θ_k + β/2 and (to first order) has length L. With the nominal
//! directions φ_k = k·120° and the small deviations ε_k = k·(β − δ) + β/2,
//!
//! ```text
//! end = L·Σ_k u(φ_k + ε_k) ≈ L·Σ_k u(φ_k) + L·Σ_k ε_k·u⊥(φ_k)
//! ```
//!
//! where u(φ) = (cos φ, sin φ) and u⊥(φ) = (−sin φ, cos φ). The first sum is zero (the
//! triangle closes). With u⊥(0°) = (0, 1), u⊥(120°) = (−√3/2, −1/2),
//! u⊥(240°) = (√3/2, −1/2), the β/2 terms cancel (Σ u⊥(φ_k) = 0) and what is left is
//! (β − δ)·[1·u⊥(120°) + 2·u⊥(240°)] = (β − δ)·(√3/2, −3/2):
//!
//! ```text
//! CCW:  x = (√3/2)·L·(β − δ)      y = −(3/2)·L·(β − δ)
//! ```
//!
//! The third corner (back to the start heading) moves nothing to first order, so it does not
//! matter whether it is driven. Only the combination β − δ is seen: a triangle in one
//! direction cannot tell a curved leg from a short turn, which is why the line test comes
//! first. A clockwise triangle is the mirror image (y → −y) of a counter-clockwise one with
//! the leg curvature reversed, which gives
//!
//! ```text
//! CW:   x = −(√3/2)·L·(β + δ)     y = −(3/2)·L·(β + δ)
//! ```
//!
//! Solving for δ, with β_t the leg curvature during the triangle runs (0 when the line's
//! correction was applied first, as the method prescribes; the line's β otherwise):
//!
//! ```text
//! CCW:  δ_x = β_t − 2·x̄/(√3·L)     δ_y = β_t + 2·ȳ/(3·L)
//! CW:   δ_x = −β_t − 2·x̄/(√3·L)    δ_y = −β_t − 2·ȳ/(3·L)
//! ```
//!
//! x̄ gives the primary estimate (as in the thesis), ȳ a check ([`TriangleAgreement`]).
//! A wheelbase error Eb = b_actual/b_nominal scales every commanded turn by 1/Eb, so a
//! commanded 120° turn comes out as 120°/Eb = 120° − δ:
//!
//! ```text
//! Eb = 120° / (120° − δ)          (δ in degrees; first order: Eb − 1 ≈ δ/120°)
//! b_actual = Eb · b_nominal
//! ```
//!
//! For comparison, UMBmark's 90° turns give Eb = 90°/(90° − α). Ruan et al. (as printed in
//! the thesis, eqs. 101-106) write x₃ ≈ −L·α, i.e. α = −x̄/L, and then use the 90° formula
//! Eb = 90°/(90° − α): they drop the factor √3/2 of the x displacement and use the 90° form
//! for a 120° turn. Both together make Eb − 1 come out 2/√3 ≈ 1.155 times too large; see
//! [`crate::thesis::triangle_discrepancies`].
//!
//! A scale error Es (measured and not yet corrected) is handled as in UMBmark: L/Es replaces
//! L, and Eb = 120°/((120° − δ)·Es).

use serde::Serialize;

use crate::borenstein::{correction_factors, ed_from_curvature, radius};
use crate::exact::{self, Solution};
use crate::thesis_gui;
use crate::types::{
    centroid, Direction, EdVariant, Endpoint, Frame, LineRuns, Mode, PartialEndpoint, ScaleError,
    TriangleRuns,
};

/// Parameters of a Triangular Path analysis. `Default` gives the thesis robot's reduced test
/// (L = 2 m) on its design wheelbase, [`crate::HENRYTWO_WHEELBASE_MM`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TriangleParams {
    /// Length L of the line and side of the triangle, cm.
    pub side_cm: f64,
    /// The wheelbase b the robot's odometry used during the runs, mm.
    pub wheelbase_mm: f64,
    /// Direction the triangle was driven in (the thesis: counter-clockwise).
    pub direction: Direction,
    /// Frame the end points are recorded in.
    pub frame: Frame,
    /// Correct formulas or the thesis GUI's.
    pub mode: Mode,
    /// Wheelbase used in the Ed formula ([`Mode::Correct`] only).
    pub ed_variant: EdVariant,
    /// Linear scale error measured before the runs, if any ([`Mode::Correct`] only).
    pub scale: Option<ScaleError>,
    /// Whether the line test's Ed correction was applied before the triangle runs (the
    /// method's procedure). If not, the line's β is taken as the triangle legs' curvature.
    pub line_correction_applied: bool,
    /// Largest accepted difference between the x- and y-based turn errors, degrees.
    pub agreement_tolerance_deg: f64,
    /// [`Mode::ThesisCompat`] only: the GUI's wheelbase constant for Ba = Eb·b, mm, when it
    /// is not `wheelbase_mm` (as printed in ANEXO D: 125 mm).
    pub compat_base_mm: Option<f64>,
    /// [`Mode::ThesisCompat`] only: the GUI's b/2 in the line's Ed formula, mm, when it is
    /// not `wheelbase_mm / 2` (as printed in ANEXO D: 6.36 cm).
    pub compat_half_wheelbase_mm: Option<f64>,
    /// First-order formulas (as derived above) or the same model solved exactly
    /// ([`Mode::Correct`] only; see [`crate::exact`]).
    pub solution: Solution,
}

impl Default for TriangleParams {
    fn default() -> Self {
        Self {
            side_cm: 200.0,
            wheelbase_mm: crate::HENRYTWO_WHEELBASE_MM,
            direction: Direction::Ccw,
            frame: Frame::Default,
            mode: Mode::Correct,
            ed_variant: EdVariant::Borenstein,
            scale: None,
            line_correction_applied: true,
            agreement_tolerance_deg: 1.0,
            compat_base_mm: None,
            compat_half_wheelbase_mm: None,
            solution: Solution::FirstOrder,
        }
    }
}

/// How well the x- and y-based turn errors of the triangle agree.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TriangleAgreement {
    /// δ_x − δ_y, degrees.
    pub alpha_diff_deg: f64,
    /// δ_x + δ_y: the disagreement if one axis were mirrored, degrees.
    pub alpha_diff_if_mirrored_deg: f64,
    /// The tolerance applied, degrees.
    pub tolerance_deg: f64,
    /// |δ_x − δ_y| within the tolerance.
    pub consistent: bool,
    /// Changes that would at least halve the disagreement (empty if none, or if consistent).
    pub explained_by: Vec<String>,
}

/// Everything a Triangular Path analysis yields.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TriangleResult {
    /// Formulas used.
    pub mode: Mode,
    /// Which solution of the model gave β and δ (always first order in compat mode).
    pub solution: Solution,
    /// Frame of the input (centroids below are reported in it).
    pub frame: Frame,
    /// Direction of the triangle runs.
    pub direction: Direction,
    /// Wheelbase used in the Ed formula.
    pub ed_variant: EdVariant,
    /// L as commanded, cm.
    pub side_cm: f64,
    /// L/Es, cm.
    pub side_actual_cm: f64,
    /// Wheelbase the odometry used during the runs, mm.
    pub wheelbase_nominal_mm: f64,
    /// Whether the line's correction was taken as applied before the triangle.
    pub line_correction_applied: bool,
    /// Number of line runs.
    pub runs_line: usize,
    /// Number of triangle runs.
    pub runs_triangle: usize,
    /// Centroid of the line runs' end errors, input frame, cm.
    pub line_centroid: Endpoint,
    /// Centroid of the triangle runs' end errors, input frame, cm (y unknown when any run
    /// lacks it).
    pub triangle_centroid: PartialEndpoint,
    /// Distance of the triangle centroid from the origin (the thesis' Table 10 error), cm.
    pub triangle_r_cm: Option<f64>,
    /// Heading change over the line (Correct: 2ȳ/L), degrees.
    pub beta_deg: f64,
    /// The same, radians.
    pub beta_rad: f64,
    /// Radius of curvature of the line, cm (positive = left; `None` when β = 0).
    pub radius_cm: Option<f64>,
    /// Diameter ratio error Ed = D_R/D_L.
    pub ed: f64,
    /// Left wheel correction factor.
    pub cl: f64,
    /// Right wheel correction factor.
    pub cr: f64,
    /// Turn error used for Eb (Correct: δ_x, the under-rotation of each 120° turn;
    /// ThesisCompat: the GUI's α_T = −x̄/L), degrees.
    pub alpha_deg: f64,
    /// The same, radians.
    pub alpha_rad: f64,
    /// δ from x̄ (default frame), degrees.
    pub alpha_x_deg: f64,
    /// The same, radians.
    pub alpha_x_rad: f64,
    /// δ from ȳ (default frame), degrees, when y is known.
    pub alpha_y_deg: Option<f64>,
    /// The same, radians.
    pub alpha_y_rad: Option<f64>,
    /// Agreement of δ_x and δ_y, when y is known.
    pub agreement: Option<TriangleAgreement>,
    /// Wheelbase error Eb = b_actual/b_nominal.
    pub eb: f64,
    /// Corrected (actual) wheelbase, mm.
    pub wheelbase_mm: f64,
    /// Linear scale error Es, when given.
    pub es: Option<f64>,
    /// Anything the reader of the numbers should know.
    pub warnings: Vec<String>,
}

/// Centroid of partial end points: x over all runs, y only when every run has it.
pub(crate) fn partial_centroid(runs: &[PartialEndpoint]) -> PartialEndpoint {
    let n = runs.len() as f64;
    let x = runs.iter().map(|p| p.x_cm).sum::<f64>() / n;
    let y = runs
        .iter()
        .map(|p| p.y_cm)
        .collect::<Option<Vec<f64>>>()
        .map(|ys| ys.iter().sum::<f64>() / n);
    PartialEndpoint::new(x, y)
}

fn to_default(frame: Frame, p: PartialEndpoint) -> PartialEndpoint {
    // Only x changes sign between the frames we know; y is carried through.
    let d = frame.to_default(Endpoint::new(p.x_cm, p.y_cm.unwrap_or(0.0)));
    PartialEndpoint::new(d.x_cm, p.y_cm.map(|_| d.y_cm))
}

/// Turn error δ (rad) per 120° turn from the triangle centroid (default frame), from x and
/// (when known) from y. `beta_t` is the legs' curvature during the triangle runs.
pub(crate) fn turn_error(
    c: PartialEndpoint,
    l: f64,
    beta_t: f64,
    direction: Direction,
) -> (f64, Option<f64>) {
    let s3 = 3f64.sqrt();
    match direction {
        Direction::Ccw => (
            beta_t - 2.0 * c.x_cm / (s3 * l),
            c.y_cm.map(|y| beta_t + 2.0 * y / (3.0 * l)),
        ),
        Direction::Cw => (
            -beta_t - 2.0 * c.x_cm / (s3 * l),
            c.y_cm.map(|y| -beta_t - 2.0 * y / (3.0 * l)),
        ),
    }
}

/// Analyse a Triangular Path experiment: the line runs give Ed, the triangle runs Eb.
///
/// Pure: the result depends on the arguments only. In [`Mode::ThesisCompat`] the GUI's
/// formulas (ANEXO D) decide β, R, Ed, cL, cR, α, Eb and the wheelbase; the x/y estimates
/// and their agreement are always the correct ones.
pub fn triangle_correction(
    line_runs: &LineRuns,
    triangle_runs: &TriangleRuns,
    params: &TriangleParams,
) -> TriangleResult {
    let mut warnings = Vec::new();
    for (what, n) in [
        ("line", line_runs.runs().len()),
        ("triangle", triangle_runs.runs().len()),
    ] {
        if n != 5 {
            warnings.push(format!("{n} {what} runs; the method asks for 5"));
        }
    }
    let line_in = centroid(line_runs.runs());
    let tri_in = partial_centroid(triangle_runs.runs());
    let line = params.frame.to_default(line_in);
    let tri = to_default(params.frame, tri_in);
    if tri.y_cm.is_none() {
        warnings.push(
            "y is missing for some triangle runs: the turn error comes from x alone, and the \
             triangle's end error (Table 10's measure) and the x/y check are unknown"
                .into(),
        );
    }
    let triangle_r_cm = tri_in.complete().map(Endpoint::norm);

    let es = match params.mode {
        Mode::Correct => params.scale.map(|s| s.es()),
        Mode::ThesisCompat => None,
    };
    let l = params.side_cm / es.unwrap_or(1.0);

    // Correct-formula estimates (always reported).
    let beta_line = 2.0 * line.y_cm / l;
    let beta_t = if params.line_correction_applied {
        0.0
    } else {
        beta_line
    };
    let (dx, dy) = turn_error(tri, l, beta_t, params.direction);
    let agreement = dy.map(|dy| {
        let d = (dx - dy).to_degrees();
        let f = (dx + dy).to_degrees();
        let consistent = d.abs() <= params.agreement_tolerance_deg;
        let explained_by = if !consistent && f.abs() <= 0.5 * d.abs() {
            vec![
                "x mirrored".to_string(),
                "y mirrored".to_string(),
                format!(
                    "the triangle driven {} instead",
                    match params.direction {
                        Direction::Ccw => "clockwise",
                        Direction::Cw => "counter-clockwise",
                    }
                ),
            ]
        } else {
            Vec::new()
        };
        TriangleAgreement {
            alpha_diff_deg: d,
            alpha_diff_if_mirrored_deg: f,
            tolerance_deg: params.agreement_tolerance_deg,
            consistent,
            explained_by,
        }
    });
    if let (Some(a), Some(dy)) = (&agreement, dy) {
        if !a.consistent {
            warnings.push(format!(
                "x- and y-based turn errors disagree by more than {}°: {:.3}° (x) vs {:.3}° (y)",
                a.tolerance_deg,
                dx.to_degrees(),
                dy.to_degrees()
            ));
        }
        if !a.explained_by.is_empty() {
            warnings.push(format!(
                "the disagreement falls from {:.2}° to {:.2}° if one of these held: {}; check the \
                 frame (declared `{:?}`) and the direction",
                a.alpha_diff_deg.abs(),
                a.alpha_diff_if_mirrored_deg.abs(),
                a.explained_by.join(", "),
                params.frame
            ));
        }
    }

    let b_nom = params.wheelbase_mm;
    let (beta_rad, radius_cm, ed, alpha_rad, eb, wheelbase_mm, ed_variant);
    match params.mode {
        Mode::Correct => {
            if params.compat_base_mm.is_some() || params.compat_half_wheelbase_mm.is_some() {
                warnings.push("compat_* parameters are ignored in Mode::Correct".into());
            }
            (beta_rad, alpha_rad) = match params.solution {
                Solution::FirstOrder => (beta_line, dx),
                Solution::Exact => {
                    let beta = exact::line_beta(line.y_cm, l);
                    let beta_t = if params.line_correction_applied {
                        Some(0.0)
                    } else {
                        beta
                    };
                    match (
                        beta,
                        beta_t.and_then(|bt| {
                            exact::triangle_delta(tri.x_cm, tri.y_cm, l, bt, params.direction)
                        }),
                    ) {
                        (Some(b), Some(d)) => {
                            warnings.extend(exact::residual_warning(d.rms_cm));
                            (b, d.params[0])
                        }
                        _ => {
                            warnings.push(
                                "the exact solution did not converge (turn errors beyond 34° or legs bending beyond 69°): first-order β and δ used"
                                    .into(),
                            );
                            (beta_line, dx)
                        }
                    }
                }
            };
            eb = 120.0 / ((120.0 - alpha_rad.to_degrees()) * es.unwrap_or(1.0));
            wheelbase_mm = eb * b_nom;
            let b_for_ed_cm = match params.ed_variant {
                EdVariant::Borenstein => b_nom,
                EdVariant::OptiOdom => wheelbase_mm,
            } / 10.0;
            let kappa = params.solution.curvature(beta_rad, l);
            radius_cm = radius(kappa);
            ed = ed_from_curvature(kappa, b_for_ed_cm);
            ed_variant = params.ed_variant;
        }
        Mode::ThesisCompat => {
            if params.direction != Direction::Ccw {
                warnings.push(
                    "the thesis GUI only knows the counter-clockwise triangle: direction ignored"
                        .into(),
                );
            }
            if params.scale.is_some() {
                warnings.push("the thesis GUI has no scale error Es: `scale` ignored".into());
            }
            let gui_line = Frame::ThesisGui.from_default(line);
            let gui_tri_x = -tri.x_cm; // default -> GUI frame mirrors x
            let half_cm = params
                .compat_half_wheelbase_mm
                .unwrap_or(params.wheelbase_mm / 2.0)
                / 10.0;
            let base_mm = params.compat_base_mm.unwrap_or(params.wheelbase_mm);
            let gl = thesis_gui::gui_triangle_line(gui_line.y_cm, params.side_cm, half_cm);
            let gt = thesis_gui::gui_triangle_turn(gui_tri_x, params.side_cm, base_mm);
            beta_rad = gl.beta_l;
            radius_cm = Some(gl.radio_c_l_cm);
            ed = gl.error_diametro_l;
            alpha_rad = gt.alpha_t_deg.to_radians();
            eb = gt.error_base_t;
            wheelbase_mm = gt.base_actual_t_mm;
            ed_variant = EdVariant::Borenstein;
            if !ed.is_finite() {
                warnings.push(
                    "the GUI's line beta is 0: it divides by sin(0) and its Ed is not a number"
                        .into(),
                );
            }
            warnings.push(
                "Mode::ThesisCompat: the thesis GUI's formulas, bugs included (90° turn formula \
                 for 120° turns, missing √3/2, inverted Ed); for reproducing the thesis only"
                    .into(),
            );
        }
    }
    let (cl, cr) = correction_factors(ed);

    TriangleResult {
        mode: params.mode,
        solution: match params.mode {
            Mode::Correct => params.solution,
            Mode::ThesisCompat => Solution::FirstOrder,
        },
        frame: params.frame,
        direction: params.direction,
        ed_variant,
        side_cm: params.side_cm,
        side_actual_cm: l,
        wheelbase_nominal_mm: b_nom,
        line_correction_applied: params.line_correction_applied,
        runs_line: line_runs.runs().len(),
        runs_triangle: triangle_runs.runs().len(),
        line_centroid: line_in,
        triangle_centroid: tri_in,
        triangle_r_cm,
        beta_deg: beta_rad.to_degrees(),
        beta_rad,
        radius_cm,
        ed,
        cl,
        cr,
        alpha_deg: alpha_rad.to_degrees(),
        alpha_rad,
        alpha_x_deg: dx.to_degrees(),
        alpha_x_rad: dx,
        alpha_y_deg: dy.map(f64::to_degrees),
        alpha_y_rad: dy,
        agreement,
        eb,
        wheelbase_mm,
        es,
        warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without a wheelbase given, the Triangular Path takes Henrytwo's 130 mm design
    /// wheelbase as nominal (what the firmware starts with and `hil calibrate --help` says),
    /// not the 125 mm the thesis' reduced tests took, and scales it by Eb.
    #[test]
    fn default_wheelbase_is_henrytwos_130_mm() {
        let line = LineRuns::new(vec![Endpoint::new(0.5, 1.0); 5]).unwrap();
        let triangle = TriangleRuns::complete(vec![Endpoint::new(2.0, -3.0); 5]).unwrap();
        let r = triangle_correction(&line, &triangle, &TriangleParams::default());
        assert_eq!(r.wheelbase_nominal_mm, 130.0);
        assert_eq!(r.wheelbase_mm, r.eb * 130.0);
    }
}
