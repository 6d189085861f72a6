//! Several manifests into one dataset: the endpoint groups of one robot, each with the
//! telemetry logged of one of its runs.

use std::path::{Path, PathBuf};

use super::LoadedManifest;
use crate::data::Dataset;
use crate::model::Reference;
use crate::GapError;

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
