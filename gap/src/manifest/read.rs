//! What a manifest's files hold: its endpoint groups, step responses and telemetry.

use calib::csv::{read_triangle_csv, read_umbmark_csv, CsvOptions};
#[cfg(doc)]
use calib::Frame;
use plant_model::identify::StepData;
use plant_model::Side;

use super::{EndpointLayout, LoadedManifest};
use crate::data::{Group, ObservedRun};
use crate::model::{Experiment, TestKind};
use crate::series::{read_telemetry, Telemetry};
use crate::GapError;

impl LoadedManifest {
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
        let text = input_file::read_text(&path).map_err(|source| GapError::Io {
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
    pub fn telemetry(&self) -> Result<Option<Telemetry>, GapError> {
        let Some(t) = &self.manifest.telemetry else {
            return Ok(None);
        };
        let path = self.resolve(&t.file);
        let text = input_file::read_text(&path).map_err(|source| GapError::Io {
            path: path.clone(),
            source,
        })?;
        read_telemetry(&text, &path, t.sample_period_s, t.rpm_unit).map(Some)
    }
}
