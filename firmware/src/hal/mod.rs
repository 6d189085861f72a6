//! A thin hardware layer over `avr-device` for the ATmega2560.
//!
//! Interrupt handlers are plain functions here; each binary binds the ones
//! it needs to its vectors, so a build links only the vectors it uses.
//!
//! Each module owns the peripheral it drives (taken by value from
//! `avr_device::atmega2560::Peripherals`), so two drivers cannot program the
//! same registers. Nothing here knows the robot: pin roles and clock values
//! are chosen in `board.rs`.
//!
//! Rules every module keeps:
//! - 16-bit timer registers are written high byte first, then low byte (the
//!   chip latches the high byte in a shared TEMP register), see [`reg`].
//! - Read-modify-write of a register that an interrupt handler may also touch
//!   happens inside `interrupt::free`.
//! - Timers 2-5 (PWM) are only ever written, never read, and none of their
//!   interrupts is enabled: the bench emulates timers 2 and 4 itself.

pub mod clock;
pub mod mega_pins;

// The rest programs registers: AVR only (`clock` is const arithmetic and
// `mega_pins` a table, which the host-side logic shares).
#[cfg(target_arch = "avr")]
pub mod adc;
#[cfg(target_arch = "avr")]
pub mod eeprom;
#[cfg(target_arch = "avr")]
pub mod exint;
#[cfg(target_arch = "avr")]
pub mod gpio;
#[cfg(target_arch = "avr")]
pub mod pwm;
#[cfg(target_arch = "avr")]
pub mod reg;
#[cfg(target_arch = "avr")]
pub mod ring;
#[cfg(target_arch = "avr")]
pub mod sleep;
#[cfg(target_arch = "avr")]
pub mod tick;
#[cfg(target_arch = "avr")]
pub mod usart;
#[cfg(target_arch = "avr")]
pub mod wdt;
