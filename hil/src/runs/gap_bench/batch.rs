//! Many predictions at once. The diagnosis' scoring ([`gap::Scorer`]) asks a model for one
//! group at a time, and one group is one bench run when only systematic effects are on: run
//! one by one, a pool of threads would have nothing to share. [`Batched::eval`] runs the
//! scoring twice: first against a recorder that notes every prediction asked for (and
//! answers zeros), then, after all of them ran on the bench in one parallel batch, against
//! the answers. Scoring asks the same questions whatever the answers are (it has no
//! branches on them), so the second pass sees only answered questions; answers are kept,
//! so a question asked again (the nominal model's) is not run again. With telemetry
//! ([`Batched::with_series`]) each question's runs record their series as they run, kept
//! beside the answer for [`Batched::series`]: the series costs no run of its own.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use gap::model::{Experiment, Model, ModelError, RunEndpoint};
use gap::{EffectParams, ParamSpec, Unsupported};

use super::{BenchModel, SeriesRun};

type Answer = Result<Vec<RunEndpoint>, ModelError>;

fn key(params: &EffectParams, exp: &Experiment) -> String {
    serde_json::to_string(&(params, exp)).expect("params and experiments serialise")
}

/// The bench with its answers kept, and batches of questions run in parallel.
pub struct Batched<'a> {
    bench: &'a BenchModel,
    answers: Mutex<HashMap<String, Answer>>,
    /// Whether runs record their series, and the series of the questions run.
    with_series: bool,
    series: Mutex<HashMap<String, Vec<SeriesRun>>>,
    runs: AtomicUsize,
}

/// Notes the questions, answers zeros.
struct Recorder<'a> {
    bench: &'a BenchModel,
    asked: Mutex<Vec<(EffectParams, Experiment)>>,
}

impl Model for Recorder<'_> {
    fn name(&self) -> String {
        self.bench.name()
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        self.bench.parameters()
    }
    fn predict(&self, params: &EffectParams, exp: &Experiment) -> Answer {
        self.asked
            .lock()
            .expect("recorder lock")
            .push((params.clone(), exp.clone()));
        Ok(vec![
            RunEndpoint {
                x_cm: 0.0,
                y_cm: 0.0,
                theta_rad: 0.0,
            };
            exp.runs
        ])
    }
}

impl<'a> Batched<'a> {
    /// No answers yet.
    pub fn new(bench: &'a BenchModel) -> Self {
        Self::with_series(bench, false)
    }

    /// No answers yet; with `series`, every question's runs record their telemetry.
    pub fn with_series(bench: &'a BenchModel, series: bool) -> Self {
        Batched {
            bench,
            answers: Mutex::new(HashMap::new()),
            with_series: series,
            series: Mutex::new(HashMap::new()),
            runs: AtomicUsize::new(0),
        }
    }

    /// Whether the runs record their series.
    pub fn records_series(&self) -> bool {
        self.with_series
    }

    /// The telemetry of every run of `(params, exp)`, run now if it was not asked before
    /// (None: the bench could not run it, or this batch records no series).
    pub fn series(&self, params: &EffectParams, exp: &Experiment) -> Option<Vec<SeriesRun>> {
        if !self.with_series {
            return None;
        }
        let k = key(params, exp);
        if !self.series.lock().expect("series lock").contains_key(&k) {
            self.answer(vec![(params.clone(), exp.clone())]);
        }
        self.series.lock().expect("series lock").get(&k).cloned()
    }

    /// Bench runs made so far.
    pub fn runs(&self) -> usize {
        self.runs.load(Ordering::Relaxed)
    }

    /// `f` against the bench, every prediction it asks for run in one parallel batch (see
    /// the module docs).
    pub fn eval<T>(&self, f: impl Fn(&dyn Model) -> T) -> T {
        let recorder = Recorder {
            bench: self.bench,
            asked: Mutex::new(Vec::new()),
        };
        let _ = f(&recorder);
        let asked = recorder.asked.into_inner().expect("recorder lock");
        self.answer(asked);
        f(self)
    }

    /// Runs the questions not answered yet, in one batch.
    fn answer(&self, asked: Vec<(EffectParams, Experiment)>) {
        let mut todo: Vec<(String, (EffectParams, Experiment))> = Vec::new();
        {
            let answers = self.answers.lock().expect("answers lock");
            for q in asked {
                let k = key(&q.0, &q.1);
                if !answers.contains_key(&k) && !todo.iter().any(|(t, _)| *t == k) {
                    todo.push((k, q));
                }
            }
        }
        if todo.is_empty() {
            return;
        }
        let questions: Vec<(EffectParams, Experiment)> =
            todo.iter().map(|(_, q)| q.clone()).collect();
        let n: usize = questions.iter().map(|q| q.1.runs).sum();
        let got = self.bench.run_many(&questions, self.with_series);
        self.runs.fetch_add(n, Ordering::Relaxed);
        let mut answers = self.answers.lock().expect("answers lock");
        let mut series = self.series.lock().expect("series lock");
        for ((k, _), a) in todo.into_iter().zip(got) {
            let a = a.map(|(ends, s)| {
                if !s.is_empty() {
                    series.insert(k.clone(), s);
                }
                ends
            });
            answers.insert(k, a);
        }
    }
}

impl Model for Batched<'_> {
    fn name(&self) -> String {
        self.bench.name()
    }

    fn parameters(&self) -> Vec<ParamSpec> {
        self.bench.parameters()
    }

    fn unsupported(&self) -> Vec<Unsupported> {
        self.bench.unsupported()
    }

    fn predict(&self, params: &EffectParams, exp: &Experiment) -> Answer {
        let k = key(params, exp);
        if let Some(a) = self.answers.lock().expect("answers lock").get(&k) {
            return a.clone();
        }
        self.answer(vec![(params.clone(), exp.clone())]);
        self.answers.lock().expect("answers lock")[&k].clone()
    }
}
