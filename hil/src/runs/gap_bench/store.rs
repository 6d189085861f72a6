//! The answers a [`super::BenchModel`] has run, shared by its clones and by the threads
//! that ask them at once.
//!
//! A run is a function of the firmware, the robot, the board, the parameters sent, the
//! effects, the experiment and the seed, so a question asked again (the nominal robot's,
//! every candidate's search grid, which do not depend on the data: the same in every case
//! of a self-test) is answered from here, the same to the bit. A question being run by
//! another thread is waited for, not run twice: two cases diagnosed side by side ask the
//! same grids at about the same time.
//!
//! The series of a run are large beside its end points (a sample per control period, two
//! series per run): the store keeps at most [`SERIES_BYTES`] of them and forgets the
//! oldest first (their end points stay). A forgotten series asked for again is run again,
//! with the same result: the store changes what a diagnosis costs, never what it says.

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};

use gap::model::ModelError;

use super::{Runs, SeriesRun};

/// The most bytes of series the store keeps (about 40 minutes of robot runs).
pub const SERIES_BYTES: usize = 1 << 30;

/// One question's answer, or the promise of it while a thread runs it.
#[derive(Default)]
struct Slot {
    answer: Mutex<Option<Result<Runs, ModelError>>>,
    ready: Condvar,
}

impl Slot {
    /// The answer as asked (its series only when `series`), None while it is being run,
    /// or when the series are wanted and it has none (kept without them, or forgotten).
    fn take(&self, series: bool, runs: usize) -> Option<Result<Runs, ModelError>> {
        let a = self.answer.lock().expect("slot lock");
        fit(a.as_ref()?, series, runs)
    }

    fn fill(&self, a: Result<Runs, ModelError>) {
        *self.answer.lock().expect("slot lock") = Some(a);
        self.ready.notify_all();
    }

    /// Waits until the slot is filled; the answer as [`Slot::take`] gives it.
    fn wait(&self, series: bool, runs: usize) -> Option<Result<Runs, ModelError>> {
        let mut a = self.answer.lock().expect("slot lock");
        while a.is_none() {
            a = self.ready.wait(a).expect("slot lock");
        }
        fit(a.as_ref()?, series, runs)
    }

    /// Drops the series, keeps the end points.
    fn forget_series(&self) {
        if let Some(Ok((_, s))) = self.answer.lock().expect("slot lock").as_mut() {
            *s = Vec::new();
        }
    }
}

/// `a` as a question with or without `series` takes it (None: it has no series and they
/// are wanted).
fn fit(
    a: &Result<Runs, ModelError>,
    series: bool,
    runs: usize,
) -> Option<Result<Runs, ModelError>> {
    match a {
        Ok((_, s)) if series && s.is_empty() && runs > 0 => None,
        Ok((ends, s)) => Some(Ok((
            ends.clone(),
            if series { s.clone() } else { Vec::new() },
        ))),
        Err(e) => Some(Err(e.clone())),
    }
}

/// Bytes of `series` in memory.
fn series_bytes(series: &[SeriesRun]) -> usize {
    series
        .iter()
        .map(|s| {
            (s.exact.samples.len() + s.counted.samples.len())
                * std::mem::size_of::<gap::series::Sample>()
        })
        .sum()
}

/// The slots holding series, oldest first with their bytes, and their bytes in all.
type Kept = (VecDeque<(Arc<Slot>, usize)>, usize);

/// The store (see the module docs).
pub(super) struct Store {
    slots: Mutex<HashMap<String, Arc<Slot>>>,
    /// The most bytes of series kept ([`SERIES_BYTES`]).
    series_bound: usize,
    kept: Mutex<Kept>,
    /// Runs made on the bench for these answers.
    runs: AtomicUsize,
}

/// What [`Store::claim`] found for each question.
pub(super) struct Claims {
    /// Answered from the store.
    pub answers: Vec<Option<Result<Runs, ModelError>>>,
    /// The questions this thread is to run (and then [`Store::fill`]).
    pub mine: Vec<usize>,
    /// The questions another thread is running.
    theirs: Vec<(usize, Arc<Slot>)>,
    /// The slots of `mine`.
    slots: Vec<Arc<Slot>>,
}

/// A thread that claimed questions and panicked before answering them leaves an error in
/// their slots, not a promise the threads waiting for them would wait on for ever.
impl Drop for Claims {
    fn drop(&mut self) {
        for slot in &self.slots {
            let mut a = slot.answer.lock().unwrap_or_else(|e| e.into_inner());
            if a.is_none() {
                *a = Some(Err(ModelError::InvalidExperiment(
                    "the thread running this question failed".to_owned(),
                )));
                slot.ready.notify_all();
            }
        }
    }
}

impl Default for Store {
    fn default() -> Self {
        Store::bounded(SERIES_BYTES)
    }
}

impl Store {
    /// An empty store that keeps at most `series_bound` bytes of series.
    fn bounded(series_bound: usize) -> Self {
        Store {
            slots: Mutex::default(),
            series_bound,
            kept: Mutex::default(),
            runs: AtomicUsize::new(0),
        }
    }

    /// Runs made on the bench for the answers.
    pub fn runs(&self) -> usize {
        self.runs.load(Ordering::Relaxed)
    }

    /// Looks each question up (`keys[i]`, `runs[i]` runs), with or without `series`: the
    /// answered ones, the ones being run by another thread, and the rest, claimed by this
    /// one (a question asked twice in one call is claimed once and waited for once).
    pub fn claim(&self, keys: &[String], runs: &[usize], series: bool) -> Claims {
        let mut c = Claims {
            answers: vec![None; keys.len()],
            mine: Vec::new(),
            theirs: Vec::new(),
            slots: Vec::new(),
        };
        let mut slots = self.slots.lock().expect("store lock");
        for (i, k) in keys.iter().enumerate() {
            if let Some(slot) = slots.get(k) {
                let pending = slot.answer.lock().expect("slot lock").is_none();
                if pending {
                    c.theirs.push((i, slot.clone()));
                    continue;
                }
                if let Some(a) = slot.take(series, runs[i]) {
                    c.answers[i] = Some(a);
                    continue;
                }
            }
            let slot = Arc::new(Slot::default());
            slots.insert(k.clone(), slot.clone());
            c.mine.push(i);
            c.slots.push(slot);
        }
        c
    }

    /// Stores the answers to `claims.mine` (`got`, in that order, `made` runs), then waits
    /// for the other threads' answers; every question's answer, in order. `run` runs a
    /// question whose answer another thread made without the series wanted.
    pub fn fill(
        &self,
        mut claims: Claims,
        got: Vec<Result<Runs, ModelError>>,
        made: usize,
        series: bool,
        runs: &[usize],
        run: impl Fn(usize) -> Result<Runs, ModelError>,
    ) -> Vec<Result<Runs, ModelError>> {
        self.runs.fetch_add(made, Ordering::Relaxed);
        for ((&i, slot), a) in claims.mine.iter().zip(&claims.slots).zip(got) {
            let bytes = a.as_ref().map_or(0, |(_, s)| series_bytes(s));
            slot.fill(a.clone());
            self.keep(slot, bytes);
            claims.answers[i] = Some(a);
        }
        for (i, slot) in std::mem::take(&mut claims.theirs) {
            let a = match slot.wait(series, runs[i]) {
                Some(a) => a,
                None => {
                    let a = run(i);
                    self.runs.fetch_add(runs[i], Ordering::Relaxed);
                    let bytes = a.as_ref().map_or(0, |(_, s)| series_bytes(s));
                    slot.fill(a.clone());
                    self.keep(&slot, bytes);
                    a
                }
            };
            claims.answers[i] = Some(a);
        }
        std::mem::take(&mut claims.answers)
            .into_iter()
            .map(|a| a.expect("every question answered"))
            .collect()
    }

    /// Counts `bytes` of series in `slot`, forgetting the oldest kept beyond the bound.
    fn keep(&self, slot: &Arc<Slot>, bytes: usize) {
        if bytes == 0 {
            return;
        }
        let mut kept = self.kept.lock().expect("kept lock");
        kept.0.push_back((slot.clone(), bytes));
        kept.1 += bytes;
        while kept.1 > self.series_bound {
            let Some((old, b)) = kept.0.pop_front() else {
                break;
            };
            kept.1 -= b;
            old.forget_series();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gap::model::RunEndpoint;
    use gap::series::{Sample, Telemetry};

    fn answer(x: f64, samples: usize) -> Result<Runs, ModelError> {
        let t = Telemetry {
            period_s: 0.015,
            samples: vec![
                Sample {
                    t_s: 0.0,
                    rpm_left: 0.0,
                    rpm_right: 0.0,
                    pwm_left: 0.0,
                    pwm_right: 0.0,
                    pose: None,
                };
                samples
            ],
        };
        let series = (samples > 0)
            .then(|| SeriesRun {
                exact: t.clone(),
                counted: t,
            })
            .into_iter()
            .collect();
        Ok((
            vec![RunEndpoint {
                x_cm: x,
                y_cm: 0.0,
                theta_rad: 0.0,
            }],
            series,
        ))
    }

    fn x(a: &Result<Runs, ModelError>) -> f64 {
        a.as_ref().unwrap().0[0].x_cm
    }

    #[test]
    fn a_question_being_run_is_waited_for_not_run_twice() {
        let store = Store::default();
        let keys = vec!["q".to_owned()];
        let first = store.claim(&keys, &[1], false);
        assert_eq!(first.mine, [0]);
        std::thread::scope(|s| {
            let waiter = s.spawn(|| {
                let second = store.claim(&keys, &[1], false);
                assert!(second.mine.is_empty(), "claimed twice");
                store.fill(second, Vec::new(), 0, false, &[1], |_| panic!("run again"))
            });
            // The waiter finds the question pending whenever it claims, before or after
            // this thread's fill.
            std::thread::sleep(std::time::Duration::from_millis(20));
            let mine = store.fill(first, vec![answer(1.5, 0)], 1, false, &[1], |_| {
                panic!("run again")
            });
            assert_eq!(x(&mine[0]), 1.5);
            assert_eq!(x(&waiter.join().unwrap()[0]), 1.5);
        });
        assert_eq!(store.runs(), 1);
    }

    #[test]
    fn a_panicked_claim_leaves_an_error_not_a_wait_for_ever() {
        let store = Store::default();
        let keys = vec!["q".to_owned()];
        drop(store.claim(&keys, &[1], false));
        let again = store.claim(&keys, &[1], false);
        assert!(again.mine.is_empty());
        assert!(again.answers[0].as_ref().is_some_and(|a| a.is_err()));
    }

    #[test]
    fn the_oldest_series_are_forgotten_beyond_the_bound_their_end_points_kept() {
        let one = 2 * 100 * std::mem::size_of::<Sample>();
        let store = Store::bounded(2 * one);
        for (k, v) in [("a", 1.0), ("b", 2.0), ("c", 3.0)] {
            let keys = vec![k.to_owned()];
            let c = store.claim(&keys, &[1], true);
            store.fill(c, vec![answer(v, 100)], 1, true, &[1], |_| unreachable!());
        }
        let keys = vec!["a".to_owned(), "b".to_owned(), "c".to_owned()];
        // Without series, all three are answered; with them, "a" is run again.
        let c = store.claim(&keys, &[1, 1, 1], false);
        assert!(c.mine.is_empty());
        drop(store.fill(c, Vec::new(), 0, false, &[1, 1, 1], |_| unreachable!()));
        let c = store.claim(&keys, &[1, 1, 1], true);
        assert_eq!(c.mine, [0]);
        assert_eq!(
            c.answers[1].as_ref().map(|a| a.as_ref().unwrap().1.len()),
            Some(1)
        );
        let got = store.fill(
            c,
            vec![answer(1.0, 100)],
            1,
            true,
            &[1, 1, 1],
            |_| unreachable!(),
        );
        assert_eq!(got.iter().map(x).collect::<Vec<_>>(), [1.0, 2.0, 3.0]);
        assert_eq!(store.runs(), 4);
    }
}
