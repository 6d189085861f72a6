//! The ATmega2560 registers the bench itself reads or watches, by their
//! data-space addresses (datasheet, register summary). The PWM timers'
//! registers are the timer model's (`crate::mcu::pwm`), the PIN registers the
//! board's (`crate::board::Pin::pin_register`).

/// MCUSR, its brown-out and its external reset flags.
pub(super) const MCUSR: u16 = 0x54;
pub(super) const MCUSR_BORF: u8 = 1 << 2;
pub(super) const MCUSR_EXTRF: u8 = 1 << 1;

/// Analog comparator control and status, and its interrupt-enable and
/// input-capture-enable bits.
pub(super) const ACSR: u16 = 0x50;
pub(super) const ACSR_ACIE: u8 = 1 << 3;
pub(super) const ACSR_ACIC: u8 = 1 << 2;

/// One timer's registers the bench watches when simavr runs it (see
/// `timers.rs`): the mode and clock (TCCRnA, TCCRnB), the interrupt enables
/// (TIMSKn), the counter's low byte (TCNTn) and the flags (TIFRn).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct TimerRegs {
    pub n: u8,
    pub tccra: u16,
    pub tccrb: u16,
    pub timsk: u16,
    pub tcnt: u16,
    pub tifr: u16,
    pub sixteen_bit: bool,
}

const fn regs(n: u8, tccra: u16, tcnt: u16, timsk: u16, tifr: u16, sixteen_bit: bool) -> TimerRegs {
    TimerRegs {
        n,
        tccra,
        tccrb: tccra + 1,
        timsk,
        tcnt,
        tifr,
        sixteen_bit,
    }
}

/// Every timer of the MCU; the bench checks those simavr runs (all but the
/// board's PWM timers, which the bench emulates itself).
pub(super) const CHECKED_TIMERS: [TimerRegs; 6] = [
    regs(0, 0x44, 0x46, 0x6E, 0x35, false),
    regs(1, 0x80, 0x84, 0x6F, 0x36, true),
    regs(2, 0xB0, 0xB2, 0x70, 0x37, false),
    regs(3, 0x90, 0x94, 0x71, 0x38, true),
    regs(4, 0xA0, 0xA4, 0x72, 0x39, true),
    regs(5, 0x120, 0x124, 0x73, 0x3A, true),
];
