//! The two wheel encoders: channel A on an external interrupt (any edge),
//! channel B read in the handler for the direction, exactly as the thesis'
//! `leftEncoderEvent` / `rightEncoderEvent`.
//!
//! The counters are the bench's `HT_LEFT_COUNT` / `HT_RIGHT_COUNT` (`i32`,
//! the thesis' `long`). This driver never resets them; users work with
//! differences.

use avr_device::interrupt;

use crate::bench;
use crate::board::{LeftEncoderA, LeftEncoderB, RightEncoderA, RightEncoderB};
use crate::hal::exint::{ExtInts, Line, Sense};
use crate::hal::gpio::{Input, Pin, PinId};
use crate::hal::sleep;

/// Both counts at one instant.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Counts {
    /// Left wheel count.
    pub left: i32,
    /// Right wheel count.
    pub right: i32,
}

/// Count change for one edge on channel A, from the levels of A (after the
/// edge) and B, as the thesis writes it: A high -> (B low ? +1 : -1),
/// A low -> (B low ? -1 : +1).
pub const fn step(a_high: bool, b_high: bool) -> i32 {
    if a_high {
        if !b_high {
            1
        } else {
            -1
        }
    } else if !b_high {
        -1
    } else {
        1
    }
}

const _: () = assert!(step(true, false) == 1 && step(true, true) == -1);
const _: () = assert!(step(false, false) == -1 && step(false, true) == 1);

/// The encoders, owning their four input pins and the external interrupts.
pub struct Encoders {
    _exint: ExtInts,
    _left_a: Pin<LeftEncoderA, Input>,
    _left_b: Pin<LeftEncoderB, Input>,
    _right_a: Pin<RightEncoderA, Input>,
    _right_b: Pin<RightEncoderB, Input>,
}

impl Encoders {
    /// Makes the four pins inputs without pull-up and enables INT4 and INT5 on
    /// any edge (EICRB ISC40 = ISC50 = 1, ISC41 = ISC51 = 0). Counting starts
    /// when global interrupts are enabled.
    pub fn new<MA, MB, MC, MD>(
        mut exint: ExtInts,
        left_a: Pin<LeftEncoderA, MA>,
        left_b: Pin<LeftEncoderB, MB>,
        right_a: Pin<RightEncoderA, MC>,
        right_b: Pin<RightEncoderB, MD>,
    ) -> Self {
        Encoders {
            _left_a: left_a.into_floating_input(),
            _left_b: left_b.into_floating_input(),
            _right_a: right_a.into_floating_input(),
            _right_b: right_b.into_floating_input(),
            _exint: {
                exint.enable(Line::Int4, Sense::AnyEdge);
                exint.enable(Line::Int5, Sense::AnyEdge);
                exint
            },
        }
    }

    /// Both counts, read with interrupts off so they belong to one instant.
    #[inline]
    pub fn counts(&self) -> Counts {
        interrupt::free(|cs| {
            let (left, right) = bench::counts(cs);
            Counts { left, right }
        })
    }
}

// Left channel A changed (Arduino D2, INT4).
#[avr_device::interrupt(atmega2560)]
fn INT4() {
    // A first, then B, as `digitalRead` does in the thesis handler.
    let a = LeftEncoderA::is_high();
    let b = LeftEncoderB::is_high();
    // SAFETY: inside the handler interrupts are off; this is the only writer.
    unsafe { bench::isr_add_left(step(a, b)) };
    sleep::wake();
}

// Right channel A changed (Arduino D3, INT5).
#[avr_device::interrupt(atmega2560)]
fn INT5() {
    let a = RightEncoderA::is_high();
    let b = RightEncoderB::is_high();
    // SAFETY: inside the handler interrupts are off; this is the only writer.
    unsafe { bench::isr_add_right(step(a, b)) };
    sleep::wake();
}
