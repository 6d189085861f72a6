//! Timer 3 as a one-shot delay: CTC mode, prescaler 256, COMPA interrupt.
//! The handler stops the timer (CS = 0) and raises a flag, so the timer costs
//! nothing (no clock, no simulator events) while no delay runs.

use core::cell::Cell;

use avr_device::atmega2560::TC3;
use avr_device::interrupt::{self, Mutex};

use super::clock::{ctc_top, Prescaler};
use super::reg::write_u16;
use super::tick::{OCF_A, OCIE_A, WGM_CTC_B};

/// Prescaler of the one-shot timer: 16 us steps at 16 MHz, up to ~1.05 s.
pub const PRESCALER: Prescaler = Prescaler::Div256;
/// Longest delay accepted, in milliseconds.
pub const MAX_MS: u16 = 1000;

/// Set by the handler when the delay has elapsed.
static FIRED: Mutex<Cell<bool>> = Mutex::new(Cell::new(false));

/// A delay length, converted to a compare value at compile time.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Delay {
    top: u16,
}

impl Delay {
    /// `ms` milliseconds (clamped to 1..=[`MAX_MS`]), rounded to the nearest
    /// timer step. The delay lasts top + 1 steps after the timer starts, minus
    /// up to one step because the prescaler shared by timers 0, 1, 3, 4 and 5
    /// is not reset.
    pub const fn from_ms(cpu_hz: u32, ms: u16) -> Self {
        let ms = if ms > MAX_MS { MAX_MS } else if ms == 0 { 1 } else { ms };
        Delay { top: ctc_top(cpu_hz, PRESCALER, ms as u32 * 1000) }
    }

    /// The compare value (OCR3A).
    pub const fn top(self) -> u16 {
        self.top
    }
}

/// The one-shot timer.
pub struct OneShot {
    tc3: TC3,
}

impl OneShot {
    /// Takes timer 3 and leaves it stopped in CTC mode.
    pub fn new(tc3: TC3) -> Self {
        // SAFETY: valid settings; CS = 0 keeps the timer stopped.
        unsafe {
            tc3.tccr3b().write(|w| w.bits(WGM_CTC_B));
            tc3.tccr3a().write(|w| w.bits(0));
            tc3.timsk3().write(|w| w.bits(0));
        }
        OneShot { tc3 }
    }

    /// Starts `delay`; a delay still running is replaced.
    ///
    /// Order: stop, OCR3A, TCNT3 = 0, clear OCF3A and the fired flag, enable
    /// OCIE3A, then TCCR3B = WGM32 | CS32 (this starts counting).
    pub fn start(&mut self, delay: Delay) {
        interrupt::free(|cs| {
            FIRED.borrow(cs).set(false);
            // SAFETY: the timer is stopped while its 16-bit registers change
            // and interrupts are off; all values are valid settings.
            unsafe {
                self.tc3.tccr3b().write(|w| w.bits(WGM_CTC_B));
                write_u16(self.tc3.ocr3a().as_ptr(), delay.top);
                write_u16(self.tc3.tcnt3().as_ptr(), 0);
                self.tc3.tifr3().write(|w| w.bits(OCF_A));
                self.tc3.timsk3().write(|w| w.bits(OCIE_A));
                self.tc3.tccr3b().write(|w| w.bits(WGM_CTC_B | PRESCALER.cs_bits()));
            }
        });
    }

    /// True once, after the delay started last has elapsed (the flag is
    /// consumed).
    pub fn take_fired(&mut self) -> bool {
        interrupt::free(|cs| FIRED.borrow(cs).replace(false))
    }

    /// Stops a running delay without firing.
    pub fn cancel(&mut self) {
        interrupt::free(|cs| {
            // SAFETY: CS = 0 stops the timer; interrupt disabled; valid values.
            unsafe {
                self.tc3.tccr3b().write(|w| w.bits(WGM_CTC_B));
                self.tc3.timsk3().write(|w| w.bits(0));
            }
            FIRED.borrow(cs).set(false);
        });
    }
}

// Delay elapsed: stop the clock (CS = 0), disable the interrupt, flag it and
// wake the main loop.
#[avr_device::interrupt(atmega2560)]
fn TIMER3_COMPA() {
    // SAFETY: the handler only stops timer 3, which the main code never
    // touches while a delay is running, except in `start`/`cancel` with
    // interrupts off.
    let tc3 = unsafe { TC3::steal() };
    // SAFETY: valid values (mode kept, clock off, interrupt off).
    unsafe {
        tc3.tccr3b().write(|w| w.bits(WGM_CTC_B));
        tc3.timsk3().write(|w| w.bits(0));
    }
    interrupt::free(|cs| FIRED.borrow(cs).set(true));
    super::sleep::wake();
}
