//! Clock arithmetic: every timer and baud value is derived here, at compile
//! time, from the CPU frequency handed in by the board (never a literal).

/// Clock prescaler of a timer (the CS bits select one of these).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Prescaler {
    /// clk/1
    Div1,
    /// clk/8
    Div8,
    /// clk/64
    Div64,
    /// clk/256
    Div256,
    /// clk/1024
    Div1024,
}

impl Prescaler {
    /// The division factor.
    pub const fn divisor(self) -> u32 {
        match self {
            Prescaler::Div1 => 1,
            Prescaler::Div8 => 8,
            Prescaler::Div64 => 64,
            Prescaler::Div256 => 256,
            Prescaler::Div1024 => 1024,
        }
    }

    /// The CS2:0 field of TCCRnB for timers 0, 1, 3, 4 and 5 (timer 2 uses a
    /// different table, see [`Prescaler::cs_bits_timer2`]).
    pub const fn cs_bits(self) -> u8 {
        match self {
            Prescaler::Div1 => 0b001,
            Prescaler::Div8 => 0b010,
            Prescaler::Div64 => 0b011,
            Prescaler::Div256 => 0b100,
            Prescaler::Div1024 => 0b101,
        }
    }

    /// The CS22:0 field of TCCR2B (timer 2 has the extra /32 and /128 steps).
    pub const fn cs_bits_timer2(self) -> u8 {
        match self {
            Prescaler::Div1 => 0b001,
            Prescaler::Div8 => 0b010,
            Prescaler::Div64 => 0b100,
            Prescaler::Div256 => 0b110,
            Prescaler::Div1024 => 0b111,
        }
    }
}

/// OCRnA value for a CTC timer whose compare match comes every `period_us`
/// microseconds: the counter runs 0..=OCRnA, so the period is OCRnA + 1 timer
/// clocks. Rounded to the nearest timer clock; saturates at `u16::MAX` and
/// never goes below 0 (a period shorter than one timer clock gives 0).
pub const fn ctc_top(cpu_hz: u32, prescaler: Prescaler, period_us: u32) -> u16 {
    let denom = prescaler.divisor() as u64 * 1_000_000;
    let clocks = (cpu_hz as u64 * period_us as u64 + denom / 2) / denom;
    if clocks == 0 {
        0
    } else if clocks - 1 > u16::MAX as u64 {
        u16::MAX
    } else {
        (clocks - 1) as u16
    }
}

/// True when `period_us` is a whole number of timer clocks, i.e. when
/// [`ctc_top`] is exact rather than rounded.
pub const fn ctc_is_exact(cpu_hz: u32, prescaler: Prescaler, period_us: u32) -> bool {
    let denom = prescaler.divisor() as u64 * 1_000_000;
    (cpu_hz as u64 * period_us as u64).is_multiple_of(denom)
}

/// UBRRn for an asynchronous USART in double-speed mode (U2Xn = 1):
/// baud = f / (8 (UBRR + 1)), rounded to the nearest divisor.
pub const fn ubrr_double_speed(cpu_hz: u32, baud: u32) -> u16 {
    let div = (cpu_hz + 4 * baud) / (8 * baud);
    if div == 0 {
        0
    } else {
        (div - 1) as u16
    }
}

/// The baud rate a given UBRRn really produces in double-speed mode, in
/// hundredths of a baud (to check the error at compile time).
pub const fn baud_double_speed_centi(cpu_hz: u32, ubrr: u16) -> u32 {
    ((cpu_hz as u64 * 100) / (8 * (ubrr as u64 + 1))) as u32
}

/// Frequency of an 8-bit phase-correct PWM (TOP = 255: the counter goes up
/// and down, 510 timer clocks per period), in millihertz.
pub const fn phase_correct_pwm_mhz(cpu_hz: u32, prescaler: Prescaler) -> u32 {
    ((cpu_hz as u64 * 1000) / (prescaler.divisor() as u64 * 510)) as u32
}

// Checks of the arithmetic against values from the datasheet tables.
const _: () = assert!(ctc_top(16_000_000, Prescaler::Div64, 15_000) == 3749);
const _: () = assert!(ctc_is_exact(16_000_000, Prescaler::Div64, 15_000));
const _: () = assert!(ctc_top(16_000_000, Prescaler::Div256, 1_000_000) == 62_499);
const _: () = assert!(ubrr_double_speed(16_000_000, 9600) == 207);
const _: () = assert!(phase_correct_pwm_mhz(16_000_000, Prescaler::Div1) == 31_372_549);
