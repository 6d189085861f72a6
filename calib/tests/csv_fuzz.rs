//! Random UMBmark and Triangular Path tables, absurd cells included (nan, inf, 1e308,
//! empty, words, wrong directions and experiment numbers, rows missing or repeated), either
//! load into end points a correction can be computed from, or are refused with one error
//! line; never a panic, and a loaded table never holds a number beyond what a run can do.

use calib::csv::{read_triangle_csv, read_umbmark_csv, CsvOptions};
use calib::{umbmark_correction, UmbmarkParams};
use proptest::prelude::*;

/// A cell of a number column: ordinary end errors, the edges, and nonsense.
fn number() -> BoxedStrategy<String> {
    prop_oneof![
        4 => (-400.0f64..400.0).prop_map(|v| format!("{v:.1}")),
        1 => prop::sample::select(vec![
            "nan", "inf", "-inf", "1e308", "-1e308", "10000", "10000.1", "", " ", "abc", "1,5",
            "0x10", "-0", "1e-320",
        ])
        .prop_map(str::to_owned),
    ]
    .boxed()
}

/// One row of a table whose groups are `groups`: mostly well-formed, sometimes not.
fn row(groups: &'static [&'static str]) -> BoxedStrategy<String> {
    let experiment = prop_oneof![4 => Just("1".to_owned()), 1 => prop::sample::select(vec!["0", "2", "-1", "x", ""]).prop_map(str::to_owned)];
    let group = prop_oneof![
        6 => prop::sample::select(groups.to_vec()).prop_map(str::to_owned),
        1 => prop::sample::select(vec!["cww", "", "CW", "left"]).prop_map(str::to_owned),
    ];
    let run = prop_oneof![6 => (1u32..=5).prop_map(|r| r.to_string()), 1 => Just("9".to_owned())];
    (experiment, group, run, number(), number())
        .prop_map(|(e, g, r, x, y)| format!("{e},{g},{r},{x},{y}"))
        .boxed()
}

fn table(header: &'static str, groups: &'static [&'static str]) -> BoxedStrategy<String> {
    prop::collection::vec(row(groups), 0..14)
        .prop_map(move |rows| format!("{header}\n{}\n", rows.join("\n")))
        .boxed()
}

/// An error is one line that says something.
fn one_line(e: &impl std::fmt::Display) -> bool {
    let s = e.to_string();
    !s.is_empty() && !s.contains('\n')
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn umbmark_tables_load_or_are_refused(text in table("experiment,direction,run,x_cm,y_cm", &["cw", "ccw"])) {
        match read_umbmark_csv(&text, 1, &CsvOptions::default()) {
            Ok(runs) => {
                for e in runs.cw().iter().chain(runs.ccw()) {
                    prop_assert!(e.x_cm.is_finite() && e.y_cm.is_finite(), "{e:?}");
                    prop_assert!(e.x_cm.abs() <= 10_000.0 && e.y_cm.abs() <= 10_000.0, "{e:?}");
                }
                let r = umbmark_correction(&runs, &UmbmarkParams::default());
                prop_assert!(r.e_max_cm.is_finite());
            }
            Err(e) => prop_assert!(one_line(&e), "{e}"),
        }
    }

    #[test]
    fn triangle_tables_load_or_are_refused(text in table("experiment,test,run,x_cm,y_cm", &["line", "triangle"])) {
        match read_triangle_csv(&text, 1, &CsvOptions::default()) {
            Ok(t) => {
                let s = format!("{t:?}");
                prop_assert!(!s.contains("NaN") && !s.contains("inf"), "{s}");
            }
            Err(e) => prop_assert!(one_line(&e), "{e}"),
        }
    }

    #[test]
    fn complete_tables_with_numbers_load_and_give_a_finite_correction(
        cells in prop::collection::vec((number(), number()), 10),
    ) {
        let rows: Vec<String> = cells
            .iter()
            .enumerate()
            .map(|(i, (x, y))| {
                let dir = if i < 5 { "cw" } else { "ccw" };
                format!("1,{dir},{},{x},{y}", i % 5 + 1)
            })
            .collect();
        let text = format!("experiment,direction,run,x_cm,y_cm\n{}\n", rows.join("\n"));
        let ordinary = |c: &str| c.parse::<f64>().is_ok_and(|v| v.is_finite() && v.abs() <= 400.0);
        let all_ordinary = cells.iter().all(|(x, y)| ordinary(x) && ordinary(y));
        match read_umbmark_csv(&text, 1, &CsvOptions::default()) {
            Ok(runs) => {
                let r = umbmark_correction(&runs, &UmbmarkParams::default());
                prop_assert!(r.e_max_cm.is_finite() && r.cl.is_finite() && r.cr.is_finite());
            }
            Err(e) => {
                prop_assert!(!all_ordinary, "a table of ordinary numbers refused: {e}");
                prop_assert!(one_line(&e), "{e}");
            }
        }
    }
}
