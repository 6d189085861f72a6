//! The thesis' calibration GUI (MATLAB, ANEXO C and D), formula by formula, and how it
//! differs from the published methods.
//!
//! Everything here reproduces what the thesis *printed*, bugs included; nothing here should
//! be used to calibrate a robot. The names of the intermediate values are the GUI's MATLAB
//! variable names.
//!
//! # The constants in the GUI code
//!
//! | constant | where | what it is |
//! |---|---|---|
//! | `200` | ANEXO C (`-4*pi*200`, `200/(2*sin(beta/2))`), ANEXO D (`/200`, `(-200)*pi`, `100/sin`) | L = 2 m in cm (reduced tests); `100` is L/2 |
//! | `12.25` | ANEXO C, `Base_act=Error_Base*12.25` (comment: "130 en mm") | the wheelbase in cm loaded in the GUI when the code was printed |
//! | `6.15` | ANEXO C, `(Radio_C+6.15)/(Radio_C-6.15)` | b/2 in cm for Ed; 2·6.15 = 12.3 ≠ 12.25: the two constants were edited separately |
//! | `6.36` | ANEXO D, `(Radio_C_L-6.36)/(Radio_C_L+6.36)` | b/2 in cm for the line's Ed: 12.72 cm, the triangle's experiment-1 result (127.27 mm) truncated |
//! | `125` | ANEXO D, `Base_Actual_T=Error_base_T*125` (mm!) | the 125 mm inner-face wheelbase the reduced tests took as nominal (chapter 7) |
//! | `4*pi*2` | ANEXO C, commented-out `%alpha=((X_Z_prom_CW+X_Z_prom_CCW)*(180))/(-4*pi*2)` | Borenstein's α from x, with L in metres against data in cm; abandoned for α from y |
//!
//! The hard-coded wheelbase was updated between experiments with the previous result, which
//! is how the printed GUI values are reproduced ([`umbmark_params_for_experiment`]):
//! experiment 1 with b = 12.5 cm, experiment 2 with 12.23 cm (experiment 1's 12.2323), and
//! experiment 3 with 12.26 cm (experiment 2's result).
//!
//! # The GUI's bugs (each reproduced by [`crate::Mode::ThesisCompat`])
//!
//! UMBmark (ANEXO C):
//! 1. `beta` is computed in degrees (`*180/pi`) and passed to `sin()`, which takes radians:
//!    R comes out ≈ 57.3 times too small and Ed − 1 ≈ 57.3 times too large.
//! 2. α is taken from the y components, `(Y_cw − Y_ccw)/(−4L)`, and β from the x components.
//!    Both are valid first-order formulas in Borenstein's frame, but the GUI's x axis looks
//!    mirrored against it (see [`crate::Frame::ThesisGui`]), which flips β's sign.
//! 3. b/2 = 6.15 cm in Ed is not half of b = 12.25 cm in Ba.
//! 4. `Error_Max` (E_max,syst) is computed and never shown; Table 10 reports the *mean* of
//!    r_cg,cw and r_cg,ccw instead.
//!
//! Triangular Path (ANEXO D):
//! 5. α_T = −x̄/L (Ruan as printed: x₃ ≈ −Lα) drops the factor √3/2 of the x displacement
//!    of a 120° turn error (see [`crate::triangle`]).
//! 6. Eb = 90/(90 − α_T) uses the 90° turn formula for 120° turns.
//! 7. Ed = (R − b/2)/(R + b/2) is the reciprocal of UMBmark's (R + b/2)/(R − b/2), so cL
//!    and cR come out exchanged.
//! 8. Ba uses a hard-coded 125 mm while the line's b/2 had been updated to 6.36 cm.
//!
//! Both GUIs divide the sums by 5 whatever the number of runs (they accept exactly 5), and
//! reset their plotted vectors to `zeros(5)` on every entry. In ANEXO C the button callbacks'
//! comments are exchanged (pushbutton19 sends 2, which the firmware runs as UMBmark CW).

use serde::Serialize;

pub use crate::thesis_gui::{
    gui_display, gui_triangle_line, gui_triangle_turn, gui_umbmark, GuiLine, GuiTriangle,
    GuiUmbmark, DESIGN_WHEELBASE_MM, GUI_SIDE_CM, TRIANGLE_GUI_BASE_MM, TRIANGLE_GUI_HALF_BASE_CM,
    UMBMARK_GUI_BASE_CM, UMBMARK_GUI_HALF_BASE_CM,
};
use crate::triangle::{triangle_correction, TriangleParams};
use crate::types::{Endpoint, Frame, LineRuns, Mode, TriangleRuns, UmbmarkRuns};
use crate::umbmark::{umbmark_correction, UmbmarkParams};

/// GUI parameters for a UMBmark computation with the constants printed in ANEXO C
/// (b = 12.25 cm, b/2 = 6.15 cm, L = 200 cm), data in the GUI frame.
pub fn umbmark_params_as_printed() -> UmbmarkParams {
    UmbmarkParams {
        side_cm: GUI_SIDE_CM,
        wheelbase_mm: UMBMARK_GUI_BASE_CM * 10.0,
        frame: Frame::ThesisGui,
        mode: Mode::ThesisCompat,
        compat_half_wheelbase_mm: Some(UMBMARK_GUI_HALF_BASE_CM * 10.0),
        ..UmbmarkParams::default()
    }
}

/// GUI parameters for the thesis' UMBmark experiment `n` (1-3), with the wheelbase the GUI
/// held at the time (inferred from the values printed in the GUI screenshots):
/// experiment 1: 125 mm (the inner-face wheelbase taken as nominal), experiment 2: 122.3 mm
/// (experiment 1's 12.2323 cm to two decimals), experiment 3: 122.6 mm (experiment 2's
/// 12.26 cm). The same value serves as b in Ba and as 2·(b/2) in Ed.
pub fn umbmark_params_for_experiment(n: u32) -> Option<UmbmarkParams> {
    let wheelbase_mm = match n {
        1 => 125.0,
        2 => 122.3,
        3 => 122.6,
        _ => return None,
    };
    Some(UmbmarkParams {
        side_cm: GUI_SIDE_CM,
        wheelbase_mm,
        frame: Frame::ThesisGui,
        mode: Mode::ThesisCompat,
        ..UmbmarkParams::default()
    })
}

/// GUI parameters for a Triangular Path computation with the constants printed in ANEXO D
/// (b/2 = 6.36 cm in Ed, Ba = Eb·125 mm, L = 200 cm). `wheelbase_mm` is set to the 127.2 mm
/// the 6.36 cm stands for (the wheelbase the robot ran experiment 2 with).
pub fn triangle_params_as_printed() -> TriangleParams {
    TriangleParams {
        side_cm: GUI_SIDE_CM,
        wheelbase_mm: TRIANGLE_GUI_HALF_BASE_CM * 20.0,
        frame: Frame::ThesisGui,
        mode: Mode::ThesisCompat,
        compat_base_mm: Some(TRIANGLE_GUI_BASE_MM),
        ..TriangleParams::default()
    }
}

/// GUI parameters for the thesis' Triangular Path experiment `n` (1-2): experiment 1 with
/// 125 mm; experiment 2 as printed ([`triangle_params_as_printed`]).
pub fn triangle_params_for_experiment(n: u32) -> Option<TriangleParams> {
    match n {
        1 => Some(TriangleParams {
            side_cm: GUI_SIDE_CM,
            wheelbase_mm: 125.0,
            frame: Frame::ThesisGui,
            mode: Mode::ThesisCompat,
            ..TriangleParams::default()
        }),
        2 => Some(triangle_params_as_printed()),
        _ => None,
    }
}

/// One formula where the thesis differs from the published method, evaluated on given data.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Discrepancy {
    /// The thesis' formula, and the correct one.
    pub formula: String,
    /// Value with the thesis' formula.
    pub thesis_value: f64,
    /// Value with the correct formula.
    pub correct_value: f64,
    /// What the difference comes from.
    pub note: String,
}

impl Discrepancy {
    /// thesis − correct.
    pub fn difference(&self) -> f64 {
        self.thesis_value - self.correct_value
    }

    fn new(formula: &str, thesis_value: f64, correct_value: f64, note: String) -> Self {
        Self {
            formula: formula.to_string(),
            thesis_value,
            correct_value,
            note,
        }
    }
}

/// The UMBmark formulas where the GUI (ANEXO C) differs from Borenstein & Feng, evaluated on
/// `runs`. `params` describes the data (frame, L, the wheelbase the robot used) and the GUI's
/// constants (`compat_*`); its `mode` is ignored: both modes are computed.
pub fn umbmark_discrepancies(runs: &UmbmarkRuns, params: &UmbmarkParams) -> Vec<Discrepancy> {
    let gui = umbmark_correction(
        runs,
        &UmbmarkParams {
            mode: Mode::ThesisCompat,
            ..params.clone()
        },
    );
    let ok = umbmark_correction(
        runs,
        &UmbmarkParams {
            mode: Mode::Correct,
            compat_base_mm: None,
            compat_half_wheelbase_mm: None,
            ..params.clone()
        },
    );
    let r_gui = gui.radius_cm.unwrap_or(f64::INFINITY);
    let r_ok = ok.radius_cm.unwrap_or(f64::INFINITY);
    // The unit bug alone: the GUI's own beta, in radians as sin() wants it.
    let r_gui_rad = params.side_cm / (2.0 * (gui.beta_rad / 2.0).sin());
    let base_mm = params.compat_base_mm.unwrap_or(params.wheelbase_mm);
    let half_mm = params
        .compat_half_wheelbase_mm
        .unwrap_or(params.wheelbase_mm / 2.0);

    let mut v = vec![
        Discrepancy::new(
            "alpha: GUI (ȳ_cw − ȳ_ccw)·180/(−4πL) vs Borenstein (x̄_cw + x̄_ccw)/(−4L)·180/π [deg]",
            gui.alpha_deg,
            ok.alpha_x_deg,
            format!(
                "the GUI takes alpha from y; in the declared frame ({:?}) y gives {:.4}°, x gives {:.4}°",
                params.frame, ok.alpha_y_deg, ok.alpha_x_deg
            ),
        ),
        Discrepancy::new(
            "beta: GUI (X̄_cw − X̄_ccw)·180/(−4πL) on the GUI's x vs (x̄_cw − x̄_ccw)/(−4L)·180/π [deg]",
            gui.beta_deg,
            ok.beta_x_deg,
            "same formula; the GUI's x is mirrored against Borenstein's frame, which flips the sign"
                .into(),
        ),
        Discrepancy::new(
            "R = L/(2·sin(β/2)) with β in degrees passed to sin() vs β in radians [cm]",
            r_gui,
            r_gui_rad,
            format!(
                "the unit bug alone (same beta): R too small by ×{:.1}",
                r_gui_rad / r_gui
            ),
        ),
        Discrepancy::new(
            "R: GUI vs Borenstein (L/2)/sin(β/2), all differences together [cm]",
            r_gui,
            r_ok,
            "unit bug and beta's sign".into(),
        ),
        Discrepancy::new(
            "Ed = (R + b/2)/(R − b/2): GUI vs Borenstein",
            gui.ed,
            ok.ed,
            format!(
                "Ed − 1 is {:.1} times the correct value",
                (gui.ed - 1.0) / (ok.ed - 1.0)
            ),
        ),
        Discrepancy::new(
            "Eb = 90/(90 − α): GUI (α from y) vs Borenstein (α from x)",
            gui.eb,
            ok.eb,
            "follows from alpha".into(),
        ),
        Discrepancy::new(
            "wheelbase = Eb·b [mm]: GUI vs Borenstein",
            gui.wheelbase_mm,
            ok.wheelbase_mm,
            format!(
                "GUI constant b = {:.2} cm, robot's b = {:.2} cm",
                base_mm / 10.0,
                params.wheelbase_mm / 10.0
            ),
        ),
        Discrepancy::new(
            "cL = 2/(Ed + 1): GUI vs Borenstein",
            gui.cl,
            ok.cl,
            "follows from Ed".into(),
        ),
        Discrepancy::new(
            "cR = 2/(1/Ed + 1): GUI vs Borenstein",
            gui.cr,
            ok.cr,
            "follows from Ed".into(),
        ),
        Discrepancy::new(
            "Table 10 error: mean(r_cg,cw, r_cg,ccw) vs Borenstein's E_max,syst = max(...) [cm]",
            gui.error_mean_cm,
            gui.e_max_cm,
            "the GUI computes Error_Max but never shows it".into(),
        ),
    ];
    if (2.0 * half_mm - base_mm).abs() > 1e-9 {
        v.push(Discrepancy::new(
            "GUI b/2 constant in Ed vs half its b constant in Ba [mm]",
            half_mm,
            base_mm / 2.0,
            "the two hard-coded wheelbases were edited separately".into(),
        ));
    }
    v
}

/// The Triangular Path formulas where the GUI (ANEXO D) differs from the derivation in
/// [`crate::triangle`], evaluated on the runs. `params.mode` is ignored.
pub fn triangle_discrepancies(
    line_runs: &LineRuns,
    triangle_runs: &TriangleRuns,
    params: &TriangleParams,
) -> Vec<Discrepancy> {
    let gui = triangle_correction(
        line_runs,
        triangle_runs,
        &TriangleParams {
            mode: Mode::ThesisCompat,
            ..params.clone()
        },
    );
    let ok = triangle_correction(
        line_runs,
        triangle_runs,
        &TriangleParams {
            mode: Mode::Correct,
            compat_base_mm: None,
            compat_half_wheelbase_mm: None,
            ..params.clone()
        },
    );
    let base_mm = params.compat_base_mm.unwrap_or(params.wheelbase_mm);
    let half_mm = params
        .compat_half_wheelbase_mm
        .unwrap_or(params.wheelbase_mm / 2.0);
    // Isolate the two turn-formula bugs on the GUI's own x.
    let x_gui = params
        .frame
        .convert(
            Endpoint::new(gui.triangle_centroid.x_cm, 0.0),
            Frame::ThesisGui,
        )
        .x_cm;
    let delta_same_x_deg = (-2.0 * x_gui / (3f64.sqrt() * params.side_cm)).to_degrees();

    let mut v = vec![
        Discrepancy::new(
            "turn error: GUI α_T = −x̄/L·180/π vs δ = −2x̄/(√3·L)·180/π per 120° turn [deg]",
            gui.alpha_deg,
            delta_same_x_deg,
            "the x displacement of a 120° turn error is (√3/2)·L·δ, not L·δ (same x̄ in both)"
                .into(),
        ),
        Discrepancy::new(
            "Eb: GUI 90/(90 − α_T) vs 120/(120 − δ)",
            gui.eb,
            ok.eb,
            format!(
                "90° formula for 120° turns and the missing √3/2: Eb − 1 is {:.3} times the \
                 correct value (first order: 2/√3 = 1.155 when the frames agree)",
                (gui.eb - 1.0) / (ok.eb - 1.0)
            ),
        ),
        Discrepancy::new(
            "wheelbase = Eb·b [mm]: GUI vs derived",
            gui.wheelbase_mm,
            ok.wheelbase_mm,
            format!(
                "GUI constant b = {base_mm:.1} mm, robot's b = {:.1} mm",
                params.wheelbase_mm
            ),
        ),
        Discrepancy::new(
            "Ed: GUI (R − b/2)/(R + b/2) vs (R + b/2)/(R − b/2)",
            gui.ed,
            ok.ed,
            "the GUI's line Ed is the reciprocal of its UMBmark Ed: cL and cR come out exchanged"
                .into(),
        ),
        Discrepancy::new(
            "cL = 2/(Ed + 1): GUI vs derived",
            gui.cl,
            ok.cl,
            "follows from Ed".into(),
        ),
        Discrepancy::new(
            "cR = 2/(1/Ed + 1): GUI vs derived",
            gui.cr,
            ok.cr,
            "follows from Ed".into(),
        ),
    ];
    if (2.0 * half_mm - base_mm).abs() > 1e-9 {
        v.push(Discrepancy::new(
            "GUI b/2 constant in the line's Ed vs half its b constant in Ba [mm]",
            half_mm,
            base_mm / 2.0,
            "6.36 cm was updated after experiment 1; the 125 mm in Ba was not".into(),
        ));
    }
    v
}
