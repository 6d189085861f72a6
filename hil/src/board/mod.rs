//! The board: which MCU pin each signal of the robot is on, as data.
//!
//! Parts (the plant's encoders and motor-driver inputs) know only their own
//! signals; a [`Board`] is the one place that names MCU pins, as the robot's
//! board does. Henrytwo's is built in ([`HENRYTWO`]) and written out in
//! `fixtures/boards/henrytwo.toml`; another robot's comes from a board TOML
//! ([`Board::load`]), checked before anything runs.
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`Board`] and its parts, [`HENRYTWO`], the firmware's driver parameters |
//! | `file.rs` | the TOML schema, as written |
//! | `check.rs` | from the file to a [`Board`]: every pin resolved on its MCU (`crate::mcu::chip`) and checked, [`BoardError`] |
//! | `henrytwo.rs` | `board_rs_names_the_same_pins`: the firmware's `board.rs` agrees with [`HENRYTWO`] |

mod check;
mod file;
#[cfg(test)]
mod henrytwo;

use std::path::Path;

use henrytwo_protocol::{DriverKind as WireKind, Param, NO_PIN};
use plant_model::Side;

pub use self::check::{BoardError, Problem, ProblemKind};
use crate::mcu::chip::{Chip, PortBit};
pub use crate::mcu::chip::{Mcu, PwmSource, UartLine};

/// A pin of `mcu` by its name, `"D<n>"`, `"A<n>"` (the Arduino core's
/// numbers for the MCU's board) or `"P<port><bit>"` (`"PE2"`).
pub fn pin_named(mcu: Mcu, name: &str) -> Option<Pin> {
    check::pin_by_name(mcu.chip(), name)
}

/// An MCU pin: IO port letter and bit, with its Arduino number where the
/// Arduino core gives it one (the 32U4's PE2 has none) and the MCU it
/// belongs to (whose description says what the pin can do).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Pin {
    pub port: char,
    pub bit: u8,
    pub arduino: Option<u8>,
    #[serde(skip)]
    pub mcu: Mcu,
}

impl Pin {
    /// Arduino pin `n` of `mcu`'s board.
    pub fn arduino(mcu: Mcu, n: u8) -> Option<Pin> {
        let (port, bit) = mcu.chip().arduino_pin(n)?;
        Some(Pin {
            port,
            bit,
            arduino: Some(n),
            mcu,
        })
    }

    /// Pin `bit` of port `port` of `mcu`, with its Arduino number if it has
    /// one.
    pub fn on_port(mcu: Mcu, port: char, bit: u8) -> Option<Pin> {
        let chip = mcu.chip();
        chip.has_pin((port, bit)).then(|| Pin {
            port,
            bit,
            arduino: chip.arduino_number((port, bit)),
            mcu,
        })
    }

    /// How reports, errors and traces name it: "D7" by its Arduino number,
    /// "PE2" by port and bit where it has none.
    pub fn name(&self) -> String {
        self.mcu.chip().pin_name((self.port, self.bit))
    }

    fn chip(&self) -> &'static Chip {
        self.mcu.chip()
    }

    fn at(&self) -> PortBit {
        (self.port, self.bit)
    }

    /// Data-space address of the pin's PIN register.
    pub fn pin_register(&self) -> u16 {
        self.chip()
            .port(self.port)
            .map(|p| p.pin)
            .expect("a pin is on a port of its MCU")
    }

    /// Whether a level change on this pin can start something in the MCU
    /// by itself, however the firmware configures it: an external or
    /// pin-change interrupt, an input capture, a counter or asynchronous
    /// clock input, a USART clock input, SPI or TWI. The analog
    /// comparator's inputs are separate ([`Pin::is_comparator_input`]).
    pub fn can_interrupt(&self) -> bool {
        self.chip().can_interrupt(self.at())
    }

    /// An analog comparator input: the comparator can interrupt or capture
    /// on it when ACSR enables that.
    pub fn is_comparator_input(&self) -> bool {
        self.chip().is_comparator_input(self.at())
    }

    /// The output-compare channels on this pin, the Arduino core's first.
    pub fn pwm_sources(&self) -> &'static [PwmSource] {
        self.chip().pwm_sources(self.at())
    }

    /// External interrupt INTn on this pin.
    pub fn external_interrupt(&self) -> Option<u8> {
        self.chip().external_interrupt(self.at()).map(|e| e.n)
    }

    /// Pin-change interrupt PCINTn on this pin.
    pub fn pin_change_interrupt(&self) -> Option<u8> {
        self.chip().pin_change_interrupt(self.at()).map(|(n, _)| n)
    }

    /// The interrupt vector a level change on this pin requests, when the
    /// firmware enables it: its INTn's, else its pin-change group's.
    pub fn interrupt_vector(&self) -> Option<u8> {
        self.chip().interrupt_vector(self.at())
    }

    /// The USART line on this pin.
    pub fn uart_line(&self) -> Option<UartLine> {
        self.chip().uart_line(self.at())
    }

    /// The ADC input channel on this pin.
    pub fn adc_channel(&self) -> Option<u8> {
        self.chip().adc_channel(self.at())
    }
}

/// One motor-driver input: its pin, and the timer channel that drives it
/// with PWM (None: a direction input, plain GPIO).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct BridgeInput {
    pub pin: Pin,
    pub pwm: Option<PwmSource>,
}

impl BridgeInput {
    /// Its Arduino number: a board check gives every motor-driver input
    /// one (the robust firmware's parameters and the drive log number
    /// them so).
    pub fn number(&self) -> u8 {
        self.pin
            .arduino
            .expect("a motor-driver input has an Arduino number (board check)")
    }
}

/// The motor driver, and what its inputs mean (each motor's pins 1-3 in
/// [`MotorWiring`], numbered as the robust firmware's parameters number
/// them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DriverKind {
    /// Two PWM inputs per motor: pin 1 IN1 (forward), pin 2 IN2 (reverse).
    /// Both low coast, both high brake (DRV8833 datasheet, table 2).
    Drv8833,
    /// Pin 1 the enable (PWM), pin 2 IN1, pin 3 IN2: enable low coasts
    /// ("free running motor stop"), IN1 = IN2 with enable high brakes
    /// ("fast motor stop") (L298 datasheet, figure 6).
    L298n,
    /// Pin 1 PWM, pin 2 IN1, pin 3 IN2: PWM low short-brakes, IN1 and IN2
    /// both high short-brake, both low stop (high impedance) (TB6612FNG
    /// datasheet, H-SW control function; STBY held high).
    Tb6612,
    /// Pin 1 PWM, pin 2 direction (high forward): PWM low brakes, both
    /// outputs low (the phase/enable drivers wired so: DRV8835 in PH/EN
    /// mode).
    PwmDir,
    /// Pin 1 EN (PWM), pin 2 PH: EN high drives, forward with PH low and
    /// in reverse with PH high; EN low brakes, both outputs low (DRV8838
    /// datasheet, table 1, nSLEEP high; Pololu's Romi 32U4).
    Drv8838,
}

impl DriverKind {
    /// The firmware's name for this kind of wiring.
    pub fn wire_kind(self) -> WireKind {
        match self {
            DriverKind::Drv8833 => WireKind::TwoPwm,
            DriverKind::L298n | DriverKind::Tb6612 => WireKind::EnableTwoDir,
            // The robust firmware has no phase/enable kind whose direction
            // high reverses: `Board::firmware_encoder_mismatch` refuses it.
            DriverKind::PwmDir | DriverKind::Drv8838 => WireKind::PwmDir,
        }
    }
}

/// One motor's driver inputs, pins 1-3 as [`DriverKind`] names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct MotorWiring {
    pub pin1: BridgeInput,
    pub pin2: BridgeInput,
    pub pin3: Option<BridgeInput>,
}

impl MotorWiring {
    /// The inputs in pin order (1, 2, then 3 if any).
    pub fn inputs(&self) -> impl Iterator<Item = BridgeInput> {
        [Some(self.pin1), Some(self.pin2), self.pin3]
            .into_iter()
            .flatten()
    }
}

/// How an encoder's two channels reach the MCU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EncoderKind {
    /// A and B each on a pin, A on an interrupt pin.
    Quadrature,
    /// Pololu's 32U4 boards: A xor B on the interrupt pin (it changes at
    /// every edge of either channel), B on another; the firmware recovers A
    /// as xor ^ B and counts all four edges of a cycle.
    Xor,
    /// Channel A alone on an interrupt pin, no B wired: the firmware counts
    /// A's edges and takes their direction from its own motor command.
    OneChannel,
}

/// One encoder's lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct EncoderWiring {
    pub kind: EncoderKind,
    /// The interrupt pin: channel A's, or the A xor B line's
    /// ([`EncoderKind::Xor`]).
    pub a: Pin,
    /// Channel B's pin: None exactly on a one-channel encoder
    /// ([`EncoderKind::OneChannel`], the board check's rule).
    pub b: Option<Pin>,
}

impl EncoderWiring {
    /// The lines' names, interrupt pin first, as traces name them: "A",
    /// "B", or "XOR", "B" (a one-channel encoder's B is on no pin).
    pub fn line_names(&self) -> [&'static str; 2] {
        match self.kind {
            EncoderKind::Quadrature | EncoderKind::OneChannel => ["A", "B"],
            EncoderKind::Xor => ["XOR", "B"],
        }
    }

    /// The wired lines, interrupt pin first: (name, pin), B's only where
    /// it is on a pin.
    pub fn lines(&self) -> Vec<(&'static str, Pin)> {
        let [a, b] = self.line_names();
        std::iter::once((a, self.a))
            .chain(self.b.map(|p| (b, p)))
            .collect()
    }

    /// What the interrupt pin shows for channel levels `(a, b)`.
    pub fn interrupt_line(&self, a: bool, b: bool) -> bool {
        match self.kind {
            EncoderKind::Quadrature | EncoderKind::OneChannel => a,
            EncoderKind::Xor => a ^ b,
        }
    }
}

/// The battery-level LEDs (thesis `Nivel_Bateria`), each lit by a high pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct LedWiring {
    pub green: Pin,
    pub blue: Pin,
    pub red: Pin,
}

/// One USART link: its number (0-3) and baud rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct UartWiring {
    pub usart: u8,
    pub baud: u32,
}

/// The battery's voltage divider into an ADC input.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BatteryWiring {
    /// ADC channel (0-15, pins A0-A15).
    pub adc: u8,
    /// Volts at the ADC pin per battery volt.
    pub divider: f64,
}

/// The whole robot's wiring.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Board {
    /// The MCU every pin is on.
    pub mcu: Mcu,
    pub driver: DriverKind,
    pub left_motor: MotorWiring,
    pub right_motor: MotorWiring,
    pub left_encoder: EncoderWiring,
    pub right_encoder: EncoderWiring,
    /// USART carrying the command link (Henrytwo: the HC-05 Bluetooth); the
    /// debug UART's on a board with one link.
    pub command_uart: UartWiring,
    /// USART carrying the debug/telemetry link (USB serial).
    pub debug_uart: UartWiring,
    /// The battery's divider into the ADC, on a board that measures it.
    pub battery: Option<BatteryWiring>,
    /// The battery LEDs, on a board that has them.
    pub battery_leds: Option<LedWiring>,
}

const fn pin(port: char, bit: u8, arduino: u8) -> Pin {
    Pin {
        port,
        bit,
        arduino: Some(arduino),
        mcu: Mcu::Atmega2560,
    }
}

const fn pwm(pin: Pin, timer: u8, channel: char) -> BridgeInput {
    BridgeInput {
        pin,
        pwm: Some(PwmSource { timer, channel }),
    }
}

/// Henrytwo as the thesis wires it (Annex A): encoders on D2-D5, the DRV8833
/// on D6-D9. `Adelante` drives D7 with the right wheel's PID and D9 with the
/// left's; `Inercia_Stop_Ad` brakes with D6 and D8: so D7/D6 are the right
/// motor's forward/reverse inputs and D9/D8 the left's.
pub const HENRYTWO: Board = Board {
    mcu: Mcu::Atmega2560,
    driver: DriverKind::Drv8833,
    right_motor: MotorWiring {
        pin1: pwm(pin('H', 4, 7), 4, 'B'),
        pin2: pwm(pin('H', 3, 6), 4, 'A'),
        pin3: None,
    },
    left_motor: MotorWiring {
        pin1: pwm(pin('H', 6, 9), 2, 'B'),
        pin2: pwm(pin('H', 5, 8), 4, 'C'),
        pin3: None,
    },
    left_encoder: EncoderWiring {
        kind: EncoderKind::Quadrature,
        a: pin('E', 4, 2),
        b: Some(pin('G', 5, 4)),
    },
    right_encoder: EncoderWiring {
        kind: EncoderKind::Quadrature,
        a: pin('E', 5, 3),
        b: Some(pin('E', 3, 5)),
    },
    command_uart: UartWiring {
        usart: 1,
        baud: 9600,
    },
    debug_uart: UartWiring {
        usart: 0,
        baud: 9600,
    },
    // 0.55 puts the thesis' LED thresholds (ADC 942 and 901 of 1023 at
    // 5 V) at a battery of 8.37 V and 8.01 V: a 2S LiPo full, half, low.
    battery: Some(BatteryWiring {
        adc: 0,
        divider: 0.55,
    }),
    // D10 green, D11 blue, D12 red (firmware/src/battery.rs).
    battery_leds: Some(LedWiring {
        green: pin('B', 4, 10),
        blue: pin('B', 5, 11),
        red: pin('B', 6, 12),
    }),
};

impl Default for Board {
    fn default() -> Self {
        HENRYTWO
    }
}

/// The encoder pins the bench's firmware builds read, left then right:
/// their INT4/INT5 handlers count channel A on D2/D3 and read B from D4/D5
/// (`firmware/src/board.rs`, which agrees with [`HENRYTWO`], tested), so
/// they cannot serve encoders wired elsewhere.
pub const FIRMWARE_ENCODERS: [EncoderWiring; 2] = [HENRYTWO.left_encoder, HENRYTWO.right_encoder];

/// "left A D2, B D4; right A D3, B D5" (a one-channel encoder's "A D2"
/// alone).
fn encoder_pins(e: [EncoderWiring; 2]) -> String {
    let one = |e: &EncoderWiring| {
        e.lines()
            .iter()
            .map(|(line, pin)| format!("{line} {}", pin.name()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!("left {}; right {}", one(&e[0]), one(&e[1]))
}

impl Board {
    /// Why the bench's firmware builds cannot serve this board: its
    /// encoders are not on [`FIRMWARE_ENCODERS`] (naming both sets of pins),
    /// or it lacks the separate command link, battery divider or LEDs the
    /// firmware drives; None when they can. A run would count no edge and
    /// end as "did not complete": a board check and every run of those
    /// builds refuse it first.
    pub fn firmware_encoder_mismatch(&self) -> Option<String> {
        let missing: Vec<&str> = [
            (self.command_uart == self.debug_uart, "[command_uart]"),
            (self.battery.is_none(), "[battery]"),
            (self.battery_leds.is_none(), "[leds]"),
        ]
        .into_iter()
        .filter_map(|(absent, what)| absent.then_some(what))
        .collect();
        if self.driver == DriverKind::Drv8838 {
            return Some(
                "the robust firmware drives no DRV8838 (phase high = reverse): give a \
                 pwm_dir driver, or run a firmware of your own (--tests)"
                    .into(),
            );
        }
        if !missing.is_empty() {
            return Some(format!(
                "the robust firmware drives a command link apart from the debug UART, a battery \
                 divider and battery LEDs; this board has no {}: add them, or run a firmware of \
                 your own (--tests)",
                missing.join(", ")
            ));
        }
        let ours = [self.left_encoder, self.right_encoder];
        (ours != FIRMWARE_ENCODERS).then(|| {
            format!(
                "the robust firmware reads its encoders on {} (its INT4/INT5 handlers); this \
                 board has them on {}: wire them there, or run a firmware of your own (--tests)",
                encoder_pins(FIRMWARE_ENCODERS),
                encoder_pins(ours)
            )
        })
    }

    /// The USARTs the board's links are on, each once: the debug UART's,
    /// then the command link's when that is another.
    pub fn link_usarts(&self) -> Vec<u8> {
        let mut v = vec![self.debug_uart.usart];
        if self.command_uart.usart != self.debug_uart.usart {
            v.push(self.command_uart.usart);
        }
        v
    }

    /// The board described by the TOML file at `path`, checked.
    pub fn load(path: impl AsRef<Path>) -> Result<Board, BoardError> {
        let path = path.as_ref();
        let text = input_file::read_text(path).map_err(|cause| BoardError::Read {
            path: path.display().to_string(),
            cause,
        })?;
        Board::from_toml_str(&text, &path.display().to_string())
    }

    /// The board described by `text`, checked; errors name `file`.
    pub fn from_toml_str(text: &str, file: &str) -> Result<Board, BoardError> {
        check::parse(text, file)
    }

    pub fn motor(&self, side: Side) -> &MotorWiring {
        match side {
            Side::Left => &self.left_motor,
            Side::Right => &self.right_motor,
        }
    }

    pub fn encoder(&self, side: Side) -> &EncoderWiring {
        match side {
            Side::Left => &self.left_encoder,
            Side::Right => &self.right_encoder,
        }
    }

    /// The board's serial links by their names (the board file's section
    /// names), in USART order: what reports call a USART's output.
    pub fn uarts(&self) -> Vec<(&'static str, UartWiring)> {
        let mut v = vec![
            ("debug_uart", self.debug_uart),
            ("command_uart", self.command_uart),
        ];
        v.sort_by_key(|(_, u)| u.usart);
        v
    }

    /// Every motor-driver input, in Arduino pin order.
    pub fn bridge_inputs(&self) -> Vec<BridgeInput> {
        let mut v: Vec<BridgeInput> = Side::BOTH
            .iter()
            .flat_map(|&s| self.motor(s).inputs())
            .collect();
        v.sort_by_key(|b| b.number());
        v
    }

    /// The timers driving the board's PWM inputs, in timer order.
    pub fn pwm_timers(&self) -> Vec<u8> {
        let mut v: Vec<u8> = self
            .bridge_inputs()
            .iter()
            .filter_map(|b| b.pwm.map(|s| s.timer))
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// The robust firmware's parameters that tell it this board's motor
    /// driver: its kind and each motor's pins 1-3 (Arduino numbers,
    /// [`NO_PIN`] where a kind has no third pin), as `protocol/README.md`
    /// (Parameters) defines them.
    pub fn firmware_params(&self) -> Vec<(Param, f32)> {
        let num = |b: Option<BridgeInput>| f32::from(b.map_or(NO_PIN, |b| b.number()));
        let (l, r) = (&self.left_motor, &self.right_motor);
        vec![
            (Param::DriverKind, f32::from(self.driver.wire_kind() as u8)),
            (Param::LeftPin1, num(Some(l.pin1))),
            (Param::LeftPin2, num(Some(l.pin2))),
            (Param::LeftPin3, num(l.pin3)),
            (Param::RightPin1, num(Some(r.pin1))),
            (Param::RightPin2, num(Some(r.pin2))),
            (Param::RightPin3, num(r.pin3)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn battery_leds_share_one_port() {
        let l = HENRYTWO.battery_leds.unwrap();
        assert!([l.blue.port, l.red.port].iter().all(|p| *p == l.green.port));
    }

    #[test]
    fn bridge_inputs_are_all_on_port_h_and_distinct() {
        let inputs = HENRYTWO.bridge_inputs();
        let arduino: Vec<u8> = inputs.iter().map(|b| b.number()).collect();
        assert_eq!(arduino, vec![6, 7, 8, 9]);
        assert!(inputs.iter().all(|b| b.pin.port == 'H'));
        assert_eq!(HENRYTWO.pwm_timers(), vec![2, 4]);
    }

    /// The thesis wires A to INT4/INT5 (D2, D3) and B to D4 (PG5) and D5
    /// (PE3, AIN1): the bench may raise B lazily only because of that.
    #[test]
    fn encoder_a_interrupts_and_b_cannot() {
        for side in [Side::Left, Side::Right] {
            let e = HENRYTWO.encoder(side);
            assert!(e.a.can_interrupt(), "{side:?} A");
            assert!(!e.b.unwrap().can_interrupt(), "{side:?} B");
        }
        let b = |side| HENRYTWO.encoder(side).b.unwrap();
        assert!(b(Side::Right).is_comparator_input());
        assert_eq!(b(Side::Left).pin_register(), 0x32); // PING
        assert_eq!(b(Side::Right).pin_register(), 0x2C); // PINE
    }

    /// Henrytwo's board is what the robust firmware assumes when nobody
    /// tells it otherwise.
    #[test]
    fn henrytwo_maps_to_the_firmwares_factory_defaults() {
        for (param, value) in HENRYTWO.firmware_params() {
            assert_eq!(value, param.factory_default(), "{param:?}");
        }
        assert_eq!(HENRYTWO.firmware_params().len(), 7);
    }

    /// Each kind's pins reach the firmware in the order its parameters
    /// name them.
    #[test]
    fn an_enable_and_two_directions_map_to_kind_1() {
        let dir = |arduino| BridgeInput {
            pin: Pin::arduino(Mcu::Atmega2560, arduino).unwrap(),
            pwm: None,
        };
        let mut b = HENRYTWO;
        b.driver = DriverKind::L298n;
        b.left_motor.pin2 = dir(22);
        b.left_motor.pin3 = Some(dir(23));
        let params = b.firmware_params();
        assert_eq!(params[0], (Param::DriverKind, 1.0));
        assert_eq!(params[1], (Param::LeftPin1, 9.0));
        assert_eq!(params[2], (Param::LeftPin2, 22.0));
        assert_eq!(params[3], (Param::LeftPin3, 23.0));
        assert_eq!(params[6], (Param::RightPin3, 255.0));
        b.driver = DriverKind::PwmDir;
        assert_eq!(b.firmware_params()[0], (Param::DriverKind, 2.0));
    }
}
