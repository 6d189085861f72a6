//! Odometry calibration math for the test bench's differential-drive robot: UMBmark
//! (Borenstein & Feng 1996), the Triangular Path test (Ruan, Li, Zhu 2012), and the thesis
//! GUI's formulas in a compatibility mode for reproducing the thesis on the robot "Henrytwo".
//!
//! Everything here is pure: functions of measured end errors and named-field parameters.
//!
//! # Frame
//!
//! All formulas are written in [`Frame::Default`], Borenstein & Feng's geometry: origin at
//! the start point, x along the first leg (the initial heading), y to the robot's left,
//! error = end position minus start position (for the straight line: minus the commanded
//! end). A counter-clockwise run turns left. Data recorded otherwise are converted when the
//! caller declares their frame; the only other frame known is [`Frame::ThesisGui`], the
//! thesis GUI's, whose x axis is mirrored. A frame is never guessed: the analyses compare the
//! x- and y-based estimates and *warn* when they disagree the way a mirrored or rotated
//! axis would explain ([`umbmark::Agreement`]).
//!
//! # UMBmark ([`umbmark`])
//!
//! Five runs clockwise and five counter-clockwise around a square of side L; centroids
//! (x_cw, y_cw), (x_ccw, y_ccw) of the end errors, r_cg = √(x² + y²) per direction,
//! E_max,syst = max(r_cg,cw, r_cg,ccw). With α the under-rotation of each 90° turn and β the
//! heading change over each leg (Borenstein & Feng 1996, eqs. 7-14; thesis eqs. 41-94):
//!
//! ```text
//! α = (x_cw + x_ccw)/(−4L)    β = (x_cw − x_ccw)/(−4L)      primary (radians)
//! α = (y_cw − y_ccw)/(−4L)    β = (y_cw + y_ccw)/(−4L)      check, derived for this frame
//! R  = (L/2)/sin(β/2)
//! Ed = (R + b'/2)/(R − b'/2)        b' = b (Borenstein) or Eb·b (OptiOdom): EdVariant
//! Eb = 90°/(90° − α)                b_actual = Eb·b_nominal
//! cL = 2/(Ed + 1)                   cR = 2/(1/Ed + 1)
//! ```
//!
//! The y formulas follow from the first-order end errors CW: x = y = −2L(α + β);
//! CCW: x = −y = −2L(α − β). A linear scale error Es = L_calc/L_actual, measured on a
//! straight line ([`ScaleError`]), is applied first when given: L/Es replaces L and
//! Eb = 90°/((90° − α)·Es).
//!
//! # Ed variants ([`EdVariant`])
//!
//! Borenstein & Feng put the nominal wheelbase b in Ed. OptiOdom uses the corrected one,
//! Eb·b, which is what actually sets a leg's curvature; the two differ by a factor ≈ Eb on
//! Ed − 1. The variant used is recorded in every result (`ed_variant`).
//!
//! # Triangular Path ([`triangle`])
//!
//! A straight line of length L (five runs) gives β = 2ȳ/L and Ed as above; then an
//! equilateral triangle of side L (five runs, one direction) gives the under-rotation δ of
//! each 120° turn: counter-clockwise x̄ = (√3/2)·L·(β_t − δ), ȳ = −(3/2)·L·(β_t − δ) to first
//! order (derived in [`triangle`]), and Eb = 120°/(120° − δ).
//!
//! # Thesis compatibility ([`Mode::ThesisCompat`], [`thesis`])
//!
//! The thesis' MATLAB GUI (ANEXO C and D) applied exactly as printed, on the numbers as its
//! authors typed them. It reproduces the values printed in the GUI screenshots and Table 10
//! ([`round`]). The bugs it reproduces:
//!
//! * UMBmark: β in degrees passed to `sin()` (R ≈ 57 times too small, Ed − 1 ≈ 57 times too
//!   large); α from the y components and β from the x components of a frame whose x looks
//!   mirrored (β's sign flips); b/2 = 6.15 cm next to b = 12.25 cm; the Table 10 error is
//!   the mean of the two r_cg, not E_max,syst.
//! * Triangular Path: α = −x̄/L (the √3/2 of a 120° turn dropped), Eb = 90/(90 − α) (the 90°
//!   formula for 120° turns), Ed = (R − b/2)/(R + b/2) (the reciprocal of UMBmark's: cL and
//!   cR exchanged), Ba from a hard-coded 125 mm while b/2 had been updated to 6.36 cm.
//! * Table 10: "before" is the 130 mm design wheelbase although the tests used 125 mm, the
//!   wheelbase correction % is computed from the wheelbase loaded for the last run rather
//!   than the "after" column, and lengths are truncated rather than rounded.
//!
//! [`thesis::umbmark_discrepancies`] and [`thesis::triangle_discrepancies`] list each
//! formula that differs and by how much on given data.
//!
//! # Other pieces
//!
//! * [`csv`]: the end-point tables (`experiment,direction,run,x_cm,y_cm` and
//!   `experiment,test,run,x_cm,y_cm`), with line-numbered errors.
//! * [`round`]: Table 10 (before/after of a calibration round) and its text table.
//! * [`plot`]: SVG and PNG plots of the end errors, centroids and their vectors.
//! * [`forward`]: exact forward model (wheel-level kinematics) to generate synthetic runs.
//!
//! # References
//!
//! * J. Borenstein, L. Feng, "Measurement and correction of systematic odometry errors in
//!   mobile robots", IEEE Trans. Robotics and Automation 12(6), 1996 (UMBmark).
//! * X. Ruan, Y. Li, X. Zhu, "Kinematic parameter calibration of two-wheeled robot", 2012
//!   (Triangular Path).
//! * The thesis on "Henrytwo" (Spanish): chapters 5.2.6-5.2.9 (methods), 6.5-6.6 (GUI and
//!   experiments, Tables 5-10), ANEXO B-D (GUI code).

mod borenstein;
pub mod csv;
mod error;
pub mod exact;
pub mod forward;
pub mod plot;
pub mod round;
pub mod thesis;
mod thesis_gui;
pub mod triangle;
mod types;
pub mod umbmark;

/// Henrytwo's design wheelbase, wheel centre to centre, mm: the nominal wheelbase `b` of
/// [`UmbmarkParams::default`] and [`TriangleParams::default`], the one the robot's firmware
/// starts with and the plant's nominal robot has. One definition, so that a calibration run
/// without a wheelbase given assumes the robot the rest of the bench describes. (The thesis'
/// reduced tests took the 125 mm between the wheels' inner faces as nominal; the GUI's
/// constants that reproduce its printed numbers are in [`thesis`].) It is the firmware's
/// factory value, from the protocol crate both share.
pub const HENRYTWO_WHEELBASE_MM: f64 =
    henrytwo_protocol::Param::WheelbaseMm.factory_default() as f64;

pub use error::Error;
pub use exact::Solution;
pub use plot::{plot_triangle, plot_umbmark};
pub use round::{improvement, Round};
pub use thesis::Discrepancy;
pub use triangle::{triangle_correction, TriangleParams, TriangleResult};
pub use types::{
    Direction, EdVariant, Endpoint, Frame, LineRuns, Mode, PartialEndpoint, ScaleError,
    TriangleRuns, UmbmarkRuns,
};
pub use umbmark::{umbmark_correction, UmbmarkParams, UmbmarkResult};
