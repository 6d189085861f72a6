//! Manifests: one small TOML file per experiment saying what was run, with which firmware
//! parameters, on which robot, and where the measurements are. The layout is documented in
//! the crate's README (`gap/README.md`); unknown fields are errors, and every error names the
//! manifest and the field.
//!
//! Paths inside a manifest are relative to the manifest's own directory.

use std::path::{Path, PathBuf};

use calib::Frame;
use plant_model::Side;
use serde::{Deserialize, Serialize};

use crate::model::{Firmware, Reference, StraightLegs, TestKind};
use crate::series::RpmUnit;
use crate::GapError;

mod check;
mod dataset;
mod read;

pub use dataset::{attach_telemetry, load_dataset, load_dir};

/// The manifest format this crate reads.
pub const FORMAT: u32 = 1;

/// A manifest as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Must be [`FORMAT`].
    pub format: u32,
    /// Unique name of the experiment (e.g. `umbmark-1`).
    pub experiment: String,
    /// Free text: what was done, where the numbers come from.
    #[serde(default)]
    pub description: String,
    /// The robot's configuration file (for the full simulator; checked to exist).
    pub robot_config: PathBuf,
    /// The physical reference the effects are relative to (endpoint data); may be left out
    /// when `robot_config` is a plant configuration, from which it is then derived.
    pub reference: Option<Reference>,
    /// The firmware parameters in force (endpoint data and telemetry).
    pub firmware: Option<FirmwareSpec>,
    /// Endpoint measurements.
    pub endpoints: Option<EndpointSource>,
    /// Motor step responses.
    pub step_response: Option<StepResponseSource>,
    /// A telemetry time series.
    pub telemetry: Option<TelemetrySource>,
}

fn d90() -> f64 {
    90.0
}
fn d120() -> f64 {
    120.0
}
fn d5() -> usize {
    5
}

/// `[firmware]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FirmwareSpec {
    /// cL.
    pub c_left: f64,
    /// cR.
    pub c_right: f64,
    /// Wheelbase for the spin targets, mm.
    pub wheelbase_mm: f64,
    /// Distance per count before cL, cR, mm.
    pub mm_per_count: f64,
    /// Leg length, mm.
    pub leg_mm: f64,
    /// UMBmark corner, degrees (default 90).
    #[serde(default = "d90")]
    pub turn_umbmark_deg: f64,
    /// Triangle corner, degrees (default 120).
    #[serde(default = "d120")]
    pub turn_triangle_deg: f64,
    /// Left speed set-point (unit of the firmware; only the ratio matters here).
    pub setpoint_left: Option<f64>,
    /// Right speed set-point.
    pub setpoint_right: Option<f64>,
    /// `speed_setpoints` (default) or `corrected_odometry`.
    #[serde(default)]
    pub straight_legs: StraightLegs,
}

impl FirmwareSpec {
    fn to_firmware(&self) -> Firmware {
        Firmware {
            c_left: self.c_left,
            c_right: self.c_right,
            wheelbase_mm: self.wheelbase_mm,
            mm_per_count: self.mm_per_count,
            leg_mm: self.leg_mm,
            turn_umbmark_deg: self.turn_umbmark_deg,
            turn_triangle_deg: self.turn_triangle_deg,
            setpoint_left: self.setpoint_left,
            setpoint_right: self.setpoint_right,
            straight_legs: self.straight_legs,
        }
    }
}

/// Per-test changes to `[firmware]` (e.g. the triangle runs after the line's correction).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FirmwareOverride {
    /// cL.
    pub c_left: Option<f64>,
    /// cR.
    pub c_right: Option<f64>,
    /// Wheelbase, mm.
    pub wheelbase_mm: Option<f64>,
    /// Distance per count, mm.
    pub mm_per_count: Option<f64>,
    /// Leg length, mm.
    pub leg_mm: Option<f64>,
    /// UMBmark corner, degrees.
    pub turn_umbmark_deg: Option<f64>,
    /// Triangle corner, degrees.
    pub turn_triangle_deg: Option<f64>,
    /// Left set-point.
    pub setpoint_left: Option<f64>,
    /// Right set-point.
    pub setpoint_right: Option<f64>,
    /// Straight-leg convention.
    pub straight_legs: Option<StraightLegs>,
}

impl FirmwareOverride {
    fn apply(&self, mut f: Firmware) -> Firmware {
        macro_rules! set {
            ($($field:ident),*) => { $( if let Some(v) = self.$field { f.$field = v; } )* };
        }
        set!(
            c_left,
            c_right,
            wheelbase_mm,
            mm_per_count,
            leg_mm,
            turn_umbmark_deg,
            turn_triangle_deg,
            straight_legs
        );
        if self.setpoint_left.is_some() {
            f.setpoint_left = self.setpoint_left;
        }
        if self.setpoint_right.is_some() {
            f.setpoint_right = self.setpoint_right;
        }
        f
    }
}

/// Layout of an endpoint table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EndpointLayout {
    /// `experiment,direction,run,x_cm,y_cm` (the thesis' UMBmark table).
    UmbmarkEndpoints,
    /// `experiment,test,run,x_cm,y_cm` (the thesis' Triangular Path table).
    TriangleEndpoints,
}

/// Unit of the lengths in a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthUnit {
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
}

impl LengthUnit {
    fn to_cm(self) -> f64 {
        match self {
            LengthUnit::Mm => 0.1,
            LengthUnit::Cm => 1.0,
            LengthUnit::M => 100.0,
        }
    }
}

/// `[endpoints]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EndpointSource {
    /// The table.
    pub file: PathBuf,
    /// Its layout.
    pub layout: EndpointLayout,
    /// The value of its `experiment` column to read.
    pub select_experiment: u32,
    /// Frame the numbers were recorded in (`default` or `thesis_gui`).
    pub frame: Frame,
    /// Unit of the `x_cm`/`y_cm` columns as they were actually recorded.
    pub length_unit: LengthUnit,
    /// Runs per test (checked; default 5).
    #[serde(default = "d5")]
    pub runs_per_group: usize,
    /// The tests of this experiment, each with optional firmware changes.
    pub tests: Vec<TestEntry>,
}

/// `[[endpoints.tests]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TestEntry {
    /// The test.
    pub kind: TestKind,
    /// Changes to `[firmware]` for this test.
    #[serde(default)]
    pub firmware: Option<FirmwareOverride>,
    /// Free text.
    #[serde(default)]
    pub note: String,
}

/// `[step_response]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepResponseSource {
    /// One file per motor.
    pub files: Vec<StepFile>,
    /// PWM levels to fit on; the other levels of each file are held out.
    pub train_levels: Vec<u16>,
    /// Must be `thesis_rpm` (true wheel RPM / 6), the unit of the thesis tables.
    pub speed_unit: RpmUnit,
}

/// One step-response file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepFile {
    /// Which motor.
    pub side: Side,
    /// The CSV (`sample,time_s,pwmNNN_rpm,...,mean_rpm`).
    pub file: PathBuf,
}

/// `[telemetry]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TelemetrySource {
    /// The CSV (layout in the README).
    pub file: PathBuf,
    /// The test it records.
    pub test: TestKind,
    /// Control period, s.
    pub sample_period_s: f64,
    /// Unit of the RPM columns.
    pub rpm_unit: RpmUnit,
    /// The endpoint experiment (its manifest's `experiment`) one of whose runs of `test`
    /// this log is: its group then carries the log ([`attach_telemetry`]), which the
    /// bench-backed diagnosis compares with the bench's run of that group. None: a log on
    /// its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run_of: Option<String>,
}

/// A manifest with its location.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedManifest {
    /// Where it was read from.
    pub path: PathBuf,
    /// What it says.
    pub manifest: Manifest,
    /// The physical reference: `[reference]`, or derived from `robot_config` when that is a
    /// plant configuration (both must agree when both are there).
    pub reference: Option<Reference>,
}

/// The reference of a plant configuration: its wheelbase, and the distance per counted edge
/// of its mean wheel (`π·D_mean / (edges per motor turn · gear ratio)`).
pub fn reference_from_config(c: &plant_model::RobotConfig) -> Reference {
    let d = (c.geometry.wheel_diameter_left_mm + c.geometry.wheel_diameter_right_mm) / 2.0;
    Reference {
        wheelbase_mm: c.geometry.wheelbase_mm,
        mm_per_count: std::f64::consts::PI * d
            / (f64::from(c.encoder.a_edges_per_motor_rev) * c.encoder.gear_ratio),
    }
}

impl LoadedManifest {
    /// Reads and validates a manifest (the files it names must exist).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, GapError> {
        let path = path.as_ref().to_path_buf();
        let text = input_file::read_text(&path).map_err(|source| GapError::Io {
            path: path.clone(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses and validates manifest text as if it were read from `path` (relative paths
    /// inside resolve against its directory).
    pub fn parse(text: &str, path: PathBuf) -> Result<Self, GapError> {
        let manifest: Manifest = toml::from_str(text).map_err(|e| GapError::Manifest {
            path: path.clone(),
            message: e.to_string().trim_end().to_owned(),
        })?;
        let mut m = LoadedManifest {
            path,
            manifest,
            reference: None,
        };
        m.validate()?;
        m.reference = m.resolve_reference()?;
        if m.manifest.endpoints.is_some() && m.reference.is_none() {
            return Err(m.err(
                "[endpoints] needs a physical reference: give [reference] (wheelbase_mm, \
                 mm_per_count) or a robot_config in the plant's format (plant_model::RobotConfig)",
            ));
        }
        Ok(m)
    }

    fn err(&self, message: impl Into<String>) -> GapError {
        GapError::Manifest {
            path: self.path.clone(),
            message: message.into(),
        }
    }

    /// A path of the manifest resolved against its directory.
    pub fn resolve(&self, p: &Path) -> PathBuf {
        self.path.parent().unwrap_or_else(|| Path::new(".")).join(p)
    }

    fn resolve_reference(&self) -> Result<Option<Reference>, GapError> {
        let from_config = plant_model::RobotConfig::load(self.resolve(&self.manifest.robot_config))
            .ok()
            .map(|c| reference_from_config(&c));
        match (self.manifest.reference, from_config) {
            (Some(r), Some(c)) => {
                if !close(r.wheelbase_mm, c.wheelbase_mm) || !close(r.mm_per_count, c.mm_per_count)
                {
                    return Err(self.err(format!(
                        "[reference] ({} mm, {} mm per count) disagrees with robot_config ({} mm, \
                         {} mm per count); drop [reference] or make them agree",
                        r.wheelbase_mm, r.mm_per_count, c.wheelbase_mm, c.mm_per_count
                    )));
                }
                Ok(Some(r))
            }
            (r, c) => Ok(r.or(c)),
        }
    }
}

/// Two values of a manifest the same to rounding (10⁻⁹ relative): one written in decimals,
/// the other derived from a robot configuration.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}
