//! The thesis' experiments on the emulated robot, as the thesis ran them on
//! the floor: the reduced UMBmark (five runs clockwise and five
//! counter-clockwise around a square of side L) and the Triangular Path (five
//! straight lines, five counter-clockwise triangles), each run from a fresh
//! firmware reset with its own seed ([`crate::runs::experiment`] runs one), end
//! errors measured by the plant as a person with a tape would, then the
//! correction; and calibration rounds that send it to the firmware and run
//! again.
//!
//! Runs are independent, so they run in parallel (rayon) and in any order,
//! and a plan can be split into shards that run on different machines:
//! [`Plan::runs`] fixes every run's index and seed up front, so a merge of
//! shards is exactly what one machine would have produced.
//!
//! - `plan`: what to run (the experiment, leg, seeds, robot,
//!   firmware), every run's spec, and which of them a [`Shard`] runs;
//! - `runs`: running specs in parallel ([`execute`]) and the [`RunSet`] they
//!   make, with its table rows;
//! - `shard`: a shard's file ([`partial_path`]) and the [`merge`] of shards;
//! - `umbmark`: Borenstein's correction from a UMBmark run set ([`report`]),
//!   its table, Markdown and plots;
//! - `triangle`: the Triangular Path's correction ([`triangle_report`]) and plot;
//! - `rounds`: calibration rounds ([`calibrate`]) and the thesis' Table 10
//!   ([`table10`]).

use thiserror::Error;

use crate::bench::BenchError;

mod plan;
mod rounds;
mod runs;
mod shard;
mod triangle;
mod umbmark;

pub use plan::{run_seed, Experiment, Plan, RunSpec, Shard};
pub use rounds::{
    calibrate, table10, Calibration, CalibrationRound, RoundOptions, RoundReport, Stop,
};
pub use runs::{execute, IndexedRun, RunRow, RunSet};
pub use shard::{merge, merge_named, partial_path};
pub use triangle::{
    triangle_report, write_triangle_outputs, write_triangle_set, TriangleReport, TRIANGLE_FILES,
};
pub use umbmark::{report, write_outputs, write_set, Report, UMBMARK_FILES};

/// Why an experiment could not be planned, run, merged or computed.
#[derive(Debug, Error)]
pub enum ExperimentError {
    #[error(transparent)]
    Bench(#[from] BenchError),
    #[error("shard {0}: give it as K/N with 1 <= K <= N, e.g. 2/4")]
    BadShard(String),
    #[error("partial results do not belong together: {0}")]
    Mismatch(String),
    #[error("run {index} is in {first} and in {second} with different results: merge one copy of each shard")]
    Conflict {
        index: usize,
        first: String,
        second: String,
    },
    #[error("runs {missing:?} are missing: merge the partial results of every shard")]
    Missing { missing: Vec<usize> },
    #[error("calibration: {0}")]
    Calib(#[from] calib::Error),
}
