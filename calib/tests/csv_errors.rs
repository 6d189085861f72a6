//! The CSV reader accepts the thesis tables and refuses every malformed input with an error
//! that names the line and what to do; a missing triangle y is accepted only where declared
//! optional, and then reported.

use calib::csv::{
    read_triangle_csv, read_triangle_file, read_umbmark_csv, triangle_experiments,
    umbmark_experiments, CsvOptions,
};
use calib::Error;
use rstest::rstest;

mod common;
use common::{data, data_path};

const U_HEAD: &str = "# comment\nexperiment,direction,run,x_cm,y_cm\n";

/// Five valid rows per direction for experiment 1, after `U_HEAD` (lines 3-12).
fn umbmark_rows() -> String {
    let mut s = String::new();
    for d in ["cw", "ccw"] {
        for run in 1..=5 {
            s.push_str(&format!("1,{d},{run},-1.5,2.5\n"));
        }
    }
    s
}

/// The thesis' UMBmark table parses: three experiments, five runs per direction, values in
/// file order.
#[test]
fn thesis_umbmark_table_parses() {
    let text = data("umbmark_endpoints.csv");
    assert_eq!(umbmark_experiments(&text).unwrap(), vec![1, 2, 3]);
    let r = read_umbmark_csv(&text, 1, &CsvOptions::default()).unwrap();
    assert_eq!(r.cw().len(), 5);
    assert_eq!((r.cw()[0].x_cm, r.cw()[0].y_cm), (-28.6, 30.5));
    assert_eq!((r.ccw()[4].x_cm, r.ccw()[4].y_cm), (-19.1, -0.1));
}

/// The thesis' triangle table: its empty triangle y cells (experiment 2, lines 21-25) are
/// refused by default, whichever experiment is selected, since the whole file is checked;
/// declared optional they are accepted, and reading experiment 2 says so in a note.
#[test]
fn thesis_triangle_table_and_the_missing_y() {
    let text = data("triangular_endpoints.csv");
    assert_eq!(triangle_experiments(&text).unwrap(), vec![1, 2]);
    for n in [1, 2] {
        let err = read_triangle_csv(&text, n, &CsvOptions::default()).unwrap_err();
        assert!(
            matches!(err, Error::MissingValue { line: 21, ref column, .. } if column == "y_cm"),
            "{err}"
        );
        assert!(err.to_string().contains("triangle_y_optional"));
    }
    let opts = CsvOptions {
        triangle_y_optional: true,
        ..CsvOptions::default()
    };
    let one = read_triangle_csv(&text, 1, &opts).unwrap();
    assert!(one.triangle.has_all_y() && one.notes.is_empty());
    let two = read_triangle_file(data_path("triangular_endpoints.csv"), 2, &opts).unwrap();
    assert!(!two.triangle.has_all_y());
    assert_eq!(two.line.runs().len(), 5);
    assert!(
        two.notes[0].contains("lines 21, 22, 23, 24, 25"),
        "{:?}",
        two.notes
    );
}

/// Declaring triangle y optional does not make the line rows' y optional.
#[test]
fn line_y_is_never_optional() {
    let mut text = String::from("experiment,test,run,x_cm,y_cm\n");
    for run in 1..=5 {
        text.push_str(&format!(
            "1,line,{run},1.0,{}\n",
            if run == 3 { "" } else { "1.0" }
        ));
    }
    for run in 1..=5 {
        text.push_str(&format!("1,triangle,{run},1.0,\n"));
    }
    let opts = CsvOptions {
        triangle_y_optional: true,
        ..CsvOptions::default()
    };
    let err = read_triangle_csv(&text, 1, &opts).unwrap_err();
    assert!(matches!(err, Error::MissingValue { line: 4, .. }), "{err}");
}

/// A malformed UMBmark table: each case names its line and the fault.
#[rstest]
#[case::wrong_header("# c\nexp,direction,run,x,y\n", 1, 2, "header")]
#[case::no_header("# only comments\n\n", 1, 3, "no header row")]
#[case::too_few_fields("1,cw,1,-1.5\n", 1, 3, "4 fields, expected 5")]
#[case::too_many_fields("1,cw,1,-1,5,2.5\n", 1, 3, "6 fields")]
#[case::empty_x("1,cw,1,,2.5\n", 1, 3, "`x_cm` is empty")]
#[case::empty_y("1,cw,1,-1.5,\n", 1, 3, "`y_cm` is empty")]
#[case::not_a_number("1,cw,1,abc,2.5\n", 1, 3, "`abc`, which is not a finite number")]
#[case::nan("1,cw,1,NaN,2.5\n", 1, 3, "not a finite number")]
#[case::unknown_direction("1,clockwise,1,-1.5,2.5\n", 1, 3, "unknown direction `clockwise`")]
#[case::bad_run("1,cw,0,-1.5,2.5\n", 1, 3, "`run` is `0`")]
#[case::bad_experiment("x,cw,1,-1.5,2.5\n", 1, 3, "`experiment` is `x`")]
#[case::duplicate_run(
    "1,cw,1,-1.5,2.5\n1,cw,1,-1.5,2.5\n",
    1,
    4,
    "already appeared on line 3"
)]
fn malformed_rows(
    #[case] body: &str,
    #[case] experiment: u32,
    #[case] line: usize,
    #[case] says: &str,
) {
    let text = if body.starts_with('#') {
        body.to_string()
    } else {
        format!("{U_HEAD}{body}{}", umbmark_rows())
    };
    let err = read_umbmark_csv(&text, experiment, &CsvOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(msg.starts_with(&format!("line {line}:")), "{msg}");
    assert!(msg.contains(says), "{msg}");
}

/// Wrong run counts are reported against the selected experiment, at the group's last line.
#[rstest]
#[case::four_ccw_runs(4, "ccw has 4 runs, expected 5", 11)]
#[case::six_cw_runs(6, "cw has 6 runs, expected 5", 8)]
fn wrong_run_counts(#[case] n: usize, #[case] says: &str, #[case] line: usize) {
    let mut text = String::from(U_HEAD);
    let (cw, ccw) = if n < 5 { (5, n) } else { (n, 5) };
    for run in 1..=cw {
        text.push_str(&format!("1,cw,{run},0,0\n"));
    }
    for run in 1..=ccw {
        text.push_str(&format!("1,ccw,{run},0,0\n"));
    }
    let err = read_umbmark_csv(&text, 1, &CsvOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains(says), "{msg}");
    assert!(msg.starts_with(&format!("line {line}:")), "{msg}");
}

/// Told to expect another run count, the reader checks that one instead.
#[test]
fn other_run_counts_when_told() {
    let mut text = String::from(U_HEAD);
    for d in ["cw", "ccw"] {
        for run in 1..=3 {
            text.push_str(&format!("1,{d},{run},0,0\n"));
        }
    }
    let three = CsvOptions {
        runs_per_group: 3,
        ..CsvOptions::default()
    };
    assert_eq!(read_umbmark_csv(&text, 1, &three).unwrap().cw().len(), 3);
    assert!(read_umbmark_csv(&text, 1, &CsvOptions::default()).is_err());
}

/// Selecting an experiment that is not there lists the ones that are.
#[test]
fn unknown_experiment_lists_the_available_ones() {
    let err =
        read_umbmark_csv(&data("umbmark_endpoints.csv"), 7, &CsvOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "experiment 7 has no rows; experiments in the file: 1, 2, 3"
    );
}

/// Unknown test names in the triangle layout are refused with their line.
#[test]
fn unknown_test_name() {
    let text = "experiment,test,run,x_cm,y_cm\n1,square,1,0,0\n";
    let err = read_triangle_csv(text, 1, &CsvOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "line 2: unknown test `square`; use `line` (straight-line runs) or `triangle`"
    );
}

/// Whitespace, CRLF line ends, a byte-order mark and upper-case direction names are
/// tolerated; runs are ordered by run number, not file order.
#[test]
fn tolerated_variations() {
    let mut text = String::from("\u{feff}experiment, direction, run, x_cm, y_cm\r\n");
    for d in ["CCW", "Cw"] {
        for run in (1..=5).rev() {
            text.push_str(&format!(" 1 , {d} , {run} , {run}.0 , -{run} \r\n"));
        }
    }
    let r = read_umbmark_csv(&text, 1, &CsvOptions::default()).unwrap();
    assert_eq!(r.cw()[0].x_cm, 1.0);
    assert_eq!(r.ccw()[4].y_cm, -5.0);
}

/// A missing file is an I/O error naming the path.
#[test]
fn missing_file() {
    let err = read_triangle_file("no/such/file.csv", 1, &CsvOptions::default()).unwrap_err();
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains("no/such/file.csv"));
}
