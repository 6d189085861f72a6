//! Timer 1 as the periodic control tick: CTC mode (WGM 4, TOP = OCR1A) with
//! the compare-match-A interrupt.
//!
//! The handler (`TIMER1_COMPA`) belongs to the code that counts the ticks
//! (`crate::tick`); this module only programs the timer.

use avr_device::atmega2560::TC1;

use super::clock::{ctc_is_exact, ctc_top, Prescaler};
use super::reg::write_u16;

/// A CTC period: prescaler and compare value, computed at compile time.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct CtcPeriod {
    /// Timer clock prescaler.
    pub prescaler: Prescaler,
    /// OCRnA: the counter runs 0..=top.
    pub top: u16,
}

impl CtcPeriod {
    /// The period closest to `period_us` for this clock and prescaler.
    pub const fn from_us(cpu_hz: u32, prescaler: Prescaler, period_us: u32) -> Self {
        CtcPeriod { prescaler, top: ctc_top(cpu_hz, prescaler, period_us) }
    }

    /// Like [`CtcPeriod::from_us`] but refuses (at compile time, when used in
    /// a `const`) a period that is not a whole number of timer clocks.
    pub const fn exact_us(cpu_hz: u32, prescaler: Prescaler, period_us: u32) -> Self {
        assert!(ctc_is_exact(cpu_hz, prescaler, period_us), "period is not a whole number of timer clocks");
        Self::from_us(cpu_hz, prescaler, period_us)
    }
}

/// TCCR1B/TCCR3B WGMn2 bit: with WGMn3:0 = 0100, CTC with TOP = OCRnA.
pub(crate) const WGM_CTC_B: u8 = 1 << 3;
/// TIMSKn OCIEnA bit.
pub(crate) const OCIE_A: u8 = 1 << 1;
/// TIFRn OCFnA bit.
pub(crate) const OCF_A: u8 = 1 << 1;

/// The running tick timer.
pub struct TickTimer {
    tc1: TC1,
}

impl TickTimer {
    /// Starts timer 1 with `period` and its COMPA interrupt enabled (the
    /// interrupt fires once global interrupts are on).
    ///
    /// Order: stop, TCCR1A = 0, OCR1A, TCNT1 = 0, clear OCF1A, OCIE1A, then
    /// TCCR1B = WGM12 | CS (this starts counting).
    pub fn start(tc1: TC1, period: CtcPeriod) -> Self {
        // SAFETY: the values are valid settings; the timer is stopped while
        // OCR1A and TCNT1 change, and no handler uses timer 1's TEMP latch.
        unsafe {
            tc1.tccr1b().write(|w| w.bits(0));
            tc1.tccr1a().write(|w| w.bits(0));
            write_u16(tc1.ocr1a().as_ptr(), period.top);
            write_u16(tc1.tcnt1().as_ptr(), 0);
            tc1.tifr1().write(|w| w.bits(OCF_A));
            tc1.timsk1().write(|w| w.bits(OCIE_A));
            tc1.tccr1b().write(|w| w.bits(WGM_CTC_B | period.prescaler.cs_bits()));
        }
        TickTimer { tc1 }
    }

    /// Starts a fresh period now: TCNT1 = 0 and a pending compare flag is
    /// dropped, so the next tick comes one full period after this call (less
    /// up to one prescaler step, since the shared prescaler keeps running).
    pub fn restart_period(&mut self) {
        avr_device::interrupt::free(|_| {
            // SAFETY: interrupts are off, so the COMPA handler cannot run
            // between the two TCNT1 bytes; writing a one clears OCF1A.
            unsafe {
                write_u16(self.tc1.tcnt1().as_ptr(), 0);
                self.tc1.tifr1().write(|w| w.bits(OCF_A));
            }
        });
    }
}
