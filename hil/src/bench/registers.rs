//! The ATmega2560 registers the bench itself reads or watches, by their
//! data-space addresses (datasheet, register summary). The PWM timers'
//! registers are the timer model's (`crate::pwm`), the PIN registers the
//! board's (`crate::board::Pin::pin_register`).

/// MCUSR and its brown-out reset flag.
pub(super) const MCUSR: u16 = 0x54;
pub(super) const MCUSR_BORF: u8 = 1 << 2;

/// Analog comparator control and status, and its interrupt-enable and
/// input-capture-enable bits.
pub(super) const ACSR: u16 = 0x50;
pub(super) const ACSR_ACIE: u8 = 1 << 3;
pub(super) const ACSR_ACIC: u8 = 1 << 2;

/// simavr-owned timers whose modes the bench checks: (timer, TCCRnA, TCCRnB).
pub(super) const CHECKED_TIMERS: [(u8, u16, u16); 4] = [
    (0, 0x44, 0x45),
    (1, 0x80, 0x81),
    (3, 0x90, 0x91),
    (5, 0x120, 0x121),
];
