//! Mode::ThesisCompat reproduces, from the thesis' own endpoint tables, the values its GUI
//! screenshots print (where legible) and Table 10 to the printed precision; the tests also
//! pin down the values that could not be reproduced, and what the correct formulas and the
//! frame check say about the same data.

use approx::assert_relative_eq;
use calib::round::{
    format_table10, thesis_improvement, thesis_triangle_improvement, truncate, TableStyle,
};
use calib::thesis::{
    gui_display, triangle_discrepancies, triangle_params_for_experiment, umbmark_discrepancies,
    umbmark_params_as_printed, umbmark_params_for_experiment, DESIGN_WHEELBASE_MM,
};
use calib::{
    triangle_correction, umbmark_correction, Frame, PartialEndpoint, TriangleRuns, UmbmarkParams,
    UmbmarkResult,
};

mod common;
use common::{table10, thesis_triangle, thesis_umbmark};

fn compat(n: u32) -> UmbmarkResult {
    umbmark_correction(
        &thesis_umbmark(n),
        &umbmark_params_for_experiment(n).unwrap(),
    )
}

/// Figure 43 (experiment 1, GUI loaded with b = 12.5 cm): cL 0.983934, cR 1.01607,
/// Ba 12.2323 cm. (The transcription reads "0.953934" and "1.01807": 8→5 and 6→8 misreads;
/// cL + cR must be 2.)
#[test]
fn figure_43_experiment_1() {
    let r = compat(1);
    assert_eq!(gui_display(r.cl), "0.983934");
    assert_eq!(gui_display(r.cr), "1.01607");
    assert_eq!(gui_display(r.wheelbase_mm / 10.0), "12.2323");
}

/// Figure 44 (experiment 2, GUI loaded with 12.23 cm, experiment 1's result): Ba 12.26 is
/// reproduced. Its cL 1.01102 is not: we get 1.01106 (cR 0.988937, printed illegibly as
/// "0.58888"); no wheelbase constant near 12.2 cm gives 1.01102 except b ≈ 12.18 cm, and a
/// 0.1 cm difference in one typed x value would explain it.
#[test]
fn figure_44_experiment_2() {
    let r = compat(2);
    assert_eq!(gui_display(r.wheelbase_mm / 10.0), "12.26");
    assert_eq!(gui_display(r.cl), "1.01106");
    assert_eq!(gui_display(r.cr), "0.988937");
    assert!((r.cl - 1.01102).abs() < 5e-5);
}

/// Figure 45 (experiment 3, GUI loaded with 12.26 cm, experiment 2's result): cL 1.01023.
/// Its wheelbase, 12.2335 cm, is Table 10's 122.3 mm.
#[test]
fn figure_45_experiment_3() {
    let r = compat(3);
    assert_eq!(gui_display(r.cl), "1.01023");
    assert_eq!(truncate(r.wheelbase_mm, 1), 122.3);
}

/// The constants printed in ANEXO C (b = 12.25 cm, b/2 = 6.15 cm) reproduce none of the
/// screenshots: the printed code is a later state of the GUI than any experiment.
#[test]
fn printed_code_constants_are_a_later_state() {
    let p = umbmark_params_as_printed();
    let r1 = umbmark_correction(&thesis_umbmark(1), &p);
    let r3 = umbmark_correction(&thesis_umbmark(3), &p);
    assert_ne!(gui_display(r1.wheelbase_mm / 10.0), "12.2323");
    assert_eq!(gui_display(r1.wheelbase_mm / 10.0), "11.9877");
    assert_eq!(gui_display(r3.cl), "1.01026");
}

fn table_row(method: &str) -> [f64; 6] {
    table10()
        .into_iter()
        .find(|(m, _)| m == method)
        .expect("row present")
        .1
}

/// Table 10, UMBmark row, from experiments 1 and 3 computed the GUI's way and combined the
/// thesis' way: 130 | 122.3 | 5.69 % | 33.77 | 15.84 | 53.09 %.
#[test]
fn table_10_umbmark_row() {
    let round = thesis_improvement(DESIGN_WHEELBASE_MM, &compat(1), &compat(3));
    let printed = table_row("umbmark_reduced");
    let got = [
        truncate(round.wheelbase_before_mm, 1),
        truncate(round.wheelbase_after_mm, 1),
        (round.wheelbase_correction_pct * 100.0).round() / 100.0,
        truncate(round.error_before_cm, 2),
        truncate(round.error_after_cm, 2),
        (round.position_correction_pct * 100.0).round() / 100.0,
    ];
    for (g, p) in got.iter().zip(printed) {
        assert_relative_eq!(*g, p, epsilon = 1e-9);
    }
    // The error is the mean of the two r_cg, not Borenstein's E_max,syst.
    assert_relative_eq!(round.error_before_cm, 33.7738, epsilon = 1e-4);
    assert!((compat(1).e_max_cm - 45.04).abs() < 0.01);
    // 5.69 % comes from the wheelbase loaded for experiment 3 (122.6 mm), not from the
    // "after" column: (130 - 122.3)/130 would be 5.92 %.
    assert_relative_eq!(
        round.wheelbase_correction_pct,
        100.0 * (130.0 - 122.6) / 130.0,
        epsilon = 1e-9
    );
    // The conclusions' "17.93 cm corrected".
    assert_eq!(
        ((round.error_before_cm - round.error_after_cm) * 100.0).round() / 100.0,
        17.93
    );
}

/// Table 10, Triangular row: 2.15 % (from the 127.2 mm loaded for experiment 2, the GUI's
/// 6.36 cm = b/2) and 13.38 cm (experiment 1's triangle centroid, 13.3875, truncated) are
/// reproduced. Experiment 2's triangle y values are lost, so the "after" error is unknown
/// and the round refuses to invent it.
#[test]
fn table_10_triangle_row_from_the_data() {
    let printed = table_row("triangular_reduced");
    let e1 = thesis_triangle(1);
    let e2 = thesis_triangle(2);
    let r1 = triangle_correction(
        &e1.line,
        &e1.triangle,
        &triangle_params_for_experiment(1).unwrap(),
    );
    let r2 = triangle_correction(
        &e2.line,
        &e2.triangle,
        &triangle_params_for_experiment(2).unwrap(),
    );
    assert!(thesis_triangle_improvement(DESIGN_WHEELBASE_MM, &r1, &r2).is_err());
    assert_relative_eq!(
        100.0 * (DESIGN_WHEELBASE_MM - r2.wheelbase_nominal_mm) / DESIGN_WHEELBASE_MM,
        2.1538,
        epsilon = 1e-4
    );
    assert_eq!(truncate(r1.triangle_r_cm.unwrap(), 2), printed[3]);
    // Rounded, it would read 13.39: the table truncates.
    assert_eq!((r1.triangle_r_cm.unwrap() * 100.0).round() / 100.0, 13.39);
    // The GUI's wheelbase after experiment 1 is 127.27 mm.
    assert_eq!(gui_display(r1.wheelbase_mm), "127.269");
}

/// With experiment 2's mean triangle y taken as 1.70 cm (the value both printed figures
/// imply), the whole Triangular row follows but the "after" wheelbase: 2.71 cm and 79.70 %
/// are reproduced; 127.6 mm is not (the printed GUI code gives 125.85 mm, experiment 1 gave
/// 127.27 mm).
#[test]
fn table_10_triangle_row_with_the_implied_y() {
    let printed = table_row("triangular_reduced");
    let e1 = thesis_triangle(1);
    let e2 = thesis_triangle(2);
    let filled = TriangleRuns::new(
        e2.triangle
            .runs()
            .iter()
            .map(|p| PartialEndpoint::new(p.x_cm, Some(1.70)))
            .collect(),
    )
    .unwrap();
    let r1 = triangle_correction(
        &e1.line,
        &e1.triangle,
        &triangle_params_for_experiment(1).unwrap(),
    );
    let r2 = triangle_correction(
        &e2.line,
        &filled,
        &triangle_params_for_experiment(2).unwrap(),
    );
    let round = thesis_triangle_improvement(DESIGN_WHEELBASE_MM, &r1, &r2).unwrap();
    assert_eq!(truncate(round.wheelbase_before_mm, 1), printed[0]);
    assert_eq!(
        (round.wheelbase_correction_pct * 100.0).round() / 100.0,
        printed[2]
    );
    assert_eq!(truncate(round.error_before_cm, 2), printed[3]);
    assert_eq!(truncate(round.error_after_cm, 2), printed[4]);
    assert_eq!(
        (round.position_correction_pct * 100.0).round() / 100.0,
        printed[5]
    );
    assert_ne!(truncate(round.wheelbase_after_mm, 1), printed[1]);
    assert_eq!(gui_display(round.wheelbase_after_mm), "125.849");
}

/// Which mean y of experiment 2's triangle is compatible with both 2.71 cm (truncated) and
/// 79.70 % (rounded)? Only a narrow band around 1.70 cm.
#[test]
fn implied_triangle_y_of_experiment_2() {
    let x = -2.12_f64; // mean of the five x values
    let before = 13.387516573285726_f64;
    let ok: Vec<f64> = (1500..1900)
        .map(|i| f64::from(i) / 1000.0)
        .filter(|y| {
            let r = x.hypot(*y);
            truncate(r, 2) == 2.71 && ((before - r) / before * 10000.0).round() / 100.0 == 79.70
        })
        .collect();
    assert!(!ok.is_empty());
    assert!(ok.iter().all(|y| (1.699..=1.702).contains(y)), "{ok:?}");
}

/// Table 10 as text, the thesis' way (lengths truncated, percentages rounded), with the
/// triangle's lost y taken as 1.70 cm.
#[test]
fn table_10_text() {
    let e1 = thesis_triangle(1);
    let e2 = thesis_triangle(2);
    let filled = TriangleRuns::new(
        e2.triangle
            .runs()
            .iter()
            .map(|p| PartialEndpoint::new(p.x_cm, Some(1.70)))
            .collect(),
    )
    .unwrap();
    let r1 = triangle_correction(
        &e1.line,
        &e1.triangle,
        &triangle_params_for_experiment(1).unwrap(),
    );
    let r2 = triangle_correction(
        &e2.line,
        &filled,
        &triangle_params_for_experiment(2).unwrap(),
    );
    let rows = [
        (
            "UMBMARK",
            thesis_improvement(DESIGN_WHEELBASE_MM, &compat(1), &compat(3)),
        ),
        (
            "TRIANGULAR",
            thesis_triangle_improvement(DESIGN_WHEELBASE_MM, &r1, &r2).unwrap(),
        ),
    ];
    insta::assert_snapshot!(format_table10(&rows, TableStyle::Thesis));
}

/// The discrepancy list on experiment 1 names the degrees-in-sin() bug (R too small by
/// ≈ 57), the sign of β from the GUI's mirrored x, α from y, and the mean-vs-max error.
#[test]
fn discrepancies_of_experiment_1() {
    let d = umbmark_discrepancies(
        &thesis_umbmark(1),
        &umbmark_params_for_experiment(1).unwrap(),
    );
    let find = |s: &str| d.iter().find(|x| x.formula.contains(s)).expect(s);
    let sin = find("degrees passed to sin()");
    assert_relative_eq!(sin.correct_value / sin.thesis_value, 56.65, epsilon = 0.05);
    let beta = find("beta:");
    assert_relative_eq!(beta.thesis_value, -beta.correct_value, epsilon = 1e-12);
    assert_relative_eq!(beta.thesis_value, 0.519959, epsilon = 1e-6);
    let alpha = find("alpha:");
    assert_relative_eq!(alpha.thesis_value, -1.969542, epsilon = 1e-6);
    assert_relative_eq!(alpha.correct_value, -3.568095, epsilon = 1e-6);
    let err = find("Table 10 error");
    assert!(err.correct_value > err.thesis_value);
    assert!(d.iter().all(|x| x.thesis_value != x.correct_value));
}

/// The frame check on the thesis' UMBmark experiment 1: declared in our default frame, its
/// x- and y-based estimates disagree in sign for both α and β, and a mirrored x axis is
/// named as an explanation; declared in the GUI frame (x mirrored) the signs agree, though
/// the magnitudes still differ by more than the tolerance. Experiments 2 and 3 favour
/// neither frame.
#[test]
fn frame_check_on_thesis_umbmark() {
    let r = umbmark_correction(&thesis_umbmark(1), &UmbmarkParams::default());
    assert!(r.alpha_x_deg * r.alpha_y_deg < 0.0 && r.beta_x_deg * r.beta_y_deg < 0.0);
    assert!(r.agreement.explained_by.iter().any(|s| s == "x mirrored"));
    let g = umbmark_correction(
        &thesis_umbmark(1),
        &UmbmarkParams {
            frame: Frame::ThesisGui,
            ..UmbmarkParams::default()
        },
    );
    assert!(g.alpha_x_deg * g.alpha_y_deg > 0.0 && g.beta_x_deg * g.beta_y_deg > 0.0);
    assert!(!g.agreement.consistent && g.agreement.explained_by.is_empty());
    for n in [2, 3] {
        for frame in [Frame::Default, Frame::ThesisGui] {
            let r = umbmark_correction(
                &thesis_umbmark(n),
                &UmbmarkParams {
                    frame,
                    ..UmbmarkParams::default()
                },
            );
            assert!(
                r.agreement.explained_by.is_empty(),
                "experiment {n} {frame:?}"
            );
        }
    }
}

/// The thesis' triangle data, by contrast, fit our default frame: x and y give turn errors
/// within 0.5° of each other there, and 4.2° apart with x mirrored.
#[test]
fn frame_check_on_thesis_triangle() {
    let e1 = thesis_triangle(1);
    let default = triangle_correction(&e1.line, &e1.triangle, &Default::default());
    let a = default.agreement.unwrap();
    assert!(a.consistent && a.alpha_diff_deg.abs() < 0.5);
    let gui = triangle_correction(
        &e1.line,
        &e1.triangle,
        &calib::TriangleParams {
            frame: Frame::ThesisGui,
            ..Default::default()
        },
    );
    let a = gui.agreement.unwrap();
    assert!(!a.consistent && a.alpha_diff_deg.abs() > 4.0);
    assert!(a.explained_by.iter().any(|s| s == "x mirrored"));
}

/// Like the GUI, compat mode has no answer for β = 0 (it divides by sin(0)): Ed is NaN and a
/// warning says why, where Mode::Correct gives exactly 1.
#[test]
fn compat_mode_fails_like_the_gui_on_straight_legs() {
    let zeros = calib::UmbmarkRuns::new(
        vec![calib::Endpoint::new(0.0, 0.0); 5],
        vec![calib::Endpoint::new(0.0, 0.0); 5],
    )
    .unwrap();
    let r = umbmark_correction(&zeros, &umbmark_params_for_experiment(1).unwrap());
    assert!(r.ed.is_nan());
    assert!(r.warnings.iter().any(|w| w.contains("sin(0)")));
    let ok = umbmark_correction(&zeros, &UmbmarkParams::default());
    assert_eq!(ok.ed, 1.0);
}

/// The Triangular Path's discrepancy list: the GUI's turn error −x̄/L against the derived
/// δ = −2x̄/(√3·L) on the same x̄ (the two differ by 2/√3, sign included), each entry's
/// difference its thesis value less its correct one, and the GUI's two hard-coded
/// wheelbases named only where they disagree: experiment 2 (b/2 = 63.6 mm in Ed against
/// 125 mm in Ba), not experiment 1 (125 mm in both).
#[test]
fn discrepancies_of_the_triangle_experiments() {
    let d: Vec<_> = [1, 2]
        .map(|n| {
            let e = thesis_triangle(n);
            triangle_discrepancies(
                &e.line,
                &e.triangle,
                &triangle_params_for_experiment(n).unwrap(),
            )
        })
        .into();
    for list in &d {
        let turn = list
            .iter()
            .find(|x| x.formula.starts_with("turn error: GUI"))
            .expect("the turn formula");
        assert_relative_eq!(
            turn.correct_value / turn.thesis_value,
            2.0 / 3f64.sqrt(),
            epsilon = 1e-12
        );
        for x in list {
            assert_eq!(x.difference(), x.thesis_value - x.correct_value, "{x:?}");
        }
    }
    let constants = |list: &[calib::thesis::Discrepancy]| {
        list.iter()
            .find(|x| x.formula.starts_with("GUI b/2 constant"))
            .map(|x| (x.thesis_value, x.correct_value))
    };
    assert_eq!(constants(&d[0]), None);
    let (half, base_half) = constants(&d[1]).expect("experiment 2's constants disagree");
    assert_relative_eq!(half, 63.6, epsilon = 1e-9);
    assert_relative_eq!(base_half, 62.5, epsilon = 1e-9);
}

/// The UMBmark GUI's `Raiz_CW` and `Raiz_CCW` are the centroids' distances from the start
/// and `Error_Max` the larger: 5 and 10 cm for centroids at (3, 4) and (−6, 8).
#[test]
fn the_gui_umbmark_error_is_the_larger_centroid_distance() {
    let g = calib::thesis::gui_umbmark(
        calib::Endpoint::new(3.0, 4.0),
        calib::Endpoint::new(-6.0, 8.0),
        200.0,
        12.5,
        6.25,
    );
    assert_eq!((g.raiz_cw, g.raiz_ccw, g.error_max), (5.0, 10.0, 10.0));
}

/// In the correct mode the GUI's constants are not used, and either one given alone is
/// reported as ignored, by UMBmark and by the Triangular Path.
#[test]
fn compat_constants_are_reported_ignored_in_the_correct_mode() {
    let ignored = |base: Option<f64>, half: Option<f64>| {
        umbmark_correction(
            &thesis_umbmark(1),
            &UmbmarkParams {
                compat_base_mm: base,
                compat_half_wheelbase_mm: half,
                ..UmbmarkParams::default()
            },
        )
        .warnings
        .iter()
        .any(|w| w.contains("compat_* parameters are ignored"))
    };
    let triangle_ignored = |base: Option<f64>, half: Option<f64>| {
        let e = thesis_triangle(1);
        triangle_correction(
            &e.line,
            &e.triangle,
            &calib::TriangleParams {
                compat_base_mm: base,
                compat_half_wheelbase_mm: half,
                ..calib::TriangleParams::default()
            },
        )
        .warnings
        .iter()
        .any(|w| w.contains("compat_* parameters are ignored"))
    };
    for ignored in [&ignored as &dyn Fn(_, _) -> bool, &triangle_ignored] {
        assert!(!ignored(None, None));
        assert!(ignored(Some(125.0), None));
        assert!(ignored(None, Some(61.5)));
        assert!(ignored(Some(125.0), Some(61.5)));
    }
}

/// `%g` leaves fixed notation below 1e-4 and from 1e6, with a signed two-digit exponent:
/// 0.0000123456 is `1.23456e-05`, 1234567 is `1.23457e+06`, 0.0001 stays `0.0001`.
#[test]
fn gui_display_is_matlab_g_with_a_signed_exponent() {
    assert_eq!(gui_display(0.0000123456), "1.23456e-05");
    assert_eq!(gui_display(1234567.0), "1.23457e+06");
    assert_eq!(gui_display(0.0001), "0.0001");
    assert_eq!(gui_display(-2.5e-7), "-2.5e-07");
}

/// UMBmark's discrepancy list names the GUI's two wheelbase constants only where they
/// disagree: with neither given both are the robot's (125 mm, b/2 62.5 mm), nothing to
/// name; with b/2 = 61.5 mm against b = 125 mm, the pair (61.5, 62.5).
#[test]
fn umbmark_discrepancies_name_the_gui_constants_only_where_they_disagree() {
    let constants = |base: Option<f64>, half: Option<f64>| {
        let params = UmbmarkParams {
            wheelbase_mm: 125.0,
            compat_base_mm: base,
            compat_half_wheelbase_mm: half,
            ..umbmark_params_for_experiment(1).unwrap()
        };
        umbmark_discrepancies(&thesis_umbmark(1), &params)
            .into_iter()
            .find(|x| x.formula.starts_with("GUI b/2 constant"))
            .map(|x| (x.thesis_value, x.correct_value))
    };
    assert_eq!(constants(None, None), None);
    assert_eq!(constants(Some(125.0), Some(61.5)), Some((61.5, 62.5)));
}
