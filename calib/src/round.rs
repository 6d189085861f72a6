//! One calibration round (before → after) in the layout of the thesis' Table 10.
//!
//! # How the thesis computed Table 10
//!
//! | column | UMBmark row | Triangular row |
//! |---|---|---|
//! | Ba antes (mm) | 130: the design wheelbase (wheel centre to centre), although the tests took 125 mm as nominal | 130, idem |
//! | Ba después (mm) | 122.3 = experiment 3's GUI wheelbase 12.2335 cm (GUI loaded with 12.26 cm) | 127.6: not reproduced (experiment 1's GUI result is 127.27 mm; experiment 2's is 125.85 mm with the printed 125 mm constant) |
//! | Corrección Ba | 5.69 % = (130 − 122.6)/130: 122.6 mm is the wheelbase *loaded* for the last run (experiment 2's result), not the "después" column | 2.15 % = (130 − 127.2)/130: 127.2 mm is the wheelbase loaded for experiment 2 (the GUI's 6.36 cm = b/2) |
//! | Error antes (cm) | 33.77 = mean of r_cg,cw and r_cg,ccw of experiment 1 (33.7738) | 13.38 = distance of experiment 1's triangle centroid (13.3875, truncated, not rounded) |
//! | Error después (cm) | 15.84 = the same for experiment 3 (15.8435) | 2.71: experiment 2's triangle y values are lost; 2.71 and 79.70 % both follow if their mean is ≈ 1.70 cm (r = 2.7174) |
//! | Corrección posición | 53.09 % = (33.7738 − 15.8435)/33.7738 | 79.70 % = (13.3875 − 2.7174)/13.3875, from the unrounded values |
//!
//! [`thesis_improvement`] and [`thesis_triangle_improvement`] apply these rules;
//! [`improvement`] and [`triangle_improvement`] give the straightforward round.
//! [`TableStyle::Thesis`] truncates lengths to the printed digits and rounds percentages, as
//! the thesis' table does.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::triangle::TriangleResult;
use crate::umbmark::UmbmarkResult;
use crate::Error;

/// One row of Table 10 (field names as in `results_table10.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Round {
    /// Wheelbase before the round, mm.
    pub wheelbase_before_mm: f64,
    /// Wheelbase after the round, mm.
    pub wheelbase_after_mm: f64,
    /// Size of the wheelbase correction relative to before, %.
    pub wheelbase_correction_pct: f64,
    /// End-position error before, cm.
    pub error_before_cm: f64,
    /// End-position error after, cm.
    pub error_after_cm: f64,
    /// Reduction of the end-position error, % of before.
    pub position_correction_pct: f64,
}

fn pct_change(before: f64, after: f64) -> f64 {
    100.0 * (before - after).abs() / before
}

fn pct_reduction(before: f64, after: f64) -> f64 {
    100.0 * (before - after) / before
}

/// A UMBmark round: `before` is the first experiment (run with the nominal wheelbase),
/// `after` the experiment run after applying the corrections.
///
/// * wheelbase before = the wheelbase `before` was run with; after = `after`'s estimate;
///   correction = |before − after|/before.
/// * error = (r_cg,cw + r_cg,ccw)/2 (Table 10's measure; E_max,syst is in each result);
///   position correction = (before − after)/before.
pub fn improvement(before: &UmbmarkResult, after: &UmbmarkResult) -> Round {
    Round {
        wheelbase_before_mm: before.wheelbase_nominal_mm,
        wheelbase_after_mm: after.wheelbase_mm,
        wheelbase_correction_pct: pct_change(before.wheelbase_nominal_mm, after.wheelbase_mm),
        error_before_cm: before.error_mean_cm,
        error_after_cm: after.error_mean_cm,
        position_correction_pct: pct_reduction(before.error_mean_cm, after.error_mean_cm),
    }
}

fn triangle_error(r: &TriangleResult, which: &str) -> Result<f64, Error> {
    r.triangle_r_cm.ok_or_else(|| {
        Error::MissingData(format!(
            "the {which} experiment's triangle runs lack y values, so its end error is unknown"
        ))
    })
}

/// A Triangular Path round; the error is the distance of the triangle runs' centroid.
/// Fails when a triangle centroid's y is unknown.
pub fn triangle_improvement(
    before: &TriangleResult,
    after: &TriangleResult,
) -> Result<Round, Error> {
    let eb = triangle_error(before, "before")?;
    let ea = triangle_error(after, "after")?;
    Ok(Round {
        wheelbase_before_mm: before.wheelbase_nominal_mm,
        wheelbase_after_mm: after.wheelbase_mm,
        wheelbase_correction_pct: pct_change(before.wheelbase_nominal_mm, after.wheelbase_mm),
        error_before_cm: eb,
        error_after_cm: ea,
        position_correction_pct: pct_reduction(eb, ea),
    })
}

/// The UMBmark row of Table 10 computed the thesis' way (see the module docs): the design
/// wheelbase as "before", `after`'s estimate as "after", and the correction percentage from
/// the wheelbase *loaded* for the `after` runs.
pub fn thesis_improvement(
    design_wheelbase_mm: f64,
    before: &UmbmarkResult,
    after: &UmbmarkResult,
) -> Round {
    Round {
        wheelbase_before_mm: design_wheelbase_mm,
        wheelbase_after_mm: after.wheelbase_mm,
        wheelbase_correction_pct: pct_reduction(design_wheelbase_mm, after.wheelbase_nominal_mm),
        error_before_cm: before.error_mean_cm,
        error_after_cm: after.error_mean_cm,
        position_correction_pct: pct_reduction(before.error_mean_cm, after.error_mean_cm),
    }
}

/// The Triangular row of Table 10 computed the thesis' way. Fails when a triangle centroid's
/// y is unknown (as for the thesis' own experiment 2).
pub fn thesis_triangle_improvement(
    design_wheelbase_mm: f64,
    before: &TriangleResult,
    after: &TriangleResult,
) -> Result<Round, Error> {
    let eb = triangle_error(before, "before")?;
    let ea = triangle_error(after, "after")?;
    Ok(Round {
        wheelbase_before_mm: design_wheelbase_mm,
        wheelbase_after_mm: after.wheelbase_mm,
        wheelbase_correction_pct: pct_reduction(design_wheelbase_mm, after.wheelbase_nominal_mm),
        error_before_cm: eb,
        error_after_cm: ea,
        position_correction_pct: pct_reduction(eb, ea),
    })
}

/// How [`format_table10`] writes numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TableStyle {
    /// Everything rounded to the printed digits (mm: 1, cm and %: 2).
    #[default]
    Rounded,
    /// As the thesis: lengths truncated to the printed digits (they were copied from the GUI),
    /// percentages rounded.
    Thesis,
}

/// `x` to `digits` decimals, truncated toward zero (robust to values like 2.71 stored as
/// 2.7099999…).
pub fn truncate(x: f64, digits: u32) -> f64 {
    let k = 10f64.powi(digits as i32);
    let scaled = x * k;
    let nearest = scaled.round();
    let t = if (scaled - nearest).abs() < 1e-9 {
        nearest
    } else {
        scaled.trunc()
    };
    t / k
}

fn fmt_len(x: f64, digits: u32, style: TableStyle) -> String {
    let v = match style {
        TableStyle::Rounded => x,
        TableStyle::Thesis => truncate(x, digits),
    };
    format!("{v:.*}", digits as usize)
}

/// Table 10 as text: one row per `(method, round)`.
pub fn format_table10(rows: &[(&str, Round)], style: TableStyle) -> String {
    let headers = [
        "method",
        "Ba before (mm)",
        "Ba after (mm)",
        "Ba correction",
        "error before (cm)",
        "error after (cm)",
        "position correction",
    ];
    let body: Vec<[String; 7]> = rows
        .iter()
        .map(|(m, r)| {
            [
                m.to_string(),
                fmt_len(r.wheelbase_before_mm, 1, style),
                fmt_len(r.wheelbase_after_mm, 1, style),
                format!("{:.2} %", r.wheelbase_correction_pct),
                fmt_len(r.error_before_cm, 2, style),
                fmt_len(r.error_after_cm, 2, style),
                format!("{:.2} %", r.position_correction_pct),
            ]
        })
        .collect();
    let mut widths = headers.map(str::len);
    for row in &body {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    let line = |out: &mut String, cells: &[String]| {
        let mut s = String::new();
        for (i, (c, w)) in cells.iter().zip(widths).enumerate() {
            if i == 0 {
                let _ = write!(s, "{c:<w$}");
            } else {
                let _ = write!(s, " | {c:>w$}");
            }
        }
        out.push_str(s.trim_end());
        out.push('\n');
    };
    line(&mut out, &headers.map(String::from));
    let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
    out.push_str(&rule.join("-|-"));
    out.push('\n');
    for row in &body {
        line(&mut out, row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wheelbase correction is the size of the change in % of the wheelbase before,
    /// whichever way it went: 130 → 122.6 mm and 130 → 137.4 mm are both 5.69 %.
    #[test]
    fn a_correction_is_the_size_of_the_change_in_percent_of_before() {
        for after in [122.6, 137.4] {
            let pct = pct_change(130.0, after);
            assert!((pct - 740.0 / 130.0).abs() < 1e-9, "{after}: {pct}");
        }
    }

    /// Truncation toward zero keeps a value whose decimal digits f64 cannot hold exactly
    /// (0.29 · 100 = 28.999999999999996): the printed 0.29, not 0.28.
    #[test]
    fn truncation_keeps_the_digits_a_value_was_written_with() {
        assert_eq!(truncate(0.29, 2), 0.29);
        assert_eq!(truncate(3.456, 2), 3.45);
        assert_eq!(truncate(-3.456, 2), -3.45);
    }
}
