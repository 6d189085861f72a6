//! The robust build's time unit: timer 1 clocks (4 us at 16 MHz / 64), as
//! its clock ([`crate::clock`]) counts them.
//!
//! Times are `u32` timer clocks and wrap after about 4.8 hours; compare them
//! only through differences ([`reached`]).

use crate::hal::clock::Prescaler;
use crate::robot::CPU_HZ;

/// Timer 1 prescaler: 4 us per timer clock at 16 MHz.
pub const PRESCALER: Prescaler = Prescaler::Div64;
/// Timer clocks per second.
pub const CLOCKS_PER_S: u32 = CPU_HZ / PRESCALER.divisor();

/// `ms` milliseconds in timer clocks (rounded down).
pub const fn ms(ms: u32) -> u32 {
    (ms as u64 * CLOCKS_PER_S as u64 / 1000) as u32
}

const _: () = assert!(ms(1000) == 250_000 && ms(5) == 1250);

/// `ms` milliseconds in timer clocks, for a run-time value: one 32-bit
/// product (a whole number of clocks per millisecond), no 64-bit division.
#[inline(always)]
pub const fn ms_of(ms: u16) -> u32 {
    ms as u32 * (CLOCKS_PER_S / 1000)
}

const _: () = assert!(CLOCKS_PER_S.is_multiple_of(1000) && ms_of(20) == ms(20) && ms_of(5) == ms(5));

/// True when `now` is at or after `deadline` (wrapping, valid for deadlines
/// less than ~2.4 hours away).
#[inline(always)]
pub const fn reached(now: u32, deadline: u32) -> bool {
    (now.wrapping_sub(deadline) as i32) >= 0
}
