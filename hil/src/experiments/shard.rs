//! Shards: a plan's runs split over machines ([`super::Plan::shard`] picks a
//! shard's runs), each shard's run set in its own file, and the merge of them
//! into exactly the set one machine would have produced.

use std::path::{Path, PathBuf};

use super::plan::Shard;
use super::runs::RunSet;
use super::ExperimentError;

/// Where a shard's run set goes by default.
pub fn partial_path(dir: &Path, shard: Shard) -> PathBuf {
    dir.join(format!("umbmark-shard-{}-of-{}.json", shard.k, shard.n))
}

/// Combine shards' run sets into the full set, checking they belong together.
pub fn merge(parts: Vec<RunSet>) -> Result<RunSet, ExperimentError> {
    let mut iter = parts.into_iter();
    let first = iter
        .next()
        .ok_or_else(|| ExperimentError::Mismatch("no partial results given".into()))?;
    let plan = first.plan.clone();
    let mut runs = first.runs;
    for p in iter {
        if p.plan != plan {
            return Err(ExperimentError::Mismatch(
                "they come from different plans (leg, seed, robot or firmware differ)".into(),
            ));
        }
        runs.extend(p.runs);
    }
    runs.sort_by_key(|r| r.spec.index);
    runs.dedup_by_key(|r| r.spec.index);
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
