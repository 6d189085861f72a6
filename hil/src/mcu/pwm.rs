//! The bench's own model of the ATmega2560's timers, those a board's PWM
//! pins are on.
//!
//! simavr emulates phase-correct PWM wrongly (it counts to 256 instead of up to
//! 255 and back down, and produces no output-pin edges), and each running
//! prescaler-1 timer costs it one callback per period and compare channel. So
//! the bench computes the waveforms of the timers a board's PWM pins are on
//! from their registers, as the datasheet specifies (ATmega640/1280/2560
//! datasheet, sections 16, 17 and 20), in one of two ways:
//!
//! - emulated ([`PwmTimer::number`]; timers 1-5): the timer is the
//!   model's, simavr never clocks it;
//! - mirrored ([`PwmTimer::mirror`]; timer 0, the Arduino core's `millis()`
//!   timer, whose overflow interrupt every Arduino sketch enables): simavr
//!   runs the counter, its interrupts and flags (judged as on any timer
//!   simavr runs, `bench/timers.rs`), and the model follows the writes to
//!   the mode, clock and compare registers to compute the outputs.
//!
//! What the model covers:
//!
//! - every waveform generation mode ([`mode`]): the 8-bit timers' (0 and 2)
//!   modes 0-7 (tables 16-8 and 20-8) and the 16-bit timers' 0-15 (table
//!   17-2): normal, CTC (TOP OCRnA or ICRn), fast PWM (8/9/10-bit, ICRn,
//!   OCRnA), phase correct (8/9/10-bit, ICRn, OCRnA), phase and frequency
//!   correct (ICRn, OCRnA); each prescaler of timer 2's table (1, 8, 32,
//!   64, 128, 256, 1024) and of the others' (1, 8, 64, 256, 1024);
//! - the compare outputs per mode (the COM tables: toggle, clear, set in the
//!   non-PWM modes; non-inverting and inverting PWM; COM = 1 toggling OCnA
//!   where the datasheet says so, else disconnected), their extreme OCR
//!   values, and OCR double buffering (updated at TOP in phase correct, at
//!   BOTTOM in fast PWM and phase and frequency correct, at once in normal
//!   and CTC) ([`waveform`], `timer.rs`);
//! - the counter as a pure function of the cycle: TCNT reads (through TEMP
//!   on the 16-bit timers), TCNT writes while the timer is stopped, ICRn
//!   writes (through TEMP, in the modes that take TOP from it);
//! - 16-bit registers are written through the shared TEMP byte: the high
//!   byte first, then the low byte commits both.
//!
//! Refused with [`PwmError`], since the bench never pretends to emulate what
//! it has not verified: on an emulated timer, its interrupts (TIMSK: the
//! firmware's clock, [`PwmError::FirmwareClock`]) and interrupt flags
//! (TIFR reads); forced output compare on a connected output, TCNT writes
//! while running; and, when they can matter (see `bench/timers.rs`),
//! external and asynchronous clocks and the reserved modes.
//!
//! The timers' register blocks are data ([`layout::ATMEGA2560`]), so that
//! an MCU description can supply its own.

pub mod layout;
pub mod mode;
mod registers;
mod timer;
pub mod waveform;

pub use mode::{Action, Kind, Mode, Top};
pub use timer::{PinDrive, PwmTimer, WriteEffect};
pub use waveform::{ChannelWave, Counter, Lead};

use thiserror::Error;

/// One of the MCU's timers, by its number (timer 0-5 on the ATmega2560).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct TimerId(pub u8);

impl TimerId {
    /// The timer's number.
    pub fn number(self) -> u8 {
        self.0
    }
}

impl std::fmt::Display for TimerId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "timer {}", self.0)
    }
}

/// A timer's mode and clock select, as the firmware set them: what an
/// error names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    pub timer: TimerId,
    pub wgm: u8,
    pub cs: u8,
    /// None for a reserved mode.
    pub mode: Option<Mode>,
    /// MAX of the counter: 0xFF or 0xFFFF.
    pub max: u32,
}

impl std::fmt::Display for Config {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.timer.number();
        let name = self.mode.map_or("reserved".into(), |m| m.name());
        write!(
            f,
            "{}: TCCR{n}A/B select mode {} ({name}) with clock select {}",
            self.timer, self.wgm, self.cs
        )
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PwmError {
    #[error("{config}, an external clock on pin T{n}, which the bench does not emulate; use clock selects 0-5", n = config.timer.number())]
    ExternalClock { config: Config },
    #[error("{config} from the asynchronous oscillator (ASSR), which the bench does not emulate; clock timer 2 from the CPU clock (AS2 = EXCLK = 0)")]
    Asynchronous { config: Config },
    #[error("{config}: a reserved mode; use a mode of datasheet table 17-2 (16-bit timers), 16-8 (timer 0) or 20-8 (timer 2)")]
    ReservedMode { config: Config },
    #[error("{config}: the counter ({tcnt}) was above TOP ({top}) and counts on to MAX past a connected output's compare value, which the bench does not emulate; change TOP while the counter is below it, or with the timer stopped")]
    MatchAboveTop { config: Config, tcnt: u32, top: u32 },
    #[error("{config}: the firmware {what}, which the bench does not emulate on the timers of the board's PWM pins (every mode's waveform and counter are; interrupts, interrupt flags and forced compares are not)")]
    UnsupportedAccess { config: Config, what: String },
    /// Interrupts enabled on a timer the bench emulates for the board's
    /// PWM pins: the firmware times itself with it.
    #[error("{config}: the firmware enabled its interrupts (TIMSK{n} = 0x{timsk:02X}), so it is the firmware's clock, and the board puts motor PWM on its compare outputs; the bench emulates a PWM pin's timer without interrupts: put the PWM on another timer's pins in the board file", n = config.timer.number())]
    FirmwareClock { config: Config, timsk: u8 },
    /// A compare output connected to a pin the board uses for something
    /// else (an encoder, an LED, another channel's PWM input).
    #[error("{config}: the firmware connected OC{n}{channel} to {pin}, which the board wires to something else; the bench models a compare output only on the motor PWM input the board gives it", n = config.timer.number())]
    ForeignOutput {
        config: Config,
        channel: char,
        /// The pin as the board names it ("D13", "PE2").
        pin: String,
    },
    #[error("{error}; the firmware {what} then")]
    Observed {
        error: Box<PwmError>,
        what: &'static str,
    },
}

impl PwmError {
    /// The same refusal, met when the firmware did `what`.
    pub fn observed(self, what: &'static str) -> PwmError {
        PwmError::Observed {
            error: Box::new(self),
            what,
        }
    }
}

#[cfg(test)]
mod tests;
