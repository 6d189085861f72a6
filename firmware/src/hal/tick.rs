//! Timer 1 as the periodic control tick and the time base: CTC mode (WGM 4,
//! TOP = OCR1A) with the compare-match-A interrupt once per period, and
//! compare match B as an optional wake-up alarm inside the current period
//! (in CTC mode OCF1B is set when TCNT1 passes OCR1B, once per period).
//!
//! The handlers belong to the code that keeps time (`crate::clock`); this
//! module only programs the timer.

use avr_device::atmega2560::TC1;

use super::clock::{ctc_is_exact, ctc_top, Prescaler};
use super::reg::{read_u16, write_u16};

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

    /// Timer clocks per period (top + 1).
    pub const fn clocks(self) -> u32 {
        self.top as u32 + 1
    }
}

/// TCCR1B/TCCR3B WGMn2 bit: with WGMn3:0 = 0100, CTC with TOP = OCRnA.
pub(crate) const WGM_CTC_B: u8 = 1 << 3;
/// TIMSKn OCIEnA bit.
pub(crate) const OCIE_A: u8 = 1 << 1;
/// TIMSKn OCIEnB bit.
pub(crate) const OCIE_B: u8 = 1 << 2;
/// TIFRn OCFnA bit.
pub(crate) const OCF_A: u8 = 1 << 1;
/// TIFRn OCFnB bit.
pub(crate) const OCF_B: u8 = 1 << 2;

/// The running tick timer.
pub struct TickTimer {
    tc1: TC1,
}

/// The counter and the pending-period flag, read at one instant.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Count {
    /// TCNT1.
    pub tcnt: u16,
    /// OCF1A was set (a period ended whose handler has not run yet).
    pub period_pending: bool,
}

impl TickTimer {
    /// Starts timer 1 with `period` and its COMPA interrupt enabled (the
    /// interrupt fires once global interrupts are on).
    ///
    /// Order: stop, TCCR1A = 0, OCR1A, OCR1B = 0, TCNT1 = 0, clear OCF1A and
    /// OCF1B, TIMSK1 = OCIE1A, then TCCR1B = WGM12 | CS (this starts
    /// counting).
    pub fn start(tc1: TC1, period: CtcPeriod) -> Self {
        // SAFETY: the values are valid settings; the timer is stopped while
        // its 16-bit registers change and interrupts are not enabled yet.
        unsafe {
            tc1.tccr1b().write(|w| w.bits(0));
            tc1.tccr1a().write(|w| w.bits(0));
            write_u16(tc1.ocr1a().as_ptr(), period.top);
            write_u16(tc1.ocr1b().as_ptr(), 0);
            write_u16(tc1.tcnt1().as_ptr(), 0);
            tc1.tifr1().write(|w| w.bits(OCF_A | OCF_B));
            tc1.timsk1().write(|w| w.bits(OCIE_A));
            tc1.tccr1b().write(|w| w.bits(WGM_CTC_B | period.prescaler.cs_bits()));
        }
        TickTimer { tc1 }
    }

    /// TCNT1 and then OCF1A. Call with interrupts off (the caller's
    /// critical section) so that nothing else uses the TEMP latch and the
    /// two reads belong together.
    #[inline(always)]
    pub fn count(&self) -> Count {
        // SAFETY: reading TCNT1 (low byte first) and TIFR1 has no side
        // effect; the caller keeps interrupts off.
        let tcnt = unsafe { read_u16(self.tc1.tcnt1().as_ptr()) };
        let period_pending = self.tc1.tifr1().read().bits() & OCF_A != 0;
        Count { tcnt, period_pending }
    }

    /// Starts a fresh period: TCNT1 = 0 and pending compare flags (A and B)
    /// dropped. The COMPB alarm is disabled. Call with interrupts off.
    pub fn restart_period(&mut self) {
        // SAFETY: interrupts are off (caller), so no handler runs between
        // the two TCNT1 bytes; writing ones clears the flags; OCIE1A alone
        // is a valid TIMSK1 value.
        unsafe {
            write_u16(self.tc1.tcnt1().as_ptr(), 0);
            self.tc1.tifr1().write(|w| w.bits(OCF_A | OCF_B));
            self.tc1.timsk1().write(|w| w.bits(OCIE_A));
        }
    }

    /// Arms the COMPB wake-up at counter value `at` of the current period:
    /// OCR1B = `at`, OCF1B cleared, TIMSK1 = OCIE1A | OCIE1B. Call with
    /// interrupts off; `at` must not exceed OCR1A.
    pub fn arm_compare_b(&mut self, at: u16) {
        // SAFETY: interrupts are off (caller); any OCR1B value is valid.
        unsafe {
            write_u16(self.tc1.ocr1b().as_ptr(), at);
            self.tc1.tifr1().write(|w| w.bits(OCF_B));
            self.tc1.timsk1().write(|w| w.bits(OCIE_A | OCIE_B));
        }
    }

    /// Disables the COMPB wake-up (TIMSK1 = OCIE1A). Call with interrupts off.
    pub fn disarm_compare_b(&mut self) {
        // SAFETY: OCIE1A alone is a valid TIMSK1 value.
        unsafe { self.tc1.timsk1().write(|w| w.bits(OCIE_A)) };
    }
}

/// Disables the COMPB interrupt from its own handler (one-shot alarm).
///
/// # Safety
/// Call only from the TIMER1_COMPB handler (interrupts off, and the main
/// code changes TIMSK1 only with interrupts off).
#[inline(always)]
pub unsafe fn isr_disarm_compare_b() {
    // SAFETY: as documented; OCIE1A alone is a valid value.
    unsafe { TC1::steal().timsk1().write(|w| w.bits(OCIE_A)) };
}
