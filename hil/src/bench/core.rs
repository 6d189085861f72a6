//! [`BenchCore`]: the bench's side of the simulation, the handler simavr
//! calls back (register writes and reads, the bench's cycle timer, watched
//! IRQs). It holds one part per concern and dispatches each callback to
//! them; the parts' own files say what each does.

use plant_model::{Robot, RobotConfig, Seconds};

use super::bridge::Bridge;
use super::edges::Encoders;
use super::error::PendingError;
use super::faults::FaultSchedule;
use super::power::Power;
use super::recorder::Recorder;
use super::registers::{ACSR, ACSR_ACIC, ACSR_ACIE, CHECKED_TIMERS};
use super::setup::{TAG_LED_PORT, TAG_PORT_DDR, TAG_PORT_REG, TAG_UART_OUT};
use super::uart::HostUart;
use super::BenchOptions;
use crate::fwvars::FwVars;
use crate::inject::Injection;
use crate::sim::{Core, Handler};
use crate::time::Clock;
use crate::wiring::Wiring;

/// No event: a cycle never reached.
pub(super) const NEVER: u64 = u64::MAX;

/// The bench's side of the simulation (see the module docs).
pub struct BenchCore {
    pub(super) clock: Clock,
    pub(super) robot: Robot,
    /// The cycle the plant has been advanced to.
    pub(super) plant_cycle: u64,
    pub(super) vars: FwVars,
    /// The injection points (`crate::inject`): encoder lines, bridge, link.
    pub(super) inject: Injection,
    pub(super) bridge: Bridge,
    pub(super) edges: Encoders,
    pub(super) uart: HostUart,
    pub(super) power: Power,
    pub(super) faults: FaultSchedule,
    pub(super) recorder: Recorder,
    pub(super) requests: Requests,
    /// The periodic plant step: its next cycle, its length, and every how
    /// many steps a trace sample is taken.
    next_step: u64,
    step_cycles: u64,
    trace_every: u32,
    steps: u32,
    /// Callbacks from simavr into the bench (timer, IO, IRQ).
    callbacks: u64,
}

/// What a callback leaves for the run loop: an error, a reset to perform,
/// the brown-out detector letting go.
#[derive(Default)]
pub(super) struct Requests {
    error: Option<PendingError>,
    reset: bool,
    bod_release: bool,
    /// Any of them (one flag read per instruction).
    attention: bool,
}

impl Requests {
    /// Record `e`, unless an error is already waiting.
    pub(super) fn fail(&mut self, e: PendingError) {
        if self.error.is_none() {
            self.error = Some(e);
            self.attention = true;
        }
    }

    /// Restart the MCU after this step.
    pub(super) fn reset(&mut self) {
        self.reset = true;
        self.attention = true;
    }

    /// The brown-out detector let go: restart the MCU with BORF set.
    pub(super) fn bod_release(&mut self) {
        self.bod_release = true;
        self.attention = true;
    }
}

impl BenchCore {
    pub(super) fn new(
        robot: &RobotConfig,
        options: &BenchOptions,
        wiring: &Wiring,
        vars: FwVars,
    ) -> Result<Self, plant_model::Error> {
        let clock = options.clock;
        let step_cycles = clock.cycles_in(Seconds(options.plant_step_s)).max(1);
        let trace_every = ((options.trace_interval_s / options.plant_step_s).round() as u32).max(1);
        Ok(Self {
            clock,
            robot: Robot::new(robot, options.seed)?,
            plant_cycle: 0,
            vars,
            inject: Injection::new(options.seed ^ 0x5eed_f417),
            bridge: Bridge::new(*wiring, clock),
            edges: Encoders::new(wiring),
            uart: HostUart::new(wiring.bluetooth_uart, clock),
            power: Power::new(
                options.supply,
                options.battery_divider,
                clock.cycles_in(Seconds(options.supply.startup_s)),
            ),
            faults: FaultSchedule::default(),
            recorder: Recorder::new(wiring.battery_leds),
            requests: Requests::default(),
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
        std::mem::take(&mut self.requests.reset)
    }

    /// The brown-out release the run loop is to perform, taken.
    pub(super) fn take_bod_release(&mut self) -> bool {
        std::mem::take(&mut self.requests.bod_release)
    }

    /// The error a callback recorded, taken.
    pub(super) fn take_error(&mut self) -> Option<PendingError> {
        self.requests.error.take()
    }

    /// The run loop has seen the flag (it handles what is behind it next).
    pub(super) fn clear_attention(&mut self) {
        self.requests.attention = false;
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

    fn check_simavr_timer(&mut self, core: &Core, timer: u8, a: u16, b: u16) {
        let tccra = core.data(a);
        let tccrb = core.data(b);
        let cs = tccrb & 0b111;
        if cs == 0 {
            return; // not clocked: any mode is harmless
        }
        let wgm = ((tccrb >> 3) & 0b11) << 2 | (tccra & 0b11);
        // The modes the firmware uses: CTC on timers 1 and 3 (the robust
        // build's tick and delays; tests/timing.rs holds the tick to its
        // 15 ms), and Arduino's timer 0 (fast PWM, /64, overflow interrupt
        // every 1024 us: millis and micros).
        let verified = matches!((timer, wgm, cs), (1, 4, 1..=5) | (3, 4, 1..=5) | (0, 3, 3));
        if !verified {
            self.requests.fail(PendingError::Timer {
                timer,
                wgm,
                cs,
                cycle: core.cycle(),
                pc: core.pc(),
            });
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
        if let Some(&(timer, a, b)) = CHECKED_TIMERS.iter().find(|t| t.1 == addr || t.2 == addr) {
            self.check_simavr_timer(core, timer, a, b);
            return;
        }
        self.write_pwm_register(core, addr, value);
    }

    fn attention(&self) -> bool {
        self.requests.attention
    }

    fn before_io_read(&mut self, core: &mut Core, addr: u16) {
        self.before_pin_read(core, addr);
    }

    fn io_read(&mut self, core: &mut Core, addr: u16) -> u8 {
        self.refuse_pwm_read(core, addr)
    }

    fn timer(&mut self, core: &mut Core, when: u64) -> u64 {
        self.callbacks += 1;
        if self.raise_planned_edges(core, when) {
            return self.next_timer();
        }
        let edge_due = self.edges.due(when);
        self.advance_plant(when);
        for which in 0..2 {
            if self.bridge.apply_top_if_due(which, when) {
                self.refresh_bridge(core, when);
            }
        }
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
        self.advance_plans(when, edge_due);
        self.next_timer()
    }

    fn irq(&mut self, core: &mut Core, tag: u32, value: u32) {
        self.callbacks += 1;
        match tag {
            TAG_LED_PORT => self.recorder.leds_changed(core.cycle(), value as u8),
            TAG_PORT_REG => {
                self.bridge.set_port(value as u8);
                self.refresh_bridge(core, core.cycle());
                core.schedule(self.next_event());
            }
            TAG_PORT_DDR => {
                self.bridge.set_ddr(value as u8);
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
