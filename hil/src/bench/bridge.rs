//! The H-bridge inputs: what the firmware's PWM timers (2 and 4, emulated by
//! the bench from their registers, see `crate::pwm`) and port H drive on the
//! four DRV8833 inputs, and how a change reaches the plant. Also the PWM
//! statistics per pin, and the [`Motion`] the two motors make together.

use plant_model::Side;

use super::recorder::{DriveEvent, Motion, Recorder};
use super::NEVER;
use crate::pwm::{PinDrive, PwmError, PwmTimer};
use crate::time::Clock;
use crate::wiring::{BridgeInput, PwmSource, Wiring};

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

/// The bridge inputs' sources (timers 2 and 4, port H) and what the plant
/// was last given.
pub(super) struct Bridge {
    clock: Clock,
    wiring: Wiring,
    timer2: PwmTimer,
    timer4: PwmTimer,
    /// Cycle of each timer's next TOP with a buffered update waiting.
    pending_top: [u64; 2],
    port_value: u8,
    port_ddr: u8,
    /// (forward, reverse) duty applied to each motor's bridge, by side index.
    duty: [(f64, f64); 2],
    /// Duty each bridge input sees (in `bridge_inputs` order).
    input_duties: [f64; 4],
    pins: [PinStats; 4],
    /// Cycle up to which the PWM statistics are integrated.
    stats_cycle: u64,
}

impl Bridge {
    pub(super) fn new(wiring: Wiring, clock: Clock) -> Self {
        Self {
            clock,
            wiring,
            timer2: PwmTimer::timer2(),
            timer4: PwmTimer::timer4(),
            pending_top: [NEVER; 2],
            port_value: 0,
            port_ddr: 0,
            duty: [(0.0, 0.0); 2],
            input_duties: [0.0; 4],
            pins: wiring.bridge_inputs().map(|b| PinStats {
                pin: b.pin.arduino,
                ..Default::default()
            }),
            stats_cycle: 0,
        }
    }

    /// Back to the reset state: timers stopped, port H all inputs.
    pub(super) fn reset(&mut self) {
        self.timer2 = PwmTimer::timer2();
        self.timer4 = PwmTimer::timer4();
        self.pending_top = [NEVER; 2];
        self.port_value = 0;
        self.port_ddr = 0;
    }

    pub(super) fn set_port(&mut self, value: u8) {
        self.port_value = value;
    }

    pub(super) fn set_ddr(&mut self, value: u8) {
        self.port_ddr = value;
    }

    /// The earliest TOP with a buffered update waiting.
    pub(super) fn next_top(&self) -> u64 {
        self.pending_top[0].min(self.pending_top[1])
    }

    /// Apply timer `which`'s buffered values if its TOP is due at `when`.
    pub(super) fn apply_top_if_due(&mut self, which: usize, when: u64) -> bool {
        if self.pending_top[which] > when {
            return false;
        }
        self.timer_mut(which).apply_buffered();
        self.pending_top[which] = NEVER;
        true
    }

    /// Make the plant see `side`'s inputs anew at the next refresh.
    pub(super) fn forget_drive(&mut self, side: Side) {
        self.duty[side.index()] = (f64::NAN, f64::NAN);
    }

    /// `side`'s forward minus reverse duty, as last given to the plant.
    pub(super) fn signed_duty(&self, side: Side) -> f64 {
        let (f, r) = self.duty[side.index()];
        f - r
    }

    fn timer_mut(&mut self, which: usize) -> &mut PwmTimer {
        if which == 0 {
            &mut self.timer2
        } else {
            &mut self.timer4
        }
    }

    fn drive(&self, input: &BridgeInput) -> PinDrive {
        match input.pwm {
            PwmSource::Timer2(ch) => self.timer2.drive(ch, self.clock.hz()),
            PwmSource::Timer4(ch) => self.timer4.drive(ch, self.clock.hz()),
        }
    }

    fn input_duty(&self, input: &BridgeInput) -> f64 {
        let bit = 1u8 << input.pin.bit;
        if self.port_ddr & bit == 0 {
            // An input pin floats; the DRV8833's inputs have internal
            // pull-downs, so the bridge sees low.
            return 0.0;
        }
        match self.drive(input) {
            PinDrive::Gpio => f64::from(self.port_value & bit != 0),
            PinDrive::Pwm { duty, .. } => duty,
        }
    }

    fn input_hz(&self, input: &BridgeInput) -> Option<f64> {
        match self.drive(input) {
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

    /// What each bridge input sees, for the PWM statistics: recomputed
    /// after every change of the timers' and the port's registers (the
    /// statistics first integrate what was held up to `cycle`).
    pub(super) fn update_input_duties(&mut self, cycle: u64) {
        self.integrate_pin_stats(cycle);
        let duties = self
            .wiring
            .bridge_inputs()
            .map(|input| self.input_duty(&input));
        self.input_duties = duties;
    }

    fn pin_slot(&self, arduino: u8) -> usize {
        self.wiring
            .bridge_inputs()
            .iter()
            .position(|b| b.pin.arduino == arduino)
            .expect("pin is a bridge input")
    }

    /// `side`'s (forward, reverse) duties now, when they differ from what
    /// the plant was given: logged per input into `log`, kept as the
    /// plant's, and returned with the old ones.
    pub(super) fn drive_change(
        &mut self,
        side: Side,
        disconnected: bool,
        cycle: u64,
        log: &mut Recorder,
    ) -> Option<((f64, f64), (f64, f64))> {
        let m = *self.wiring.motor(side);
        let i = side.index();
        let (fwd, rev) = if disconnected {
            (0.0, 0.0)
        } else {
            (self.input_duty(&m.forward), self.input_duty(&m.reverse))
        };
        let (old_f, old_r) = self.duty[i];
        if (fwd, rev) == (old_f, old_r) {
            return None;
        }
        for (input, old, new) in [(m.forward, old_f, fwd), (m.reverse, old_r, rev)] {
            if old != new {
                let wave = match input.pwm {
                    PwmSource::Timer2(ch) => self.timer2.waveform(ch),
                    PwmSource::Timer4(ch) => self.timer4.waveform(ch),
                }
                .filter(|(_, _, com)| *com != crate::pwm::Com::Disconnected);
                log.drive(DriveEvent {
                    cycle,
                    pin: input.pin.arduino,
                    duty: new,
                    wave,
                });
                if let Some(hz) = self.input_hz(&input) {
                    let k = self.pin_slot(input.pin.arduino);
                    self.pins[k].hz = hz;
                }
            }
        }
        self.duty[i] = (fwd, rev);
        Some(((old_f, old_r), (fwd, rev)))
    }

    /// What the two motors do together.
    pub(super) fn motion(&self) -> Motion {
        let sign = |(f, r): (f64, f64)| match (f > 0.0, r > 0.0) {
            (false, false) => 0,
            (true, false) => 1,
            (false, true) => -1,
            (true, true) => 2,
        };
        Motion::classify(sign(self.duty[0]), sign(self.duty[1]))
    }

    /// A write to a register of timer 2 or 4, at `cycle` (the caller
    /// brought the plant there first): whether the outputs changed (then
    /// the caller refreshes the bridge).
    pub(super) fn write_register(
        &mut self,
        addr: u16,
        value: u8,
        cycle: u64,
    ) -> Result<bool, PwmError> {
        let which = if self.timer2.owns_write(addr) { 0 } else { 1 };
        let effect = self.timer_mut(which).write(addr, value, cycle);
        self.update_input_duties(cycle);
        let effect = effect?;
        if effect.pending_update {
            self.pending_top[which] = self
                .timer_mut(which)
                .pending_update_at(cycle)
                .unwrap_or(NEVER);
        }
        if effect.outputs_changed && self.pending_top[which] == NEVER {
            // A timer that just started applies buffered values at its
            // first TOP.
            self.pending_top[which] = self
                .timer_mut(which)
                .pending_update_at(cycle)
                .unwrap_or(NEVER);
        }
        Ok(effect.outputs_changed)
    }

    /// A read of a register of timer 2 or 4: none is verified, so the run
    /// ends with this error naming it.
    pub(super) fn refused_read(&self, addr: u16) -> PwmError {
        let timer = if self.timer2.read_addresses().contains(&addr) {
            &self.timer2
        } else {
            &self.timer4
        };
        timer.read(addr)
    }

    /// Mean active duty per pin, finalised.
    pub(super) fn pin_stats(&self) -> [PinStats; 4] {
        let mut out = self.pins;
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
