//! What an experiment runs: the plan (everything that changes a result), every
//! run's index, test and seed, and which of them one shard runs.

use plant_model::RobotConfig;

use super::ExperimentError;
use crate::board::Board;
use crate::firmware::elf::Firmware;
use crate::firmware::link::Param;
use crate::firmware::params::{Believed, Tell};
use crate::runs::experiment::Test;

/// Which experiment a plan runs: a set of the firmware's tests, run in two
/// groups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Experiment {
    /// UMBmark: CW squares, then CCW squares.
    #[default]
    Umbmark,
    /// Triangular Path: straight lines, then counter-clockwise triangles.
    Triangle,
}

impl Experiment {
    /// The `kind` of its run sets.
    pub fn kind(self) -> &'static str {
        match self {
            Experiment::Umbmark => "umbmark",
            Experiment::Triangle => "triangle",
        }
    }

    /// The test of each group: the first (CW squares, or the lines), then
    /// the second (CCW squares, or the triangles).
    pub fn tests(self) -> [Test; 2] {
        match self {
            Experiment::Umbmark => [Test::UmbmarkCw, Test::UmbmarkCcw],
            Experiment::Triangle => [Test::Line, Test::Triangle],
        }
    }
}

/// What to run. Everything that changes a result is in here.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    #[serde(default)]
    pub experiment: Experiment,
    pub leg_mm: f64,
    pub runs_per_direction: usize,
    /// The experiment's seed: run `i` uses [`run_seed`]`(seed, i)`.
    pub seed: u64,
    /// The robot config, by content (a file name would not pin it).
    pub robot: String,
    /// The firmware, by name and content hash.
    pub firmware: String,
    pub firmware_hash: String,
    /// Firmware parameters set over the protocol before each run: (id, value)
    /// (see protocol/README.md: 1 cL, 2 cR, 3 wheelbase mm, ...): the robot's
    /// geometry where it is not the firmware's factory values, then any
    /// correction.
    #[serde(default)]
    pub params: Vec<(u8, f32)>,
    /// E.g. a firmware whose geometry is not the robot's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// How a firmware without the bench interface is run (see
    /// [`crate::firmware::description`]); the firmware's hash pins the rest.
    #[serde(skip)]
    pub description: Option<std::sync::Arc<crate::firmware::description::Description>>,
}

/// The seed of run `index` of an experiment seeded `seed`: the `index`-th
/// output of a SplitMix64 stream started from `mix(seed)`. Mixing the seed
/// first makes the streams of different seeds unrelated, so two experiments
/// with seeds 1 and 2 draw independent samples (with `seed + index`, seeds
/// 1 and 2 shared 9 of 10 runs); the same seed still gives the same runs on
/// every machine, and a run's seed depends only on its index, so shards stay
/// exact.
pub fn run_seed(seed: u64, index: usize) -> u64 {
    use plant_model::rng::{mix, GOLDEN};
    mix(mix(seed).wrapping_add((index as u64).wrapping_add(1).wrapping_mul(GOLDEN)))
}

/// One run of a plan: its index, direction and seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    pub index: usize,
    pub test: Test,
    pub seed: u64,
}

/// K of N, 1-based: runs whose index i has i % N == K - 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = ExperimentError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || ExperimentError::BadShard(s.into());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl Plan {
    /// A UMBmark of `firmware` on `robot` wired by `board`; the firmware is
    /// told the robot's geometry and the board's driver wiring (in `params`)
    /// unless `tell` says to keep its own.
    pub fn new(
        leg_mm: f64,
        seed: u64,
        robot: &RobotConfig,
        board: &Board,
        firmware: &Firmware,
        tell: Tell,
    ) -> Self {
        let name = firmware.name();
        let (params, _, warning) = crate::firmware::params::plan(firmware, robot, board, tell, &[]);
        Self {
            experiment: Experiment::Umbmark,
            leg_mm,
            runs_per_direction: 5,
            seed,
            robot: toml::to_string(robot).unwrap_or_default(),
            firmware: name,
            firmware_hash: firmware.content_hash(),
            params: params.iter().map(|(p, v)| (p.id(), *v)).collect(),
            warnings: warning.into_iter().collect(),
            description: None,
        }
    }

    /// The plan for a firmware without the bench interface, run as `d`
    /// describes: nothing is sent to it but each test's start.
    pub fn described(
        mut self,
        d: std::sync::Arc<crate::firmware::description::Description>,
    ) -> Self {
        self.params.clear();
        self.warnings.clear();
        if let Some(name) = &d.name {
            self.firmware = name.clone();
        }
        self.description = Some(d);
        self
    }

    /// The plan's parameters, decoded.
    pub fn firmware_params(&self) -> Vec<(Param, f32)> {
        self.params
            .iter()
            .filter_map(|&(id, v)| Param::from_u8(id).map(|p| (p, v)))
            .collect()
    }

    /// What the firmware believes about the robot in this plan's runs.
    pub fn believed(&self) -> Believed {
        Believed::factory().after(&self.firmware_params())
    }

    /// The same plan for the Triangular Path.
    pub fn triangle(mut self) -> Self {
        self.experiment = Experiment::Triangle;
        self
    }

    /// Every run: the first group (CW, or the lines), then the second.
    pub fn runs(&self) -> Vec<RunSpec> {
        let n = self.runs_per_direction;
        let [first, second] = self.experiment.tests();
        (0..2 * n)
            .map(|i| RunSpec {
                index: i,
                test: if i < n { first } else { second },
                seed: run_seed(self.seed, i),
            })
            .collect()
    }

    /// The runs of one shard.
    pub fn shard(&self, shard: Shard) -> Vec<RunSpec> {
        self.runs()
            .into_iter()
            .filter(|r| r.index % shard.n == shard.k - 1)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::run_seed;

    /// Experiments seeded 0..50 share no run (same seed and same test): with
    /// `seed + i`, consecutive seeds shared 8 of their 10 runs. One seed
    /// always gives the same run seeds.
    #[test]
    fn different_seeds_share_no_run_and_one_seed_repeats() {
        let n = 5;
        let runs =
            |seed| -> Vec<(bool, u64)> { (0..2 * n).map(|i| (i < n, run_seed(seed, i))).collect() };
        let mut seen = std::collections::HashMap::new();
        for seed in 0..50u64 {
            for r in runs(seed) {
                if let Some(other) = seen.insert(r, seed) {
                    panic!("seeds {other} and {seed} share the run seed {}", r.1);
                }
            }
        }
        assert_eq!(runs(7), runs(7));
        assert_eq!(
            run_seed(7, 3),
            0xe21b_5034_36e9_7f5b,
            "run seeds are pinned"
        );
    }
}
