//! The ATmega2560 registers the bench itself reads or watches, by their
//! data-space addresses (datasheet, register summary). The PWM timers'
//! registers are the timer model's (`crate::mcu::pwm`), the PIN registers the
//! board's (`crate::board::Pin::pin_register`); those of the timers simavr
//! runs, watched by `timers.rs`, are the same table's
//! (`crate::mcu::pwm::layout::ATMEGA2560`).

/// MCUSR, its brown-out and its external reset flags.
pub(super) const MCUSR: u16 = 0x54;
pub(super) const MCUSR_BORF: u8 = 1 << 2;
pub(super) const MCUSR_EXTRF: u8 = 1 << 1;

/// Analog comparator control and status, and its interrupt-enable and
/// input-capture-enable bits.
pub(super) const ACSR: u16 = 0x50;
pub(super) const ACSR_ACIE: u8 = 1 << 3;
pub(super) const ACSR_ACIC: u8 = 1 << 2;
