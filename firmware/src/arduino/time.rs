//! Arduino's timer 0 time keeping (`wiring.c`).
//!
//! Timer 0 runs in fast PWM mode (WGM0 = 3, TOP = 0xFF) at clk/64 with the
//! overflow interrupt: one overflow every 64 * 256 = 16 384 cycles
//! (1 024 us at 16 MHz). The handler adds 1 ms and 3/125 ms (the fraction in
//! 8-us units) to `millis`, and counts overflows for `micros`, which is
//! `(overflows * 256 + TCNT0) * 4` with a correction for an overflow whose
//! interrupt is pending: 4 us resolution. `delay(ms)` busy-waits on
//! `micros()`, 1000 us per millisecond.

use core::cell::Cell;

use avr_device::atmega2560::TC0;
use avr_device::interrupt::{self, CriticalSection, Mutex};

use crate::board::CPU_HZ;

/// TCCR0A: WGM01 | WGM00 (fast PWM, TOP = 0xFF), outputs disconnected.
pub const TCCR0A_FAST_PWM: u8 = 0b0000_0011;
/// TCCR0B: CS01 | CS00 (clk/64), WGM02 = 0.
pub const TCCR0B_DIV64: u8 = 0b0000_0011;
/// TIMSK0: TOIE0.
pub const TIMSK0_TOIE: u8 = 0b0000_0001;
/// TIFR0 bit TOV0.
const TOV0: u8 = 1;

const CYCLES_PER_US: u32 = CPU_HZ / 1_000_000;
/// Arduino's `MICROSECONDS_PER_TIMER0_OVERFLOW`: 1024 at 16 MHz.
const US_PER_OVERFLOW: u32 = 64 * 256 / CYCLES_PER_US;
/// `MILLIS_INC`: whole milliseconds per overflow (1).
const MILLIS_INC: u32 = US_PER_OVERFLOW / 1000;
/// `FRACT_INC`: the rest, in 8-us units (3).
const FRACT_INC: u8 = ((US_PER_OVERFLOW % 1000) >> 3) as u8;
/// `FRACT_MAX`: one millisecond in 8-us units (125).
const FRACT_MAX: u8 = (1000 >> 3) as u8;
/// Microseconds per timer 0 count (4).
const US_PER_COUNT: u32 = 64 / CYCLES_PER_US;

const _: () = assert!(US_PER_OVERFLOW == 1024 && MILLIS_INC == 1 && FRACT_INC == 3 && FRACT_MAX == 125);

/// `timer0_overflow_count`.
static OVERFLOWS: Mutex<Cell<u32>> = Mutex::new(Cell::new(0));
/// `timer0_millis`.
static MILLIS: Mutex<Cell<u32>> = Mutex::new(Cell::new(0));
/// `timer0_fract`.
static FRACT: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));

/// Timer 0 running as Arduino's time base.
pub struct Timer0 {
    tc0: TC0,
}

impl Timer0 {
    /// Arduino's `init()` for timer 0: TCCR0A = 0x03, TCCR0B = 0x03,
    /// TIMSK0 = 0x01. (Arduino sets the four bits one read-modify-write at a
    /// time, passing through TCCR0A = 0x02 and TCCR0B = 0x02 for a few
    /// cycles; here each register is written once with its final value.)
    pub fn start(tc0: TC0) -> Self {
        // SAFETY: valid settings; the counter starts with the TCCR0B write.
        unsafe {
            tc0.tccr0a().write(|w| w.bits(TCCR0A_FAST_PWM));
            tc0.tccr0b().write(|w| w.bits(TCCR0B_DIV64));
            tc0.timsk0().write(|w| w.bits(TIMSK0_TOIE));
        }
        Timer0 { tc0 }
    }

    /// Arduino's `micros()`.
    pub fn micros(&self) -> u32 {
        interrupt::free(|cs| {
            let mut m = OVERFLOWS.borrow(cs).get();
            let t = self.tc0.tcnt0().read().bits();
            if self.tc0.tifr0().read().bits() & TOV0 != 0 && t < 255 {
                m = m.wrapping_add(1);
            }
            (m << 8).wrapping_add(t as u32).wrapping_mul(US_PER_COUNT)
        })
    }

    /// Arduino's `millis()`.
    pub fn millis(&self) -> u32 {
        interrupt::free(|cs| MILLIS.borrow(cs).get())
    }

    /// Arduino's `delay(ms)`: busy-waits, counting off 1000 us of `micros()`
    /// per millisecond (`yield()` is empty on the Mega).
    pub fn delay(&self, ms: u32) {
        let mut ms = ms;
        let mut start = self.micros();
        while ms > 0 {
            while ms > 0 && self.micros().wrapping_sub(start) >= 1000 {
                ms -= 1;
                start = start.wrapping_add(1000);
            }
        }
    }
}

/// Body of the TIMER0_OVF vector (Arduino's `ISR(TIMER0_OVF_vect)`).
///
/// # Safety
/// Call only from the TIMER0_OVF vector.
#[inline(always)]
pub unsafe fn on_overflow() {
    // SAFETY: interrupts are off inside the handler.
    let cs = unsafe { CriticalSection::new() };
    let mut m = MILLIS.borrow(cs).get().wrapping_add(MILLIS_INC);
    let mut f = FRACT.borrow(cs).get() + FRACT_INC;
    if f >= FRACT_MAX {
        f -= FRACT_MAX;
        m = m.wrapping_add(1);
    }
    FRACT.borrow(cs).set(f);
    MILLIS.borrow(cs).set(m);
    let o = OVERFLOWS.borrow(cs);
    o.set(o.get().wrapping_add(1));
}
