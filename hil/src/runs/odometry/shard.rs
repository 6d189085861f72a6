//! Shards: a plan's runs split over machines ([`super::Plan::shard`] picks a
//! shard's runs), each shard's run set in its own file, and the merge of them
//! into exactly the set one machine would have produced.

use std::path::{Path, PathBuf};

use super::plan::Shard;
use super::runs::{IndexedRun, RunSet};
use super::ExperimentError;

/// Where a shard's run set goes by default.
pub fn partial_path(dir: &Path, shard: Shard) -> PathBuf {
    dir.join(format!("umbmark-shard-{}-of-{}.json", shard.k, shard.n))
}

/// Combine shards' run sets into the full set, checking they belong together
/// (the parts named by their place in `parts`, "part 1" first).
pub fn merge(parts: Vec<RunSet>) -> Result<RunSet, ExperimentError> {
    merge_named(
        parts
            .into_iter()
            .enumerate()
            .map(|(i, p)| (format!("part {}", i + 1), p))
            .collect(),
    )
}

/// [`merge`] of parts named (e.g. by their files): a run given twice must be
/// the same run both times, or the merge is refused naming both parts, since
/// no order of the arguments makes one of them the right one.
pub fn merge_named(parts: Vec<(String, RunSet)>) -> Result<RunSet, ExperimentError> {
    let mut iter = parts.into_iter();
    let (first_name, first) = iter
        .next()
        .ok_or_else(|| ExperimentError::Mismatch("no partial results given".into()))?;
    let plan = first.plan.clone();
    let mut runs: Vec<(String, IndexedRun)> = first
        .runs
        .into_iter()
        .map(|r| (first_name.clone(), r))
        .collect();
    for (name, p) in iter {
        if p.plan != plan {
            return Err(ExperimentError::Mismatch(format!(
                "{name} comes from another plan than {first_name} (leg, seed, robot or firmware differ)"
            )));
        }
        runs.extend(p.runs.into_iter().map(|r| (name.clone(), r)));
    }
    // Stable: of equal runs, the first given stays.
    runs.sort_by_key(|(_, r)| r.spec.index);
    let mut merged: Vec<(String, IndexedRun)> = Vec::with_capacity(runs.len());
    for (name, r) in runs {
        match merged.last() {
            Some((kept_name, kept)) if kept.spec.index == r.spec.index => {
                if !same_run(kept, &r) {
                    return Err(ExperimentError::Conflict {
                        index: r.spec.index,
                        first: kept_name.clone(),
                        second: name,
                    });
                }
            }
            _ => merged.push((name, r)),
        }
    }
    let runs: Vec<IndexedRun> = merged.into_iter().map(|(_, r)| r).collect();
    let expected = plan.runs();
    let missing: Vec<usize> = expected
        .iter()
        .filter(|s| !runs.iter().any(|r| r.spec == **s))
        .map(|s| s.index)
        .collect();
    if !missing.is_empty() {
        return Err(ExperimentError::Missing { missing });
    }
    Ok(RunSet::new(plan, None, runs))
}

/// Two copies of one run: equal as they travel (their JSON), the only form
/// both sides of a merge have.
fn same_run(a: &IndexedRun, b: &IndexedRun) -> bool {
    a.spec == b.spec && serde_json::to_value(a).ok() == serde_json::to_value(b).ok()
}
