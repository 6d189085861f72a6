//! The telemetry a run records, as data: what a [`crate::Model`] returns and what the series
//! analysis reads. A leaf, so that the model interface does not depend on the analysis:
//! [`crate::series`] (the CSV layout, its reader, the comparisons) re-exports these types.

use serde::{Deserialize, Serialize};

/// Unit of a wheel-speed column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RpmUnit {
    /// The thesis firmware's "RPM": true wheel RPM / 6.
    ThesisRpm,
    /// True wheel revolutions per minute.
    WheelRpm,
}

/// Header of the telemetry CSV without the pose.
pub const TELEMETRY_HEADER: &str = "t_s,rpm_left,rpm_right,pwm_left,pwm_right";
/// The optional pose columns.
pub const TELEMETRY_POSE: &str = "x_mm,y_mm,theta_rad";

/// One control period.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sample {
    /// Time, s.
    pub t_s: f64,
    /// Left wheel speed, thesis RPM (converted on reading).
    pub rpm_left: f64,
    /// Right wheel speed, thesis RPM.
    pub rpm_right: f64,
    /// Left duty command, −255..255.
    pub pwm_left: f64,
    /// Right duty command.
    pub pwm_right: f64,
    /// Pose (x mm, y mm, θ rad), when recorded.
    pub pose: Option<(f64, f64, f64)>,
}

/// A telemetry time series, speeds in thesis RPM.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Telemetry {
    /// Control period, s.
    pub period_s: f64,
    /// The samples.
    pub samples: Vec<Sample>,
}
