//! The callbacks' work that needs several parts of the bench: each part
//! does its share, given the others (or the few values it needs of them).

use super::*;
use crate::bench::recorder::SharedTap;

/// How far behind the run a tap is told it has settled: longer than any
/// record is made after its cycle (a UART frame queued behind the one on
/// the line starts up to a frame later; at 300 baud that is 33 ms).
const TAP_SETTLE_S: f64 = 0.1;

/// The callbacks' work that needs several parts: each part does its share,
/// given the others (or the few values it needs of them).
impl BenchCore {
    pub(in crate::bench) fn connect_encoders(
        &mut self,
        core: &mut Core,
        irq: [[Option<DrivenPin>; 2]; 2],
    ) {
        self.edges.connect(core, irq, &self.robot);
    }

    pub(in crate::bench) fn plan_edges(&mut self, now: u64) {
        self.edges.plan(&self.robot, self.clock, now);
    }

    /// Show the plant's levels on both encoders' pins.
    pub(in crate::bench) fn raise_encoders(&mut self, core: &mut Core, when: u64) {
        let (robot, inject, rec) = (&self.robot, &mut self.inject, &mut self.recorder);
        self.edges.raise_all(core, robot, inject, rec, when);
    }

    /// Raise B lazily or not, as it may now (see `Encoders::lazy_b_change`):
    /// on a change the lines are brought up to date and both wheels
    /// re-planned.
    pub(in crate::bench) fn update_lazy_b(&mut self, core: &mut Core, cycle: u64) {
        if let Some(lazy) = self.edges.lazy_b_change(&self.inject) {
            self.advance_plant(cycle);
            self.raise_encoders(core, cycle);
            self.edges.set_lazy_b(lazy);
            self.plan_edges(cycle);
        }
    }

    /// The analog comparator's interrupt or capture was switched.
    pub(in crate::bench) fn set_comparator(&mut self, core: &mut Core, on: bool) {
        self.edges.set_comparator(on);
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// Raise B at its own transitions from now on (see `Bench::true_waveforms`).
    pub(in crate::bench) fn true_waveforms(&mut self, core: &mut Core) {
        self.edges.forbid_lazy_b();
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// Planned encoder edges with nothing else due at `when`, raised from
    /// the plan alone (see `Encoders::raise_planned_edges`).
    #[inline]
    pub(super) fn raise_planned_edges(&mut self, core: &mut Core, when: u64) -> bool {
        if self.next_other_event() <= when || self.power.releasing() {
            return false;
        }
        let (robot, inject, rec) = (&self.robot, &mut self.inject, &mut self.recorder);
        self.edges
            .raise_planned_edges(core, robot, self.clock, inject, rec, when)
    }

    /// Record every encoder pin change from now on (see
    /// `Bench::start_recording`), starting with the wired lines' levels.
    pub(in crate::bench) fn start_recording(&mut self, cycle: u64) {
        self.recorder.start_pins(cycle, &self.edges.levels_shown());
    }

    /// [`Self::start_recording`], the records given to `tap` as they are
    /// made (see `Bench::stream_records`).
    pub(in crate::bench) fn stream_records(&mut self, cycle: u64, tap: SharedTap) {
        self.recorder
            .stream_to(tap, cycle, &self.edges.levels_shown());
    }

    /// A trace sample of the plant at `cycle`; a tap has the UART bytes so
    /// far and is settled up to [`TAP_SETTLE_S`] before it.
    pub(super) fn sample(&mut self, cycle: u64) {
        let duty = Side::BOTH.map(|side| self.bridge.signed_duty(side));
        let t_s = self.clock.seconds(cycle).0;
        self.recorder.sample(t_s, &self.robot, duty);
        let settled = cycle.saturating_sub(self.clock.cycles_in(Seconds(TAP_SETTLE_S)));
        self.recorder
            .feed_tap(self.uart.log(), self.uart.rx_log(), settled);
    }

    /// VCC and the brown-out detector (see `Power::update_supply`).
    pub(in crate::bench) fn update_supply(&mut self, core: &mut Core, cycle: u64) {
        let battery = self.robot.battery_voltage().0;
        match self
            .power
            .update_supply(core, cycle, battery, &mut self.recorder)
        {
            Some(Brownout::Pulled) => self.requests.reset(),
            Some(Brownout::Released) => self.requests.bod_release(),
            None => {}
        }
    }

    /// Drive A0 with the battery's voltage when it changed.
    pub(in crate::bench) fn update_adc(&mut self, core: &mut Core, cycle: u64) {
        let battery = self.robot.battery_voltage().0;
        self.power
            .update_adc(core, cycle, battery, &mut self.recorder);
    }

    /// Re-read what the bridge inputs see; apply changes to the plant.
    pub(super) fn refresh_bridge(&mut self, core: &Core, cycle: u64) {
        self.advance_plant(cycle);
        self.bridge.update_input_duties(cycle);
        let mut changed = [false; 2];
        for side in Side::BOTH {
            let i = side.index();
            let disconnected = self.inject.motor_disconnected[i];
            let Some(((old_f, old_r), (fwd, rev))) =
                self.bridge
                    .drive_change(side, disconnected, cycle, &mut self.recorder)
            else {
                continue;
            };
            changed[i] = true;
            let cut_forward = old_f > 0.0 && fwd == 0.0;
            if cut_forward || (old_r > 0.0 && rev == 0.0) {
                let at = self.snapshot(core, cycle);
                self.recorder.cutoff(side, cut_forward, at);
            }
            for (forward, was, now) in [(true, old_f, fwd), (false, old_r, rev)] {
                if was == 0.0 && now > 0.0 {
                    self.recorder.drive_on(side, forward, cycle);
                }
            }
            self.robot.set_bridge(
                side,
                Duty::new(fwd).unwrap_or(Duty::from_pwm8(0)),
                Duty::new(rev).unwrap_or(Duty::from_pwm8(0)),
            );
        }
        if changed != [false; 2] {
            self.edges
                .replan_changed_wheels(&self.robot, self.clock, changed, cycle);
            let motion = self.bridge.motion();
            if self.recorder.motion() != Some(motion) {
                let at = self.snapshot(core, cycle);
                self.recorder.motion_changed(MotionEvent { motion, at });
                self.faults.motion_started(cycle, motion);
            }
        }
    }

    /// A write to a register of an emulated timer (see `crate::mcu::pwm`): the plant is brought to this
    /// cycle before the output can change.
    pub(super) fn write_pwm_register(&mut self, core: &mut Core, addr: u16, value: u8) {
        let cycle = core.cycle();
        // The bench emulates these registers; keep data space readable (a
        // mirrored timer's simavr stored already).
        if !self.bridge.mirrors(addr) {
            core.set_data(addr, value);
        }
        self.advance_plant(cycle);
        match self.bridge.write_register(addr, value, cycle, core.pc()) {
            Ok(outputs_changed) => {
                if outputs_changed {
                    self.refresh_bridge(core, cycle);
                }
                core.schedule(self.next_event());
            }
            Err(e) => self.requests.fail(PendingError::Pwm(e, cycle, core.pc())),
        }
    }

    /// Put on the wire each byte from the host due at `when`.
    pub(super) fn send_due_host_bytes(&mut self, core: &mut Core, when: u64) {
        for n in 0..4 {
            let Some(due) = self.uart.take_due(n, when) else {
                continue;
            };
            if let Some((b, irq)) = due {
                // The Bluetooth link's faults hit the byte now, at the
                // time it is on the air, after the actions armed for it.
                let arrived = if n == self.uart.bluetooth() {
                    self.faults.host_byte(when);
                    self.apply_due_actions(core, when);
                    self.inject.link_bytes(b)
                } else {
                    vec![b]
                };
                for b in arrived {
                    self.uart.delivered(when, n, b);
                    core.raise(irq, b as u32);
                }
            }
            self.uart.reschedule(n, when);
        }
    }

    pub(super) fn apply_due_actions(&mut self, core: &mut Core, when: u64) {
        while let Some(action) = self.faults.take_due_action(when) {
            self.apply_action(core, when, action);
        }
    }

    /// Glitch pulse edges due at `when`, each at its own cycle.
    pub(super) fn apply_due_glitches(&mut self, core: &mut Core, when: u64) {
        while let Some((i, ch, on)) = self.faults.take_due_glitch(when) {
            self.inject.glitch[i][ch] = on;
            self.raise_encoders(core, when);
        }
    }

    /// Apply `action` at `cycle` and log it; an action the plant refuses is
    /// not logged but left for the run loop to report.
    pub(super) fn apply_action(&mut self, core: &mut Core, cycle: u64, action: Action) {
        let t_s = self.clock.seconds(cycle).0;
        match self.act(core, cycle, &action) {
            Ok(()) => {
                tracing::debug!(t_s, ?action, "fault action applied");
                self.faults.log_applied(cycle, action);
            }
            Err(error) => {
                tracing::debug!(t_s, ?action, %error, "fault action refused by the plant");
                self.requests.fail(PendingError::Refused {
                    action,
                    error,
                    cycle,
                    pc: core.pc(),
                });
            }
        }
    }

    pub(super) fn act(
        &mut self,
        core: &mut Core,
        cycle: u64,
        action: &Action,
    ) -> Result<(), plant_model::Error> {
        match *action {
            Action::Encoder { side, fault } => {
                // B must be exact from here on if the fault acts on the lines.
                self.advance_plant(cycle);
                self.raise_encoders(core, cycle);
                self.inject.encoder[side.index()] = fault;
                self.update_lazy_b(core, cycle);
            }
            Action::Link { fault } => self.inject.link = fault,
            Action::MotorDisconnected { side, disconnected } => {
                self.inject.motor_disconnected[side.index()] = disconnected;
                // Force a re-read: the plant sees the bridge anew.
                self.bridge.forget_drive(side);
                self.refresh_bridge(core, cycle);
            }
            Action::Reset => self.requests.reset(),
            Action::Motor { side, fault } => {
                self.robot.set_motor_fault(side, fault)?;
                self.plan_edges(cycle);
            }
            Action::SlipBurst { side, slip } => self.robot.set_slip_burst(side, slip)?,
            Action::BatteryVolts { volts } => {
                self.robot
                    .set_battery_voltage_override(volts.map(plant_model::Volts))?;
                self.plan_edges(cycle);
                self.update_supply(core, cycle);
            }
            Action::EncoderGlitch {
                side,
                channel,
                pulses,
                width_us,
                period_us,
            } => {
                let width = self.clock.cycles_in(Seconds(width_us * 1e-6)).max(1);
                let period = self
                    .clock
                    .cycles_in(Seconds(period_us * 1e-6))
                    .max(width + 1);
                let at = (side.index(), channel as usize);
                self.faults.glitch_burst(cycle, at, pulses, width, period);
            }
            Action::HostSend { ref bytes } => {
                let n = self.uart.bluetooth();
                self.queue_uart(n, bytes, cycle);
            }
        }
        Ok(())
    }
}
