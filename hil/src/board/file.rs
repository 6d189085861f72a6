//! A board TOML as written: pins by their Arduino names, numbers as given.
//! `check.rs` turns it into a [`super::Board`]; nothing here is checked
//! beyond its shape (an unknown field is refused).
//!
//! A pin is a string: `"D<n>"` for Arduino pin n, `"A<n>"` for analog pin
//! n, exactly as the Arduino core and the board's silk screen name them for
//! the board's MCU (a Mega's A0 is D54, an Uno's D14), or `"P<port><bit>"`
//! (`"PE2"`) by the MCU's port and bit.

use serde::Deserialize;

/// The whole file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoardFile {
    /// avr-gcc's name of the board's MCU; the ATmega2560 when absent.
    pub mcu: Option<String>,
    pub motor_driver: DriverFile,
    pub encoders: Sides<EncoderFile>,
    /// Absent on a board with one link (an Uno's one USART): the debug
    /// UART carries the commands too.
    pub command_uart: Option<UartFile>,
    pub debug_uart: UartFile,
    /// Absent on a board that does not measure its battery.
    pub battery: Option<BatteryFile>,
    /// Absent on a board with no battery LEDs.
    pub leds: Option<LedsFile>,
}

/// Something per motor or encoder.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Sides<T> {
    pub left: T,
    pub right: T,
}

/// `[motor_driver]`: the kind, and each motor's pins under its own names.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum DriverFile {
    Drv8833 {
        left: TwoPwmFile,
        right: TwoPwmFile,
    },
    L298n {
        left: EnableFile,
        right: EnableFile,
    },
    Tb6612 {
        left: PwmInFile,
        right: PwmInFile,
    },
    PwmDir {
        left: PwmDirFile,
        right: PwmDirFile,
    },
    Drv8838 {
        left: PhaseEnableFile,
        right: PhaseEnableFile,
    },
}

/// DRV8838 (phase/enable): EN with PWM, PH the direction (high reverse).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PhaseEnableFile {
    pub enable: String,
    pub phase: String,
}

/// DRV8833: IN1 driven with PWM drives forward, IN2 reverse.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TwoPwmFile {
    pub forward: String,
    pub reverse: String,
}

/// L298N: ENA/ENB with PWM, IN1 and IN2 as direction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EnableFile {
    pub enable: String,
    pub in1: String,
    pub in2: String,
}

/// TB6612FNG: PWMA/PWMB with PWM, AIN1/AIN2 (BIN1/BIN2) as direction.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PwmInFile {
    pub pwm: String,
    pub in1: String,
    pub in2: String,
}

/// A PWM/DIR driver: one PWM input and one direction input.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PwmDirFile {
    pub pwm: String,
    pub dir: String,
}

/// An encoder: `a` and `b` (A/B quadrature, A on an interrupt pin), `a`
/// alone (a one-channel encoder), or `xor` and `b` (Pololu's boards: A xor
/// B on the interrupt pin, B on another). `xor` without `b` is refused by
/// the check, in its own words rather than serde's.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct EncoderFile {
    pub a: Option<String>,
    pub xor: Option<String>,
    pub b: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct UartFile {
    pub usart: i64,
    pub baud: i64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BatteryFile {
    pub adc: i64,
    pub divider: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LedsFile {
    pub green: String,
    pub blue: String,
    pub red: String,
}
