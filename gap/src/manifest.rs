//! Manifests: one small TOML file per experiment saying what was run, with which firmware
//! parameters, on which robot, and where the measurements are. The layout is documented in
//! the crate's README (`gap/README.md`); unknown fields are errors, and every error names the
//! manifest and the field.
//!
//! Paths inside a manifest are relative to the manifest's own directory.

use std::path::{Path, PathBuf};

use calib::csv::{read_triangle_csv, read_umbmark_csv, CsvOptions};
use calib::Frame;
use plant_model::identify::StepData;
use plant_model::Side;
use serde::{Deserialize, Serialize};

use crate::data::{Dataset, Group, ObservedRun};
use crate::model::{Experiment, Firmware, Reference, StraightLegs, TestKind};
use crate::series::{read_telemetry, RpmUnit, Telemetry};
use crate::GapError;

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
        let text = std::fs::read_to_string(&path).map_err(|source| GapError::Io {
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

    fn check_file(&self, field: &str, p: &Path) -> Result<(), GapError> {
        let r = self.resolve(p);
        if !r.is_file() {
            return Err(self.err(format!(
                "`{field}` = \"{}\" does not exist (resolved against the manifest's directory: {})",
                p.display(),
                r.display()
            )));
        }
        Ok(())
    }

    fn validate(&self) -> Result<(), GapError> {
        let m = &self.manifest;
        if m.format != FORMAT {
            return Err(self.err(format!(
                "`format` = {} is not supported; this reader knows format {FORMAT}",
                m.format
            )));
        }
        if m.experiment.trim().is_empty() || m.experiment.contains('/') {
            return Err(
                self.err("`experiment` must be a non-empty name without `/` (e.g. \"umbmark-1\")")
            );
        }
        self.check_file("robot_config", &m.robot_config)?;
        let sources = [
            m.endpoints.is_some(),
            m.step_response.is_some(),
            m.telemetry.is_some(),
        ];
        if sources.iter().filter(|s| **s).count() != 1 {
            return Err(self
                .err("exactly one of [endpoints], [step_response] and [telemetry] must be given"));
        }
        if let Some(fw) = &m.firmware {
            self.check_firmware("firmware", &fw.to_firmware())?;
        }
        if let Some(r) = m.reference {
            for (f, v) in [
                ("reference.wheelbase_mm", r.wheelbase_mm),
                ("reference.mm_per_count", r.mm_per_count),
            ] {
                if !(v.is_finite() && v > 0.0) {
                    return Err(self.err(format!("`{f}` must be a positive number, got {v}")));
                }
            }
        }
        if let Some(e) = &m.endpoints {
            let fw = m.firmware.as_ref().ok_or_else(|| {
                self.err("[endpoints] needs [firmware] (the parameters in force)")
            })?;
            self.check_file("endpoints.file", &e.file)?;
            if e.tests.is_empty() {
                return Err(self.err("[endpoints] lists no [[endpoints.tests]]"));
            }
            for (i, t) in e.tests.iter().enumerate() {
                let ok = match e.layout {
                    EndpointLayout::UmbmarkEndpoints => {
                        matches!(t.kind, TestKind::UmbmarkCw | TestKind::UmbmarkCcw)
                    }
                    EndpointLayout::TriangleEndpoints => matches!(
                        t.kind,
                        TestKind::Line | TestKind::TriangleCcw | TestKind::TriangleCw
                    ),
                };
                if !ok {
                    return Err(self.err(format!(
                        "endpoints.tests[{i}]: kind `{}` is not in a {:?} table (umbmark_endpoints \
                         holds umbmark_cw and umbmark_ccw; triangle_endpoints holds line and \
                         triangle_ccw or triangle_cw)",
                        t.kind, e.layout
                    )));
                }
                if e.tests[..i].iter().any(|u| u.kind == t.kind)
                    || (t.kind == TestKind::TriangleCw
                        && e.tests.iter().any(|u| u.kind == TestKind::TriangleCcw))
                {
                    return Err(self.err(format!(
                        "endpoints.tests[{i}]: `{}` listed twice (a triangle table has one \
                         triangle direction)",
                        t.kind
                    )));
                }
                let f = t
                    .firmware
                    .as_ref()
                    .map_or_else(|| fw.to_firmware(), |o| o.apply(fw.to_firmware()));
                self.check_firmware(&format!("endpoints.tests[{i}].firmware"), &f)?;
            }
        }
        if let Some(s) = &m.step_response {
            if s.speed_unit != RpmUnit::ThesisRpm {
                return Err(self.err(
                    "step_response.speed_unit must be \"thesis_rpm\" (the step-response layout's \
                     unit)",
                ));
            }
            if s.files.is_empty() {
                return Err(self.err("[step_response] lists no files"));
            }
            for (i, f) in s.files.iter().enumerate() {
                self.check_file(&format!("step_response.files[{i}].file"), &f.file)?;
            }
            if s.train_levels.len() < 2 {
                return Err(self.err(
                    "step_response.train_levels needs at least two PWM levels (gain and dead \
                     band)",
                ));
            }
        }
        if let Some(t) = &m.telemetry {
            self.check_file("telemetry.file", &t.file)?;
            if !(t.sample_period_s.is_finite() && t.sample_period_s > 0.0) {
                return Err(self.err("telemetry.sample_period_s must be positive"));
            }
        }
        Ok(())
    }

    fn check_firmware(&self, what: &str, f: &Firmware) -> Result<(), GapError> {
        for (name, v) in [
            ("c_left", f.c_left),
            ("c_right", f.c_right),
            ("wheelbase_mm", f.wheelbase_mm),
            ("mm_per_count", f.mm_per_count),
            ("leg_mm", f.leg_mm),
            ("turn_umbmark_deg", f.turn_umbmark_deg),
            ("turn_triangle_deg", f.turn_triangle_deg),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(self.err(format!("`{what}.{name}` must be positive, got {v}")));
            }
        }
        for (name, v) in [
            ("setpoint_left", f.setpoint_left),
            ("setpoint_right", f.setpoint_right),
        ] {
            if v.is_some_and(|v| !(v.is_finite() && v > 0.0)) {
                return Err(self.err(format!("`{what}.{name}` must be positive")));
            }
        }
        if f.setpoint_left.is_some() != f.setpoint_right.is_some() {
            return Err(self.err(format!(
                "`{what}`: give both setpoint_left and setpoint_right, or neither"
            )));
        }
        Ok(())
    }

    /// The endpoint groups of this manifest (in [`Frame::Default`], cm), and notes from the
    /// reader (e.g. missing y values).
    pub fn endpoint_groups(&self) -> Result<(Vec<Group>, Vec<String>), GapError> {
        let m = &self.manifest;
        let Some(e) = &m.endpoints else {
            return Ok((vec![], vec![]));
        };
        let reference = self.reference.expect("validated");
        let fw = m.firmware.as_ref().expect("validated").to_firmware();
        let path = self.resolve(&e.file);
        let text = std::fs::read_to_string(&path).map_err(|source| GapError::Io {
            path: path.clone(),
            source,
        })?;
        let csv_err = |source| GapError::Endpoints {
            manifest: self.path.clone(),
            path: path.clone(),
            source,
        };
        let opts = CsvOptions {
            runs_per_group: e.runs_per_group,
            triangle_y_optional: true,
            ..CsvOptions::default()
        };
        let k = e.length_unit.to_cm();
        let conv = |x: f64, y: Option<f64>| {
            // The frame conversion only mirrors axes; y unknown stays unknown.
            let p = e
                .frame
                .to_default(calib::Endpoint::new(x * k, y.unwrap_or(0.0) * k));
            ObservedRun {
                x_cm: p.x_cm,
                y_cm: y.map(|_| p.y_cm),
                theta_rad: None,
            }
        };
        let mut notes = Vec::new();
        let mut per_test: Vec<(TestKind, Vec<ObservedRun>)> = Vec::new();
        match e.layout {
            EndpointLayout::UmbmarkEndpoints => {
                let runs = read_umbmark_csv(&text, e.select_experiment, &opts).map_err(csv_err)?;
                for (kind, dir) in [
                    (TestKind::UmbmarkCw, calib::Direction::Cw),
                    (TestKind::UmbmarkCcw, calib::Direction::Ccw),
                ] {
                    let v = runs
                        .runs(dir)
                        .iter()
                        .map(|p| conv(p.x_cm, Some(p.y_cm)))
                        .collect();
                    per_test.push((kind, v));
                }
            }
            EndpointLayout::TriangleEndpoints => {
                let t = read_triangle_csv(&text, e.select_experiment, &opts).map_err(csv_err)?;
                notes.extend(t.notes.iter().map(|n| format!("{}: {n}", m.experiment)));
                let line = t
                    .line
                    .runs()
                    .iter()
                    .map(|p| conv(p.x_cm, Some(p.y_cm)))
                    .collect();
                let tri: Vec<ObservedRun> = t
                    .triangle
                    .runs()
                    .iter()
                    .map(|p| conv(p.x_cm, p.y_cm))
                    .collect();
                per_test.push((TestKind::Line, line));
                per_test.push((TestKind::TriangleCcw, tri.clone()));
                per_test.push((TestKind::TriangleCw, tri));
            }
        }
        let mut groups = Vec::new();
        for t in &e.tests {
            let firmware = t
                .firmware
                .as_ref()
                .map_or_else(|| fw.clone(), |o| o.apply(fw.clone()));
            let runs = per_test
                .iter()
                .find(|(k, _)| *k == t.kind)
                .map(|(_, r)| r.clone())
                .expect("every test kind of the layout was read");
            let exp = Experiment {
                test: t.kind,
                firmware,
                reference,
                runs: runs.len(),
                seed: 0,
            };
            groups.push(Group::new(&m.experiment, exp, runs)?);
        }
        Ok((groups, notes))
    }

    /// The step responses of this manifest, with their sides.
    pub fn step_responses(&self) -> Result<Vec<(Side, StepData)>, GapError> {
        let Some(s) = &self.manifest.step_response else {
            return Ok(vec![]);
        };
        s.files
            .iter()
            .map(|f| {
                let path = self.resolve(&f.file);
                StepData::load(path.as_path())
                    .map(|d| (f.side, d))
                    .map_err(|source| GapError::StepResponse {
                        manifest: self.path.clone(),
                        path,
                        source,
                    })
            })
            .collect()
    }

    /// The telemetry of this manifest.
    /// A log that is a run of `group` and states its own `[firmware]`, or a reference of its
    /// own (`[reference]` or its `robot_config`), must state the group's: the bench replays
    /// the group's firmware and robot, so a log of another state would be compared with the
    /// wrong run.
    fn check_same_run(&self, group: &crate::data::Group) -> Result<(), GapError> {
        let e = &group.experiment;
        let differs = |what: &str, ours: serde_json::Value, theirs: serde_json::Value| {
            let (serde_json::Value::Object(ours), serde_json::Value::Object(theirs)) =
                (ours, theirs)
            else {
                return None;
            };
            let same = |a: &serde_json::Value, b: Option<&serde_json::Value>| match (a.as_f64(), b)
            {
                (Some(x), Some(b)) => b.as_f64().is_some_and(|y| close(x, y)),
                _ => b == Some(a),
            };
            let field = ours.iter().find(|(k, v)| !same(v, theirs.get(*k)))?;
            Some(self.err(format!(
                "telemetry.run_of: `{what}.{}` is {} here but {} in {}, the run this log \
                 is of (a log of one run must state the firmware and reference of its group)",
                field.0,
                field.1,
                theirs.get(field.0).unwrap_or(&serde_json::Value::Null),
                group.id
            )))
        };
        if let Some(fw) = &self.manifest.firmware {
            if let Some(err) = differs("firmware", to_json(&fw.to_firmware()), to_json(&e.firmware))
            {
                return Err(err);
            }
        }
        if let Some(r) = &self.reference {
            if let Some(err) = differs("reference", to_json(r), to_json(&e.reference)) {
                return Err(err);
            }
        }
        Ok(())
    }

    pub fn telemetry(&self) -> Result<Option<Telemetry>, GapError> {
        let Some(t) = &self.manifest.telemetry else {
            return Ok(None);
        };
        let path = self.resolve(&t.file);
        let text = std::fs::read_to_string(&path).map_err(|source| GapError::Io {
            path: path.clone(),
            source,
        })?;
        read_telemetry(&text, &path, t.sample_period_s, t.rpm_unit).map(Some)
    }
}

/// Two values of a manifest the same to rounding (10⁻⁹ relative): one written in decimals,
/// the other derived from a robot configuration.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// Plain data (numbers, strings, enums) as JSON, to compare field by field.
fn to_json<T: Serialize>(v: &T) -> serde_json::Value {
    serde_json::to_value(v).expect("plain data serialises")
}

/// Loads the endpoint groups of several manifests into one dataset. All manifests with
/// endpoints must give the same `[reference]` (one robot), and experiment names must be
/// unique.
pub fn load_dataset(manifests: &[LoadedManifest]) -> Result<(Dataset, Vec<String>), GapError> {
    let mut data = Dataset::default();
    let mut notes = Vec::new();
    let mut reference: Option<(Reference, &Path)> = None;
    let mut names: Vec<&str> = Vec::new();
    for m in manifests {
        if names.contains(&m.manifest.experiment.as_str()) {
            return Err(GapError::Manifest {
                path: m.path.clone(),
                message: format!(
                    "experiment name `{}` is used by another manifest",
                    m.manifest.experiment
                ),
            });
        }
        names.push(&m.manifest.experiment);
        if let (Some(r), Some(_)) = (m.reference, &m.manifest.endpoints) {
            match reference {
                None => reference = Some((r, &m.path)),
                Some((r0, p0)) if r0 != r => {
                    return Err(GapError::Manifest {
                        path: m.path.clone(),
                        message: format!(
                            "[reference] differs from the one in {} ({r0:?}); the effects are \
                             relative to one physical reference per robot",
                            p0.display()
                        ),
                    })
                }
                Some(_) => {}
            }
        }
        let (groups, n) = m.endpoint_groups()?;
        notes.extend(n);
        for g in groups {
            data.push(g)?;
        }
    }
    Ok((data, notes))
}

/// Gives each group of `data` the telemetry of the manifest whose `[telemetry] run_of` names
/// its experiment (with the same test); notes the logs that belong to no group.
pub fn attach_telemetry(
    data: &mut Dataset,
    manifests: &[LoadedManifest],
) -> Result<Vec<String>, GapError> {
    let mut notes = Vec::new();
    for m in manifests {
        let Some(t) = &m.manifest.telemetry else {
            continue;
        };
        let Some(of) = &t.run_of else {
            notes.push(format!(
                "{}: telemetry belongs to no endpoint group (no `run_of`): not scored with one",
                m.manifest.experiment
            ));
            continue;
        };
        let telemetry = m.telemetry()?.expect("has telemetry");
        let id = crate::data::GroupId {
            experiment: of.clone(),
            test: t.test,
        };
        if let Some(g) = data.groups().iter().find(|g| g.id == id) {
            m.check_same_run(g)?;
        }
        data.attach_telemetry(&id, telemetry)
            .map_err(|e| GapError::Manifest {
                path: m.path.clone(),
                message: format!("telemetry.run_of: {e}"),
            })?;
    }
    Ok(notes)
}

/// Loads every `*.toml` manifest of a directory, sorted by file name.
pub fn load_dir(dir: impl AsRef<Path>) -> Result<Vec<LoadedManifest>, GapError> {
    let dir = dir.as_ref();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|source| GapError::Io {
            path: dir.to_path_buf(),
            source,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths.iter().map(LoadedManifest::load).collect()
}
