//! The raw simavr replay of a recorded run: the same ELF and inputs in a
//! bare simavr, nothing else.

use std::time::Instant;

use super::record::{fingerprint, Recorded};
use super::Measured;
use crate::bench::{AnalogEvent, AnalogInput, BenchError, BenchOptions, PinEvent};
use crate::firmware::elf::Firmware;
use crate::mcu::pwm::PwmTimer;
use crate::mcu::sim::{Avr, Core, DrivenPin, Handler, IoClaim, Irq};

/// A replay, with whether it ended where the bench run did.
pub struct Replayed {
    pub measured: Measured,
    /// The firmware's counters at the end equal the bench run's: the replay
    /// executed the same program path, so the wall times compare.
    pub faithful: bool,
}

/// Replays recorded inputs (encoder lines, analog inputs, the command
/// byte); nothing else.
struct Replay {
    edges: Vec<PinEvent>,
    next: usize,
    analog: Vec<AnalogEvent>,
    next_analog: usize,
    pins: [Option<DrivenPin>; 4],
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
            if let Some(pin) = self.pins[e.line as usize] {
                core.drive(pin, e.level);
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

/// Replay a recorded run in bare simavr, on the MCU and pins of the board
/// it ran on; `simavr_pwm_timers`: leave the timers the bench emulates for
/// the board's PWM pins (2 and 4 on Henrytwo's board, none on the Uno's,
/// whose timer 0 the bench mirrors) to simavr (as shipped) or take them off
/// (as the bench does).
#[inline(never)] // profiled by name: see docs/design/performance.md
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
    let w = &rec.board;
    let chip = w.mcu.chip();
    let mut avr = Avr::new(chip.simavr_core, clock.hz(), handler)?;
    // The reference: simavr as upstream runs it, back to its cycle timers
    // after every instruction.
    avr.set_free_run(false);
    for (addr, bytes) in &fw.segments {
        avr.load_flash(*addr, bytes)?;
    }
    if !simavr_pwm_timers {
        for n in crate::bench::emulated_timers(w) {
            let t = PwmTimer::emulated(chip.timer(n).expect("a board's PWM timers are modelled"));
            for a in t.write_addresses() {
                avr.claim_io_write(a, IoClaim::Replace)?;
            }
        }
    }
    // Driven from outside, as the bench drives them (see `DrivenPin`).
    let [[left_a, left_b], [right_a, right_b]] = crate::bench::encoder_pins(&mut avr, w)?;
    let (uart_in, _) = avr.uart(rec.command_usart)?;
    for n in w.link_usarts() {
        if n != rec.command_usart {
            let _ = avr.uart(n)?;
        }
    }
    // The battery's divider, where the board has one (the bench's analog
    // log holds its input's levels).
    let adc0 = match w.battery {
        Some(b) => Some(avr.adc_input(b.adc)?),
        None => None,
    };
    {
        let h = avr.handler_mut();
        h.pins = [left_a, left_b, right_a, right_b];
        h.uart = Some(uart_in);
        h.adc0 = adc0;
    }
    // The bench raised the lines' levels at cycle 0, and the robot rests
    // until the command: the recording's first levels are those since boot.
    let start = rec.edges.first().map_or(0, |e| e.cycle);
    let (initial, rest): (Vec<PinEvent>, Vec<PinEvent>) =
        rec.edges.iter().partition(|e| e.cycle == start);
    let analog = rec.analog.clone();
    avr.with_core(|h, core| {
        for e in initial {
            if let Some(pin) = h.pins[e.line as usize] {
                core.drive(pin, e.level);
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
    let faithful = fingerprint(avr.chip(), |a| avr.data(a)) == rec.fingerprint;
    Ok(Replayed { measured, faithful })
}
