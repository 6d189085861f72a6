//! [`BenchCore`]: the bench's side of the simulation, the handler simavr
//! calls back (register writes and reads, the bench's cycle timer, watched
//! IRQs). It holds one part per concern and dispatches each callback to
//! them; the parts' own files say what each does. The parts know nothing
//! of the core: what needs several of them (a bridge change reaching the
//! plant and the encoder plans, a fault action) is done here, each part
//! given the others or the few values it needs of them.

use plant_model::{Duty, Robot, RobotConfig, Seconds, Side};

use super::bridge::{Bridge, PinStats};
use super::edges::Encoders;
use super::error::PendingError;
use super::faults::{Action, FaultSchedule, Trigger};
use super::power::{Brownout, Power};
use super::recorder::{
    AnalogEvent, Cutoff, DriveEvent, LedEvent, MotionEvent, PinEvent, Recorder, Retained, Sample,
    Snapshot,
};
use super::registers::{ACSR, ACSR_ACIC, ACSR_ACIE};
use super::requests::Requests;
use super::timers::{Look, SimavrTimers};
use super::uart::HostUart;
use super::{BenchOptions, NEVER};
use crate::bench::inject::Injection;
use crate::board::Board;
use crate::mcu::clock::Clock;
use crate::mcu::sim::{Core, Handler, Irq};

/// Tags of the IRQs the bench watches (see `BenchCore::irq`).
/// A driver input port's PORT and DDR register: + the port's index in
/// `Bridge::ports`.
pub(super) const TAG_PORT_REG: u32 = 0x100;
pub(super) const TAG_PORT_DDR: u32 = 0x200;
pub(super) const TAG_LED_PORT: u32 = 3;
pub(super) const TAG_UART_OUT: u32 = 16; // + USART number

/// The bench's side of the simulation (see the module docs).
pub struct BenchCore {
    pub(super) clock: Clock,
    pub(super) robot: Robot,
    /// The cycle the plant has been advanced to.
    pub(super) plant_cycle: u64,
    /// The firmware's wheel counters (32-bit variables), when known.
    counts: Option<[u16; 2]>,
    /// The injection points (`crate::bench::inject`): encoder lines, bridge, link.
    pub(super) inject: Injection,
    pub(super) bridge: Bridge,
    pub(super) edges: Encoders,
    pub(super) uart: HostUart,
    pub(super) power: Power,
    pub(super) faults: FaultSchedule,
    pub(super) recorder: Recorder,
    pub(super) requests: Requests,
    /// The timers simavr runs, as the bench judges them (see `timers.rs`).
    pub(super) simavr_timers: SimavrTimers,
    /// The periodic plant step: its next cycle, its length, and every how
    /// many steps a trace sample is taken.
    next_step: u64,
    step_cycles: u64,
    trace_every: u32,
    steps: u32,
    /// Callbacks from simavr into the bench (timer, IO, IRQ).
    callbacks: u64,
}

impl BenchCore {
    pub(super) fn new(
        robot: &RobotConfig,
        options: &BenchOptions,
        wiring: &Board,
        counts: Option<[u16; 2]>,
    ) -> Result<Self, plant_model::Error> {
        let clock = options.clock;
        let step_cycles = clock.cycles_in(Seconds(options.plant_step_s)).max(1);
        let trace_every = ((options.trace_interval_s / options.plant_step_s).round() as u32).max(1);
        Ok(Self {
            clock,
            robot: Robot::new(robot, options.seed)?,
            plant_cycle: 0,
            counts,
            inject: Injection::new(options.seed ^ 0x5eed_f417),
            bridge: Bridge::new(*wiring, clock),
            edges: Encoders::new(wiring),
            uart: HostUart::new(wiring.command_uart.usart, clock),
            power: Power::new(
                options.supply,
                wiring.battery.divider,
                clock.cycles_in(Seconds(options.supply.startup_s)),
            ),
            faults: FaultSchedule::default(),
            recorder: Recorder::new(wiring.battery_leds),
            requests: Requests::default(),
            simavr_timers: SimavrTimers::new(wiring, &wiring.pwm_timers()),
            next_step: step_cycles,
            step_cycles,
            trace_every,
            steps: 0,
            callbacks: 0,
        })
    }

    /// The plant (synced to the current cycle outside the run loop).
    pub fn robot(&self) -> &Robot {
        &self.robot
    }

    /// Callbacks from simavr into the bench (timer, IO, IRQ).
    pub fn callbacks(&self) -> u64 {
        self.callbacks
    }

    pub(super) fn advance_plant(&mut self, cycle: u64) {
        if cycle > self.plant_cycle {
            // The plant refuses only time going backwards, which the check
            // above rules out.
            let _ = self.robot.advance_to(self.clock.seconds(cycle));
            self.plant_cycle = cycle;
        }
    }

    /// Bring the plant and the PWM statistics to `cycle`. Between its own
    /// events the bench lets the plant lag (a planned edge needs nothing of
    /// it); whoever looks at them from outside a callback sees them synced.
    pub fn sync(&mut self, cycle: u64) {
        self.advance_plant(cycle);
        self.bridge.integrate_pin_stats(cycle);
    }

    pub(super) fn next_event(&self) -> u64 {
        self.edges
            .next_edge()
            .min(self.next_other_event())
            .min(self.power.release_at())
    }

    /// The next event that is not an encoder edge (nor the brown-out
    /// detector's release).
    pub(super) fn next_other_event(&self) -> u64 {
        self.next_step
            .min(self.bridge.next_top())
            .min(self.uart.next_due())
            .min(self.faults.next_due())
            .min(self.edges.next_internal())
    }

    /// What a cycle timer callback returns: the next event, or 0 for none.
    fn next_timer(&self) -> u64 {
        match self.next_event() {
            NEVER => 0,
            next => next,
        }
    }

    /// Bring the bench's own peripheral models to their reset state.
    pub(super) fn after_reset(&mut self, core: &mut Core) {
        let cycle = core.cycle();
        self.set_comparator(core, false);
        self.bridge.reset();
        self.refresh_bridge(core, cycle);
        // The LED pins are inputs again: all dark.
        self.recorder.leds_changed(cycle, 0);
    }

    /// The reset the run loop is to perform, taken.
    pub(super) fn take_reset(&mut self) -> bool {
        self.requests.take_reset()
    }

    /// The brown-out release the run loop is to perform, taken.
    pub(super) fn take_bod_release(&mut self) -> bool {
        self.requests.take_bod_release()
    }

    /// The error a callback recorded, taken.
    pub(super) fn take_error(&mut self) -> Option<PendingError> {
        self.requests.take_error()
    }

    /// The run loop has seen the flag (it handles what is behind it next).
    pub(super) fn clear_attention(&mut self) {
        self.requests.clear_attention();
    }

    /// The periodic plant step, when due: A0 and the trace.
    fn plant_step(&mut self, core: &mut Core, when: u64) {
        if self.next_step <= when {
            self.update_adc(core, when);
            self.steps += 1;
            if self.steps % self.trace_every == 0 {
                self.sample(when);
            }
            self.next_step = when + self.step_cycles;
        }
    }

    /// A look at a timer simavr runs (see `timers.rs`): the run ends if it
    /// shows an unverified configuration.
    fn check_simavr_timer(&mut self, core: &Core, look: Look) {
        if let Some(e) = self.simavr_timers.judge(core, look) {
            self.requests.fail(e);
        }
    }

    /// The bench's timers' updates and graces due at `when`.
    fn pwm_timers_due(&mut self, core: &mut Core, when: u64) {
        for which in 0..self.bridge.timers().len() {
            match self.bridge.apply_top_if_due(which, when) {
                Ok(true) => self.refresh_bridge(core, when),
                Ok(false) => {}
                Err(e) => self.requests.fail(PendingError::Pwm(e, when, core.pc())),
            }
        }
        if let Some((e, cycle, pc)) = self.bridge.expired_grace(when) {
            self.requests.fail(PendingError::Pwm(e, cycle, pc));
        }
    }
}

/// The callbacks' work that needs several parts: each part does its share,
/// given the others (or the few values it needs of them).
impl BenchCore {
    pub(super) fn connect_encoders(&mut self, core: &mut Core, irq: [[Irq; 2]; 2]) {
        self.edges.connect(core, irq, &self.robot);
    }

    pub(super) fn plan_edges(&mut self, now: u64) {
        self.edges.plan(&self.robot, self.clock, now);
    }

    /// Show the plant's levels on both encoders' pins.
    pub(super) fn raise_encoders(&mut self, core: &mut Core, when: u64) {
        let (robot, inject, rec) = (&self.robot, &mut self.inject, &mut self.recorder);
        self.edges.raise_all(core, robot, inject, rec, when);
    }

    /// Raise B lazily or not, as it may now (see `Encoders::lazy_b_change`):
    /// on a change the lines are brought up to date and both wheels
    /// re-planned.
    pub(super) fn update_lazy_b(&mut self, core: &mut Core, cycle: u64) {
        if let Some(lazy) = self.edges.lazy_b_change(&self.inject) {
            self.advance_plant(cycle);
            self.raise_encoders(core, cycle);
            self.edges.set_lazy_b(lazy);
            self.plan_edges(cycle);
        }
    }

    /// The analog comparator's interrupt or capture was switched.
    pub(super) fn set_comparator(&mut self, core: &mut Core, on: bool) {
        self.edges.set_comparator(on);
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// Raise B at its own transitions from now on (see `Bench::true_waveforms`).
    pub(super) fn true_waveforms(&mut self, core: &mut Core) {
        self.edges.forbid_lazy_b();
        let cycle = core.cycle();
        self.update_lazy_b(core, cycle);
    }

    /// Planned encoder edges with nothing else due at `when`, raised from
    /// the plan alone (see `Encoders::raise_planned_edges`).
    #[inline]
    fn raise_planned_edges(&mut self, core: &mut Core, when: u64) -> bool {
        if self.next_other_event() <= when || self.power.releasing() {
            return false;
        }
        let (robot, inject, rec) = (&self.robot, &mut self.inject, &mut self.recorder);
        self.edges
            .raise_planned_edges(core, robot, self.clock, inject, rec, when)
    }

    /// Record every encoder pin change from now on (see
    /// `Bench::start_recording`), starting with the four lines' levels.
    pub(super) fn start_recording(&mut self, cycle: u64) {
        self.recorder.start_pins(cycle, self.edges.levels_shown());
    }

    /// A trace sample of the plant at `cycle`.
    fn sample(&mut self, cycle: u64) {
        let duty = Side::BOTH.map(|side| self.bridge.signed_duty(side));
        let t_s = self.clock.seconds(cycle).0;
        self.recorder.sample(t_s, &self.robot, duty);
    }

    /// VCC and the brown-out detector (see `Power::update_supply`).
    pub(super) fn update_supply(&mut self, core: &mut Core, cycle: u64) {
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
    pub(super) fn update_adc(&mut self, core: &mut Core, cycle: u64) {
        let battery = self.robot.battery_voltage().0;
        self.power
            .update_adc(core, cycle, battery, &mut self.recorder);
    }

    /// Re-read what the bridge inputs see; apply changes to the plant.
    fn refresh_bridge(&mut self, core: &Core, cycle: u64) {
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
    fn write_pwm_register(&mut self, core: &mut Core, addr: u16, value: u8) {
        let cycle = core.cycle();
        // The bench emulates these registers; keep data space readable.
        core.set_data(addr, value);
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
    fn send_due_host_bytes(&mut self, core: &mut Core, when: u64) {
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

    fn apply_due_actions(&mut self, core: &mut Core, when: u64) {
        while let Some(action) = self.faults.take_due_action(when) {
            self.apply_action(core, when, action);
        }
    }

    /// Glitch pulse edges due at `when`, each at its own cycle.
    fn apply_due_glitches(&mut self, core: &mut Core, when: u64) {
        while let Some((i, ch, on)) = self.faults.take_due_glitch(when) {
            self.inject.glitch[i][ch] = on;
            self.raise_encoders(core, when);
        }
    }

    /// Apply `action` at `cycle` and log it; an action the plant refuses is
    /// not logged but left for the run loop to report.
    fn apply_action(&mut self, core: &mut Core, cycle: u64, action: Action) {
        match self.act(core, cycle, &action) {
            Ok(()) => self.faults.log_applied(cycle, action),
            Err(error) => self.requests.fail(PendingError::Refused {
                action,
                error,
                cycle,
                pc: core.pc(),
            }),
        }
    }

    fn act(
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

/// What the parts hold, for the bench and its callers.
impl BenchCore {
    /// The plant and the firmware's counters now (`cycle` is the current one).
    pub fn snapshot(&self, core: &Core, cycle: u64) -> Snapshot {
        Snapshot::take(&self.robot, self.counts, core, cycle)
    }

    /// The longest a level on the bridge inputs may last and still be a
    /// stale one, not a cut-off: one period of the slowest PWM seen on them
    /// (a firmware writing the inputs one after the other leaves a level
    /// for a few instructions; a real stop lasts at least a period), and at
    /// least 64 us for drivers switched by plain pin writes.
    pub fn stale_level_cycles(&self) -> u64 {
        let hz = self.clock.hz() as f64;
        self.bridge
            .pin_stats()
            .iter()
            .filter(|p| p.hz > 0.0)
            .map(|p| (hz / p.hz).ceil() as u64)
            .max()
            .unwrap_or(0)
            .max(self.clock.cycles_in(Seconds(64e-6)))
    }

    /// Where the firmware keeps its wheel counters, when known.
    pub fn count_variables(&self) -> Option<[u16; 2]> {
        self.counts
    }

    pub(super) fn set_count_variables(&mut self, counts: [u16; 2]) {
        self.counts = Some(counts);
    }

    /// Trace samples, one per `BenchOptions::trace_interval_s`.
    pub fn trace(&self) -> &[Sample] {
        self.recorder.trace()
    }

    /// Every change of an H-bridge input.
    pub fn drive_log(&self) -> &[DriveEvent] {
        self.recorder.drive_log()
    }

    pub fn cutoffs(&self) -> &[Cutoff] {
        self.recorder.cutoffs()
    }

    pub fn motions(&self) -> &[MotionEvent] {
        self.recorder.motions()
    }

    /// Changes of [`crate::bench::Motion`] since the start, kept or not.
    pub fn motion_changes(&self) -> u64 {
        self.recorder.motion_changes()
    }

    /// How many items each record holds now.
    pub fn retained(&self) -> Retained {
        let (uart_bytes, uart_log) = self.uart.retained();
        Retained {
            uart_bytes,
            uart_log,
            applied: self.faults.applied().len(),
            ..self.recorder.retained()
        }
    }

    /// A notice for each record that reached its cap (see `log.rs`): what
    /// the run's results do not cover.
    pub fn record_notices(&self) -> Vec<String> {
        let interval_s = self.clock.seconds(self.step_cycles).0 * f64::from(self.trace_every);
        let mut v = self.recorder.notices(interval_s);
        v.extend(self.uart.notices());
        v
    }

    pub(super) fn keep_latest_records(&mut self) {
        self.recorder.keep_latest();
        self.uart.keep_latest();
    }

    pub(super) fn take_uart_out(&mut self, n: usize) -> Vec<u8> {
        self.uart.take_out(n)
    }

    /// Battery LED changes.
    pub fn leds(&self) -> &[LedEvent] {
        self.recorder.leds()
    }

    /// Encoder pin changes since `Bench::start_recording` (None before).
    pub fn recording(&self) -> Option<&[PinEvent]> {
        self.recorder.recording()
    }

    /// Every change of the analog inputs since cycle 0.
    pub fn analog_log(&self) -> &[AnalogEvent] {
        self.recorder.analog_log()
    }

    /// Mean active duty per pin, finalised.
    pub fn pin_stats(&self) -> Vec<PinStats> {
        self.bridge.pin_stats()
    }

    /// A edges raised on the pins per side, signed as the thesis' decoder
    /// counts them.
    pub fn edges_raised(&self) -> [i64; 2] {
        self.edges.edges_raised()
    }

    /// Cycle at which the last A edge of each encoder was due.
    pub fn last_a_edge(&self) -> [u64; 2] {
        self.edges.last_a_edge()
    }

    /// Callbacks that raised planned edges from the plan alone.
    pub fn lean_edge_callbacks(&self) -> u64 {
        self.edges.lean_edge_callbacks()
    }

    /// PIN reads that brought a lazy B up to date.
    pub fn lazy_b_reads(&self) -> u64 {
        self.edges.lazy_b_reads()
    }

    /// PIN reads of a lazy B answered from the last A edge.
    pub fn quiet_b_reads(&self) -> u64 {
        self.edges.quiet_b_reads()
    }

    /// PIN reads of a lazy B that evaluated the plant.
    pub fn b_reads_evaluated(&self) -> u64 {
        self.edges.b_reads_evaluated()
    }

    /// The brown-out detector holds the MCU in reset.
    pub fn held_in_reset(&self) -> bool {
        self.power.holds_reset()
    }

    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    pub fn brownouts(&self) -> &[(u64, Option<u64>)] {
        self.power.brownouts()
    }

    /// Schedule `action` at `cycle` (kept sorted; equal cycles keep order).
    pub fn schedule_action(&mut self, cycle: u64, action: Action) {
        self.faults.at(cycle, action);
    }

    /// Run `action` when `trigger` fires, and `undo` `duration` cycles later.
    pub fn schedule_triggered(
        &mut self,
        trigger: Trigger,
        action: Action,
        undo: Option<(u64, Action)>,
    ) {
        self.faults.arm(self.clock, trigger, action, undo);
    }

    /// The actions applied so far: (cycle, action).
    pub fn applied(&self) -> &[(u64, Action)] {
        self.faults.applied()
    }

    /// Queue bytes from the host for USART `n`.
    pub fn queue_uart(&mut self, n: usize, bytes: &[u8], now: u64) {
        self.uart.queue(n, bytes, now);
    }

    /// Bytes the firmware sent on USART `n` so far.
    pub fn uart_out(&self, n: usize) -> &[u8] {
        self.uart.out(n)
    }

    /// Bytes the firmware sent: (cycle, USART, byte).
    pub fn uart_log(&self) -> &[(u64, u8, u8)] {
        self.uart.log()
    }

    /// Bytes that arrived at the firmware's receivers from the host's side:
    /// (cycle, USART, byte).
    pub fn uart_rx_log(&self) -> &[(u64, u8, u8)] {
        self.uart.rx_log()
    }
}

impl Handler for BenchCore {
    fn io_write(&mut self, core: &mut Core, addr: u16, value: u8) {
        self.callbacks += 1;
        if addr == ACSR {
            // Observed: simavr's comparator has stored the value already.
            self.set_comparator(core, value & (ACSR_ACIE | ACSR_ACIC) != 0);
            core.schedule(self.next_event());
            return;
        }
        if self.simavr_timers.watches(Look::Write(addr)) {
            self.check_simavr_timer(core, Look::Write(addr));
            return;
        }
        self.write_pwm_register(core, addr, value);
    }

    fn attention(&self) -> bool {
        self.requests.attention()
    }

    fn before_io_read(&mut self, core: &mut Core, addr: u16) {
        if self.simavr_timers.watches(Look::Read(addr)) {
            self.check_simavr_timer(core, Look::Read(addr));
            return;
        }
        let (robot, inject, rec) = (&self.robot, &mut self.inject, &mut self.recorder);
        self.edges
            .before_pin_read(core, robot, self.clock, inject, rec, addr);
    }

    fn io_read(&mut self, core: &mut Core, addr: u16) -> u8 {
        // The emulated timers' counters (and flags, refused).
        match self.bridge.read_register(addr, core.cycle()) {
            Ok(v) => v,
            Err(e) => {
                self.requests
                    .fail(PendingError::Pwm(e, core.cycle(), core.pc()));
                0
            }
        }
    }

    fn timer(&mut self, core: &mut Core, when: u64) -> u64 {
        self.callbacks += 1;
        if self.raise_planned_edges(core, when) {
            return self.next_timer();
        }
        let edge_due = self.edges.due(when);
        self.advance_plant(when);
        self.pwm_timers_due(core, when);
        self.apply_due_actions(core, when);
        self.apply_due_glitches(core, when);
        self.send_due_host_bytes(core, when);
        self.raise_encoders(core, when);
        self.plant_step(core, when);
        self.update_supply(core, when);
        if self.edges.next_internal() <= when {
            // The plant changed its own dynamics: every prediction is stale.
            self.plan_edges(when);
        }
        self.edges
            .advance_plans(&self.robot, self.clock, when, edge_due);
        self.next_timer()
    }

    fn irq(&mut self, core: &mut Core, tag: u32, value: u32) {
        self.callbacks += 1;
        match tag {
            TAG_LED_PORT => self.recorder.leds_changed(core.cycle(), value as u8),
            t if (TAG_PORT_REG..TAG_PORT_REG + 16).contains(&t) => {
                self.bridge
                    .set_port((t - TAG_PORT_REG) as usize, value as u8);
                self.refresh_bridge(core, core.cycle());
                core.schedule(self.next_event());
            }
            t if (TAG_PORT_DDR..TAG_PORT_DDR + 16).contains(&t) => {
                self.bridge
                    .set_ddr((t - TAG_PORT_DDR) as usize, value as u8);
                self.refresh_bridge(core, core.cycle());
                core.schedule(self.next_event());
            }
            t if (TAG_UART_OUT..TAG_UART_OUT + 4).contains(&t) => {
                let n = (t - TAG_UART_OUT) as usize;
                self.uart.received(core.cycle(), n, value as u8);
            }
            _ => {}
        }
    }
}
