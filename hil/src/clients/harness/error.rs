//! [`HarnessError`]: one line each, saying what went wrong, where, and what
//! is allowed.

use thiserror::Error;

use crate::bench::BenchError;
use crate::board::BoardError;
use crate::firmware::description::DescriptionError;
use crate::firmware::elf::ElfError;

/// Debug prints the same line as Display: a test that ends in `?` or
/// `.unwrap()` shows the sentence, not the fields.
#[derive(Error)]
pub enum HarnessError {
    /// [`super::HarnessBuilder::build`] without [`super::HarnessBuilder::firmware`].
    #[error("the harness has no firmware: give its ELF with .firmware(path) (e.g. hil::paths::firmware_elf(\"robust\")), or a test description that names it (.tests(path), its firmware.elf)")]
    NoFirmware,
    /// The robot config: its message names the file, the field and the range.
    #[error(transparent)]
    Robot(#[from] plant_model::Error),
    #[error(transparent)]
    Board(#[from] BoardError),
    #[error(transparent)]
    Firmware(#[from] ElfError),
    /// The test description: its message names the file, the field and
    /// what is allowed.
    #[error(transparent)]
    Description(#[from] DescriptionError),
    /// A start the firmware cannot be given as asked (no bench interface
    /// and no description, a pin the board's MCU does not have, ...).
    #[error("start: {0}")]
    Start(String),
    /// The firmware answered a command with an error reply.
    #[error("{command}: the firmware replied {reply}")]
    Refused { command: String, reply: String },
    /// The bench stopped: the CPU crashed, a fault action was refused, the
    /// firmware hung, ...
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// A condition out of its range (as a scenario file's `[[expect]]`
    /// would be refused).
    #[error("run_until: the condition {message}")]
    Condition { message: String },
    /// A robot time out of range.
    #[error("{what} = {value} s: give more than 0 and at most 86400 s (a day) of robot time")]
    Time { what: &'static str, value: f64 },
    /// A leg the firmware would refuse.
    #[error("start: leg_mm = {leg_mm}: the firmware's legs are {min} to {max} mm")]
    Leg { leg_mm: f64, min: f32, max: f32 },
    /// [`super::Harness::run_until`] ran out of robot time before its
    /// condition held.
    #[error("run_until: {what} did not hold within {within_s} s of robot time (from {from_s:.3} s to {to_s:.3} s); last seen: {seen}")]
    Timeout {
        /// The condition, in words.
        what: String,
        within_s: f64,
        from_s: f64,
        to_s: f64,
        /// What the bench saw instead, at the end of the wait.
        seen: String,
    },
}

impl std::fmt::Debug for HarnessError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self, f)
    }
}
