//! 8-bit phase-correct PWM on timers 4 (OC4A/B/C) and 2 (OC2B), prescaler 1,
//! with Arduino `analogWrite` semantics.
//!
//! Register use, which the bench relies on (it emulates timers 2 and 4):
//! - Setup writes TCCRnA = WGMn0 (mode 1, 8-bit phase-correct, all COM bits 0),
//!   then TCCRnB = CSn0 (clock/1). Nothing else is configured: no interrupt of
//!   timer 2 or 4 is ever enabled.
//! - Timer registers are only written, never read: the COM bits live in a
//!   shadow copy of TCCRnA and every change writes the whole register.
//! - `set_duty(0)` / `set_duty(255)`: the PORTH bit is set to the final level
//!   first, then the channel's COMnx bits are cleared (pin becomes a plain
//!   GPIO output), so the pin never shows a stale level in between.
//! - `set_duty(d)`, 1 <= d <= 254: OCRnx = d first (timer 4: high byte 0,
//!   then low byte d), then COMnx1 is set (non-inverting).

use core::cell::Cell;

use avr_device::atmega2560::{TC2, TC4};
use avr_device::interrupt::{self, CriticalSection, Mutex};

use super::clock::Prescaler;
use super::gpio::{Output, Pin, PinId, PH3, PH4, PH5, PH6};
use super::reg::write_u16;

/// A PWM output whose duty can be set from 0 (always low) to 255 (always high).
///
/// Implementations keep Arduino `analogWrite` behaviour: 0 and 255 give a
/// steady level with the compare unit disconnected; anything else gives the
/// timer's PWM with that compare value.
pub trait PwmChannel {
    /// Sets the duty.
    fn set_duty(&mut self, duty: u8);
}

/// WGMn0 in TCCRnA: with WGMn2 (and WGMn3 on timer 4) clear, mode 1.
const WGM_PHASE_CORRECT_8BIT: u8 = 0b01;
/// Timer 4 clock select in TCCR4B.
const TIMER4_CS: u8 = Prescaler::Div1.cs_bits();
/// Timer 2 clock select in TCCR2B.
const TIMER2_CS: u8 = Prescaler::Div1.cs_bits_timer2();

/// Shadow of TCCR4A (the register itself is never read back).
static TCCR4A_SHADOW: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));
/// Shadow of TCCR2A.
static TCCR2A_SHADOW: Mutex<Cell<u8>> = Mutex::new(Cell::new(0));

/// The three timer 4 channels, each owning its pin.
pub struct Timer4Channels {
    /// OC4A on PH3 (Arduino D6).
    pub a: Oc4a,
    /// OC4B on PH4 (Arduino D7).
    pub b: Oc4b,
    /// OC4C on PH5 (Arduino D8).
    pub c: Oc4c,
}

/// Starts timer 4 in 8-bit phase-correct PWM at clock/1 with all three
/// channels disconnected and their pins driven low.
pub fn timer4(tc4: TC4, ph3: Pin<PH3, Output>, ph4: Pin<PH4, Output>, ph5: Pin<PH5, Output>) -> Timer4Channels {
    interrupt::free(|cs| {
        TCCR4A_SHADOW.borrow(cs).set(WGM_PHASE_CORRECT_8BIT);
        // SAFETY: mode 1 with COM bits 0 and clock/1 are valid settings; the
        // mode is written before the clock starts the counter.
        unsafe {
            tc4.tccr4a().write(|w| w.bits(WGM_PHASE_CORRECT_8BIT));
            tc4.tccr4b().write(|w| w.bits(TIMER4_CS));
        }
    });
    // The PAC handle is dropped on purpose: from here on only the channels
    // touch timer 4, each its own COM bits and OCR.
    let _ = tc4;
    Timer4Channels { a: Oc4a { _pin: ph3 }, b: Oc4b { _pin: ph4 }, c: Oc4c { _pin: ph5 } }
}

/// Starts timer 2 in 8-bit phase-correct PWM at clock/1; only OC2B is used.
pub fn timer2(tc2: TC2, ph6: Pin<PH6, Output>) -> Oc2b {
    interrupt::free(|cs| {
        TCCR2A_SHADOW.borrow(cs).set(WGM_PHASE_CORRECT_8BIT);
        // SAFETY: as for timer 4; timer 2 runs from the system clock (ASSR
        // left at reset: AS2 = 0).
        unsafe {
            tc2.tccr2a().write(|w| w.bits(WGM_PHASE_CORRECT_8BIT));
            tc2.tccr2b().write(|w| w.bits(TIMER2_CS));
        }
    });
    let _ = tc2;
    Oc2b { _pin: ph6 }
}

/// Applies `duty` to one channel following the order in the module docs.
///
/// `write_ocr` writes the compare register, `write_tccra` the control
/// register; both run with interrupts off.
#[inline(always)]
fn apply_duty<P: PinId>(
    cs: CriticalSection,
    shadow: &Mutex<Cell<u8>>,
    com1: u8,
    duty: u8,
    write_ocr: impl FnOnce(u8),
    write_tccra: impl FnOnce(u8),
) {
    let shadow = shadow.borrow(cs);
    match duty {
        0 | 255 => {
            // SAFETY: PORTx of a pin this channel owns as an output; interrupts
            // are off (we hold `cs`), so the read-modify-write is atomic.
            unsafe {
                let port = P::port_reg();
                let v = core::ptr::read_volatile(port);
                let v = if duty == 0 { v & !P::MASK } else { v | P::MASK };
                core::ptr::write_volatile(port, v);
            }
            let tccra = shadow.get() & !com1;
            shadow.set(tccra);
            write_tccra(tccra);
        }
        d => {
            write_ocr(d);
            let tccra = shadow.get() | com1;
            shadow.set(tccra);
            write_tccra(tccra);
        }
    }
}

macro_rules! timer4_channel {
    ($name:ident, $pin:ident, $ocr:ident, $com1:literal, $doc:literal) => {
        #[doc = $doc]
        pub struct $name {
            _pin: Pin<$pin, Output>,
        }

        impl PwmChannel for $name {
            fn set_duty(&mut self, duty: u8) {
                // SAFETY: this channel exists once (created by `timer4`, which
                // consumed TC4) and only writes its own OCR and, through the
                // shadow, its own COM bits of TCCR4A.
                let tc4 = unsafe { TC4::steal() };
                interrupt::free(|cs| {
                    apply_duty::<$pin>(
                        cs,
                        &TCCR4A_SHADOW,
                        1 << $com1,
                        duty,
                        // SAFETY: 16-bit OCR of timer 4; no interrupt handler
                        // uses timer 4, and interrupts are off anyway.
                        |d| unsafe { write_u16(tc4.$ocr().as_ptr(), d as u16) },
                        // SAFETY: mode 1 plus COM bits, all valid.
                        |v| unsafe {
                            tc4.tccr4a().write(|w| w.bits(v));
                        },
                    )
                });
            }
        }
    };
}

timer4_channel!(Oc4a, PH3, ocr4a, 7, "Timer 4 channel A: OC4A on PH3 (Arduino D6); COM4A1 is TCCR4A bit 7.");
timer4_channel!(Oc4b, PH4, ocr4b, 5, "Timer 4 channel B: OC4B on PH4 (Arduino D7); COM4B1 is TCCR4A bit 5.");
timer4_channel!(Oc4c, PH5, ocr4c, 3, "Timer 4 channel C: OC4C on PH5 (Arduino D8); COM4C1 is TCCR4A bit 3.");

/// Timer 2 channel B: OC2B on PH6 (Arduino D9); COM2B1 is TCCR2A bit 5.
pub struct Oc2b {
    _pin: Pin<PH6, Output>,
}

impl PwmChannel for Oc2b {
    fn set_duty(&mut self, duty: u8) {
        // SAFETY: created once by `timer2`, which consumed TC2; writes only
        // OCR2B and, through the shadow, its own COM bits of TCCR2A.
        let tc2 = unsafe { TC2::steal() };
        interrupt::free(|cs| {
            apply_duty::<PH6>(
                cs,
                &TCCR2A_SHADOW,
                1 << 5,
                duty,
                // SAFETY: 8-bit compare register, any value is valid.
                |d| unsafe {
                    tc2.ocr2b().write(|w| w.bits(d));
                },
                // SAFETY: mode 1 plus COM bits, all valid.
                |v| unsafe {
                    tc2.tccr2a().write(|w| w.bits(v));
                },
            )
        });
    }
}
