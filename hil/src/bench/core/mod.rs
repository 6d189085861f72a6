//! [`BenchCore`]: the bench's side of the simulation, the handler simavr
//! calls back (register writes and reads, the bench's cycle timer, watched
//! IRQs). It holds one part per concern and dispatches each callback to
//! them; the parts' own files say what each does. The parts know nothing
//! of the core: what needs several of them (a bridge change reaching the
//! plant and the encoder plans, a fault action) is done here, each part
//! given the others or the few values it needs of them.

use plant_model::{Duty, Robot, RobotConfig, Seconds, Side};

use crate::bench::bridge::{Bridge, PinStats};
use crate::bench::edges::Encoders;
use crate::bench::error::PendingError;
use crate::bench::faults::{Action, FaultSchedule, Trigger};
use crate::bench::inject::Injection;
use crate::bench::power::{Brownout, Power};
use crate::bench::recorder::{
    AnalogEvent, Cutoff, DriveEvent, LedEvent, MotionEvent, PinEvent, Recorder, Retained, Sample,
    Snapshot,
};
use crate::bench::registers::{ACSR, ACSR_ACIC, ACSR_ACIE};
use crate::bench::requests::Requests;
use crate::bench::timers::{Look, SimavrTimers};
use crate::bench::uart::{HostUart, USB_SERIAL};
use crate::bench::usb::UsbHost;
use crate::bench::{BenchOptions, NEVER};
use crate::board::Board;
use crate::mcu::clock::Clock;
use crate::mcu::sim::{Core, DrivenPin, Handler};

mod parts;
mod records;

/// Tags of the IRQs the bench watches (see `BenchCore::irq`).
/// A driver input port's PORT and DDR register: + the port's index in
/// `Bridge::ports`.
pub(in crate::bench) const TAG_PORT_REG: u32 = 0x100;
pub(in crate::bench) const TAG_PORT_DDR: u32 = 0x200;
pub(in crate::bench) const TAG_LED_PORT: u32 = 3;
pub(in crate::bench) const TAG_UART_OUT: u32 = 16; // + USART number
/// The USB controller's attach line.
pub(in crate::bench) const TAG_USB_ATTACH: u32 = 24;

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
    /// The USB host, on an MCU with USB (set up by `setup.rs`).
    pub(in crate::bench) usb: Option<UsbHost>,
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
    pub(in crate::bench) fn new(
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
            robot: {
                let mut r = Robot::new(robot, options.seed)?;
                for side in Side::BOTH {
                    let all = wiring.encoder(side).kind == crate::board::EncoderKind::Xor;
                    r.count_all_edges(side, all);
                }
                r
            },
            plant_cycle: 0,
            counts,
            inject: Injection::new(options.seed ^ 0x5eed_f417),
            bridge: Bridge::new(*wiring, clock),
            edges: Encoders::new(wiring),
            uart: HostUart::new(wiring.command_uart.usart, clock),
            usb: None,
            power: Power::new(
                options.supply,
                wiring.battery.map_or(0.0, |b| b.divider),
                clock.cycles_in(Seconds(options.supply.startup_s)),
            ),
            faults: FaultSchedule::default(),
            recorder: Recorder::new(wiring.battery_leds),
            requests: Requests::default(),
            simavr_timers: SimavrTimers::new(wiring),
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
    pub(crate) fn callbacks(&self) -> u64 {
        self.callbacks
    }

    pub(in crate::bench) fn advance_plant(&mut self, cycle: u64) {
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

    pub(in crate::bench) fn next_event(&self) -> u64 {
        self.edges
            .next_edge()
            .min(self.next_other_event())
            .min(self.power.release_at())
    }

    /// The next event that is not an encoder edge (nor the brown-out
    /// detector's release).
    pub(in crate::bench) fn next_other_event(&self) -> u64 {
        self.next_step
            .min(self.bridge.next_top())
            .min(self.uart.next_due())
            .min(self.usb.as_ref().map_or(NEVER, UsbHost::next_due))
            .min(self.faults.next_due())
            .min(self.edges.next_internal())
    }

    /// What a cycle timer callback returns: the next event, or 0 for none.
    pub(super) fn next_timer(&self) -> u64 {
        match self.next_event() {
            NEVER => 0,
            next => next,
        }
    }

    /// Bring the bench's own peripheral models to their reset state.
    pub(in crate::bench) fn after_reset(&mut self, core: &mut Core) {
        let cycle = core.cycle();
        self.set_comparator(core, false);
        self.bridge.reset();
        self.refresh_bridge(core, cycle);
        // The LED pins are inputs again: all dark.
        self.recorder.leds_changed(cycle, 0);
        // The USB controller is detached again; the cable stays in.
        if let Some(usb) = &mut self.usb {
            usb.plug(core);
        }
    }

    /// The USB host's actions due at `when`, their bytes recorded as a
    /// USART's are.
    fn usb_due(&mut self, core: &mut Core, when: u64) {
        let Some(usb) = &mut self.usb else { return };
        if usb.next_due() > when {
            return;
        }
        let traffic = usb.step(core, when);
        for b in traffic.received {
            self.uart.received(when, USB_SERIAL as usize, b);
        }
        for b in traffic.delivered {
            self.uart.delivered(when, USB_SERIAL as usize, b);
        }
    }

    /// The reset the run loop is to perform, taken.
    pub(in crate::bench) fn take_reset(&mut self) -> bool {
        self.requests.take_reset()
    }

    /// The brown-out release the run loop is to perform, taken.
    pub(in crate::bench) fn take_bod_release(&mut self) -> bool {
        self.requests.take_bod_release()
    }

    /// The error a callback recorded, taken.
    pub(in crate::bench) fn take_error(&mut self) -> Option<PendingError> {
        self.requests.take_error()
    }

    /// The run loop has seen the flag (it handles what is behind it next).
    pub(in crate::bench) fn clear_attention(&mut self) {
        self.requests.clear_attention();
    }

    /// The periodic plant step, when due: A0 and the trace.
    pub(super) fn plant_step(&mut self, core: &mut Core, when: u64) {
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
    pub(super) fn check_simavr_timer(&mut self, core: &Core, look: Look) {
        if let Some(e) = self.simavr_timers.judge(core, look) {
            self.requests.fail(e);
        }
    }

    /// The bench's timers' updates and graces due at `when`.
    pub(super) fn pwm_timers_due(&mut self, core: &mut Core, when: u64) {
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
        }
        // A mirrored timer's registers are both simavr's and the bench's.
        if self.bridge.owns_write(addr) {
            self.write_pwm_register(core, addr, value);
        }
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
        self.usb_due(core, when);
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
            TAG_USB_ATTACH => {
                if let Some(usb) = &mut self.usb {
                    usb.attach(core.cycle(), value != 0, self.clock);
                    core.schedule(self.next_event());
                }
            }
            t if (TAG_UART_OUT..TAG_UART_OUT + 4).contains(&t) => {
                let n = (t - TAG_UART_OUT) as usize;
                self.uart.received(core.cycle(), n, value as u8);
            }
            _ => {}
        }
    }
}
