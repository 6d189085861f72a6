//! Measured data: groups of runs of one test under one firmware state, and the split into
//! training and held-out sets.
//!
//! A [`Dataset`] is split by *consuming* it: [`Dataset::split`] moves every group into
//! exactly one of [`TrainSet`] and [`HeldOutSet`], neither of which can be built any other
//! way, and the fits only accept a [`TrainSet`]. The training side cannot see a held-out
//! run.

use serde::{Deserialize, Serialize};

use crate::model::{Experiment, TestKind};
use crate::telemetry::Telemetry;
use crate::GapError;

/// One measured run, in [`calib::Frame::Default`] (converted from the recorded frame by the
/// loader). `y_cm` may be unknown (the thesis' triangle experiment 2), and so may the heading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObservedRun {
    /// x error, cm.
    pub x_cm: f64,
    /// y error, cm, when recorded.
    pub y_cm: Option<f64>,
    /// Heading error, rad, when recorded.
    pub theta_rad: Option<f64>,
}

/// Identifies a group: experiment name and test.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct GroupId {
    /// The experiment (manifest) name, e.g. `umbmark-1`.
    pub experiment: String,
    /// The test.
    pub test: TestKind,
}

impl std::fmt::Display for GroupId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.experiment, self.test)
    }
}

/// The runs of one test under one firmware state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Group {
    /// Which.
    pub id: GroupId,
    /// What was run (its `runs` is the number of measured runs).
    pub experiment: Experiment,
    /// The measured runs.
    pub runs: Vec<ObservedRun>,
    /// The telemetry of one run of the group (wheel speeds and duties per control period),
    /// when it was logged.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub telemetry: Option<Telemetry>,
}

impl Group {
    /// A group; the experiment's test must be the id's and there must be runs.
    pub fn new(
        experiment_name: &str,
        experiment: Experiment,
        runs: Vec<ObservedRun>,
    ) -> Result<Self, GapError> {
        if runs.is_empty() {
            return Err(GapError::Data(format!(
                "{experiment_name}/{}: no runs",
                experiment.test
            )));
        }
        if runs
            .iter()
            .any(|r| !r.x_cm.is_finite() || r.y_cm.is_some_and(|y| !y.is_finite()))
        {
            return Err(GapError::Data(format!(
                "{experiment_name}/{}: a run is not finite",
                experiment.test
            )));
        }
        let mut experiment = experiment;
        experiment.runs = runs.len();
        Ok(Group {
            id: GroupId {
                experiment: experiment_name.to_owned(),
                test: experiment.test,
            },
            experiment,
            runs,
            telemetry: None,
        })
    }

    /// The group with `telemetry`, one run of it logged every control period.
    pub fn with_telemetry(self, telemetry: Telemetry) -> Self {
        Group {
            telemetry: Some(telemetry),
            ..self
        }
    }

    /// Whether every run has its y.
    pub fn has_y(&self) -> bool {
        self.runs.iter().all(|r| r.y_cm.is_some())
    }

    /// Summary statistics of the runs.
    pub fn stats(&self) -> Stats {
        let xs: Vec<f64> = self.runs.iter().map(|r| r.x_cm).collect();
        let ys: Option<Vec<f64>> = self.runs.iter().map(|r| r.y_cm).collect();
        Stats::of(&xs, ys.as_deref())
    }
}

/// Mean and spread of a set of runs (cm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Number of runs.
    pub n: usize,
    /// Mean x.
    pub mean_x: f64,
    /// Mean y (when known).
    pub mean_y: Option<f64>,
    /// Sample standard deviation of x (n − 1; 0 for one run).
    pub sd_x: f64,
    /// Sample standard deviation of y.
    pub sd_y: Option<f64>,
    /// Sample covariance of x and y, cm².
    pub cov_xy: Option<f64>,
}

impl Stats {
    /// Statistics of `xs` and, when known, `ys` (same length).
    pub fn of(xs: &[f64], ys: Option<&[f64]>) -> Stats {
        let n = xs.len();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let mx = mean(xs);
        let my = ys.map(mean);
        let dof = (n.max(2) - 1) as f64;
        let var = |v: &[f64], m: f64| {
            if v.len() < 2 {
                0.0
            } else {
                v.iter().map(|a| (a - m).powi(2)).sum::<f64>() / dof
            }
        };
        let cov = ys.map(|ys| {
            if n < 2 {
                0.0
            } else {
                xs.iter()
                    .zip(ys)
                    .map(|(a, b)| (a - mx) * (b - my.unwrap_or(0.0)))
                    .sum::<f64>()
                    / dof
            }
        });
        Stats {
            n,
            mean_x: mx,
            mean_y: my,
            sd_x: var(xs, mx).sqrt(),
            sd_y: ys.map(|v| var(v, my.unwrap_or(0.0)).sqrt()),
            cov_xy: cov,
        }
    }
}

/// All measured groups.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Dataset {
    groups: Vec<Group>,
}

impl Dataset {
    /// A dataset; group ids must be unique.
    pub fn new(groups: Vec<Group>) -> Result<Self, GapError> {
        let mut d = Dataset::default();
        for g in groups {
            d.push(g)?;
        }
        Ok(d)
    }

    /// Adds a group (its id must be new).
    pub fn push(&mut self, group: Group) -> Result<(), GapError> {
        if self.groups.iter().any(|g| g.id == group.id) {
            return Err(GapError::Data(format!("group {} appears twice", group.id)));
        }
        self.groups.push(group);
        Ok(())
    }

    /// The groups.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// Gives the group `id` the telemetry of one of its runs (it must have none yet).
    pub fn attach_telemetry(&mut self, id: &GroupId, telemetry: Telemetry) -> Result<(), GapError> {
        let g = self
            .groups
            .iter_mut()
            .find(|g| g.id == *id)
            .ok_or_else(|| GapError::Data(format!("telemetry of {id}: no such group")))?;
        if g.telemetry.is_some() {
            return Err(GapError::Data(format!("{id}: telemetry given twice")));
        }
        g.telemetry = Some(telemetry);
        Ok(())
    }

    /// The experiment names, in order of first appearance.
    pub fn experiments(&self) -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        for g in &self.groups {
            if !v.contains(&g.id.experiment) {
                v.push(g.id.experiment.clone());
            }
        }
        v
    }

    /// Moves every group into the training or the held-out set according to `rule`. Both
    /// must be non-empty.
    pub fn split(self, rule: &SplitRule) -> Result<(TrainSet, HeldOutSet), GapError> {
        let known = self.experiments();
        for name in rule.named_experiments() {
            if !known.iter().any(|k| k == name) {
                return Err(GapError::Split(format!(
                    "experiment `{name}` is not in the data (have: {})",
                    known.join(", ")
                )));
            }
        }
        let (train, held): (Vec<Group>, Vec<Group>) =
            self.groups.into_iter().partition(|g| rule.trains_on(&g.id));
        if train.is_empty() {
            return Err(GapError::Split(format!(
                "{}: nothing left to train on",
                rule.describe()
            )));
        }
        if held.is_empty() {
            return Err(GapError::Split(format!(
                "{}: nothing held out",
                rule.describe()
            )));
        }
        Ok((
            TrainSet {
                rule: rule.describe(),
                groups: train,
            },
            HeldOutSet {
                rule: rule.describe(),
                groups: held,
            },
        ))
    }
}

/// Which groups are trained on; all others are held out.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitRule {
    /// Train on these experiments, hold out the rest (e.g. fit on experiment 1, predict 2
    /// and 3).
    TrainOnExperiments(Vec<String>),
    /// Hold out these experiments, train on the rest (leave-one-experiment-out).
    LeaveOut(Vec<String>),
    /// Train on these tests of every experiment, hold out the other tests (e.g. CW vs CCW).
    TrainOnTests(Vec<TestKind>),
}

impl SplitRule {
    fn trains_on(&self, id: &GroupId) -> bool {
        match self {
            SplitRule::TrainOnExperiments(v) => v.contains(&id.experiment),
            SplitRule::LeaveOut(v) => !v.contains(&id.experiment),
            SplitRule::TrainOnTests(v) => v.contains(&id.test),
        }
    }

    fn named_experiments(&self) -> &[String] {
        match self {
            SplitRule::TrainOnExperiments(v) | SplitRule::LeaveOut(v) => v,
            SplitRule::TrainOnTests(_) => &[],
        }
    }

    /// A one-line description.
    pub fn describe(&self) -> String {
        match self {
            SplitRule::TrainOnExperiments(v) => {
                format!("train on {}, hold out the rest", v.join(", "))
            }
            SplitRule::LeaveOut(v) => format!("hold out {}, train on the rest", v.join(", ")),
            SplitRule::TrainOnTests(v) => format!(
                "train on tests {}, hold out the other tests",
                v.iter().map(|t| t.as_str()).collect::<Vec<_>>().join(", ")
            ),
        }
    }
}

/// The groups a fit may see. Only [`Dataset::split`] makes one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrainSet {
    rule: String,
    groups: Vec<Group>,
}

/// The groups only the evaluation sees. Only [`Dataset::split`] makes one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOutSet {
    rule: String,
    groups: Vec<Group>,
}

impl TrainSet {
    /// The groups.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The rule that made it.
    pub fn rule(&self) -> &str {
        &self.rule
    }

    /// The same training set with the runs of each group resampled with replacement (for
    /// the bootstrap over runs).
    pub(crate) fn resampled(&self, rng: &mut crate::rng::Rng) -> TrainSet {
        TrainSet {
            rule: self.rule.clone(),
            groups: self
                .groups
                .iter()
                .map(|g| Group {
                    runs: (0..g.runs.len())
                        .map(|_| g.runs[rng.below(g.runs.len())])
                        .collect(),
                    ..g.clone()
                })
                .collect(),
        }
    }
}

impl HeldOutSet {
    /// The groups.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The rule that made it.
    pub fn rule(&self) -> &str {
        &self.rule
    }
}
