//! The options of the bench-backed diagnosis: its candidates, its searches' resolution, the
//! runs each centroid is predicted from, and its joint fits.

use gap::fit::FitOptions;
use serde::{Deserialize, Serialize};

/// Runs each centroid is predicted from, each from its own start phase
/// ([`super::super::start_phase_s`]): their mean is smooth in the effects' values where one run's
/// end jumps with the firmware's discrete decisions, and their spread says how well the
/// mean is known.
pub const CENTROID_RUNS: usize = 3;

/// Options of [`diagnose_bench`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SelectOptions {
    /// How many of the kinematic diagnosis' best single effects the bench fits (besides
    /// every effect the kinematic model cannot represent); 7, the default, is all of them,
    /// so that every effect of the library is a candidate: the kinematic ranking is
    /// unreliable exactly where the bench is needed (it takes the nominal firmware's turn
    /// overshoot for an effect). A smaller number trades candidates for time.
    pub shortlist: usize,
    /// Points of the grid over each effect's range (the neutral value is added).
    pub grid: usize,
    /// Golden-section steps of the fit on all training groups.
    pub refine: usize,
    /// Golden-section steps of each cross-validation fold's fit.
    pub fold_refine: usize,
    /// Weights and seeds of the scoring (as the kinematic diagnosis').
    pub fit: FitOptions,
    /// Score the training groups' telemetry too, when they have it (see the module docs).
    pub series: bool,
    /// Most effects the chosen model may hold: 1 fits single effects only; 2 adds the
    /// joint fits of pairs, 3 a third effect on the best pair (see `select/joint.rs`).
    #[serde(default = "three")]
    pub max_effects: usize,
    /// Pairs fitted jointly at most.
    #[serde(default = "four")]
    pub joint_pairs: usize,
    /// Levenberg-Marquardt iterations of a joint fit on all training groups, and of each
    /// cross-validation fold's refit from it.
    #[serde(default = "six")]
    pub joint_iterations: usize,
    #[serde(default = "two")]
    pub joint_fold_iterations: usize,
    /// Regression steps that end a joint fit of three effects (see `select/regression.rs`).
    #[serde(default = "five")]
    pub joint_regression_steps: usize,
}

fn two() -> usize {
    2
}
fn three() -> usize {
    3
}
fn four() -> usize {
    4
}
fn five() -> usize {
    5
}
fn six() -> usize {
    6
}

/// The default search's grid points and golden-section steps ([`SelectOptions::grid`], `refine`).
pub const GRID_POINTS: usize = 7;
pub const REFINE_STEPS: usize = 8;

impl Default for SelectOptions {
    fn default() -> Self {
        SelectOptions {
            shortlist: 7,
            grid: GRID_POINTS,
            refine: REFINE_STEPS,
            fold_refine: 2,
            fit: FitOptions {
                centroid_runs: CENTROID_RUNS,
                ..FitOptions::default()
            },
            series: true,
            max_effects: three(),
            joint_pairs: four(),
            joint_iterations: six(),
            joint_fold_iterations: two(),
            joint_regression_steps: five(),
        }
    }
}
