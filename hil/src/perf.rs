//! `hil bench`: how fast the bench runs, measured in one run, as ratios.
//!
//! Three runs of the same firmware over the same robot time:
//! - the bench: the firmware against the plant, as every scenario runs it;
//! - raw simavr: the same ELF in a bare simavr (its own timer modules,
//!   timers 2 and 4 included), with the encoder edges the bench produced
//!   replayed on the pins at the same cycles and the command byte sent at the
//!   same cycle, so the firmware executes the same instructions; no plant, no
//!   PWM model, no analysis;
//! - raw simavr without its PWM timers: the same, with timers 2 and 4 taken
//!   off simavr (their registers just stored), which is what the bench does.
//!
//! The bench's overhead is its wall time over the last one's. Wall time is
//! read from the host clock around whole runs, never inside a simulation.

use std::time::Instant;

use plant_model::RobotConfig;
use serde::Serialize;

use crate::bench::{BenchError, BenchOptions, PinEvent};
use crate::elf::Firmware;
use crate::experiment::Test;
use crate::line::ready_bench;
use crate::pwm::PwmTimer;
use crate::sim::{Avr, Core, CpuState, Handler, IoClaim, Irq};
use crate::wiring::HENRYTWO;

/// One measured run.
#[derive(Debug, Clone, Serialize)]
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

/// A bench run recorded for replay.
pub struct Recorded {
    pub measured: Measured,
    pub awake_fraction: f64,
    pub callbacks: u64,
    pub command_cycle: u64,
    pub command: u8,
    pub end_cycle: u64,
    pub edges: Vec<PinEvent>,
    pub completed: bool,
}

/// Run `test` on the bench, recording the encoder edges.
pub fn bench_run(
    fw: &Firmware,
    robot: &RobotConfig,
    test: Test,
    leg_mm: f64,
) -> Result<Recorded, BenchError> {
    let wall = Instant::now();
    let (mut bench, before, command_cycle) =
        ready_bench(fw.clone(), robot, BenchOptions::default(), leg_mm)?;
    let vars = *bench.vars();
    bench.start_recording();
    bench.send(1, &[test.command_byte()]);
    let (legs, turns, _) = test.shape();
    let limit = legs as f64 * (leg_mm / 50.0 + 3.0) + turns as f64 * 8.0 + 5.0;
    let completed = bench.run_until(limit, |b| {
        b.read_u16(vars.done_count) != before && b.read_u8(vars.state) == 1
    })?;
    let wall_s = wall.elapsed().as_secs_f64();
    let end_cycle = bench.cycle();
    let core = bench.core();
    Ok(Recorded {
        measured: Measured::new(bench.robot_time_s(), wall_s),
        awake_fraction: bench.awake_fraction(),
        callbacks: core.callbacks,
        command_cycle,
        command: test.command_byte(),
        end_cycle,
        edges: core.recording.clone().unwrap_or_default(),
        completed,
    })
}

/// Replays recorded pin changes; nothing else.
struct Replay {
    edges: Vec<PinEvent>,
    next: usize,
    pins: [Option<Irq>; 4],
    uart: Option<Irq>,
    command: Option<(u64, u8)>,
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
        if let Some((at, byte)) = self.command {
            if at <= when {
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
        let edge = self.edges.get(self.next).map_or(u64::MAX, |e| e.cycle);
        let cmd = self.command.map_or(u64::MAX, |c| c.0);
        let n = edge.min(cmd);
        if n == u64::MAX {
            0
        } else {
            n
        }
    }

    fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
}

/// Replay a recorded run in bare simavr; `simavr_pwm_timers`: leave timers
/// 2 and 4 to simavr (as shipped) or take them off (as the bench does).
pub fn raw_replay(
    fw: &Firmware,
    rec: &Recorded,
    simavr_pwm_timers: bool,
) -> Result<Measured, BenchError> {
    let wall = Instant::now();
    let clock = BenchOptions::default().clock;
    let handler = Replay {
        edges: rec.edges.clone(),
        next: 0,
        pins: [None; 4],
        uart: None,
        command: Some((rec.command_cycle, rec.command)),
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
    let (uart_in, _) = avr.uart(w.bluetooth_uart)?;
    let _ = avr.uart(w.debug_uart)?;
    {
        let h = avr.handler_mut();
        h.pins = pins.map(Some);
        h.uart = Some(uart_in);
    }
    let first = rec
        .edges
        .first()
        .map_or(rec.command_cycle, |e| e.cycle.min(rec.command_cycle));
    avr.schedule(first);
    while avr.cycle() < rec.end_cycle {
        match avr.step() {
            CpuState::Running | CpuState::Sleeping => {}
            _ => break,
        }
    }
    Ok(Measured::new(
        clock.seconds(avr.cycle()).0,
        wall.elapsed().as_secs_f64(),
    ))
}

/// The `hil bench` result.
#[derive(Debug, Clone, Serialize)]
pub struct BenchReport {
    pub test: String,
    pub rtf_robust_umbmark: f64,
    pub rtf_thesis: Option<f64>,
    pub rtf_raw_simavr: f64,
    pub rtf_raw_simavr_without_pwm_timers: f64,
    /// Bench wall time over raw simavr's (without its PWM timers) for the
    /// same robot time and the same instructions.
    pub overhead_ratio: f64,
    pub awake_fraction: f64,
    /// Callbacks from simavr into the bench per robot second.
    pub callbacks_per_robot_s: f64,
    pub robot_s: f64,
    pub bench: Measured,
    pub raw: Measured,
    pub raw_without_pwm_timers: Measured,
    pub thesis: Option<Measured>,
    pub completed: bool,
}

impl BenchReport {
    pub fn render(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "speed of {} ({:.1} s of robot time each):",
            self.test, self.robot_s
        );
        let _ = writeln!(s, "  {:<46} {:>10} {:>8}", "run", "wall s", "x real");
        let row = |s: &mut String, name: &str, m: &Measured| {
            let _ = writeln!(s, "  {:<46} {:>10.3} {:>8.1}", name, m.wall_s, m.rtf);
        };
        row(&mut s, "bench (robust firmware + plant)", &self.bench);
        row(&mut s, "raw simavr, same ELF and edges", &self.raw);
        row(
            &mut s,
            "raw simavr without its PWM timers",
            &self.raw_without_pwm_timers,
        );
        if let Some(t) = &self.thesis {
            row(&mut s, "bench, thesis firmware", t);
        }
        let _ = writeln!(
            s,
            "  bench overhead over raw simavr (no PWM timers): {:.2}x; CPU awake {:.2} %; {:.0} bench callbacks per robot s",
            self.overhead_ratio,
            self.awake_fraction * 100.0,
            self.callbacks_per_robot_s
        );
        s
    }
}
