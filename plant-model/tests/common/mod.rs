//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use plant_model::{Duty, RobotConfig};

/// A file under the repository's `fixtures/` folder.
pub fn fixture(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("fixtures")
        .join(relative)
}

/// A duty from a fraction known to be valid.
pub fn duty(fraction: f64) -> Duty {
    Duty::new(fraction).expect("test duty in [0, 1]")
}

/// The nominal robot with the right motor on both sides, so both wheels behave identically.
pub fn symmetric_config() -> RobotConfig {
    let mut config = RobotConfig::default();
    config.motor.left = config.motor.right.clone();
    config
}
