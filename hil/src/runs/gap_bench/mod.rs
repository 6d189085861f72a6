//! The bench itself as the sim-to-real gap model: [`BenchModel`] implements [`gap::Model`]
//! by running the real firmware ELF on the plant with candidate effects of
//! `plant_model::effects` switched on, so that what the nominal robot does by itself (the
//! firmware's turn overshoot from coasting, its start-up transients) is in every prediction
//! and never mistaken for an effect.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | the model: runs of an experiment on the bench, in parallel, by seed |
//! | `params.rs` | one number per library effect, and its `[effects.<name>]` table |
//! | `reading.rs` | a value as a person reads it: its size, side in words, unit, bound |
//! | `batch.rs` | many predictions asked for at once, run in one parallel batch |
//! | `select.rs` | the bench-backed diagnosis: 1-D fits, cross-validation, held-out gap |
//! | `shard.rs` | the diagnosis' candidates split over machines, and the merge of the shards |
//! | `store.rs` | the answers run, shared by a model's clones and threads |
//! | `speed.rs` | the diagnosis timed with one job and with N (`hil bench --diagnosis`) |
//! | `select/options.rs` | its options: candidates, the searches' resolution, runs per centroid, joint fits |
//! | `select/choose.rs` | the choice over fitted candidates, the alike set, the notes |
//! | `select/render.rs` | the diagnosis' report as text |
//! | `select/telemetry.rs` | its telemetry part: the series score of a candidate's runs, its report |
//! | `select/tests.rs` | the selection's unit tests: folds and choices on made-up groups |
//! | `selftest.rs` | "real" data made by the bench with one hidden effect, diagnosed blind |
//! | `series.rs` | the telemetry of a run, one row per control period, and its residual score |

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use gap::model::{check_params, Experiment, Model, ModelError, RunEndpoint, TestKind};
use gap::{EffectParams, ParamSpec};
use plant_model::RobotConfig;

use crate::bench::BenchOptions;
use crate::bench::Observer;
use crate::firmware::elf::Firmware;
use crate::firmware::link::Param;
use crate::firmware::params::Tell;
use crate::runs::experiment::{run_test_observed, Test, TestOptions};
use crate::runs::odometry::run_seed;
use store::Store;

mod batch;
mod params;
pub mod reading;
mod select;
mod selftest;
mod series;
mod shard;
mod speed;
mod store;

pub use batch::Batched;
pub use params::{apply, bench_parameters};
pub use select::{
    choose, diagnose_bench, fit_candidates, fit_effects_jointly, fit_nominal, kinematic_shortlist,
    third_starts, training_score, BenchCandidate, BenchDiagnosis, ChosenValue, FitPlan,
    FittedCandidate, JointFit, NominalFit, SelectOptions, Surrogate, CENTROID_RUNS, GRID_POINTS,
    REFINE_STEPS,
};
pub use selftest::{
    bench_self_test, bench_self_test_of, bench_self_test_on, self_test_split, BenchCase,
    BenchSelfTest, SelfTestDesign, DEFAULT_CASES, HELDOUT_CUT_PCT, REAL_ROBOT_CASE, RUNS_PER_GROUP,
    SHUTTLE_CORNER_DEG, SHUTTLE_GROUP, THREE_EFFECT_CASE, TWO_EFFECT_CASES, VALUE_WITHIN_PCT,
};
pub use series::{
    series_chi2, series_chi2_of_runs, series_noise, SegmentFit, SeriesNoise, SeriesRun,
    SeriesScore, CONTROL_PERIOD_S,
};
pub use shard::{merge, partial_path, run_shard, MergeError, Partial, ShardPlan, PARTIAL_KIND};
pub use speed::{measure_diagnosis, DiagnosisSpeed, SpeedPlan, Timed, BUDGET_S};

/// Where in the firmware's control period run `run` of the `runs` of an experiment seeded
/// `seed` starts, s. A person starts each run at no particular phase of the controller's
/// tick, and the firmware's discrete decisions (the tick a turn's count is reached at, the
/// count a leg stops on) depend on it: runs of one robot from one start phase would all
/// make the same of them, and a prediction from one phase jumps with the smallest change
/// of an effect. The runs spread evenly over one period, from an offset drawn from the
/// seed (a stratified sample: their mean varies less with the offset than that of as many
/// phases drawn one by one, so a prediction moves less when everything before the start
/// shifts, as a firmware that boots sooner shifts it). Drawn apart from the plant's own
/// streams (the seed's mix with a constant of its own).
pub fn start_phase_s(seed: u64, run: usize, runs: usize) -> f64 {
    use plant_model::rng::{mix, unit};
    let offset = unit(mix(seed ^ START_PHASE_STREAM));
    (run as f64 + offset) / runs.max(1) as f64 * CONTROL_PERIOD_S
}

/// The stream constant of [`start_phase_s`].
const START_PHASE_STREAM: u64 = 0x57a2_7fa5_e000_0001;

/// Robot time without progress after which a run is ended as hung, s.
const HANG_AFTER_S: f64 = 5.0;

/// The bench as a [`gap::Model`]: the firmware, the nominal robot the effects are applied
/// to, and how many runs go in parallel.
#[derive(Clone)]
pub struct BenchModel {
    firmware: Firmware,
    nominal: RobotConfig,
    bench: BenchOptions,
    jobs: usize,
    /// Parameters sent after each experiment's own (`--param`: theirs win).
    params: Vec<(Param, f32)>,
    /// The answers of this model and its clones (`store.rs`).
    store: Arc<Store>,
}

/// One run to make: the robot with its effects, the test, the firmware's parameters and
/// leg, and the run's seed.
struct RunJob {
    robot: usize,
    test: Test,
    params: Vec<(Param, f32)>,
    leg_mm: f64,
    seed: u64,
    /// Where in the control period the run starts, s ([`start_phase_s`]).
    start_delay_s: f64,
    /// Commanded heading change of the whole test, rad.
    heading_rad: f64,
    /// Record the run's telemetry (see `series.rs`).
    series: bool,
}

/// The answer to one request of [`BenchModel::run_many`]: the end of every run, and the
/// telemetry of every run when it was asked for (else none).
type Runs = (Vec<RunEndpoint>, Vec<SeriesRun>);

impl BenchModel {
    /// `firmware` on `nominal` (whose geometry is the reference of the effects), `jobs`
    /// runs at a time (at least 1).
    pub fn new(firmware: Firmware, nominal: RobotConfig, jobs: usize) -> Self {
        BenchModel {
            firmware,
            nominal,
            bench: BenchOptions::default(),
            jobs: jobs.max(1),
            params: Vec::new(),
            store: Arc::default(),
        }
    }

    /// The same model on the robot wired by `board` (default Henrytwo's).
    pub fn on_board(mut self, board: crate::board::Board) -> Self {
        self.bench.board = board;
        self.store = Arc::default();
        self
    }

    /// The same model with `params` sent before every run, after the robot
    /// config's settings and each experiment's parameters (a later value wins).
    pub fn with_params(mut self, params: Vec<(Param, f32)>) -> Self {
        self.params = params;
        self.store = Arc::default();
        self
    }

    /// Runs this model and its clones have made on the bench (an answer kept is not run
    /// again, nor counted again).
    pub fn runs_made(&self) -> usize {
        self.store.runs()
    }

    /// The same model with no answers kept from before (for timing it).
    pub(crate) fn without_answers(&self) -> Self {
        BenchModel {
            store: Arc::default(),
            ..self.clone()
        }
    }

    /// The nominal robot.
    pub fn nominal(&self) -> &RobotConfig {
        &self.nominal
    }

    /// The firmware it runs.
    pub fn firmware(&self) -> &Firmware {
        &self.firmware
    }

    /// The physical reference of the nominal robot, as the manifests state it.
    pub fn reference(&self) -> gap::Reference {
        gap::manifest::reference_from_config(&self.nominal)
    }

    /// Why the bench cannot run `exp`, if it cannot.
    fn check(&self, exp: &Experiment) -> Result<Test, ModelError> {
        let test = match exp.test {
            TestKind::Firmware(t) => t,
            TestKind::TriangleCw => {
                return Err(ModelError::Unsupported {
                    model: self.name(),
                    what: "the clockwise triangle (the firmware has no selector for it)".into(),
                })
            }
        };
        let ours = self.reference();
        let theirs = exp.reference;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs());
        if !(close(ours.wheelbase_mm, theirs.wheelbase_mm)
            && close(ours.mm_per_count, theirs.mm_per_count))
        {
            return Err(ModelError::InvalidExperiment(format!(
                "its reference ({} mm wheelbase, {} mm per count) is not the bench's nominal \
                 robot ({} mm, {} mm per count): give the robot config the data were \
                 recorded against",
                theirs.wheelbase_mm, theirs.mm_per_count, ours.wheelbase_mm, ours.mm_per_count
            )));
        }
        let fw = &exp.firmware;
        if !(fw.leg_mm.is_finite() && fw.leg_mm > 0.0) {
            return Err(ModelError::InvalidExperiment(format!(
                "leg {} mm: it must be positive",
                fw.leg_mm
            )));
        }
        if fw.straight_legs != gap::StraightLegs::SpeedSetpoints {
            return Err(ModelError::Unsupported {
                model: self.name(),
                what: "corrected-odometry straight legs (the bench's firmware holds each \
                       wheel at its speed set-point)"
                    .into(),
            });
        }
        Ok(test)
    }

    /// The firmware parameters of `exp`, sent over the protocol as a real run's host does,
    /// after the nominal robot's geometry.
    ///
    /// The set-points are sent times cL and cR: the data's firmware
    /// ([`gap::StraightLegs::SpeedSetpoints`], the thesis' own) holds each wheel's count rate
    /// at its set-point, and its corrections weigh only the stop rules; the bench's firmware
    /// takes its set-points as ground speeds and holds set-point / c counts. Sent as given, a
    /// correction would straighten (or bend) the bench's legs where the robot's stayed as
    /// they were: the thesis' UMBmark 2 and 3, run with cL, cR 1.6 % off 1, would curve
    /// twice as much on the bench as on the floor. Without set-points in the data, the
    /// firmware's own (the robot config's, else its factory values) are the base.
    fn firmware_params(&self, exp: &Experiment) -> Vec<(Param, f32)> {
        let fw = &exp.firmware;
        let mut p = vec![
            (Param::MmPerCountLeft, fw.mm_per_count as f32),
            (Param::MmPerCountRight, fw.mm_per_count as f32),
            (Param::WheelbaseMm, fw.wheelbase_mm as f32),
            (Param::CorrLeft, fw.c_left as f32),
            (Param::CorrRight, fw.c_right as f32),
            (Param::TurnUmbmarkDeg, fw.turn_umbmark_deg as f32),
            (Param::TurnTriangleDeg, fw.turn_triangle_deg as f32),
        ];
        let given = match (fw.setpoint_left, fw.setpoint_right) {
            (Some(l), Some(r)) => Some((l, r)),
            _ => None,
        };
        if given.is_some() || fw.c_left != 1.0 || fw.c_right != 1.0 {
            let (l, r) = given.unwrap_or_else(|| {
                let believed = crate::firmware::params::plan(
                    &self.firmware,
                    &self.nominal,
                    &self.bench.board,
                    Tell::Robot,
                    &self.params,
                )
                .1;
                (believed.setpoint_rpm[0], believed.setpoint_rpm[1])
            });
            p.push((Param::SetpointLeft, (l * fw.c_left) as f32));
            p.push((Param::SetpointRight, (r * fw.c_right) as f32));
        }
        p
    }

    /// Runs every `(params, experiment)` of `requests`, all their runs in one pool of
    /// [`BenchModel::new`]'s `jobs` threads; answers in request order. Run `i` of an
    /// experiment has the seed `run_seed(experiment.seed, i)` whatever the job count, so
    /// the answers do not depend on it.
    pub fn predict_many(
        &self,
        requests: &[(EffectParams, Experiment)],
    ) -> Vec<Result<Vec<RunEndpoint>, ModelError>> {
        self.run_many(requests, false)
            .into_iter()
            .map(|a| a.map(|(ends, _)| ends))
            .collect()
    }

    /// [`BenchModel::predict_many`], with the telemetry of each request's run 0 when
    /// `series` (the same runs: recording the telemetry changes nothing in them).
    /// Answers kept from an earlier question (of this model or a clone) are not run again.
    pub fn run_many(
        &self,
        requests: &[(EffectParams, Experiment)],
        series: bool,
    ) -> Vec<Result<Runs, ModelError>> {
        let keys: Vec<String> = requests
            .iter()
            .map(|(p, e)| serde_json::to_string(&(p, e)).expect("params and experiments serialise"))
            .collect();
        let runs: Vec<usize> = requests.iter().map(|(_, e)| e.runs).collect();
        let claims = self.store.claim(&keys, &runs, series);
        let asked: Vec<(EffectParams, Experiment)> =
            claims.mine.iter().map(|&i| requests[i].clone()).collect();
        let got = if asked.is_empty() {
            Vec::new()
        } else {
            self.run_fresh(&asked, series)
        };
        let made = asked.iter().map(|(_, e)| e.runs).sum();
        self.store.fill(claims, got, made, series, &runs, |i| {
            self.run_fresh(std::slice::from_ref(&requests[i]), series)
                .remove(0)
        })
    }

    /// [`BenchModel::run_many`] without the store: every request run now.
    fn run_fresh(
        &self,
        requests: &[(EffectParams, Experiment)],
        series: bool,
    ) -> Vec<Result<Runs, ModelError>> {
        let specs = bench_parameters();
        let mut robots = Vec::new();
        let mut jobs = Vec::new();
        let mut answers: Vec<Result<Runs, ModelError>> = Vec::with_capacity(requests.len());
        // (request, first job, runs)
        let mut spans = Vec::new();
        for (i, (params, exp)) in requests.iter().enumerate() {
            let test =
                match check_params(&self.name(), &specs, params).and_then(|()| self.check(exp)) {
                    Ok(t) => t,
                    Err(e) => {
                        answers.push(Err(e));
                        continue;
                    }
                };
            match apply(&self.nominal, params) {
                Ok(robot) => robots.push(robot),
                Err(e) => {
                    answers.push(Err(e));
                    continue;
                }
            }
            answers.push(Ok((Vec::new(), Vec::new())));
            let mut fw_params = self.firmware_params(exp);
            fw_params.extend_from_slice(&self.params);
            let legs = exp.test.legs() as f64;
            let heading_rad =
                (legs * exp.test.turn_sign() * exp.test.turn_deg(&exp.firmware)).to_radians();
            spans.push((i, jobs.len(), exp.runs));
            for run in 0..exp.runs {
                jobs.push(RunJob {
                    robot: robots.len() - 1,
                    test,
                    params: fw_params.clone(),
                    leg_mm: exp.firmware.leg_mm,
                    seed: run_seed(exp.seed, run),
                    start_delay_s: start_phase_s(exp.seed, run, exp.runs),
                    heading_rad,
                    series,
                });
            }
        }
        let results = self.run_jobs(&robots, &jobs);
        for (i, first, runs) in spans {
            answers[i] = results[first..first + runs]
                .iter()
                .cloned()
                .collect::<Result<Vec<_>, _>>()
                .map(|v| v.into_iter().unzip())
                .map(|(ends, telemetry): (Vec<_>, Vec<Option<SeriesRun>>)| {
                    (ends, telemetry.into_iter().flatten().collect())
                });
        }
        answers
    }

    /// Runs `jobs` over the pool; results in job order.
    fn run_jobs(
        &self,
        robots: &[RobotConfig],
        jobs: &[RunJob],
    ) -> Vec<Result<(RunEndpoint, Option<SeriesRun>), ModelError>> {
        let next = AtomicUsize::new(0);
        let threads = self.jobs.min(jobs.len()).max(1);
        type Done = (usize, Result<(RunEndpoint, Option<SeriesRun>), ModelError>);
        let mut done: Vec<Done> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    s.spawn(|| {
                        let mut mine = Vec::new();
                        loop {
                            let k = next.fetch_add(1, Ordering::Relaxed);
                            let Some(job) = jobs.get(k) else { break };
                            mine.push((k, self.run_one(&robots[job.robot], job)));
                        }
                        mine
                    })
                })
                .collect();
            workers
                .into_iter()
                .flat_map(|w| w.join().expect("a bench worker panicked"))
                .collect()
        });
        done.sort_by_key(|(k, _)| *k);
        done.into_iter().map(|(_, r)| r).collect()
    }

    /// One run on the bench, its end in the experiment's frame (and its telemetry, when the
    /// job asks for it).
    fn run_one(
        &self,
        robot: &RobotConfig,
        job: &RunJob,
    ) -> Result<(RunEndpoint, Option<SeriesRun>), ModelError> {
        let opts = TestOptions {
            leg_mm: job.leg_mm,
            bench: BenchOptions {
                seed: job.seed,
                ..self.bench
            },
            params: job.params.clone(),
            tell: Tell::Robot,
            // A robot that cannot move (a dead band beyond its drive) stops the run early
            // instead of using the whole time limit.
            hang_after_s: Some(HANG_AFTER_S),
            start_delay_s: job.start_delay_s,
            ..TestOptions::default()
        };
        let probe = job
            .series
            .then(|| Box::new(series::SeriesProbe::new(CONTROL_PERIOD_S)) as Box<dyn Observer>);
        let (run, probe) = run_test_observed(self.firmware.clone(), robot, job.test, &opts, probe)
            .map_err(|e| {
                ModelError::InvalidExperiment(format!(
                    "the bench could not run {}: {e}",
                    job.test.name()
                ))
            })?;
        let telemetry = probe
            .and_then(|p| p.into_any().downcast::<series::SeriesProbe>().ok())
            .map(|p| p.finish());
        let theta = run.final_pose.theta_deg.to_radians() - job.heading_rad;
        let end = RunEndpoint {
            x_cm: run.x_cm,
            y_cm: run.y_cm,
            theta_rad: theta.sin().atan2(theta.cos()),
        };
        Ok((end, telemetry))
    }
}

impl Model for BenchModel {
    fn name(&self) -> String {
        format!("bench ({})", self.firmware.name())
    }

    fn parameters(&self) -> Vec<ParamSpec> {
        bench_parameters()
    }

    fn predict(
        &self,
        params: &EffectParams,
        experiment: &Experiment,
    ) -> Result<Vec<RunEndpoint>, ModelError> {
        self.predict_many(&[(params.clone(), experiment.clone())])
            .pop()
            .expect("one answer per request")
    }

    /// One run of `experiment` (seed `run_seed(experiment.seed, 0)`, the run 0 of
    /// [`Model::predict`]), sampled once per control period ([`CONTROL_PERIOD_S`]); see
    /// `series.rs` for what a row holds. Its speeds are the encoder counts' of each period
    /// ([`series::SeriesRun::counted`]), as a robot's firmware logs them: the telemetry it
    /// is compared with is such a log, and the plant's exact wheel angles would differ from
    /// it by up to a count per period even where the model is the robot.
    fn predict_series(
        &self,
        params: &EffectParams,
        experiment: &Experiment,
    ) -> Result<gap::series::Telemetry, ModelError> {
        let one = Experiment {
            runs: 1,
            ..experiment.clone()
        };
        let (_, series) = self
            .run_many(&[(params.clone(), one)], true)
            .pop()
            .expect("one answer per request")?;
        Ok(series
            .into_iter()
            .next()
            .expect("run 0 records its series")
            .counted)
    }
}
