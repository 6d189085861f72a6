//! The motor driver's inputs: what the firmware's PWM timers (those of the
//! board's PWM pins, emulated by the bench from their registers, see
//! `crate::mcu::pwm`) and the inputs' ports drive on them, and how a change
//! reaches the plant (through the driver's truth table, `driver.rs`). Also
//! the PWM statistics per pin, and the [`Motion`] the two motors make
//! together.

use plant_model::Side;

use super::driver;
use super::recorder::{DriveEvent, Motion, Recorder};
use super::timers::{self, Grace};
use super::NEVER;
use crate::board::{Board, BridgeInput, PwmSource};
use crate::mcu::clock::Clock;
use crate::mcu::pwm::{Action, PinDrive, PwmError, PwmTimer};

/// Per-pin PWM statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct PinStats {
    pub pin: u8,
    /// Frequency of the waveform last seen on the pin while it was PWM.
    pub hz: f64,
    /// Time-weighted duty while the pin was not at 0.
    pub mean_active_duty: f64,
    pub active_s: f64,
    #[serde(skip)]
    duty_integral: f64,
}

/// One IO port a driver input is on: what the firmware last wrote to its
/// PORT and DDR registers.
#[derive(Debug, Clone, Copy)]
struct PortState {
    port: char,
    value: u8,
    ddr: u8,
}

/// The driver inputs' sources (the board's PWM timers, their ports) and
/// what the plant was last given.
pub(super) struct Bridge {
    clock: Clock,
    board: Board,
    /// Every driver input, in Arduino pin order.
    inputs: Vec<BridgeInput>,
    /// The timers the board's PWM inputs are on, in timer order.
    timers: Vec<PwmTimer>,
    /// Cycle of each timer's next update (a buffered OCR value at TOP or
    /// BOTTOM, a set or clear output's match; see
    /// `PwmTimer::pending_update_at`).
    pending_top: Vec<u64>,
    /// Each timer's unverified configuration, until judged (see `timers.rs`).
    grace: Vec<Grace<PwmError>>,
    /// Each timer's channels whose pin the board uses otherwise (see
    /// `timers::foreign_channels`).
    foreign: Vec<[Option<String>; 3]>,
    ports: Vec<PortState>,
    /// Each motor's pin 1-3 duties as last seen, by side index.
    seen: [[f64; 3]; 2],
    /// The DRV8833 inputs (in1, in2) last given to each motor's plant
    /// bridge, by side index (see `driver.rs`).
    duty: [(f64, f64); 2],
    /// Duty each driver input sees (in `inputs` order).
    input_duties: Vec<f64>,
    pins: Vec<PinStats>,
    /// Cycle up to which the PWM statistics are integrated.
    stats_cycle: u64,
}

/// The timers of the board's PWM inputs, emulated or mirrored (see
/// `timers.rs`).
fn timers_of(board: &Board) -> Vec<PwmTimer> {
    board
        .pwm_timers()
        .into_iter()
        .map(|n| {
            let layout = board.mcu.chip().timer(n);
            let layout = layout.expect("a board's PWM sources are its MCU's modelled timers");
            if timers::mirrored(n) {
                PwmTimer::mirrored(layout)
            } else {
                PwmTimer::emulated(layout)
            }
        })
        .collect()
}

impl Bridge {
    pub(super) fn new(board: Board, clock: Clock) -> Self {
        let inputs = board.bridge_inputs();
        let mut ports: Vec<PortState> = Vec::new();
        for i in &inputs {
            if !ports.iter().any(|p| p.port == i.pin.port) {
                ports.push(PortState {
                    port: i.pin.port,
                    value: 0,
                    ddr: 0,
                });
            }
        }
        let timers = timers_of(&board);
        Self {
            clock,
            foreign: timers
                .iter()
                .map(|t| timers::foreign_channels(&board, t.id().number()))
                .collect(),
            board,
            pending_top: vec![NEVER; timers.len()],
            grace: vec![Grace::default(); timers.len()],
            timers,
            ports,
            seen: [[0.0; 3]; 2],
            duty: [(0.0, 0.0); 2],
            input_duties: vec![0.0; inputs.len()],
            pins: inputs
                .iter()
                .map(|b| PinStats {
                    pin: b.number(),
                    ..Default::default()
                })
                .collect(),
            inputs,
            stats_cycle: 0,
        }
    }

    /// Back to the reset state: timers stopped, every port all inputs.
    pub(super) fn reset(&mut self) {
        self.timers = timers_of(&self.board);
        self.pending_top.fill(NEVER);
        self.grace.fill(Grace::default());
        for p in &mut self.ports {
            p.value = 0;
            p.ddr = 0;
        }
    }

    /// Whether a timer of the bridge takes writes to `addr`.
    pub(super) fn owns_write(&self, addr: u16) -> bool {
        self.timers.iter().any(|t| t.owns_write(addr))
    }

    /// Whether `addr` is a register of a mirrored timer (simavr's too).
    pub(super) fn mirrors(&self, addr: u16) -> bool {
        let t = self.timers.iter().find(|t| t.owns_write(addr));
        t.is_some_and(|t| t.is_mirrored())
    }

    /// The timers this bridge emulates or mirrors, in timer order.
    pub(super) fn timers(&self) -> &[PwmTimer] {
        &self.timers
    }

    /// The ports the driver inputs are on, indexed as `set_port` takes them.
    pub(super) fn ports(&self) -> Vec<char> {
        self.ports.iter().map(|p| p.port).collect()
    }

    pub(super) fn set_port(&mut self, k: usize, value: u8) {
        self.ports[k].value = value;
    }

    pub(super) fn set_ddr(&mut self, k: usize, value: u8) {
        self.ports[k].ddr = value;
    }

    /// The earliest update waiting, or the end of a grace.
    pub(super) fn next_top(&self) -> u64 {
        let updates = self.pending_top.iter().copied();
        let graces = self.grace.iter().map(|g| g.due());
        updates.chain(graces).min().unwrap_or(NEVER)
    }

    /// Apply timer `which`'s update if it is due at `when`: whether it was.
    pub(super) fn apply_top_if_due(&mut self, which: usize, when: u64) -> Result<bool, PwmError> {
        let at = self.pending_top[which];
        if at > when {
            return Ok(false);
        }
        self.timers[which].apply_update(at)?;
        self.pending_top[which] = self.timers[which].pending_update_at(at).unwrap_or(NEVER);
        Ok(true)
    }

    /// A configuration still unverified at the end of its grace, with the
    /// cycle and PC of the write that set it (see `timers.rs`).
    pub(super) fn expired_grace(&mut self, when: u64) -> Option<(PwmError, u64, u32)> {
        for (timer, grace) in self.timers.iter().zip(&mut self.grace) {
            if let Some((error, cycle, pc)) = grace.expired(when) {
                if timer.unverified(when).is_some() {
                    return Some((error, cycle, pc));
                }
            }
        }
        None
    }

    /// Make the plant see `side`'s inputs anew at the next refresh.
    pub(super) fn forget_drive(&mut self, side: Side) {
        self.seen[side.index()] = [f64::NAN; 3];
        self.duty[side.index()] = (f64::NAN, f64::NAN);
    }

    /// `side`'s forward minus reverse duty, as last given to the plant.
    pub(super) fn signed_duty(&self, side: Side) -> f64 {
        let (f, r) = self.duty[side.index()];
        f - r
    }

    fn timer_of(&self, source: PwmSource) -> &PwmTimer {
        self.timers
            .iter()
            .find(|t| t.id().number() == source.timer)
            .expect("a PWM input's timer is emulated")
    }

    fn drive(&self, input: &BridgeInput, cycle: u64) -> PinDrive {
        match input.pwm {
            Some(source) => self
                .timer_of(source)
                .drive(source.channel, self.clock.hz(), cycle),
            None => PinDrive::Gpio,
        }
    }

    fn input_duty(&self, input: &BridgeInput, cycle: u64) -> f64 {
        let bit = 1u8 << input.pin.bit;
        let port = self
            .ports
            .iter()
            .find(|p| p.port == input.pin.port)
            .expect("a driver input's port is watched");
        if port.ddr & bit == 0 {
            // An input pin floats; the DRV8833's and TB6612's inputs have
            // internal pull-downs, the L298N's are taken as pulled down on
            // its board: the driver sees low.
            return 0.0;
        }
        match self.drive(input, cycle) {
            PinDrive::Gpio => f64::from(port.value & bit != 0),
            PinDrive::Pwm { duty, .. } => duty,
        }
    }

    fn input_hz(&self, input: &BridgeInput, cycle: u64) -> Option<f64> {
        match self.drive(input, cycle) {
            PinDrive::Pwm { hz, duty } if hz > 0.0 && duty > 0.0 && duty < 1.0 => Some(hz),
            _ => None,
        }
    }

    /// The PWM statistics integrate the duty held since the last change
    /// (or sync), in the same pieces however the plant is advanced.
    pub(super) fn integrate_pin_stats(&mut self, cycle: u64) {
        if cycle > self.stats_cycle {
            let dt = self.clock.seconds(cycle - self.stats_cycle).0;
            for (i, &d) in self.input_duties.iter().enumerate() {
                if d > 0.0 {
                    self.pins[i].active_s += dt;
                    self.pins[i].duty_integral += d * dt;
                }
            }
            self.stats_cycle = cycle;
        }
    }

    /// What each driver input sees, for the PWM statistics: recomputed
    /// after every change of the timers' and the ports' registers (the
    /// statistics first integrate what was held up to `cycle`).
    pub(super) fn update_input_duties(&mut self, cycle: u64) {
        self.integrate_pin_stats(cycle);
        let duties = self
            .inputs
            .iter()
            .map(|i| self.input_duty(i, cycle))
            .collect();
        self.input_duties = duties;
    }

    fn pin_slot(&self, arduino: u8) -> usize {
        self.inputs
            .iter()
            .position(|b| b.number() == arduino)
            .expect("pin is a driver input")
    }

    /// `side`'s DRV8833-equivalent inputs (in1, in2) now, when its driver's
    /// inputs differ from what was last seen: each changed input logged
    /// into `log`, the pair kept as the plant's, and returned with the old
    /// one.
    pub(super) fn drive_change(
        &mut self,
        side: Side,
        disconnected: bool,
        cycle: u64,
        log: &mut Recorder,
    ) -> Option<((f64, f64), (f64, f64))> {
        let m = *self.board.motor(side);
        let i = side.index();
        let inputs = [Some(m.pin1), Some(m.pin2), m.pin3];
        let now = inputs.map(|input| match input {
            Some(input) if !disconnected => self.input_duty(&input, cycle),
            _ => 0.0,
        });
        let old = self.seen[i];
        if now == old {
            return None;
        }
        for ((input, old), new) in inputs.into_iter().zip(old).zip(now) {
            let Some(input) = input else { continue };
            if old != new {
                let wave = input
                    .pwm
                    .and_then(|s| self.timer_of(s).waveform(s.channel))
                    .filter(|w| w.action != Action::Disconnected);
                log.drive(DriveEvent {
                    cycle,
                    pin: input.number(),
                    duty: new,
                    wave,
                });
                if let Some(hz) = self.input_hz(&input, cycle) {
                    let k = self.pin_slot(input.number());
                    self.pins[k].hz = hz;
                }
            }
        }
        self.seen[i] = now;
        let pair = if disconnected {
            // The motor's wires are cut: it coasts whatever the driver does.
            (0.0, 0.0)
        } else {
            driver::plant_inputs(self.board.driver, now)
        };
        let old_pair = std::mem::replace(&mut self.duty[i], pair);
        Some((old_pair, pair))
    }

    /// What the two motors do together.
    pub(super) fn motion(&self) -> Motion {
        let sign = |pair| driver::motion_sign(self.board.driver, pair);
        Motion::classify(sign(self.duty[0]), sign(self.duty[1]))
    }

    /// A write to a register of an emulated timer, at `cycle` by the
    /// instruction at `pc` (the caller brought the plant there first):
    /// whether the outputs changed (then the caller refreshes the bridge).
    /// An unverified configuration is refused at once when a compare
    /// output shows it, else remembered for its grace (see `timers.rs`).
    pub(super) fn write_register(
        &mut self,
        addr: u16,
        value: u8,
        cycle: u64,
        pc: u32,
    ) -> Result<bool, PwmError> {
        let which = self
            .timers
            .iter()
            .position(|t| t.owns_write(addr))
            .expect("the bench claims only its timers' registers");
        let effect = self.timers[which].write(addr, value, cycle);
        self.update_input_duties(cycle);
        let effect = effect?;
        if effect.pending_update {
            self.pending_top[which] = self.timers[which].pending_update_at(cycle).unwrap_or(NEVER);
        }
        if effect.outputs_changed && self.pending_top[which] == NEVER {
            // A timer that just started applies buffered values at its
            // first update point.
            self.pending_top[which] = self.timers[which].pending_update_at(cycle).unwrap_or(NEVER);
        } else if effect.outputs_changed {
            // A set or clear output's first match may come before.
            let next = self.timers[which].pending_update_at(cycle).unwrap_or(NEVER);
            self.pending_top[which] = self.pending_top[which].min(next);
        }
        let timer = &self.timers[which];
        let foreign = ['A', 'B', 'C'].into_iter().zip(self.foreign[which].clone());
        for (channel, pin) in foreign {
            if let Some(pin) = pin.filter(|_| timer.channel_connected(channel)) {
                return Err(PwmError::ForeignOutput {
                    config: timer.config(),
                    channel,
                    pin,
                });
            }
        }
        let problem = timer.unverified(cycle);
        if let Some(e) = problem.clone().filter(|_| timer.connected()) {
            return Err(e.observed("connected a compare output"));
        }
        self.grace[which].note(problem, cycle, pc);
        Ok(effect.outputs_changed)
    }

    /// A read of a register of an emulated timer at `cycle`: the counter's
    /// value, or the refusal naming it.
    pub(super) fn read_register(&mut self, addr: u16, cycle: u64) -> Result<u8, PwmError> {
        let which = self
            .timers
            .iter()
            .position(|t| t.read_addresses().contains(&addr))
            .expect("the bench claims only its timers' registers");
        self.timers[which].read(addr, cycle)
    }

    /// Mean active duty per driver input, finalised, in Arduino pin order.
    pub(super) fn pin_stats(&self) -> Vec<PinStats> {
        let mut out = self.pins.clone();
        for p in &mut out {
            p.mean_active_duty = if p.active_s > 0.0 {
                p.duty_integral / p.active_s
            } else {
                0.0
            };
        }
        out
    }
}

#[cfg(test)]
mod tests;
