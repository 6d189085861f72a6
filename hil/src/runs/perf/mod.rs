//! `hil bench`: how fast the bench runs, measured in one run, as ratios.
//!
//! Three runs of the same firmware over the same robot time:
//! - the bench: the firmware against the plant, as every scenario runs it;
//! - raw simavr: the same ELF in a bare simavr (its own timer modules,
//!   timers 2 and 4 included), given the bench run's inputs at their cycles
//!   (the encoder lines as the firmware saw them, the battery on A0 and VCC,
//!   the leg length written before the command, the command byte), so the
//!   firmware executes the same instructions; no plant, no PWM model, no
//!   analysis. A replay must end with the bench run's SRAM, or the times do
//!   not compare ([`PerfError::ReplayDiverged`]);
//! - raw simavr without its PWM timers: the same, with timers 2 and 4 taken
//!   off simavr (their registers just stored), which is what the bench does.
//!
//! The bench's overhead is its wall time over the last one's. Wall time is
//! read from the host clock around whole runs, never inside a simulation.

//!
//! | file | part |
//! |---|---|
//! | `record.rs` | a bench run recorded for replay ([`Recorded`]) |
//! | `replay.rs` | the raw simavr replay ([`raw_replay`]) |

use plant_model::RobotConfig;
use serde::Serialize;

use crate::bench::BenchError;
use crate::board::Board;
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::runs::experiment::TestName;

mod record;
mod replay;

pub use record::{bench_run, bench_run_described, replayable_start, Recorded};
pub use replay::{raw_replay, Replayed};

/// One measured run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Measured {
    pub robot_s: f64,
    pub wall_s: f64,
    pub rtf: f64,
}

impl Measured {
    fn new(robot_s: f64, wall_s: f64) -> Self {
        Self {
            robot_s,
            wall_s,
            rtf: robot_s / wall_s.max(1e-9),
        }
    }
}

/// What `hil bench` runs.
pub struct BenchPlan<'a> {
    /// The firmware timed first: the robust build, or the user's.
    pub robust: &'a Firmware,
    /// Its test description when it is run black-box (a firmware without
    /// the bench interface); None: its bench interface.
    pub described: Option<&'a Description>,
    /// The board the described firmware runs on (the bench's builds and
    /// the thesis sketch run on Henrytwo's).
    pub board: &'a Board,
    /// The thesis build, when it is to be timed too.
    pub thesis: Option<&'a Firmware>,
    pub robot: &'a RobotConfig,
    /// A thesis test, or with `described` any test it names.
    pub test: TestName,
    pub leg_mm: f64,
    /// Each robust run is timed this many times, interleaved; the fastest
    /// counts (the least disturbed by the rest of the machine). The thesis
    /// build's long runs are timed once.
    pub repeats: usize,
    /// A firmware without the bench interface and its description (the
    /// thesis sketch), when it is to be timed too.
    pub sketch: Option<(&'a Firmware, &'a Description)>,
    /// Also time raw simavr with its own PWM timers (slow).
    pub raw_with_pwm_timers: bool,
    /// Told what is being timed, before each run.
    pub progress: &'a dyn Fn(&str),
}

/// Errors of `hil bench`.
#[derive(Debug, thiserror::Error)]
pub enum PerfError {
    #[error(transparent)]
    Bench(#[from] BenchError),
    #[error(
        "the raw simavr replay of the {build} build did not end in the bench run's firmware \
         state, so their times do not compare; the replay misses an input the bench gave"
    )]
    ReplayDiverged { build: String },
    #[error(
        "the {build} build's bench run ended elsewhere when its inputs were recorded; \
         recording must not change a run (a bug in the bench)"
    )]
    RecordingChangedTheRun { build: String },
}

/// The bench and raw simavr on one build: fastest of the repeats each.
#[derive(Debug, Clone, Serialize)]
pub struct BuildSpeed {
    pub bench: Measured,
    pub raw_without_pwm_timers: Measured,
    pub raw: Option<Measured>,
    /// Bench wall time over raw simavr's (without its PWM timers) for the
    /// same robot time and the same instructions.
    pub overhead_ratio: f64,
    /// Each round's bench wall time over the raw replay's timed right after
    /// it: their spread shows how steady the machine was (the fastest runs,
    /// which `overhead_ratio` compares, may come from different rounds).
    pub round_ratios: Vec<f64>,
    pub awake_fraction: f64,
    /// Callbacks from simavr into the bench per robot second.
    pub callbacks_per_robot_s: f64,
    /// Share of the callbacks that raised planned encoder edges without
    /// touching the plant.
    pub lean_edge_fraction: f64,
    /// Share of the reads of a lazy B answered without the plant.
    pub quiet_b_read_fraction: f64,
    pub completed: bool,
}

impl BuildSpeed {
    /// The lowest and highest of the rounds' ratios.
    pub fn round_ratio_range(&self) -> (f64, f64) {
        let lo = self
            .round_ratios
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let hi = self.round_ratios.iter().copied().fold(0.0, f64::max);
        (lo, hi)
    }

    /// Whether some round's ratio lies more than 15 % from the fastest
    /// runs' (`overhead_ratio`): the machine's load changed while timing.
    pub fn rounds_disagree(&self) -> bool {
        let (lo, hi) = self.round_ratio_range();
        hi > 1.15 * self.overhead_ratio || lo < self.overhead_ratio / 1.15
    }
}

/// Keep the faster of `best` and `m`.
fn keep_fastest(best: &mut Option<Measured>, m: Measured) {
    if best.is_none_or(|b| m.wall_s < b.wall_s) {
        *best = Some(m);
    }
}

/// `a`'s wall time over `b`'s.
fn wall_ratio(a: Measured, b: Measured) -> f64 {
    a.wall_s / b.wall_s.max(1e-9)
}

/// How a build is run: by its bench interface with legs of `leg_mm`, or
/// black-box from its test description.
#[derive(Clone, Copy)]
enum How<'a> {
    Interface { leg_mm: f64 },
    Described(&'a Description, &'a Board),
}

/// Time one build as `how` says: a recorded bench run for the
/// replays (not timed), then the plan's `repeats` times over: an unrecorded
/// bench run and the replays.
fn measure_build(
    fw: &Firmware,
    plan: &BenchPlan,
    how: How,
    raw_with_pwm_timers: bool,
) -> Result<BuildSpeed, PerfError> {
    let name = fw.name();
    let bench_run = |fw: &Firmware, robot, test: &TestName, record| match how {
        How::Interface { leg_mm } => {
            let thesis = test.thesis().ok_or_else(|| {
                BenchError::Description(format!(
                    "{test} is no test of the bench's own builds (umbmark-cw, umbmark-ccw, line, \
                     triangle)"
                ))
            })?;
            bench_run(fw, robot, thesis, leg_mm, record)
        }
        How::Described(d, board) => bench_run_described(fw, robot, test, d, board, record),
    };
    (plan.progress)(&format!("{name}: recording the bench run's inputs"));
    let rec = bench_run(fw, plan.robot, &plan.test, true)?;
    let mut bench: Option<Measured> = None;
    let mut raw_np: Option<Measured> = None;
    let mut raw: Option<Measured> = None;
    let mut round_ratios = Vec::new();
    let repeats = plan.repeats.max(1);
    for i in 0..repeats {
        (plan.progress)(&format!("{name}: timing, round {} of {repeats}", i + 1));
        let run = bench_run(fw, plan.robot, &plan.test, false)?;
        if run.end_cycle != rec.end_cycle || run.fingerprint != rec.fingerprint {
            return Err(PerfError::RecordingChangedTheRun {
                build: fw.name().to_string(),
            });
        }
        keep_fastest(&mut bench, run.measured);
        let replay = |pwm: bool, best: &mut Option<Measured>| -> Result<Measured, PerfError> {
            let r = raw_replay(fw, &rec, pwm)?;
            if !r.faithful {
                return Err(PerfError::ReplayDiverged {
                    build: fw.name().to_string(),
                });
            }
            keep_fastest(best, r.measured);
            Ok(r.measured)
        };
        let raw_round = replay(false, &mut raw_np)?;
        round_ratios.push(wall_ratio(run.measured, raw_round));
        if raw_with_pwm_timers {
            replay(true, &mut raw)?;
        }
    }
    let raw_np = raw_np.expect("at least one repeat");
    let bench = bench.expect("at least one repeat");
    Ok(BuildSpeed {
        overhead_ratio: wall_ratio(bench, raw_np),
        round_ratios,
        awake_fraction: rec.awake_fraction,
        callbacks_per_robot_s: rec.callbacks as f64 / rec.measured.robot_s,
        lean_edge_fraction: rec.lean_edge_callbacks as f64 / rec.callbacks.max(1) as f64,
        quiet_b_read_fraction: rec.quiet_b_reads as f64 / rec.b_reads.max(1) as f64,
        completed: rec.completed,
        bench,
        raw_without_pwm_timers: raw_np,
        raw,
    })
}

/// Run the plan: the robust build (bench, raw simavr with and without its
/// PWM timers), then the thesis build (bench, raw without PWM timers).
pub fn measure(plan: &BenchPlan) -> Result<BenchReport, PerfError> {
    let how = match plan.described {
        Some(d) => How::Described(d, plan.board),
        None => How::Interface {
            leg_mm: plan.leg_mm,
        },
    };
    let robust = measure_build(plan.robust, plan, how, plan.raw_with_pwm_timers)?;
    // The thesis build is slow (busy loops): its square is smaller, so that
    // its runs too can be timed more than once (a busy loop's speed does not
    // depend on the leg).
    let thesis = match plan.thesis {
        Some(fw) => Some(measure_build(
            fw,
            plan,
            How::Interface {
                leg_mm: plan.leg_mm.min(THESIS_LEG_MM),
            },
            false,
        )?),
        None => None,
    };
    // The thesis sketch, black-box: its own 400 mm legs.
    let henrytwo = Board::default();
    let sketch = match plan.sketch {
        Some((fw, d)) => Some(measure_build(
            fw,
            plan,
            How::Described(d, &henrytwo),
            false,
        )?),
        None => None,
    };
    Ok(BenchReport {
        test: plan.test.name().into(),
        firmware: match plan.described {
            Some(d) => d.firmware_name(plan.robust),
            None => plan.robust.name(),
        },
        rtf_robust_umbmark: robust.bench.rtf,
        rtf_thesis: thesis.as_ref().map(|t| t.bench.rtf),
        rtf_raw_simavr: robust.raw.as_ref().map(|r| r.rtf),
        rtf_raw_simavr_without_pwm_timers: robust.raw_without_pwm_timers.rtf,
        overhead_ratio: robust.overhead_ratio,
        thesis_overhead_ratio: thesis.as_ref().map(|t| t.overhead_ratio),
        awake_fraction: robust.awake_fraction,
        callbacks_per_robot_s: robust.callbacks_per_robot_s,
        robot_s: robust.bench.robot_s,
        thesis_robot_s: thesis.as_ref().map(|t| t.bench.robot_s),
        sketch_overhead_ratio: sketch.as_ref().map(|t| t.overhead_ratio),
        repeats: plan.repeats.max(1),
        robust,
        thesis,
        sketch,
    })
}

/// Longest leg of the thesis build's timed square.
pub const THESIS_LEG_MM: f64 = 500.0;

/// The `hil bench` result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub test: String,
    /// The firmware timed first (`robust`, `rtf_robust_umbmark`,
    /// `overhead_ratio`): the robust build's name, or a described
    /// firmware's.
    pub firmware: String,
    pub rtf_robust_umbmark: f64,
    pub rtf_thesis: Option<f64>,
    /// Raw simavr with its own PWM timers (when timed).
    pub rtf_raw_simavr: Option<f64>,
    pub rtf_raw_simavr_without_pwm_timers: f64,
    /// The robust build's bench wall time over raw simavr's (without its PWM
    /// timers) for the same robot time and the same instructions.
    pub overhead_ratio: f64,
    /// The same for the thesis build.
    pub thesis_overhead_ratio: Option<f64>,
    /// The same for the thesis sketch run black-box.
    pub sketch_overhead_ratio: Option<f64>,
    pub awake_fraction: f64,
    /// Callbacks from simavr into the bench per robot second.
    pub callbacks_per_robot_s: f64,
    pub robot_s: f64,
    /// Robot time of the thesis build's runs (a smaller square).
    pub thesis_robot_s: Option<f64>,
    /// Times each run was timed (the fastest counts).
    pub repeats: usize,
    pub robust: BuildSpeed,
    pub thesis: Option<BuildSpeed>,
    pub sketch: Option<BuildSpeed>,
}

impl BenchReport {
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "speed of {} ({:.1} s of robot time each{}; each the fastest of {}):",
            self.test,
            self.robot_s,
            self.thesis_robot_s
                .map(|t| format!(", thesis {t:.1} s"))
                .unwrap_or_default(),
            self.repeats
        );
        let _ = writeln!(s, "  {:<46} {:>10} {:>8}", "run", "wall s", "x real");
        let row = |s: &mut String, name: &str, m: &Measured| {
            let _ = writeln!(s, "  {:<46} {:>10.3} {:>8.1}", name, m.wall_s, m.rtf);
        };
        let r = &self.robust;
        let name = &self.firmware;
        row(&mut s, &format!("bench, {name} firmware + plant"), &r.bench);
        if let Some(raw) = &r.raw {
            row(&mut s, "raw simavr, same ELF and inputs", raw);
        }
        row(
            &mut s,
            "raw simavr without its PWM timers",
            &r.raw_without_pwm_timers,
        );
        if let Some(t) = &self.thesis {
            row(&mut s, "bench, thesis firmware + plant", &t.bench);
            row(
                &mut s,
                "raw simavr without its PWM timers, thesis",
                &t.raw_without_pwm_timers,
            );
        }
        if let Some(t) = &self.sketch {
            row(&mut s, "bench, thesis sketch black-box + plant", &t.bench);
            row(
                &mut s,
                "raw simavr without its PWM timers, sketch",
                &t.raw_without_pwm_timers,
            );
        }
        let _ = writeln!(
            s,
            "  bench overhead over raw simavr (no PWM timers): {:.2}x {name}{}{}",
            self.overhead_ratio,
            self.thesis_overhead_ratio
                .map(|t| format!(", {t:.2}x thesis"))
                .unwrap_or_default(),
            self.sketch_overhead_ratio
                .map(|t| format!(", {t:.2}x sketch (black-box)"))
                .unwrap_or_default()
        );
        if self.repeats > 1 {
            let spread = |b: &BuildSpeed| {
                let (lo, hi) = b.round_ratio_range();
                format!("{lo:.2}x to {hi:.2}x")
            };
            let _ = writeln!(
                s,
                "  round by round (bench over the replay timed next to it): {} {name}{}{}",
                spread(r),
                self.thesis
                    .as_ref()
                    .map(|t| format!(", {} thesis", spread(t)))
                    .unwrap_or_default(),
                if r.rounds_disagree() || self.thesis.iter().any(BuildSpeed::rounds_disagree) {
                    " (a wide spread: the machine was busy; time again when it is quiet)"
                } else {
                    ""
                }
            );
        }
        let _ = writeln!(
            s,
            "  {name}: CPU awake {:.2} %; {:.0} bench callbacks per robot s, {:.0} % of them \
             edges raised from the plan alone; {:.0} % of the B reads answered from the \
             last A edge",
            self.awake_fraction * 100.0,
            self.callbacks_per_robot_s,
            self.robust.lean_edge_fraction * 100.0,
            self.robust.quiet_b_read_fraction * 100.0,
        );
        s
    }
}

#[cfg(test)]
mod tests;
