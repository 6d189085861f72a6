//! The crate's error type.

use std::path::PathBuf;

use crate::model::ModelError;

/// Everything that can go wrong.
#[derive(Debug, thiserror::Error)]
pub enum GapError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// A manifest is not valid TOML, has unknown or missing fields, or inconsistent values.
    #[error("manifest {path}: {message}")]
    Manifest {
        /// The manifest.
        path: PathBuf,
        /// What is wrong and what to write instead.
        message: String,
    },
    /// An endpoint table named by a manifest could not be read.
    #[error("manifest {manifest}: endpoint table {path}: {source}")]
    Endpoints {
        /// The manifest.
        manifest: PathBuf,
        /// The table.
        path: PathBuf,
        /// The reader's error (with its line number).
        #[source]
        source: calib::Error,
    },
    /// A step-response file could not be read.
    #[error("manifest {manifest}: step response {path}: {source}")]
    StepResponse {
        /// The manifest.
        manifest: PathBuf,
        /// The file.
        path: PathBuf,
        /// The reader's error.
        #[source]
        source: plant_model::identify::IdentifyError,
    },
    /// A telemetry file is malformed.
    #[error("telemetry {path}: line {line}: {message}")]
    Telemetry {
        /// The file (or `<text>`).
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Measured data that cannot be used.
    #[error("data: {0}")]
    Data(String),
    /// A split that leaves nothing on one side or names unknown experiments.
    #[error("split: {0}")]
    Split(String),
    /// A fit that could not run.
    #[error("fit: {0}")]
    Fit(String),
    /// The model refused.
    #[error("model: {0}")]
    Model(#[from] ModelError),
    /// A time-series comparison that cannot be made.
    #[error("series: {0}")]
    Series(String),
    /// A plot could not be drawn.
    #[error("plot: {0}")]
    Plot(String),
}
