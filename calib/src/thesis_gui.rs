//! The thesis GUI's formulas (MATLAB, ANEXO C and D) as printed, bugs included, on the
//! numbers as the GUI held them: the constants hard-coded in the GUI code and one function
//! per button callback.
//!
//! A leaf below the methods: [`crate::umbmark`] and [`crate::triangle`] call it in
//! [`crate::Mode::ThesisCompat`], and [`crate::thesis`] (which compares the GUI with the
//! methods, so depends on them) re-exports it. What each constant and bug is: [`crate::thesis`].

use serde::Serialize;

use crate::borenstein::correction_factors;
use crate::types::Endpoint;

/// L hard-coded in both GUIs, cm.
pub const GUI_SIDE_CM: f64 = 200.0;
/// ANEXO C as printed: `Base_act=Error_Base*12.25`, cm.
pub const UMBMARK_GUI_BASE_CM: f64 = 12.25;
/// ANEXO C as printed: `(Radio_C+6.15)/(Radio_C-6.15)`, cm.
pub const UMBMARK_GUI_HALF_BASE_CM: f64 = 6.15;
/// ANEXO D as printed: `(Radio_C_L-6.36)/(Radio_C_L+6.36)`, cm.
pub const TRIANGLE_GUI_HALF_BASE_CM: f64 = 6.36;
/// ANEXO D as printed: `Base_Actual_T=Error_base_T*125`, mm.
pub const TRIANGLE_GUI_BASE_MM: f64 = 125.0;
/// The robot's design wheelbase (wheel centre to centre), Table 10's "Ba antes", mm: the
/// crate's default wheelbase, [`crate::HENRYTWO_WHEELBASE_MM`].
pub const DESIGN_WHEELBASE_MM: f64 = crate::HENRYTWO_WHEELBASE_MM;

/// The UMBmark GUI's intermediate values (ANEXO C, `pushbutton15_Callback`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GuiUmbmark {
    /// `Raiz_CW`, cm.
    pub raiz_cw: f64,
    /// `Raiz_CCW`, cm.
    pub raiz_ccw: f64,
    /// `Error_Max`, cm.
    pub error_max: f64,
    /// `alpha = ((Y_Z_prom_CW-Y_Z_prom_CCW)*(180))/(-4*pi*200)`, degrees.
    pub alpha_deg: f64,
    /// `beta = ((X_Z_prom_CW-X_Z_prom_CCW)*(180))/(-4*pi*200)`, degrees.
    pub beta_deg: f64,
    /// `Radio_C = 200/(2*(sin(beta/2)))`: the degrees go into `sin()`, cm.
    pub radio_c_cm: f64,
    /// `Error_Base = 90/(90-alpha)`.
    pub error_base: f64,
    /// `Base_act = Error_Base*12.25`, cm.
    pub base_act_cm: f64,
    /// `Error_Diametro = (Radio_C+6.15)/(Radio_C-6.15)`.
    pub error_diametro: f64,
    /// `cL = 2/(Error_Diametro+1)`.
    pub cl: f64,
    /// `cR = 2/((1/Error_Diametro)+1)`.
    pub cr: f64,
}

/// ANEXO C's computation on the two centroids (GUI frame, cm), with L = `side_cm` (the GUI:
/// 200), b = `base_cm` (printed: 12.25) and b/2 = `half_base_cm` (printed: 6.15).
pub fn gui_umbmark(
    cw: Endpoint,
    ccw: Endpoint,
    side_cm: f64,
    base_cm: f64,
    half_base_cm: f64,
) -> GuiUmbmark {
    use std::f64::consts::PI;
    let raiz_cw = (cw.x_cm.powi(2) + cw.y_cm.powi(2)).sqrt();
    let raiz_ccw = (ccw.x_cm.powi(2) + ccw.y_cm.powi(2)).sqrt();
    let alpha_deg = ((cw.y_cm - ccw.y_cm) * 180.0) / (-4.0 * PI * side_cm);
    let beta_deg = ((cw.x_cm - ccw.x_cm) * 180.0) / (-4.0 * PI * side_cm);
    let radio_c_cm = side_cm / (2.0 * (beta_deg / 2.0).sin());
    let error_base = 90.0 / (90.0 - alpha_deg);
    let base_act_cm = error_base * base_cm;
    let error_diametro = (radio_c_cm + half_base_cm) / (radio_c_cm - half_base_cm);
    let (cl, cr) = correction_factors(error_diametro);
    GuiUmbmark {
        raiz_cw,
        raiz_ccw,
        error_max: raiz_cw.max(raiz_ccw),
        alpha_deg,
        beta_deg,
        radio_c_cm,
        error_base,
        base_act_cm,
        error_diametro,
        cl,
        cr,
    }
}

/// The Triangular Path GUI's line-test values (ANEXO D, `pushbutton7_Callback`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GuiLine {
    /// `Beta_L = (2*Y_Z_prom_L)/200`, radians (correctly: no degree conversion here).
    pub beta_l: f64,
    /// `Radio_C_L = 100/sin(Beta_L/2)`, cm.
    pub radio_c_l_cm: f64,
    /// `Error_Diametro_L = (Radio_C_L-6.36)/(Radio_C_L+6.36)`.
    pub error_diametro_l: f64,
    /// `cL`.
    pub cl: f64,
    /// `cR`.
    pub cr: f64,
}

/// ANEXO D's line computation on the line centroid's y (GUI frame, cm).
pub fn gui_triangle_line(y_mean_cm: f64, side_cm: f64, half_base_cm: f64) -> GuiLine {
    let beta_l = (2.0 * y_mean_cm) / side_cm;
    let radio_c_l_cm = (side_cm / 2.0) / (beta_l / 2.0).sin();
    let error_diametro_l = (radio_c_l_cm - half_base_cm) / (radio_c_l_cm + half_base_cm);
    let (cl, cr) = correction_factors(error_diametro_l);
    GuiLine {
        beta_l,
        radio_c_l_cm,
        error_diametro_l,
        cl,
        cr,
    }
}

/// The Triangular Path GUI's triangle values (ANEXO D, `pushbutton5_Callback`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GuiTriangle {
    /// `alpha_T = (X_Z_prom_T*180)/((-200)*pi)`, degrees.
    pub alpha_t_deg: f64,
    /// `Error_base_T = 90/(90-alpha_T)`.
    pub error_base_t: f64,
    /// `Base_Actual_T = Error_base_T*125`, mm.
    pub base_actual_t_mm: f64,
}

/// ANEXO D's triangle computation on the triangle centroid's x (GUI frame, cm).
pub fn gui_triangle_turn(x_mean_cm: f64, side_cm: f64, base_mm: f64) -> GuiTriangle {
    use std::f64::consts::PI;
    let alpha_t_deg = (x_mean_cm * 180.0) / ((-side_cm) * PI);
    let error_base_t = 90.0 / (90.0 - alpha_t_deg);
    GuiTriangle {
        alpha_t_deg,
        error_base_t,
        base_actual_t_mm: error_base_t * base_mm,
    }
}

/// A number as the GUI showed it: MATLAB's `%g`, 6 significant digits, trailing zeros
/// dropped (`0.983934`, `1.01607`, `12.2323`, `12.26`).
pub fn gui_display(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else if x > 0.0 {
            "Inf".into()
        } else {
            "-Inf".into()
        };
    }
    if x == 0.0 {
        return "0".into();
    }
    // Round to 6 significant digits first, so that the exponent is the rounded one.
    let sci = format!("{x:.5e}");
    let (mantissa, exp) = sci.split_once('e').expect("`{:e}` always has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` exponent is an integer");
    let strip = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if !(-4..6).contains(&exp) {
        let m = strip(mantissa.to_string());
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{m}e{sign}{:02}", exp.abs())
    } else {
        let decimals = (5 - exp).max(0) as usize;
        strip(format!("{x:.decimals$}"))
    }
}
