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

/// On a panic: interrupts off, both motors' PWM inputs disconnected and
/// driven low (the robot coasts), then halt.
#[cfg(target_arch = "avr")]
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    // SAFETY: nothing else runs any more (interrupts are off and this never
    // returns), so taking the peripherals again cannot race. Writing mode 1
    // with COM bits 0 keeps the PWM mode but disconnects the pins; the PORTH
    // bits of D6..D9 (PH3..PH6) go low.
    unsafe {
        let tc4 = avr_device::atmega2560::TC4::steal();
        let tc2 = avr_device::atmega2560::TC2::steal();
        let porth = avr_device::atmega2560::PORTH::steal();
        porth.porth().modify(|r, w| w.bits(r.bits() & !0b0111_1000));
        tc4.tccr4a().write(|w| w.bits(0b01));
        tc2.tccr2a().write(|w| w.bits(0b01));
    }
    loop {}
}
