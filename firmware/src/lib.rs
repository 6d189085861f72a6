//! Firmware of the Henrytwo odometry-calibration robot (ATmega2560).
//!
//! Layers, bottom up:
//! - [`hal`]: a thin layer over `avr-device` registers (pins, external
//!   interrupts, PWM, the tick timer, ADC, watchdog, USARTs, sleep);
//! - [`board`]: the clock and every pin of the robot, named once;
//! - drivers: [`encoder`] (with the segment-end trips), [`motors`] (the
//!   thesis build's compiled wiring), [`driver`] (the robust build's, told at
//!   run time), [`battery`], and [`clock`] (the robust build's clock);
//! - [`io`]: the small traits the drivers implement for the logic above them;
//! - [`arduino`]: the pieces of the Arduino core the thesis build needs
//!   (`millis`/`micros`/`delay` on timer 0, `Serial.print`);
//! - the control law and the tests: [`pid`], [`odometry`], [`plan`], with the
//!   robot's numbers in [`robot`] and the run-time parameters in [`settings`];
//! - [`robust`]: the robust build's logic (control tick, progress watchdog,
//!   sequencer, command dispatch), on the [`io`] traits only;
//! - [`selector`]: when the robust build takes a raw byte as a selector;
//! - [`time`]: the robust build's time unit;
//! - [`bench`]: the variables the hardware-in-the-loop bench reads by symbol.
//!
//! The binaries in `src/bin/` build the applications from these parts and
//! bind the interrupt vectors they use (the library defines no vector, so a
//! build links only its own).
//!
//! What touches registers is compiled for the AVR only; the rest (the logic,
//! the maths, [`bench`]'s variables as plain statics) also for the host,
//! where its unit tests run (README.md says how).

#![cfg_attr(not(test), no_std)]
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// `robust::Hardware`'s EEPROM by default, so a board need not name it.
#![cfg_attr(target_arch = "avr", feature(associated_type_defaults))]

#[cfg(target_arch = "avr")]
pub mod arduino;
pub mod battery;
pub mod bench;
#[cfg(target_arch = "avr")]
pub mod board;
#[cfg(target_arch = "avr")]
pub mod clock;
pub mod critical;
pub mod driver;
#[cfg(target_arch = "avr")]
pub mod encoder;
pub mod hal;
pub mod io;
#[cfg(target_arch = "avr")]
pub mod motors;
pub mod odometry;
pub mod pid;
pub mod plan;
pub mod robot;
pub mod robust;
pub mod selector;
pub mod settings;
pub mod time;

/// Errors of this crate.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Error {
    /// A transmit buffer had no room for the whole message.
    TxFull,
}

/// On a panic: interrupts off, every compare output of timers 2-5 (the
/// ones a motor driver's PWM inputs may be on, whatever the wiring)
/// disconnected and its pin driven low (the robot coasts), then halt.
#[cfg(target_arch = "avr")]
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    // SAFETY: nothing else runs any more (interrupts are off and this never
    // returns), so taking the peripherals again cannot race. Clearing the
    // COM bits keeps each timer's mode but gives its pins back to PORT; the
    // PORT bits of every OCnx pin of timers 2-5 go low: PB4 (OC2A), PH6
    // (OC2B), PE3-PE5 (OC3A-C), PH3-PH5 (OC4A-C), PL3-PL5 (OC5A-C).
    unsafe {
        use avr_device::atmega2560::{PORTB, PORTE, PORTH, PORTL, TC2, TC3, TC4, TC5};
        TC2::steal().tccr2a().modify(|r, w| w.bits(r.bits() & 0b11));
        TC3::steal().tccr3a().modify(|r, w| w.bits(r.bits() & 0b11));
        TC4::steal().tccr4a().modify(|r, w| w.bits(r.bits() & 0b11));
        TC5::steal().tccr5a().modify(|r, w| w.bits(r.bits() & 0b11));
        PORTB::steal().portb().modify(|r, w| w.bits(r.bits() & !0b0001_0000));
        PORTE::steal().porte().modify(|r, w| w.bits(r.bits() & !0b0011_1000));
        PORTH::steal().porth().modify(|r, w| w.bits(r.bits() & !0b0111_1000));
        PORTL::steal().portl().modify(|r, w| w.bits(r.bits() & !0b0011_1000));
    }
    loop {}
}
