//! The two wheel encoders: channel A on an external interrupt (any edge),
//! channel B read in the handler for the direction, exactly as the thesis'
//! `leftEncoderEvent` / `rightEncoderEvent`.
//!
//! The counters are the bench's `HT_LEFT_COUNT` / `HT_RIGHT_COUNT` (`i32`,
//! the thesis' `long`).
//!
//! # Trips
//!
//! Each handler also checks its wheel's "trip": armed with a count and a
//! direction, it fires on the edge that brings the count to that value in
//! that direction. A fired trip disarms itself, sets its bit in the
//! tripped mask and wakes the main loop, so the main loop is woken when a
//! segment's end is near, not on every edge. A spin turn arms each wheel at
//! its target; a leg re-arms both wheels at about half the remaining
//! distance each time one fires (see the robust build), which brings the
//! main loop to the exact end with a dozen wake-ups per leg.
//!
//! Unarmed, a trip costs the handler one byte test; armed, a 16-bit
//! decrement (or increment) and a test for zero.

use core::ptr::{addr_of_mut, read_volatile, write_volatile};

use avr_device::interrupt;

use crate::bench;
use crate::board::{LeftEncoderA, LeftEncoderB, RightEncoderA, RightEncoderB};
use crate::hal::exint::{ExtInts, Line, Sense};
use crate::hal::gpio::{Input, Pin};
use crate::hal::sleep;
use crate::io::WheelEncoders;
pub use crate::io::{Counts, Side, TRIP_LEFT, TRIP_RIGHT};

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

/// One wheel's trip, laid out for the assembly handlers: counts still to
/// go before it fires. Edges in the trip's direction take one off, edges
/// against it add one back; it fires when `remaining` reaches 0 (steps of one
/// cannot skip it).
#[repr(C)]
pub struct Trip {
    /// Offset 0: armed (0 or 1).
    armed: u8,
    /// Offset 1: the trip's direction, 1 counts going up, 0 down.
    up: u8,
    /// Offsets 2-3: counts still to go in that direction (little-endian).
    remaining: u16,
}

/// The left wheel's trip (INT4 handler). Main code touches it only with
/// interrupts off.
#[doc(hidden)]
pub static mut LEFT_TRIP: Trip = Trip { armed: 0, up: 1, remaining: 0 };
/// The right wheel's trip (INT5 handler).
#[doc(hidden)]
pub static mut RIGHT_TRIP: Trip = Trip { armed: 0, up: 1, remaining: 0 };
/// PINE as each handler last counted from it: only its wheel's A bit
/// (left PE4, right PE5) is compared. An edge whose handler finds A back at
/// that level was undone before the handler read it (a glitch pulse shorter
/// than the interrupt response and the handler's first instructions, ~20
/// cycles when the edge wakes the CPU): it is not counted, nor is the edge
/// that undid it, which finds the same level. Set from the pins before the
/// interrupts are enabled.
#[doc(hidden)]
pub static mut LEFT_LAST_PINE: u8 = 0;
/// As [`LEFT_LAST_PINE`], for the right wheel (INT5 handler).
#[doc(hidden)]
pub static mut RIGHT_LAST_PINE: u8 = 0;
/// Trips fired since the main loop last took them ([`TRIP_LEFT`],
/// [`TRIP_RIGHT`] bits).
#[doc(hidden)]
pub static mut TRIPPED: u8 = 0;

/// Largest distance a trip can be armed ahead (counts).
pub const MAX_TRIP_AHEAD: i32 = u16::MAX as i32;

fn trip_of(side: Side) -> *mut Trip {
    match side {
        Side::Left => addr_of_mut!(LEFT_TRIP),
        Side::Right => addr_of_mut!(RIGHT_TRIP),
    }
}

// The INT4 and INT5 handlers, in assembly because they run on every encoder
// edge (about 1 750 times per second while driving) and a Rust handler saves
// thirteen registers: this one saves r24, r25 and SREG and takes about 47
// cycles from the vector jump to `reti` with the trip unarmed, 65 armed (the
// Rust version took about 128; the glitch check below adds 7). Per edge:
// 0. A compared with the level the last counted edge left: unchanged, the
//    edge was undone before this read (a glitch) and nothing is counted;
//    changed, the new PINE is kept for the next edge;
// 1. up = A xor B (the thesis' rule: A high and B low, or A low and B high,
//    counts up), A read before B;
// 2. the 32-bit count: +1 or -1 on the low byte, the carry or borrow carried
//    into the next bytes only when it happens (so the count is written low
//    byte first; a reader between two of these stores sees a half update);
// 3. if the trip is armed: `remaining` -1 when the edge goes the trip's way,
//    +1 otherwise; at 0 the trip is disarmed, its bit set in TRIPPED and the
//    sleep flag WOKEN set.
// PINE is I/O 0x0C (A left = PE4, A right = PE5, B right = PE3), PING is
// I/O 0x12 (B left = PG5), SREG is I/O 0x3F.
macro_rules! edge_tail {
    () => {
        "
    bst r24, 5
    clr r24
    bld r24, 0
    sbrs r24, 0
    rjmp 3f
    lds r25, {count}
    inc r25
    sts {count}, r25
    brne 4f
    lds r25, {count}+1
    inc r25
    sts {count}+1, r25
    brne 4f
    lds r25, {count}+2
    inc r25
    sts {count}+2, r25
    brne 4f
    lds r25, {count}+3
    inc r25
    sts {count}+3, r25
    rjmp 4f
3:
    lds r25, {count}
    subi r25, 1
    sts {count}, r25
    brcc 4f
    lds r25, {count}+1
    subi r25, 1
    sts {count}+1, r25
    brcc 4f
    lds r25, {count}+2
    subi r25, 1
    sts {count}+2, r25
    brcc 4f
    lds r25, {count}+3
    subi r25, 1
    sts {count}+3, r25
4:
    lds r25, {trip}
    tst r25
    breq 6f
    lds r25, {trip}+1
    cp r24, r25
    lds r24, {trip}+2
    lds r25, {trip}+3
    brne 5f
    sbiw r24, 1
    rjmp 7f
5:
    adiw r24, 1
7:
    sts {trip}+3, r25
    sts {trip}+2, r24
    brne 6f
    clr r24
    sts {trip}, r24
    lds r24, {tripped}
    ori r24, {bit}
    sts {tripped}, r24
    ldi r24, 1
    sts {woken}, r24
6:
    pop r25
    pop r24
    out 0x3f, r24
    pop r24
    reti
"
    };
}

/// Holds the two vectors' code. The handlers are emitted from inline
/// assembly inside this (never called) function into their own sections
/// (`.pushsection`), because module-level assembly (`global_asm!`, naked
/// functions) is assembled without the ATmega2560's instruction set on this
/// target; inline assembly in a function gets the function's CPU. `KEEP`
/// keeps the function, so its assembly, in the build.
// The two named labels are the vector symbols themselves; the lint guards
// against an asm block emitted twice (inlining, unrolling), which
// `inline(never)` and the single call-free use rule out here.
#[allow(named_asm_labels)]
#[inline(never)]
fn encoder_vectors() {
    // SAFETY: the assembly only defines the two interrupt handlers in their
    // own sections; nothing of it runs as part of this function, which
    // executes no instruction of it (and is never called anyway).
    unsafe {
        core::arch::asm!(
            ".pushsection .text.__vector_5,\"ax\",@progbits",
            ".global __vector_5",
            ".type __vector_5, @function",
            "__vector_5:",
            "push r24",
            "in r24, 0x3f",
            "push r24",
            "push r25",
            "in r24, 0x0c",
            "lds r25, {last}",
            "eor r25, r24",
            "sbrs r25, 4",
            "rjmp 6f",
            "sts {last}, r24",
            "in r25, 0x12",
            "lsl r24",
            "eor r24, r25",
            edge_tail!(),
            ".size __vector_5, . - __vector_5",
            ".popsection",
            count = sym bench::HT_LEFT_COUNT,
            last = sym LEFT_LAST_PINE,
            trip = sym LEFT_TRIP,
            tripped = sym TRIPPED,
            woken = sym sleep::WOKEN,
            bit = const TRIP_LEFT,
        );
        core::arch::asm!(
            ".pushsection .text.__vector_6,\"ax\",@progbits",
            ".global __vector_6",
            ".type __vector_6, @function",
            "__vector_6:",
            "push r24",
            "in r24, 0x3f",
            "push r24",
            "push r25",
            "in r24, 0x0c",
            "lds r25, {last}",
            "eor r25, r24",
            "sbrs r25, 5",
            "rjmp 6f",
            "sts {last}, r24",
            "mov r25, r24",
            "lsl r25",
            "lsl r25",
            "eor r24, r25",
            edge_tail!(),
            ".size __vector_6, . - __vector_6",
            ".popsection",
            count = sym bench::HT_RIGHT_COUNT,
            last = sym RIGHT_LAST_PINE,
            trip = sym RIGHT_TRIP,
            tripped = sym TRIPPED,
            woken = sym sleep::WOKEN,
            bit = const TRIP_RIGHT,
        );
    }
}

#[used]
static KEEP: fn() = encoder_vectors;

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
        let left_a = left_a.into_floating_input();
        let right_a = right_a.into_floating_input();
        // SAFETY: the handlers that read these are not enabled yet (INT4/5
        // are enabled below), so nothing else accesses them.
        unsafe {
            write_volatile(addr_of_mut!(LEFT_LAST_PINE), if left_a.is_high() { 1 << 4 } else { 0 });
            write_volatile(addr_of_mut!(RIGHT_LAST_PINE), if right_a.is_high() { 1 << 5 } else { 0 });
        }
        Encoders {
            _left_a: left_a,
            _left_b: left_b.into_floating_input(),
            _right_a: right_a,
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

    /// Arms `side`'s trip at count `at`, reached going `up` (count rising)
    /// or down. If the count is already there, the trip fires at once
    /// (tripped bit set, not armed). `at` is clamped to
    /// [`MAX_TRIP_AHEAD`] counts from the current count.
    pub fn arm(&mut self, side: Side, up: bool, at: i32) {
        interrupt::free(|cs| {
            let (bit, count) = match side {
                Side::Left => (TRIP_LEFT, bench::counts(cs).0),
                Side::Right => (TRIP_RIGHT, bench::counts(cs).1),
            };
            let ahead = if up { at.saturating_sub(count) } else { count.saturating_sub(at) };
            let t = trip_of(side);
            // SAFETY: interrupts are off, so the handler that shares the trip
            // cannot run; the pointers are to statics.
            unsafe {
                if ahead <= 0 {
                    write_volatile(addr_of_mut!((*t).armed), 0);
                    let m = addr_of_mut!(TRIPPED);
                    write_volatile(m, read_volatile(m) | bit);
                } else {
                    write_volatile(addr_of_mut!((*t).up), up as u8);
                    write_volatile(addr_of_mut!((*t).remaining), ahead.min(MAX_TRIP_AHEAD) as u16);
                    write_volatile(addr_of_mut!((*t).armed), 1);
                }
            }
        });
    }

    /// Disarms both trips and forgets fired ones.
    pub fn disarm_all(&mut self) {
        interrupt::free(|_| {
            // SAFETY: interrupts are off; plain byte stores to the statics.
            unsafe {
                write_volatile(addr_of_mut!(LEFT_TRIP.armed), 0);
                write_volatile(addr_of_mut!(RIGHT_TRIP.armed), 0);
                write_volatile(addr_of_mut!(TRIPPED), 0);
            }
        });
    }

    /// The trips fired since the last call ([`TRIP_LEFT`], [`TRIP_RIGHT`]
    /// bits) and the counts at this instant.
    #[inline]
    pub fn take_tripped(&mut self) -> (u8, Counts) {
        interrupt::free(|cs| {
            let (left, right) = bench::counts(cs);
            // SAFETY: interrupts are off, so the handlers cannot set a bit
            // between the read and the clear.
            let t = unsafe {
                let m = addr_of_mut!(TRIPPED);
                let t = read_volatile(m);
                write_volatile(m, 0);
                t
            };
            (t, Counts { left, right })
        })
    }
}

impl WheelEncoders for Encoders {
    #[inline(always)]
    fn counts(&self) -> Counts {
        Encoders::counts(self)
    }

    #[inline(always)]
    fn arm(&mut self, side: Side, up: bool, at: i32) {
        Encoders::arm(self, side, up, at)
    }

    #[inline(always)]
    fn disarm_all(&mut self) {
        Encoders::disarm_all(self)
    }

    #[inline(always)]
    fn take_tripped(&mut self) -> (u8, Counts) {
        Encoders::take_tripped(self)
    }
}
