//! Everything a set of manifests holds, diagnosed: endpoint groups, step responses and
//! telemetry.

use super::{diagnose, DiagnoseOptions, Diagnosis};
use crate::data::SplitRule;
use crate::manifest::{load_dataset, LoadedManifest};
use crate::model::{Experiment, Model};
use crate::series::{motor_holdout, series_gap, LevelSplit};
use crate::GapError;

/// Everything the manifests hold, diagnosed: the endpoint groups split by `rule` and
/// diagnosed with `model`; each step-response manifest's motors fitted on its
/// `train_levels` and checked on the others ([`motor_holdout`]); each telemetry manifest
/// compared with the model's series ([`series_gap`]) when the model has one (otherwise a
/// note says it was not compared).
pub fn diagnose_manifests(
    model: &dyn Model,
    manifests: &[LoadedManifest],
    rule: &SplitRule,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, GapError> {
    let with_endpoints: Vec<LoadedManifest> = manifests
        .iter()
        .filter(|m| m.manifest.endpoints.is_some())
        .cloned()
        .collect();
    let (data, data_notes) = load_dataset(&with_endpoints)?;
    let (train, held) = data.split(rule)?;
    let mut d = diagnose(model, &train, &held, opts)?;
    d.notes.splice(0..0, data_notes);
    for m in manifests {
        if let Some(s) = &m.manifest.step_response {
            for (side, steps) in m.step_responses()? {
                let all: Vec<u16> = steps.levels.iter().filter_map(|c| c.pwm).collect();
                let split =
                    LevelSplit::new(&all, &s.train_levels).map_err(|e| GapError::Manifest {
                        path: m.path.clone(),
                        message: e.to_string(),
                    })?;
                d.motor.push(motor_holdout(&steps, side, &split)?);
            }
        }
        if let Some(real) = m.telemetry()? {
            let t = m.manifest.telemetry.as_ref().expect("has telemetry");
            let (Some(fw), Some(reference)) = (&m.manifest.firmware, m.reference) else {
                d.notes.push(format!(
                    "{}: telemetry not compared (the manifest gives no [firmware] and [reference] \
                     to simulate it with)",
                    m.manifest.experiment
                ));
                continue;
            };
            let exp = Experiment {
                test: t.test,
                firmware: crate::model::Firmware {
                    c_left: fw.c_left,
                    c_right: fw.c_right,
                    wheelbase_mm: fw.wheelbase_mm,
                    mm_per_count: fw.mm_per_count,
                    leg_mm: fw.leg_mm,
                    turn_umbmark_deg: fw.turn_umbmark_deg,
                    turn_triangle_deg: fw.turn_triangle_deg,
                    setpoint_left: fw.setpoint_left,
                    setpoint_right: fw.setpoint_right,
                    straight_legs: fw.straight_legs,
                },
                reference,
                runs: 1,
                seed: opts.fit.seed,
            };
            let winner = d.winner_fit().map(|f| f.params.clone()).unwrap_or_default();
            match model.predict_series(&winner, &exp) {
                Ok(sim) => {
                    let g = series_gap(&m.manifest.experiment, &real, &sim)?;
                    d.series.push(g);
                }
                Err(e) => d.notes.push(format!(
                    "{}: telemetry not compared: {e}",
                    m.manifest.experiment
                )),
            }
        }
    }
    Ok(d)
}
