//! When a timer's configuration is judged: the bench's own timers (the
//! board's PWM pins', `crate::mcu::pwm`) and those simavr runs.
//!
//! Firmware sets a timer up one register, often one bit, at a time:
//! Arduino's `init()` passes timer 0 through mode 3 at clock/8 for an
//! instruction, timers 1, 3, 4 and 5 through mode 0 at clock/64 before
//! mode 1, timer 2 through mode 0. Such a state lasts 2 to 6 cycles and
//! nothing sees it. So a configuration is judged when it can matter, not
//! at the write that passes through it:
//!
//! - at once, when something observes it: a compare output connected, an
//!   interrupt enabled, the counter or the flags read;
//! - [`GRACE_CYCLES`] after it was set, if it is still in force then (the
//!   remembered write's cycle and PC name it).
//!
//! On the bench's timers every mode is emulated; what is not (an external
//! or asynchronous clock, a reserved mode) is refused at either moment.
//! Their interrupts are refused at once: the firmware times itself with
//! the timer (its clock), which the bench does not emulate on a timer it
//! runs for the board's PWM pins. Timer 0, the Arduino core's `millis()`
//! timer, is not taken over but mirrored ([`mirrored`]): simavr runs it,
//! judged as below, and the bench computes the outputs on the board's PWM
//! pins from the registers written.
//!
//! On simavr's timers a clocked configuration is accepted when it is
//! verified, or when nothing can observe it: no interrupt of the timer
//! enabled, its counter and flags not read, no compare output on a pin the
//! board uses (a pin the board does not wire to the robot cannot matter to
//! the plant). So the grace never refuses there: an unobserved state is
//! accepted however long it lasts. Verified (`tests/timer_modes.rs` holds
//! simavr's interrupt periods to the datasheet's, on every timer and
//! prescaler): normal, CTC with TOP = OCRnA, fast PWM with a fixed TOP or
//! TOP = ICRn, from the CPU clock, with no compare output on a board pin
//! (simavr's output waveforms are not verified). simavr gets the others
//! wrong (phase correct counts to 256, fast PWM with TOP = OCRnA overflows
//! every step, CTC with TOP = ICRn never sets the capture flag): observed,
//! they are refused.

use crate::board::{Board, PwmSource};
use crate::mcu::pwm::layout::Layout;
use crate::mcu::pwm::{mode, Kind, Mode, Top};
use crate::mcu::sim::Core;

use super::error::PendingError;
use super::NEVER;

/// How long an unverified configuration may stay in force unobserved:
/// longer than any of Arduino's intermediate states (2-6 cycles: one to
/// three read-modify-write instructions), shorter than any setup that
/// means to keep a configuration (it then lasts for good).
pub const GRACE_CYCLES: u64 = 16;

/// An unverified configuration remembered until it is judged.
#[derive(Debug, Clone)]
pub(super) struct Grace<E> {
    pending: Option<(E, u64, u32)>,
}

impl<E> Default for Grace<E> {
    fn default() -> Self {
        Self { pending: None }
    }
}

impl<E: PartialEq> Grace<E> {
    /// The configuration is now `problem` (None: verified), set at `cycle`
    /// by the instruction at `pc`: a new problem is remembered from this
    /// write, the same one from the write that first set it.
    pub(super) fn note(&mut self, problem: Option<E>, cycle: u64, pc: u32) {
        match problem {
            None => self.pending = None,
            Some(e) if self.pending.as_ref().is_some_and(|p| p.0 == e) => {}
            Some(e) => self.pending = Some((e, cycle, pc)),
        }
    }

    /// The cycle the remembered configuration is judged at.
    pub(super) fn due(&self) -> u64 {
        self.pending.as_ref().map_or(NEVER, |p| p.1 + GRACE_CYCLES)
    }

    /// The remembered configuration, taken if its grace is over at `now`:
    /// (problem, cycle, pc) of the write that set it.
    pub(super) fn expired(&mut self, now: u64) -> Option<(E, u64, u32)> {
        if self.due() <= now {
            self.pending.take()
        } else {
            None
        }
    }
}

/// Whether the bench mirrors timer `n` when a board's PWM pin is on it
/// (simavr runs it, the model computes its outputs: `PwmTimer::mirror`)
/// rather than emulating it. Timer 0 is the Arduino core's `millis()`
/// timer, whose overflow interrupt every Arduino sketch enables and whose
/// counter and flags `micros()` reads: the bench has no model of a timer's
/// interrupts, simavr's are verified for the mode the core uses (fast PWM,
/// 8-bit), so its counter stays simavr's. The others are emulated, and
/// their interrupts refused as the firmware's clock.
pub(super) fn mirrored(n: u8) -> bool {
    n == 0
}

/// The timers of the board's PWM pins the bench emulates (those it does
/// not mirror), in timer order.
pub fn emulated(board: &Board) -> Vec<u8> {
    let mut v = board.pwm_timers();
    v.retain(|&n| !mirrored(n));
    v
}

/// For each channel A, B, C of timer `n`: the pin the board uses for
/// something other than that channel's own PWM input, if its compare
/// output is on one (an encoder or LED pin, or a motor input the board
/// drives from another channel: PB7 is OC0A and OC1C). A compare output
/// connected there would drive a pin the bench models otherwise.
pub(super) fn foreign_channels(board: &Board, n: u8) -> [Option<String>; 3] {
    let mut pins: Vec<_> = board
        .battery_leds
        .iter()
        .flat_map(|l| [(l.green, None), (l.blue, None), (l.red, None)])
        .collect();
    for side in plant_model::Side::BOTH {
        let e = board.encoder(side);
        pins.extend(e.lines().into_iter().map(|(_, p)| (p, None)));
    }
    pins.extend(board.bridge_inputs().iter().map(|b| (b.pin, b.pwm)));
    ['A', 'B', 'C'].map(|channel| {
        let oc = PwmSource { timer: n, channel };
        pins.iter()
            .find(|(p, own)| p.pwm_sources().contains(&oc) && *own != Some(oc))
            .map(|(p, _)| p.name())
    })
}

/// A timer simavr runs, as the bench checks it.
#[derive(Debug, Clone)]
struct SimavrTimer {
    regs: Layout,
    /// Channels A, B, C whose pin the board uses (other than as the
    /// channel's own PWM input, which the bench models: a mirrored timer).
    on_board: [bool; 3],
}

/// The timers simavr runs (those the board's PWM pins are not on).
#[derive(Debug, Clone)]
pub(super) struct SimavrTimers {
    timers: Vec<SimavrTimer>,
}

/// What made the bench look at a simavr timer's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Look {
    /// A write to TCCRnA, TCCRnB or TIMSKn.
    Write(u16),
    /// A read of TCNTn or TIFRn.
    Read(u16),
}

impl SimavrTimers {
    /// The timers of `board` that simavr runs: all but those the bench
    /// emulates ([`emulated`]; it mirrors the others, whose compare
    /// outputs on the board's PWM inputs are then the bench's).
    pub(super) fn new(board: &Board) -> Self {
        let emulated = emulated(board);
        let timers = board
            .mcu
            .chip()
            .timers
            .iter()
            .filter(|r| !emulated.contains(&r.id.number()))
            .map(|&regs| SimavrTimer {
                regs,
                on_board: foreign_channels(board, regs.id.number()).map(|p| p.is_some()),
            })
            .collect();
        Self { timers }
    }

    /// Registers whose writes the bench observes.
    pub(super) fn write_addresses(&self) -> Vec<u16> {
        let r = self.timers.iter().map(|t| t.regs);
        r.flat_map(|r| [r.tccra, r.tccrb, r.timsk]).collect()
    }

    /// Registers whose reads the bench observes.
    pub(super) fn read_addresses(&self) -> Vec<u16> {
        let r = self.timers.iter().map(|t| t.regs);
        r.flat_map(|r| [r.tcnt, r.tifr]).collect()
    }

    fn find(&self, look: Look) -> Option<&SimavrTimer> {
        self.timers.iter().find(|t| {
            let r = t.regs;
            match look {
                Look::Write(a) => a == r.tccra || a == r.tccrb || a == r.timsk,
                Look::Read(a) => a == r.tcnt || a == r.tifr,
            }
        })
    }

    /// Whether `look` concerns one of these timers.
    pub(super) fn watches(&self, look: Look) -> bool {
        self.find(look).is_some()
    }

    /// Judge the timer `look` concerns, with its registers as `core` holds
    /// them (after simavr stored the write): the refusal, if observed and
    /// unverified.
    pub(super) fn judge(&self, core: &Core, look: Look) -> Option<PendingError> {
        let t = self.find(look)?;
        let r = t.regs;
        let (tccra, tccrb, timsk) = (core.data(r.tccra), core.data(r.tccrb), core.data(r.timsk));
        let cs = tccrb & 0b111;
        if cs == 0 {
            return None; // not clocked: nothing happens
        }
        let wgm = if r.sixteen_bit {
            ((tccrb >> 3) & 0b11) << 2 | (tccra & 0b11)
        } else {
            ((tccrb >> 3) & 0b1) << 2 | (tccra & 0b11)
        };
        let mode = Mode::decode(wgm, r.sixteen_bit);
        // Clock selects 6 and 7 of the shared prescaler are the external
        // clock on pin Tn; timer 2's table has none.
        let internal_clock = mode::prescaler(cs, r.prescalers).is_some();
        // What tests/timer_modes.rs holds to the datasheet: simavr gets
        // the dual slope modes, fast PWM with TOP = OCRnA and CTC with TOP
        // = ICRn wrong.
        let verified_mode = internal_clock
            && mode.is_some_and(|m| match m.kind {
                Kind::Normal => true,
                Kind::Ctc => m.top == Top::Ocra,
                Kind::Fast => m.top != Top::Ocra,
                Kind::PhaseCorrect | Kind::PhaseFrequencyCorrect => false,
            });
        // Cheap tests first: this runs at every read of a watched counter
        // (Arduino's micros() reads TCNT0 and TIFR0 each call), and only a
        // refusal needs words.
        let com_on_board = (0..3).filter(|&i| t.on_board[i] && (tccra >> (6 - 2 * i)) & 0b11 != 0);
        let connected = com_on_board.clone().next().is_some();
        let is_observed = matches!(look, Look::Read(_)) || connected || timsk != 0;
        if !is_observed || (verified_mode && !connected) {
            return None;
        }
        let n = r.id.number();
        let observed = match look {
            Look::Read(a) if a == r.tcnt => format!("read TCNT{n}"),
            Look::Read(_) => format!("read TIFR{n}"),
            _ if connected => format!(
                "connected OC{n}{} to a pin the board uses",
                com_on_board.map(|i| ['A', 'B', 'C'][i]).collect::<String>()
            ),
            _ => format!("enabled its interrupts (TIMSK{n} = 0x{timsk:02X})"),
        };
        Some(PendingError::Timer {
            timer: n,
            wgm,
            cs,
            mode: mode.map_or("reserved".into(), |m| m.name()),
            observed,
            cycle: core.cycle(),
            pc: core.pc(),
        })
    }
}

#[cfg(test)]
mod tests;
