//! What can end a run: [`BenchError`], and the errors a callback records for
//! the run loop to report ([`PendingError`]: a callback cannot return one).

use thiserror::Error;

use super::faults::Action;
use crate::firmware::elf::{ElfError, Firmware, Location};
use crate::mcu::clock::Clock;
use crate::mcu::pwm::PwmError;
use crate::mcu::sim::SimError;

#[derive(Debug, Error)]
pub enum BenchError {
    #[error(transparent)]
    Elf(#[from] ElfError),
    #[error(transparent)]
    Sim(#[from] SimError),
    /// A bench-interface path (the robust or thesis build's own tests) on
    /// a firmware without that interface.
    #[error("{0}; a firmware that knows nothing of the bench runs with a test description (--tests FILE; docs/reference/test-description.md)")]
    NoInterface(String),
    /// A test description that does not fit the firmware or the run.
    #[error("{0}")]
    Description(String),
    #[error(transparent)]
    Plant(#[from] plant_model::Error),
    #[error("{error} ({at})")]
    Pwm { error: PwmError, at: Location },
    #[error("timer {timer}: TCCR{timer}A/B select mode {wgm} ({mode}) with clock select {cs}, and the firmware {observed} ({at}); on the timers simavr runs the bench accepts, once observed, only normal, CTC with TOP OCRnA and fast PWM with a fixed TOP or TOP ICRn, from the CPU clock, with no compare output on a pin the board uses (verified against the datasheet), and any mode while nothing observes it")]
    UnverifiedTimer {
        timer: u8,
        wgm: u8,
        cs: u8,
        mode: String,
        observed: String,
        at: Location,
    },
    /// A scheduled action the plant refused (a slip outside [0, 1], a
    /// negative battery voltage, ...): it was not applied, and the run ends
    /// rather than go on without the fault it was asked for.
    #[error("the plant refused the scheduled action {action:?}: {error} ({at})")]
    ActionRefused {
        action: Box<Action>,
        error: Box<plant_model::Error>,
        at: Location,
    },
    #[error("the firmware crashed {at}")]
    Crashed { at: Location },
    #[error("the firmware stopped (sleep with interrupts disabled or a break) {at}")]
    Stopped { at: Location },
    #[error("{what}: no progress within {robot_s} s of robot time ({at})")]
    Timeout {
        what: String,
        robot_s: f64,
        at: Location,
    },
    /// The firmware was busy in a test without progress (see [`crate::bench::hang`]).
    #[error("the firmware hung: busy in a test without progress (no wheel motion, no change of state, phase, segment or fault) for {still:.3} s of robot time, {report}", still = .0.still_s, report = .0)]
    Hang(crate::bench::hang::HangReport),
    /// The debugger ended the run (`kill`, or its connection went away).
    #[error("the debugger ended the run: {0}")]
    Debugger(String),
}

/// An error met inside a callback, with the cycle and PC it happened at.
pub(super) enum PendingError {
    Pwm(PwmError, u64, u32),
    Timer {
        timer: u8,
        wgm: u8,
        cs: u8,
        mode: String,
        observed: String,
        cycle: u64,
        pc: u32,
    },
    Refused {
        action: Action,
        error: plant_model::Error,
        cycle: u64,
        pc: u32,
    },
}

impl PendingError {
    /// The error to report, located in `firmware`.
    pub(super) fn located(self, firmware: &Firmware, clock: Clock) -> BenchError {
        let at = |cycle, pc| firmware.location(clock, cycle, pc);
        match self {
            PendingError::Pwm(error, cycle, pc) => BenchError::Pwm {
                error,
                at: at(cycle, pc),
            },
            PendingError::Timer {
                timer,
                wgm,
                cs,
                mode,
                observed,
                cycle,
                pc,
            } => BenchError::UnverifiedTimer {
                timer,
                wgm,
                cs,
                mode,
                observed,
                at: at(cycle, pc),
            },
            PendingError::Refused {
                action,
                error,
                cycle,
                pc,
            } => BenchError::ActionRefused {
                action: Box::new(action),
                error: Box::new(error),
                at: at(cycle, pc),
            },
        }
    }
}
