//! From a board file to a [`Board`]: every pin resolved on the board's MCU
//! (`mcu = "atmega328p"`; the ATmega2560 when absent) and every rule checked
//! before anything runs. Each problem is one line:
//! the file, the field, what is wrong and what is allowed.

use std::collections::BTreeMap;

use thiserror::Error;

use super::file::{BatteryFile, BoardFile, DriverFile, EncoderFile, Sides};
use super::{
    BatteryWiring, Board, BridgeInput, DriverKind, EncoderKind, EncoderWiring, LedWiring,
    MotorWiring, Pin, UartLine, UartWiring,
};
use crate::mcu::chip::{Chip, Mcu};
use crate::mcu::clock::Clock;

/// Why a board file is refused.
#[derive(Debug, Error)]
pub enum BoardError {
    /// (The cause is in the message, not a `source`: a chain would print it twice.)
    #[error("board {path}: {cause}")]
    Read { path: String, cause: std::io::Error },
    /// Not TOML, or not the schema (an unknown or missing field, a wrong type).
    #[error("{file}:{line}: {message}")]
    Syntax {
        file: String,
        line: usize,
        message: String,
    },
    /// The schema's fields, with values no board may have: one line each.
    #[error("{}", .0.iter().map(ToString::to_string).collect::<Vec<_>>().join("\n"))]
    Invalid(Vec<Problem>),
}

/// One thing wrong with a board: where, and what.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub file: String,
    /// The field, as a TOML path (`motor_driver.left.forward`).
    pub field: String,
    pub kind: ProblemKind,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}: {}", self.file, self.field, self.kind)
    }
}

/// What is wrong with one field. What is allowed comes from the MCU's
/// description.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ProblemKind {
    #[error("no MCU {given:?} is described; give one of {}", Mcu::names())]
    UnknownMcu { given: String },
    #[error("no {mcu} pin {given:?}; give {}", pin_names(mcu.chip()))]
    UnknownPin { given: String, mcu: Mcu },
    #[error("{pin} is already used by {first}; each pin carries one signal")]
    PinReused { pin: String, first: String },
    #[error("{pin} is on no timer's output-compare channel, so no PWM reaches it; {mcu} PWM pins: {}", mcu.chip().pwm_pins())]
    NotPwm { pin: String, mcu: Mcu },
    #[error("{pin} is on timer {timer}: {}; {mcu} PWM pins: {}", mcu.chip().unemulated_timer(*timer).unwrap_or("not emulated"), mcu.chip().pwm_pins())]
    TimerNotEmulated { pin: String, timer: u8, mcu: Mcu },
    #[error("{pin} cannot interrupt (no INTn or PCINTn), so the firmware would miss {line}'s edges; give {}", mcu.chip().interrupt_pins())]
    CannotInterrupt {
        pin: String,
        line: &'static str,
        mcu: Mcu,
    },
    #[error("{pin} has no Arduino number; a motor-driver input needs one (the drive log and the robust firmware's parameters number them): give a pin \"D0\"-\"D{}\"", mcu.chip().last_arduino_pin())]
    NoArduinoNumber { pin: String, mcu: Mcu },
    #[error("{} give channel A's pin (`a`: with `b` A/B quadrature, alone a one-channel encoder) or the A xor B line's (`xor`, Pololu's boards, with `b`)", if *given { "both `a` and `xor` given:" } else { "no `a` or `xor`:" })]
    EncoderLines { given: bool },
    #[error("no `b`: an A xor B line is decoded with channel B; give B's pin (an encoder with channel A alone is given as `a`)")]
    XorWithoutB,
    #[error("no USART {usart}; the {mcu} has USART {}", mcu.chip().usart_range())]
    UartOutOfRange { usart: i64, mcu: Mcu },
    #[error("USART {usart} already carries {first}; each link needs a USART of its own ({})", mcu.chip().usart_range())]
    UartReused { usart: u8, first: String, mcu: Mcu },
    #[error("no ADC channel {adc} on a pin of the {mcu}; give {}", mcu.chip().adc_channels())]
    AdcOutOfRange { adc: i64, mcu: Mcu },
    #[error("{baud} baud is not within {BAUD_TOLERANCE_PERCENT} % of a rate the USART makes from 16 MHz (UBRR 0-4095, normal or double speed); e.g. 9600, 19200, 38400, 57600, 115200")]
    BadBaud { baud: i64 },
    #[error("divider {divider} is not a ratio of volts at the pin per battery volt; give one above 0 and at most 1")]
    BadDivider { divider: f64 },
}

/// The receiver's tolerance the bench accepts: the datasheet recommends at
/// most 2 % for 8-bit frames (table 22-2); the Arduino core's 115200 baud at
/// 16 MHz is 2.1 % off and works, so 2.5 %.
const BAUD_TOLERANCE_PERCENT: f64 = 2.5;

/// Whether the USART can make `baud` from the 16 MHz clock within the
/// tolerance (datasheet 22.3.1: BAUD = f / (16 (UBRR + 1)), or 8 with U2X).
fn baud_ok(baud: i64) -> bool {
    if baud <= 0 {
        return false;
    }
    let f = f64::from(Clock::MEGA_16MHZ.hz());
    let b = baud as f64;
    [16.0, 8.0].iter().any(|&div| {
        let ubrr = (f / (div * b)).round() - 1.0;
        (0.0..=4095.0).contains(&ubrr) && {
            let actual = f / (div * (ubrr + 1.0));
            ((actual / b - 1.0) * 100.0).abs() <= BAUD_TOLERANCE_PERCENT
        }
    })
}

/// `text` as a board, checked; errors name `file`.
pub(super) fn parse(text: &str, file: &str) -> Result<Board, BoardError> {
    let raw: BoardFile = toml::from_str(text).map_err(|e| BoardError::Syntax {
        file: file.to_string(),
        line: e
            .span()
            .map_or(0, |s| text[..s.start].matches('\n').count() + 1),
        message: e.message().replace('\n', " "),
    })?;
    let mcu = match raw.mcu.as_deref().map(|m| (m, Mcu::named(m))) {
        None => Mcu::Atmega2560,
        Some((_, Some(mcu))) => mcu,
        Some((given, None)) => {
            return Err(BoardError::Invalid(vec![Problem {
                file: file.to_string(),
                field: "mcu".into(),
                kind: ProblemKind::UnknownMcu {
                    given: given.to_string(),
                },
            }]))
        }
    };
    let mut c = Checker {
        chip: mcu.chip(),
        file,
        problems: Vec::new(),
        used: BTreeMap::new(),
        uarts: Vec::new(),
    };
    let board = c.board(&raw);
    match board {
        Some(b) if c.problems.is_empty() => Ok(b),
        _ => Err(BoardError::Invalid(c.problems)),
    }
}

/// The problems found so far and the pins taken, by port and bit.
struct Checker<'a> {
    chip: &'static Chip,
    file: &'a str,
    problems: Vec<Problem>,
    used: BTreeMap<(char, u8), String>,
    /// The USARTs taken, and by which link.
    uarts: Vec<(u8, String)>,
}

/// The pin of `chip` named `name`: `"D<n>"` or `"A<n>"` by the Arduino
/// core's numbers for its board, or `"P<port><bit>"` by port and bit.
pub(super) fn pin_by_name(chip: &Chip, name: &str) -> Option<Pin> {
    let digits = |s: &str| -> Option<u8> {
        (!s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()) && s.len() <= 2)
            .then(|| s.parse().ok())
            .flatten()
    };
    let n = if let Some(n) = name.strip_prefix('D').and_then(digits) {
        n
    } else if let Some(n) = name.strip_prefix('A').and_then(digits) {
        chip.analog_pin(n)?
    } else {
        let mut c = name.strip_prefix('P')?.chars();
        let (port, bit) = (c.next()?, c.next()?.to_digit(10)? as u8);
        if c.next().is_some() {
            return None;
        }
        // A port pin need not have an Arduino number (the 32U4's PE2).
        return Pin::on_port(chip.mcu, port, bit);
    };
    Pin::arduino(chip.mcu, n)
}

/// The pin names `chip` offers, as errors say them.
fn pin_names(chip: &Chip) -> String {
    format!(
        "\"D0\"-\"D{}\", \"A0\"-\"A{}\" or a port pin (\"P{}0\")",
        chip.last_arduino_pin(),
        chip.analog.channels.len() - 1,
        chip.ports[0].letter
    )
}

impl Checker<'_> {
    fn problem(&mut self, field: &str, kind: ProblemKind) {
        self.problems.push(Problem {
            file: self.file.to_string(),
            field: field.to_string(),
            kind,
        });
    }

    /// The MCU's pin `bit` of port `port`, which the description has (a
    /// USART's or an ADC channel's).
    fn port_pin(&self, port: char, bit: u8) -> Pin {
        Pin::on_port(self.chip.mcu, port, bit).expect("a USART's or ADC's pin is on a port")
    }

    /// Take `pin` for `what` (said in the message of a later clash).
    fn take(&mut self, field: &str, pin: Pin, what: String) {
        if let Some(first) = self.used.get(&(pin.port, pin.bit)) {
            let first = first.clone();
            self.problem(
                field,
                ProblemKind::PinReused {
                    pin: pin.name(),
                    first,
                },
            );
        } else {
            self.used.insert((pin.port, pin.bit), what);
        }
    }

    /// The pin named at `field`, taken.
    fn pin(&mut self, field: &str, name: &str) -> Option<Pin> {
        let Some(pin) = pin_by_name(self.chip, name) else {
            self.problem(
                field,
                ProblemKind::UnknownPin {
                    given: name.to_string(),
                    mcu: self.chip.mcu,
                },
            );
            return None;
        };
        self.take(field, pin, field.to_string());
        Some(pin)
    }

    /// A driver input driven with PWM, by the timer channel on its pin
    /// (on D13, which carries OC0A and OC1C, OC0A: the Arduino core's
    /// `analogWrite`). Whether the firmware may use that timer as well (as
    /// its clock) is judged when it runs (`bench/timers.rs`).
    fn pwm(&mut self, field: &str, name: &str) -> Option<BridgeInput> {
        let pin = self.driver_pin(field, name)?;
        let Some(&source) = pin.pwm_sources().first() else {
            self.problem(
                field,
                ProblemKind::NotPwm {
                    pin: pin.name(),
                    mcu: self.chip.mcu,
                },
            );
            return None;
        };
        if self.chip.unemulated_timer(source.timer).is_some() {
            self.problem(
                field,
                ProblemKind::TimerNotEmulated {
                    pin: pin.name(),
                    timer: source.timer,
                    mcu: self.chip.mcu,
                },
            );
            return None;
        }
        Some(BridgeInput {
            pin,
            pwm: Some(source),
        })
    }

    /// A direction input: any pin with an Arduino number, as GPIO.
    fn gpio(&mut self, field: &str, name: &str) -> Option<BridgeInput> {
        let pin = self.driver_pin(field, name)?;
        Some(BridgeInput { pin, pwm: None })
    }

    /// The pin of a motor-driver input, taken: one with an Arduino number.
    fn driver_pin(&mut self, field: &str, name: &str) -> Option<Pin> {
        let pin = self.pin(field, name)?;
        if pin.arduino.is_none() {
            let (pin, mcu) = (pin.name(), self.chip.mcu);
            self.problem(field, ProblemKind::NoArduinoNumber { pin, mcu });
            return None;
        }
        Some(pin)
    }

    fn motors(&mut self, d: &DriverFile) -> Option<(DriverKind, [MotorWiring; 2])> {
        let f = |side: &str, name: &str| format!("motor_driver.{side}.{name}");
        let motor = |c: &mut Self, side: &str| -> Option<MotorWiring> {
            let (p1, p2, p3) = match d {
                DriverFile::Drv8833 { left, right } => {
                    let m = if side == "left" { left } else { right };
                    let p1 = c.pwm(&f(side, "forward"), &m.forward);
                    (p1, c.pwm(&f(side, "reverse"), &m.reverse), Some(None))
                }
                DriverFile::L298n { left, right } => {
                    let m = if side == "left" { left } else { right };
                    let p1 = c.pwm(&f(side, "enable"), &m.enable);
                    let p2 = c.gpio(&f(side, "in1"), &m.in1);
                    (p1, p2, c.gpio(&f(side, "in2"), &m.in2).map(Some))
                }
                DriverFile::Tb6612 { left, right } => {
                    let m = if side == "left" { left } else { right };
                    let p1 = c.pwm(&f(side, "pwm"), &m.pwm);
                    let p2 = c.gpio(&f(side, "in1"), &m.in1);
                    (p1, p2, c.gpio(&f(side, "in2"), &m.in2).map(Some))
                }
                DriverFile::PwmDir { left, right } => {
                    let m = if side == "left" { left } else { right };
                    let p1 = c.pwm(&f(side, "pwm"), &m.pwm);
                    (p1, c.gpio(&f(side, "dir"), &m.dir), Some(None))
                }
                DriverFile::Drv8838 { left, right } => {
                    let m = if side == "left" { left } else { right };
                    let p1 = c.pwm(&f(side, "enable"), &m.enable);
                    (p1, c.gpio(&f(side, "phase"), &m.phase), Some(None))
                }
            };
            Some(MotorWiring {
                pin1: p1?,
                pin2: p2?,
                pin3: p3?,
            })
        };
        let left = motor(self, "left");
        let right = motor(self, "right");
        let kind = match d {
            DriverFile::Drv8833 { .. } => DriverKind::Drv8833,
            DriverFile::L298n { .. } => DriverKind::L298n,
            DriverFile::Tb6612 { .. } => DriverKind::Tb6612,
            DriverFile::PwmDir { .. } => DriverKind::PwmDir,
            DriverFile::Drv8838 { .. } => DriverKind::Drv8838,
        };
        Some((kind, [left?, right?]))
    }

    fn encoders(&mut self, e: &Sides<EncoderFile>) -> Option<[EncoderWiring; 2]> {
        let one = |c: &mut Self, side: &str, e: &EncoderFile| {
            let (kind, key, name, line) = match (&e.a, &e.xor, &e.b) {
                (Some(a), None, Some(_)) => (EncoderKind::Quadrature, "a", a, "channel A"),
                // Channel A alone: its pin is checked as quadrature A's.
                (Some(a), None, None) => (EncoderKind::OneChannel, "a", a, "channel A"),
                (None, Some(x), _) => (EncoderKind::Xor, "xor", x, "the A xor B line"),
                _ => {
                    let given = e.a.is_some();
                    c.problem(
                        &format!("encoders.{side}"),
                        ProblemKind::EncoderLines { given },
                    );
                    return None;
                }
            };
            let a_field = format!("encoders.{side}.{key}");
            let a = c.pin(&a_field, name);
            if let Some(a) = a.filter(|a| !a.can_interrupt()) {
                let (pin, mcu) = (a.name(), c.chip.mcu);
                c.problem(&a_field, ProblemKind::CannotInterrupt { pin, line, mcu });
            }
            let b_field = format!("encoders.{side}.b");
            let b = match (&e.b, kind) {
                (None, EncoderKind::OneChannel) => None,
                (None, _) => {
                    c.problem(&b_field, ProblemKind::XorWithoutB);
                    return None;
                }
                (Some(b_name), _) => Some(c.pin(&b_field, b_name)?),
            };
            Some(EncoderWiring { kind, a: a?, b })
        };
        let left = one(self, "left", &e.left);
        let right = one(self, "right", &e.right);
        Some([left?, right?])
    }

    /// A USART: its number in range, its two pins taken.
    fn uart(&mut self, name: &str, u: &super::file::UartFile) -> Option<UartWiring> {
        let usart_field = format!("{name}.usart");
        let pins = u8::try_from(u.usart)
            .ok()
            .and_then(|n| self.chip.usart(n))
            .map(|u| [u.rxd, u.txd].map(|(port, bit)| self.port_pin(port, bit)));
        let first = self
            .uarts
            .iter()
            .find(|(n, _)| i64::from(*n) == u.usart)
            .map(|(_, name)| name.clone());
        match (pins, first) {
            (None, _) => self.problem(
                &usart_field,
                ProblemKind::UartOutOfRange {
                    usart: u.usart,
                    mcu: self.chip.mcu,
                },
            ),
            (Some(_), Some(first)) => self.problem(
                &usart_field,
                ProblemKind::UartReused {
                    usart: u.usart as u8,
                    first,
                    mcu: self.chip.mcu,
                },
            ),
            (Some(pins), None) => {
                self.uarts.push((u.usart as u8, name.to_string()));
                for p in pins {
                    let line = match p.uart_line() {
                        Some(UartLine::Rxd(n)) => format!("RXD{n}"),
                        Some(UartLine::Txd(n)) => format!("TXD{n}"),
                        None => unreachable!("a USART's pin is on its line"),
                    };
                    self.take(&usart_field, p, format!("{name}'s {line}"));
                }
            }
        }
        let baud_ok = baud_ok(u.baud);
        if !baud_ok {
            self.problem(
                &format!("{name}.baud"),
                ProblemKind::BadBaud { baud: u.baud },
            );
        }
        Some(UartWiring {
            usart: u8::try_from(u.usart).ok().filter(|_| pins.is_some())?,
            baud: u32::try_from(u.baud).ok().filter(|_| baud_ok)?,
        })
    }

    fn board(&mut self, raw: &BoardFile) -> Option<Board> {
        let motors = self.motors(&raw.motor_driver);
        let encoders = self.encoders(&raw.encoders);
        let leds = raw.leds.as_ref().map(|leds| {
            (
                self.pin("leds.green", &leds.green),
                self.pin("leds.blue", &leds.blue),
                self.pin("leds.red", &leds.red),
            )
        });
        let command = raw
            .command_uart
            .as_ref()
            .map(|u| self.uart("command_uart", u));
        let debug = self.uart("debug_uart", &raw.debug_uart);
        let battery = raw.battery.as_ref().map(|b| self.battery(b));
        let (driver, [left_motor, right_motor]) = motors?;
        let [left_encoder, right_encoder] = encoders?;
        Some(Board {
            mcu: self.chip.mcu,
            driver,
            left_motor,
            right_motor,
            left_encoder,
            right_encoder,
            command_uart: command.unwrap_or(debug)?,
            debug_uart: debug?,
            battery: match battery {
                None => None,
                Some(b) => Some(b?),
            },
            battery_leds: match leds {
                None => None,
                Some((green, blue, red)) => Some(LedWiring {
                    green: green?,
                    blue: blue?,
                    red: red?,
                }),
            },
        })
    }

    /// `[battery]`: its ADC channel on the board's MCU, and a divider that
    /// can be (0 to 1).
    fn battery(&mut self, b: &BatteryFile) -> Option<BatteryWiring> {
        let adc_pin = u8::try_from(b.adc)
            .ok()
            .and_then(|n| self.chip.adc_pin(n))
            .map(|(port, bit)| self.port_pin(port, bit));
        match adc_pin {
            Some(p) => self.take("battery.adc", p, format!("battery.adc (ADC{})", b.adc)),
            None => self.problem(
                "battery.adc",
                ProblemKind::AdcOutOfRange {
                    adc: b.adc,
                    mcu: self.chip.mcu,
                },
            ),
        }
        let divider_ok = b.divider > 0.0 && b.divider <= 1.0;
        if !divider_ok {
            self.problem(
                "battery.divider",
                ProblemKind::BadDivider { divider: b.divider },
            );
        }
        Some(BatteryWiring {
            adc: adc_pin.map(|_| b.adc as u8)?,
            divider: b.divider,
        })
        .filter(|_| divider_ok)
    }
}
