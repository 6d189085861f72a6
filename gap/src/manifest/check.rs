//! A manifest's checks: every field against its range and the files it names, before
//! anything is read; and a telemetry log against the group it says it is a run of.

use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use super::{close, EndpointLayout, LoadedManifest, FORMAT};
use crate::model::{Firmware, TestKind};
use crate::series::RpmUnit;
use crate::GapError;

impl LoadedManifest {
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

    pub(super) fn validate(&self) -> Result<(), GapError> {
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
                self.check_range(f, v)?;
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
            ("setpoint_left", f.setpoint_left.unwrap_or(1.0)),
            ("setpoint_right", f.setpoint_right.unwrap_or(1.0)),
        ] {
            self.check_range(&format!("{what}.{name}"), v)?;
        }
        if f.setpoint_left.is_some() != f.setpoint_right.is_some() {
            return Err(self.err(format!(
                "`{what}`: give both setpoint_left and setpoint_right, or neither"
            )));
        }
        Ok(())
    }

    /// `field` (its last part names the quantity) within what a robot of the
    /// thesis' kind can have ([`RANGES`]): positive alone let a distance per
    /// count of 1e308 mm through to a diagnosis.
    fn check_range(&self, field: &str, v: f64) -> Result<(), GapError> {
        let name = field.rsplit('.').next().unwrap_or(field);
        let (low, high, unit) = RANGES
            .iter()
            .find(|(n, ..)| *n == name)
            .map(|(_, low, high, unit)| (*low, *high, *unit))
            .unwrap_or((0.0, f64::MAX, ""));
        if v.is_finite() && v > 0.0 && (low..=high).contains(&v) {
            return Ok(());
        }
        Err(self.err(format!(
            "`{field}` = {v}: give a positive number from {low} to {high}{unit}"
        )))
    }

    /// A log that is a run of `group` and states its own `[firmware]`, or a reference of its
    /// own (`[reference]` or its `robot_config`), must state the group's: the bench replays
    /// the group's firmware and robot, so a log of another state would be compared with the
    /// wrong run.
    pub(super) fn check_same_run(&self, group: &crate::data::Group) -> Result<(), GapError> {
        let e = &group.experiment;
        let firmware = self
            .manifest
            .firmware
            .as_ref()
            .and_then(|fw| first_difference(&fw.to_firmware(), &e.firmware));
        let reference = self
            .reference
            .as_ref()
            .and_then(|r| first_difference(r, &e.reference));
        for (what, difference) in [("firmware", firmware), ("reference", reference)] {
            if let Some((field, ours, theirs)) = difference {
                return Err(self.err(format!(
                    "telemetry.run_of: `{what}.{field}` is {ours} here but {theirs} in {}, the \
                     run this log is of (a log of one run must state the firmware and reference \
                     of its group)",
                    group.id
                )));
            }
        }
        Ok(())
    }
}

/// The range of each number of a manifest's `[firmware]` and `[reference]`,
/// by field name: the firmware's own parameter ranges (protocol/README.md)
/// widened to robots of other sizes. Zero is never allowed.
const RANGES: &[(&str, f64, f64, &str)] = &[
    ("c_left", 0.1, 10.0, ""),
    ("c_right", 0.1, 10.0, ""),
    ("wheelbase_mm", 10.0, 5000.0, " mm"),
    ("mm_per_count", 0.0001, 100.0, " mm"),
    ("leg_mm", 1.0, 100_000.0, " mm"),
    ("turn_umbmark_deg", 1.0, 360.0, " degrees"),
    ("turn_triangle_deg", 1.0, 360.0, " degrees"),
    ("setpoint_left", 0.01, 1000.0, " thesis RPM"),
    ("setpoint_right", 0.01, 1000.0, " thesis RPM"),
];

/// The first field (in name order) where two values of plain data (numbers, strings, enums)
/// differ, with both values; numbers the same to rounding ([`close`]) do not differ.
fn first_difference<T: Serialize>(ours: &T, theirs: &T) -> Option<(String, Value, Value)> {
    let json = |v: &T| serde_json::to_value(v).expect("plain data serialises");
    let (Value::Object(ours), Value::Object(theirs)) = (json(ours), json(theirs)) else {
        return None;
    };
    let same = |a: &Value, b: &Value| match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => close(x, y),
        _ => a == b,
    };
    ours.into_iter().find_map(|(field, v)| {
        let t = theirs.get(&field).cloned().unwrap_or(Value::Null);
        (!same(&v, &t)).then_some((field, v, t))
    })
}
