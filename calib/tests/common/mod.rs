//! Shared helpers for the integration tests: the thesis data vendored in `tests/data/`.
#![allow(dead_code)]

use std::path::PathBuf;

pub mod svg;

use calib::csv::{read_triangle_csv, read_umbmark_csv, CsvOptions, TriangleExperiment};
use calib::UmbmarkRuns;

/// Path of a file in `tests/data/`.
pub fn data_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// Text of a file in `tests/data/`.
pub fn data(name: &str) -> String {
    std::fs::read_to_string(data_path(name)).expect("test data file present")
}

/// UMBmark experiment `n` of the thesis (Tables 5-7).
pub fn thesis_umbmark(n: u32) -> UmbmarkRuns {
    read_umbmark_csv(&data("umbmark_endpoints.csv"), n, &CsvOptions::default())
        .expect("thesis UMBmark table parses")
}

/// Triangular Path experiment `n` of the thesis (Tables 8-9); triangle y declared optional.
pub fn thesis_triangle(n: u32) -> TriangleExperiment {
    let opts = CsvOptions {
        triangle_y_optional: true,
        ..CsvOptions::default()
    };
    read_triangle_csv(&data("triangular_endpoints.csv"), n, &opts)
        .expect("thesis triangle table parses")
}

/// Table 10 as printed: rows of (method, the six numbers).
pub fn table10() -> Vec<(String, [f64; 6])> {
    data("results_table10.csv")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("method"))
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let v: Vec<f64> = f[1..].iter().map(|s| s.parse().unwrap()).collect();
            (f[0].to_string(), [v[0], v[1], v[2], v[3], v[4], v[5]])
        })
        .collect()
}
