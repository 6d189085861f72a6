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

use std::time::Instant;

use plant_model::RobotConfig;
use serde::Serialize;

use crate::bench::{AnalogEvent, AnalogInput, BenchError, BenchOptions, PinEvent};
use crate::board::HENRYTWO;
use crate::elf::Firmware;
use crate::experiment::Test;
use crate::line::ready_bench;
use crate::pwm::PwmTimer;
use crate::sim::{Avr, Core, Handler, IoClaim, Irq};

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

/// A replay, with whether it ended where the bench run did.
pub struct Replayed {
    pub measured: Measured,
    /// The firmware's counters at the end equal the bench run's: the replay
    /// executed the same program path, so the wall times compare.
    pub faithful: bool,
}

/// A bench run recorded for replay.
pub struct Recorded {
    pub measured: Measured,
    pub awake_fraction: f64,
    pub callbacks: u64,
    /// Callbacks that raised planned edges from the plan alone.
    pub lean_edge_callbacks: u64,
    /// Reads of a lazy B answered from the last A edge.
    pub quiet_b_reads: u64,
    /// Reads of a lazy B in all.
    pub b_reads: u64,
    pub command_cycle: u64,
    pub command: u8,
    /// RAM the bench wrote before the command (the leg length), written by
    /// the replay at the command's cycle too.
    pub pokes: Vec<(u16, u8)>,
    pub end_cycle: u64,
    pub edges: Vec<PinEvent>,
    pub analog: Vec<AnalogEvent>,
    pub completed: bool,
    /// SRAM at the end, which a faithful replay must reach.
    pub fingerprint: Vec<u8>,
}

/// The ATmega2560's internal SRAM (data space addresses).
const SRAM: std::ops::Range<u16> = 0x0200..0x2200;

/// The state a replay must end in: all of SRAM, variables and stack alike
/// (the IO registers differ with simavr's own PWM timers, which is the point
/// of that replay).
fn fingerprint(read: impl Fn(u16) -> u8) -> Vec<u8> {
    SRAM.map(read).collect()
}

/// Run `test` on the bench; with `record`, recording the inputs a replay
/// needs (which costs the bench time and memory no scenario spends: the
/// timed runs do not record).
#[inline(never)] // profiled by name: see the README's speed section
pub fn bench_run(
    fw: &Firmware,
    robot: &RobotConfig,
    test: Test,
    leg_mm: f64,
    record: bool,
) -> Result<Recorded, BenchError> {
    let wall = Instant::now();
    let (mut bench, before, command_cycle) =
        ready_bench(fw.clone(), robot, BenchOptions::default(), leg_mm)?;
    let vars = *bench.vars()?;
    if record {
        bench.start_recording();
    }
    bench.send(1, &[test.command_byte()]);
    let (legs, turns, _) = test.shape();
    let limit = legs as f64 * (leg_mm / 50.0 + 3.0) + turns as f64 * 8.0 + 5.0;
    let completed = bench.run_until(limit, |b| {
        b.read_u16(vars.done_count) != before && b.is_idle()
    })?;
    let wall_s = wall.elapsed().as_secs_f64();
    let end_cycle = bench.cycle();
    let fingerprint = fingerprint(|a| bench.read_u8(a));
    let core = bench.core();
    Ok(Recorded {
        measured: Measured::new(bench.robot_time_s(), wall_s),
        awake_fraction: bench.awake_fraction(),
        callbacks: core.callbacks(),
        lean_edge_callbacks: core.lean_edge_callbacks(),
        quiet_b_reads: core.quiet_b_reads(),
        b_reads: core.quiet_b_reads() + core.b_reads_evaluated(),
        command_cycle,
        command: test.command_byte(),
        pokes: (vars.leg_length_mm..)
            .zip((leg_mm as f32).to_le_bytes())
            .collect(),
        end_cycle,
        edges: core.recording().unwrap_or_default().to_vec(),
        analog: core.analog_log().to_vec(),
        completed,
        fingerprint,
    })
}

/// Replays recorded inputs (encoder lines, analog inputs, the command
/// byte); nothing else.
struct Replay {
    edges: Vec<PinEvent>,
    next: usize,
    analog: Vec<AnalogEvent>,
    next_analog: usize,
    pins: [Option<Irq>; 4],
    adc0: Option<Irq>,
    uart: Option<Irq>,
    command: Option<(u64, u8)>,
    pokes: Vec<(u16, u8)>,
}

impl Replay {
    fn apply_analog(&mut self, core: &mut Core, when: u64) {
        while let Some(a) = self
            .analog
            .get(self.next_analog)
            .filter(|a| a.cycle <= when)
        {
            match a.input {
                AnalogInput::Adc0 => {
                    if let Some(irq) = self.adc0 {
                        core.raise(irq, a.mv);
                    }
                }
                AnalogInput::Supply => core.set_supply_mv(a.mv),
            }
            self.next_analog += 1;
        }
    }

    /// The cycle of the next input to replay (`u64::MAX`: none).
    fn next_input(&self) -> u64 {
        let edge = self.edges.get(self.next).map_or(u64::MAX, |e| e.cycle);
        let analog = self
            .analog
            .get(self.next_analog)
            .map_or(u64::MAX, |a| a.cycle);
        let cmd = self.command.map_or(u64::MAX, |c| c.0);
        edge.min(analog).min(cmd)
    }
}

impl Handler for Replay {
    fn io_write(&mut self, core: &mut Core, addr: u16, value: u8) {
        // Timers 2 and 4 taken off simavr: their registers are only stored.
        core.set_data(addr, value);
    }

    fn io_read(&mut self, core: &mut Core, addr: u16) -> u8 {
        core.data(addr)
    }

    fn timer(&mut self, core: &mut Core, when: u64) -> u64 {
        self.apply_analog(core, when);
        if let Some((at, byte)) = self.command {
            if at <= when {
                for &(addr, byte) in &self.pokes {
                    core.set_data(addr, byte);
                }
                if let Some(irq) = self.uart {
                    core.raise(irq, byte as u32);
                }
                self.command = None;
            }
        }
        while self.next < self.edges.len() && self.edges[self.next].cycle <= when {
            let e = self.edges[self.next];
            if let Some(irq) = self.pins[e.line as usize] {
                core.raise(irq, e.level as u32);
            }
            self.next += 1;
        }
        match self.next_input() {
            u64::MAX => 0,
            n => n,
        }
    }

    fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
}

/// Replay a recorded run in bare simavr; `simavr_pwm_timers`: leave timers
/// 2 and 4 to simavr (as shipped) or take them off (as the bench does).
#[inline(never)] // profiled by name: see the README's speed section
pub fn raw_replay(
    fw: &Firmware,
    rec: &Recorded,
    simavr_pwm_timers: bool,
) -> Result<Replayed, BenchError> {
    let wall = Instant::now();
    let clock = BenchOptions::default().clock;
    let handler = Replay {
        edges: Vec::new(),
        next: 0,
        analog: Vec::new(),
        next_analog: 0,
        pins: [None; 4],
        adc0: None,
        uart: None,
        command: Some((rec.command_cycle, rec.command)),
        pokes: rec.pokes.clone(),
    };
    let mut avr = Avr::new("atmega2560", clock.hz(), handler)?;
    for (addr, bytes) in &fw.segments {
        avr.load_flash(*addr, bytes)?;
    }
    if !simavr_pwm_timers {
        for t in [PwmTimer::timer2(), PwmTimer::timer4()] {
            for a in t.write_addresses() {
                avr.claim_io_write(a, IoClaim::Replace)?;
            }
        }
    }
    let w = HENRYTWO;
    let pins = [
        avr.port_pin(w.left_encoder.a.port, w.left_encoder.a.bit)?,
        avr.port_pin(w.left_encoder.b.port, w.left_encoder.b.bit)?,
        avr.port_pin(w.right_encoder.a.port, w.right_encoder.a.bit)?,
        avr.port_pin(w.right_encoder.b.port, w.right_encoder.b.bit)?,
    ];
    let (uart_in, _) = avr.uart(w.command_uart.usart)?;
    let _ = avr.uart(w.debug_uart.usart)?;
    let adc0 = avr.adc_input(0)?;
    {
        let h = avr.handler_mut();
        h.pins = pins.map(Some);
        h.uart = Some(uart_in);
        h.adc0 = Some(adc0);
    }
    // The bench raised the lines' levels at cycle 0, and the robot rests
    // until the command: the recording's first levels are those since boot.
    let start = rec.edges.first().map_or(0, |e| e.cycle);
    let (initial, rest): (Vec<PinEvent>, Vec<PinEvent>) =
        rec.edges.iter().partition(|e| e.cycle == start);
    let analog = rec.analog.clone();
    avr.with_core(|h, core| {
        for e in initial {
            if let Some(irq) = h.pins[e.line as usize] {
                core.raise(irq, e.level as u32);
            }
        }
        h.edges = rest;
        h.analog = analog;
        h.apply_analog(core, 0);
    });
    let first = avr.handler().next_input();
    avr.schedule(first);
    avr.run_to(rec.end_cycle);
    let measured = Measured::new(clock.seconds(avr.cycle()).0, wall.elapsed().as_secs_f64());
    let faithful = fingerprint(|a| avr.data(a)) == rec.fingerprint;
    Ok(Replayed { measured, faithful })
}

/// What `hil bench` runs.
pub struct BenchPlan<'a> {
    pub robust: &'a Firmware,
    /// The thesis build, when it is to be timed too.
    pub thesis: Option<&'a Firmware>,
    pub robot: &'a RobotConfig,
    pub test: Test,
    pub leg_mm: f64,
    /// Each robust run is timed this many times, interleaved; the fastest
    /// counts (the least disturbed by the rest of the machine). The thesis
    /// build's long runs are timed once.
    pub repeats: usize,
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

/// Time one build on squares of `leg_mm`: a recorded bench run for the
/// replays (not timed), then the plan's `repeats` times over: an unrecorded
/// bench run and the replays.
fn measure_build(
    fw: &Firmware,
    plan: &BenchPlan,
    leg_mm: f64,
    raw_with_pwm_timers: bool,
) -> Result<BuildSpeed, PerfError> {
    let name = fw.name();
    (plan.progress)(&format!("{name}: recording the bench run's inputs"));
    let rec = bench_run(fw, plan.robot, plan.test, leg_mm, true)?;
    let mut bench: Option<Measured> = None;
    let mut raw_np: Option<Measured> = None;
    let mut raw: Option<Measured> = None;
    let mut round_ratios = Vec::new();
    let repeats = plan.repeats.max(1);
    for i in 0..repeats {
        (plan.progress)(&format!("{name}: timing, round {} of {repeats}", i + 1));
        let run = bench_run(fw, plan.robot, plan.test, leg_mm, false)?;
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
    let robust = measure_build(plan.robust, plan, plan.leg_mm, plan.raw_with_pwm_timers)?;
    // The thesis build is slow (busy loops): its square is smaller, so that
    // its runs too can be timed more than once (a busy loop's speed does not
    // depend on the leg).
    let thesis = match plan.thesis {
        Some(fw) => Some(measure_build(
            fw,
            plan,
            plan.leg_mm.min(THESIS_LEG_MM),
            false,
        )?),
        None => None,
    };
    Ok(BenchReport {
        test: plan.test.name().into(),
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
        repeats: plan.repeats.max(1),
        robust,
        thesis,
    })
}

/// Longest leg of the thesis build's timed square.
pub const THESIS_LEG_MM: f64 = 500.0;

/// The `hil bench` result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub test: String,
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
        row(&mut s, "bench, robust firmware + plant", &r.bench);
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
        let _ = writeln!(
            s,
            "  bench overhead over raw simavr (no PWM timers): {:.2}x robust{}",
            self.overhead_ratio,
            self.thesis_overhead_ratio
                .map(|t| format!(", {t:.2}x thesis"))
                .unwrap_or_default()
        );
        if self.repeats > 1 {
            let spread = |b: &BuildSpeed| {
                let (lo, hi) = b.round_ratio_range();
                format!("{lo:.2}x to {hi:.2}x")
            };
            let _ = writeln!(
                s,
                "  round by round (bench over the replay timed next to it): {} robust{}{}",
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
            "  robust: CPU awake {:.2} %; {:.0} bench callbacks per robot s, {:.0} % of them \
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
mod tests {
    use super::*;

    fn speed(overhead_ratio: f64, round_ratios: Vec<f64>) -> BuildSpeed {
        let m = Measured::new(10.0, 0.1);
        BuildSpeed {
            bench: m,
            raw_without_pwm_timers: m,
            raw: None,
            overhead_ratio,
            round_ratios,
            awake_fraction: 0.02,
            callbacks_per_robot_s: 1800.0,
            lean_edge_fraction: 0.75,
            quiet_b_read_fraction: 0.73,
            completed: true,
        }
    }

    fn report(robust: BuildSpeed, thesis: Option<BuildSpeed>, repeats: usize) -> BenchReport {
        BenchReport {
            test: "umbmark-cw".into(),
            rtf_robust_umbmark: 250.0,
            rtf_thesis: thesis.as_ref().map(|_| 5.6),
            rtf_raw_simavr: None,
            rtf_raw_simavr_without_pwm_timers: 318.0,
            overhead_ratio: robust.overhead_ratio,
            thesis_overhead_ratio: thesis.as_ref().map(|t| t.overhead_ratio),
            awake_fraction: 0.02,
            callbacks_per_robot_s: 1800.0,
            robot_s: 74.3,
            thesis_robot_s: thesis.as_ref().map(|_| 32.8),
            repeats,
            robust,
            thesis,
        }
    }

    #[test]
    fn the_report_shows_the_rounds_spread_and_warns_when_it_is_wide() {
        let steady = report(speed(1.26, vec![1.27, 1.26, 1.29]), None, 3);
        let text = steady.render();
        assert!(text.contains("1.26x to 1.29x robust"), "{text}");
        assert!(!text.contains("busy"), "{text}");
        // One round of the thesis build timed while the machine was loaded.
        let loaded = report(
            speed(1.26, vec![1.27, 1.26]),
            Some(speed(1.04, vec![1.05, 1.31])),
            2,
        );
        let text = loaded.render();
        assert!(text.contains("1.05x to 1.31x thesis"), "{text}");
        assert!(text.contains("the machine was busy"), "{text}");
        // One round: no spread to show.
        let once = report(speed(1.26, vec![1.26]), None, 1);
        assert!(!once.render().contains("round by round"));
    }
}
