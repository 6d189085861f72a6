//! A bench-backed diagnosis in shards: its candidates are independent (each is searched,
//! cross-validated and held out alone), so shard K of N fits the candidates whose place `i`
//! in the plan's list has `i % N == K - 1` ([`run_shard`]) and writes them with the plan
//! they belong to; the [`merge`] of every shard makes the selection one machine makes, and
//! so the same report, byte for byte.
//!
//! Every partial also holds the nominal robot's numbers (training χ², residuals, the gap on
//! training and held-out data): they are deterministic and take a few runs, and a shard that
//! disagrees with another on them is refused like one of another plan.

use std::path::{Path, PathBuf};

use gap::data::{HeldOutSet, TrainSet};
use gap::GapError;
use serde::{Deserialize, Serialize};

use super::select::{choose, fit_candidates, fit_nominal, FitPlan, FittedCandidate, NominalFit};
use super::{Batched, BenchDiagnosis, BenchModel, SelectOptions};
use crate::runs::odometry::Shard;

/// The `kind` of a partial.
pub const PARTIAL_KIND: &str = "gap-bench-partial";

/// Everything a shard's numbers depend on. Two shards belong to one diagnosis when theirs
/// are equal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardPlan {
    /// FNV-1a (64 bits) of the training and held-out data as JSON: every group, run,
    /// firmware parameter and the split.
    pub dataset_hash: String,
    /// The nominal robot, by content (TOML).
    pub robot: String,
    /// The firmware, by name and a hash of its flash image.
    pub firmware: String,
    pub firmware_hash: String,
    /// The options of the search and the scoring.
    pub options: SelectOptions,
    /// The predictions' seed (`options.fit.seed`, named here for the reader).
    pub seed: u64,
    /// The candidate list, in order, and the folds.
    pub fit: FitPlan,
}

impl ShardPlan {
    /// The plan of the diagnosis of `train` and `held` by `bench`.
    pub fn new(
        bench: &BenchModel,
        shortlist: &[String],
        train: &TrainSet,
        held: &HeldOutSet,
        opts: &SelectOptions,
    ) -> Self {
        let data = serde_json::to_string(&(train, held)).expect("data serialise");
        ShardPlan {
            dataset_hash: format!("{:016x}", fnv1a(data.as_bytes())),
            robot: toml::to_string(bench.nominal()).unwrap_or_default(),
            firmware: bench.firmware().name(),
            firmware_hash: bench.firmware().content_hash(),
            options: opts.clone(),
            seed: opts.fit.seed,
            fit: FitPlan::new(bench, shortlist, train, opts),
        }
    }

    /// The places in the candidate list that `shard` fits.
    pub fn candidates_of(&self, shard: Shard) -> Vec<usize> {
        (0..self.fit.candidates.len())
            .filter(|i| i % shard.n == shard.k - 1)
            .collect()
    }

    /// What differs between two plans, for a refusal.
    fn difference(&self, other: &ShardPlan) -> &'static str {
        if self.dataset_hash != other.dataset_hash {
            "the data (dataset hash)"
        } else if self.robot != other.robot {
            "the robot config"
        } else if (&self.firmware, &self.firmware_hash) != (&other.firmware, &other.firmware_hash) {
            "the firmware (flash hash)"
        } else if self.options != other.options || self.seed != other.seed {
            "the options"
        } else {
            "the candidate list or the folds"
        }
    }
}

/// One shard's part of a diagnosis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Partial {
    /// [`PARTIAL_KIND`].
    pub kind: String,
    pub plan: ShardPlan,
    pub shard: Shard,
    /// The nominal robot's numbers (in every shard).
    pub nominal: NominalFit,
    /// The candidates of this shard, each fitted completely, in plan order.
    pub candidates: Vec<FittedCandidate>,
    /// Bench runs this shard made for its candidates (the nominal robot's are in
    /// `nominal`).
    pub bench_runs: usize,
}

/// Where a shard's partial goes in `dir`.
pub fn partial_path(dir: &Path, shard: Shard) -> PathBuf {
    dir.join(format!("gap-bench-shard-{}-of-{}.json", shard.k, shard.n))
}

/// Fits the nominal robot and the candidates of `shard` (see the module docs); the
/// arguments are [`super::diagnose_bench`]'s.
pub fn run_shard(
    bench: &BenchModel,
    shortlist: &[String],
    train: &TrainSet,
    held: &HeldOutSet,
    opts: &SelectOptions,
    shard: Shard,
    progress: &dyn Fn(&str),
) -> Result<Partial, GapError> {
    let plan = ShardPlan::new(bench, shortlist, train, held, opts);
    let batched = Batched::new(bench);
    let nominal = fit_nominal(&batched, &plan.fit, train, held, opts, progress)?;
    let mine = plan.candidates_of(shard);
    progress(&format!(
        "bench: shard {}/{}: {} of the {} candidates",
        shard.k,
        shard.n,
        mine.len(),
        plan.fit.candidates.len()
    ));
    let candidates = fit_candidates(&batched, &plan.fit, &mine, train, held, opts, progress)?;
    Ok(Partial {
        kind: PARTIAL_KIND.to_owned(),
        bench_runs: batched.runs() - nominal.bench_runs,
        plan,
        shard,
        nominal,
        candidates,
    })
}

/// Why partials do not merge.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("no partial results given")]
    Empty,
    #[error("{name} is not a partial of `hil gap --bench --shard` (kind `{kind}`)")]
    Kind { name: String, kind: String },
    #[error("{name} comes from another plan than {first}: {what} differ")]
    Plan {
        name: String,
        first: String,
        what: &'static str,
    },
    #[error(
        "{name} is shard {k}/{n} but {first} is of {first_n} shards: merge the shards of one \
         split"
    )]
    Split {
        name: String,
        k: usize,
        n: usize,
        first: String,
        first_n: usize,
    },
    #[error(
        "{second} and {first} disagree on the nominal robot's numbers for the same plan: \
         one of them was changed"
    )]
    Nominal { first: String, second: String },
    #[error(
        "shard {k}/{n} is in {first} and in {second} with different results: merge one copy \
         of each shard"
    )]
    Conflict {
        k: usize,
        n: usize,
        first: String,
        second: String,
    },
    #[error(
        "{name} does not hold the candidates of shard {k}/{n} ({expected:?} of the plan's \
         list): it was changed"
    )]
    Candidates {
        name: String,
        k: usize,
        n: usize,
        expected: Vec<usize>,
    },
    #[error("shards {missing} of {n} are missing: merge the partial results of every shard")]
    Missing { missing: String, n: usize },
}

/// The diagnosis of `parts` (each named, e.g. by its file): they must be of one plan and
/// one split, every shard given, a shard given twice the same both times.
pub fn merge(parts: Vec<(String, Partial)>) -> Result<BenchDiagnosis, MergeError> {
    let (first_name, first) = parts.first().ok_or(MergeError::Empty)?;
    let n = first.shard.n;
    // (name, partial) per shard, by K.
    let mut by_k: Vec<Option<&(String, Partial)>> = vec![None; n];
    for part @ (name, p) in &parts {
        if p.kind != PARTIAL_KIND {
            return Err(MergeError::Kind {
                name: name.clone(),
                kind: p.kind.clone(),
            });
        }
        if p.plan != first.plan {
            return Err(MergeError::Plan {
                name: name.clone(),
                first: first_name.clone(),
                what: first.plan.difference(&p.plan),
            });
        }
        if p.shard.n != n || p.shard.k == 0 || p.shard.k > n {
            return Err(MergeError::Split {
                name: name.clone(),
                k: p.shard.k,
                n: p.shard.n,
                first: first_name.clone(),
                first_n: n,
            });
        }
        if json(&p.nominal) != json(&first.nominal) {
            return Err(MergeError::Nominal {
                first: first_name.clone(),
                second: name.clone(),
            });
        }
        let expected = p.plan.candidates_of(p.shard);
        let held: Vec<usize> = p.candidates.iter().map(|c| c.index).collect();
        let named = |c: &FittedCandidate| p.plan.fit.candidates[c.index].0 == c.candidate.effect;
        if held != expected || !p.candidates.iter().all(named) {
            return Err(MergeError::Candidates {
                name: name.clone(),
                k: p.shard.k,
                n,
                expected,
            });
        }
        let slot = &mut by_k[p.shard.k - 1];
        match slot {
            Some((kept_name, kept)) if json(kept) != json(p) => {
                return Err(MergeError::Conflict {
                    k: p.shard.k,
                    n,
                    first: kept_name.clone(),
                    second: name.clone(),
                })
            }
            Some(_) => {}
            None => *slot = Some(part),
        }
    }
    let missing: Vec<String> = (1..=n)
        .filter(|k| by_k[k - 1].is_none())
        .map(|k| k.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(MergeError::Missing {
            missing: missing.join(", "),
            n,
        });
    }
    let shards: Vec<&Partial> = by_k.into_iter().flatten().map(|(_, p)| p).collect();
    let runs = first.nominal.bench_runs + shards.iter().map(|p| p.bench_runs).sum::<usize>();
    let fitted = shards
        .iter()
        .flat_map(|p| p.candidates.iter().cloned())
        .collect();
    let mut d = choose(&first.plan.fit, &first.nominal, fitted, runs);
    if first.plan.options.max_effects >= 2 {
        d.notes.push(
            "no joint fits: shards fit single effects only, and the joint fits start from all \
             of them; run without --shard for pairs and triples"
                .to_owned(),
        );
    }
    Ok(d)
}

/// A value as it travels (its JSON): the one form both sides of a merge have.
fn json<T: Serialize>(v: &T) -> Option<serde_json::Value> {
    serde_json::to_value(v).ok()
}

/// FNV-1a, 64 bits (as the firmware's content hash).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
