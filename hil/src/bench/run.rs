//! The run loops: [`Bench::run_until`] and its kin, the checks they make on
//! a grid of robot time (`done`, the hang watch, the limit), and the
//! instruction-level [`Observer`] and [`Debugger`] hooks.

use plant_model::Seconds;

use super::registers::{MCUSR, MCUSR_BORF};
use super::{Bench, BenchError};
use crate::mcu::sim::{CpuState, Handler};

/// How often [`Bench::run_until`] checks its `done` (robot time: 1024
/// cycles at 16 MHz). Short beside anything a test waits for, long beside
/// the 100-odd host instructions a check costs, so that the run loop is
/// simavr's own loop with one bound (the check's cycle) most of the time.
pub const CHECK_PERIOD_S: f64 = 64e-6;

/// One executed step of the CPU, for observers that need instruction-level
/// detail (timing analysis, traces). Observing costs speed; the bench runs
/// without an observer by default.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    pub pc_before: u32,
    pub pc_after: u32,
    pub cycle_before: u64,
    pub cycle_after: u64,
    pub sp_before: u16,
    pub sp_after: u16,
    pub interrupts_before: bool,
    pub interrupts_after: bool,
    /// The opcode at `pc_before` (the instruction executed, unless asleep).
    pub opcode: u16,
    /// The CPU slept during (part of) the step.
    pub slept: bool,
    /// Cycle of the last A-channel edge raised on each encoder (left, right).
    pub last_a_edge: [u64; 2],
}

/// Sees every step of the CPU, or only the run loop's checks.
pub trait Observer: std::any::Any {
    fn step(&mut self, step: &Step);
    /// Whether [`Observer::step`] is wanted: seeing every step costs the
    /// run loop its speed; an observer of the checks alone does not.
    fn wants_steps(&self) -> bool {
        true
    }
    /// Called at each of the run loop's checks (every [`CHECK_PERIOD_S`] of
    /// robot time, on the grid [`Bench::run_until`] describes), before its
    /// `done`: the same cycles in every run, whatever watches it. The plant
    /// may lag the CPU there, as for `done`.
    fn check(&mut self, _bench: &Bench) {}
    /// For taking a concrete observer back out of the bench.
    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any>;
}

/// A debugger driving the run loop (`crate::bench::gdb`): told before and after
/// each step of every run loop, it pauses the run by serving its client
/// inside [`Debugger::after_step`]. The run loop is the one without a
/// debugger, step for step, so a run under a debugger that only pauses it
/// is the run without one.
pub trait Debugger {
    /// Before a step, the MCU as the step will find it.
    fn before_step(&mut self, bench: &Bench);
    /// After a step (`slept`: no instruction ran, the CPU slept or was
    /// held in reset). Ok(false): the debugger left, the run goes on
    /// without it; an error ends the run.
    fn after_step(&mut self, bench: &mut Bench, slept: bool) -> Result<bool, BenchError>;
    /// The step crashed or stopped the CPU: the debugger may look before
    /// the run ends with that error.
    fn fault(&mut self, bench: &mut Bench);
    /// The run is over (`completed`: its test completed); the debugger is
    /// let go after this.
    fn run_over(&mut self, bench: &Bench, completed: bool);
}

impl Bench {
    /// Run until `done` holds or `limit_s` of robot time pass; Ok(false) on
    /// the limit. `done` is checked after the first step, then after the
    /// first step that reaches each point of a grid of [`CHECK_PERIOD_S`]
    /// of robot time (a step is an instruction, or a sleep up to the next
    /// event; the grid starts at cycle 0, so the checks fall at the same
    /// cycles however a run is split into calls); the run ends after the
    /// first step that reaches the limit.
    /// `done` should look at the firmware (memory, pins), not at the plant,
    /// which may lag the CPU by an encoder edge or two between the bench's
    /// own events. On return the plant is at the current cycle.
    pub fn run_until(
        &mut self,
        limit_s: f64,
        done: impl FnMut(&Bench) -> bool,
    ) -> Result<bool, BenchError> {
        let result = self.run_until_unsynced(limit_s, done);
        self.sync_plant();
        result
    }

    /// Run until `done`, or fail with a timeout naming `what`.
    pub fn run_expect(
        &mut self,
        what: &str,
        limit_s: f64,
        done: impl FnMut(&Bench) -> bool,
    ) -> Result<(), BenchError> {
        if self.run_until(limit_s, done)? {
            Ok(())
        } else {
            Err(BenchError::Timeout {
                what: what.into(),
                robot_s: limit_s,
                at: self.location(),
            })
        }
    }

    /// Run for `seconds` of robot time.
    pub fn run_for(&mut self, seconds: f64) -> Result<(), BenchError> {
        self.run_until(seconds, |_| false).map(|_| ())
    }

    /// Bring the plant (and the statistics) to the current cycle: the run
    /// loop lets them lag between the bench's own events.
    pub(super) fn sync_plant(&mut self) {
        let now = self.avr.cycle();
        self.avr.handler_mut().sync(now);
    }

    /// [`Bench::run_until`] without the plant brought up to date at the end
    /// (`done` must not look at the plant).
    fn run_until_unsynced(
        &mut self,
        limit_s: f64,
        mut done: impl FnMut(&Bench) -> bool,
    ) -> Result<bool, BenchError> {
        let limit = self.avr.cycle() + self.clock.cycles_in(Seconds(limit_s));
        let ms = self.clock.cycles_per_ms();
        let period = self.clock.cycles_in(Seconds(CHECK_PERIOD_S)).max(1);
        // The first check after the first step, then one per grid point.
        let mut check_at = self.avr.cycle();
        // (At the limit the check ends the run: what follows is not used.)
        let next_check = |now: u64| ((now / period + 1) * period).min(limit);
        let mut hang_check_at = check_at;
        // Instruction-level detail costs speed: only when someone looks.
        let watch = self.profile.is_some()
            || self.observer.as_ref().is_some_and(|o| o.wants_steps())
            || self.debugger.is_some();
        let mut sleeping = self.avr.state() == CpuState::Sleeping;
        if !watch {
            // The same steps and checks as the loop below, in bursts that
            // stay inside the simulator module up to the next check. (Holding
            // or releasing the reset always raises attention, which ends a
            // burst, so a burst never runs through a brown-out.)
            loop {
                let state = if self.avr.handler().held_in_reset() {
                    let before = self.avr.cycle();
                    self.avr.hold_step();
                    self.sleep_cycles += self.avr.cycle() - before;
                    sleeping = true;
                    CpuState::Running
                } else {
                    let burst = self.avr.run_burst(check_at, &mut sleeping);
                    self.sleep_cycles += burst.slept;
                    burst.state
                };
                if !matches!(state, CpuState::Running | CpuState::Sleeping) {
                    return Err(self.stop_error(state));
                }
                if self.avr.handler().attention() {
                    self.attend()?;
                    sleeping = self.avr.state() == CpuState::Sleeping;
                }
                let now = self.avr.cycle();
                if now >= check_at {
                    check_at = next_check(now);
                    if let Some(end) =
                        self.check_point(now, &mut done, &mut hang_check_at, ms, limit)?
                    {
                        return Ok(end);
                    }
                }
            }
        }
        loop {
            let before = self.avr.cycle();
            let (pc_before, sp_before, i_before) = if watch {
                (self.avr.pc(), self.avr.sp(), self.avr.interrupts_enabled())
            } else {
                (0, 0, false)
            };
            if let Some(mut d) = self.debugger.take() {
                d.before_step(self);
                self.debugger = Some(d);
            }
            // Held in reset by the brown-out detector: no instruction runs,
            // the plant and the bench's events go on.
            let held = self.avr.handler().held_in_reset();
            let state = if held {
                self.avr.hold_step();
                CpuState::Running
            } else {
                self.avr.step()
            };
            let now = self.avr.cycle();
            // simavr jumps over a sleep in the same step that executes the
            // `sleep` instruction, and again in each step while asleep.
            let asleep = state == CpuState::Sleeping || held;
            let slept = sleeping || asleep;
            sleeping = asleep;
            if slept {
                self.sleep_cycles += now - before;
            }
            if watch {
                if let (false, Some(profile)) = (slept, &mut self.profile) {
                    profile[(pc_before / 2) as usize] += now - before;
                }
                if self.observer.as_ref().is_some_and(|o| o.wants_steps()) {
                    self.observe(pc_before, before, sp_before, i_before, slept);
                }
            }
            if !matches!(state, CpuState::Running | CpuState::Sleeping) {
                if let Some(mut d) = self.debugger.take() {
                    d.fault(self);
                    self.debugger = Some(d);
                }
                return Err(self.stop_error(state));
            }
            if self.avr.handler().attention() {
                self.attend()?;
                sleeping = self.avr.state() == CpuState::Sleeping;
            }
            if let Some(mut d) = self.debugger.take() {
                if d.after_step(self, slept)? {
                    self.debugger = Some(d);
                }
            }
            if now >= check_at {
                check_at = next_check(now);
                if let Some(end) =
                    self.check_point(now, &mut done, &mut hang_check_at, ms, limit)?
                {
                    return Ok(end);
                }
            }
        }
    }

    /// `run_until`'s periodic check at cycle `now`: `done`, the hang watch
    /// (once per `ms`), the time limit. Some(end) ends the run.
    fn check_point(
        &mut self,
        now: u64,
        done: &mut impl FnMut(&Bench) -> bool,
        hang_check_at: &mut u64,
        ms: u64,
        limit: u64,
    ) -> Result<Option<bool>, BenchError> {
        if let Some(mut o) = self.observer.take() {
            o.check(self);
            self.observer = Some(o);
        }
        if done(self) {
            return Ok(Some(true));
        }
        if now >= *hang_check_at {
            *hang_check_at = now + ms;
            self.check_hang()?;
        }
        Ok((now >= limit).then_some(false))
    }

    /// The error for a CPU that stopped running and sleeping.
    fn stop_error(&self, state: CpuState) -> BenchError {
        let at = self.location();
        if state == CpuState::Crashed {
            BenchError::Crashed { at }
        } else {
            BenchError::Stopped { at }
        }
    }

    /// Stop a hung firmware (checked once per millisecond of robot time).
    fn check_hang(&mut self) -> Result<(), BenchError> {
        if self.hang.is_none() {
            return Ok(());
        }
        // The watch looks at the wheels.
        self.sync_plant();
        let progress = self.progress();
        let Some(cycles) = self.hang.as_mut().and_then(|w| w.check(&progress)) else {
            return Ok(());
        };
        tracing::debug!(
            t_s = self.robot_time_s(),
            still_s = self.clock.seconds(cycles).0,
            at = %self.location(),
            "hung: no progress, the run is stopped"
        );
        Err(BenchError::Hang(crate::bench::hang::HangReport {
            still_s: self.clock.seconds(cycles).0,
            at: self.location(),
            callers: crate::bench::hang::callers(&self.avr, &self.firmware, 4),
        }))
    }

    /// Handle what a callback flagged: a reset to perform, an error to report.
    fn attend(&mut self) -> Result<(), BenchError> {
        let core = self.avr.handler_mut();
        core.clear_attention();
        if core.take_reset() {
            self.reset_mcu();
        }
        if self.avr.handler_mut().take_bod_release() {
            // The detector lets go: the MCU starts from its reset vector,
            // with BORF set in MCUSR as the datasheet says.
            self.reset_mcu();
            let mcusr = self.avr.data(MCUSR);
            self.avr.set_data(MCUSR, mcusr | MCUSR_BORF);
        }
        match self.avr.handler_mut().take_error() {
            Some(e) => Err(e.located(&self.firmware, self.clock)),
            None => Ok(()),
        }
    }

    fn observe(
        &mut self,
        pc_before: u32,
        cycle_before: u64,
        sp_before: u16,
        i_before: bool,
        slept: bool,
    ) {
        let step = Step {
            pc_before,
            pc_after: self.avr.pc(),
            cycle_before,
            cycle_after: self.avr.cycle(),
            sp_before,
            sp_after: self.avr.sp(),
            interrupts_before: i_before,
            interrupts_after: self.avr.interrupts_enabled(),
            opcode: self.avr.flash_word(pc_before),
            slept,
            last_a_edge: self.avr.handler().last_a_edge(),
        };
        if let Some(o) = &mut self.observer {
            o.step(&step);
        }
    }
}
