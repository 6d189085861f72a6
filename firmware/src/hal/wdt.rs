//! The watchdog timer (system reset mode only) and the reset cause.
//!
//! Changing WDTCSR needs the timed sequence: write WDCE | WDE, then the new
//! value within four cycles. Both writes are two back-to-back `sts`
//! instructions in inline assembly, with interrupts off.

use core::arch::asm;

use avr_device::atmega2560::{CPU, WDT};
use avr_device::interrupt;

/// MCUSR bit WDRF (the last reset came from the watchdog).
pub const WDRF: u8 = 1 << 3;
/// WDTCSR bit WDCE (change enable).
const WDCE: u8 = 1 << 4;
/// WDTCSR bit WDE (system reset on time-out).
const WDE: u8 = 1 << 3;
/// WDTCSR WDP2:0 = 100: 32 768 watchdog-oscillator cycles, about 0.25 s.
const WDP_250MS: u8 = 0b100;
/// The value [`Watchdog::enable_250ms`] writes: WDE | WDP2 (WDIE = 0).
pub const WDTCSR_RESET_250MS: u8 = WDE | WDP_250MS;

/// Reads MCUSR, clears it (WDRF must be clear before WDE can be cleared)
/// and returns the old value.
pub fn take_reset_cause(cpu: &CPU) -> u8 {
    let v = cpu.mcusr().read().bits();
    // SAFETY: writing zero clears the reset flags; always valid.
    unsafe { cpu.mcusr().write(|w| w.bits(0)) };
    v
}

/// The watchdog.
pub struct Watchdog {
    _wdt: WDT,
}

/// Writes WDTCSR through the timed sequence.
fn timed_write(value: u8) {
    interrupt::free(|_| {
        // SAFETY: 0x60 is WDTCSR on the ATmega2560 (data space address);
        // the two stores follow each other, so the second lands within the
        // four cycles WDCE allows. Interrupts are off.
        unsafe {
            asm!(
                "sts 0x60, {change}",
                "sts 0x60, {value}",
                change = in(reg) WDCE | WDE,
                value = in(reg) value,
            )
        };
    });
}

impl Watchdog {
    /// Takes the watchdog and turns it off (call [`take_reset_cause`] first:
    /// WDE cannot be cleared while WDRF is set).
    pub fn disabled(wdt: WDT) -> Self {
        timed_write(0);
        Watchdog { _wdt: wdt }
    }

    /// Resets the MCU unless [`Watchdog::feed`] runs at least every ~0.25 s
    /// (WDTCSR = WDE | WDP2 = 0x0C).
    pub fn enable_250ms(&mut self) {
        avr_device::asm::wdr();
        timed_write(WDTCSR_RESET_250MS);
    }

    /// Restarts the watchdog period (`wdr`).
    #[inline(always)]
    pub fn feed(&mut self) {
        avr_device::asm::wdr();
    }
}
