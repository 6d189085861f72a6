//! The wiring table: which MCU pin each signal of the robot is on.
//!
//! Parts (the plant's encoders and H-bridge inputs) know only their own
//! signals; this table is the one place that names MCU pins, as the robot's
//! board does (firmware/src/board.rs names the same pins from the firmware's
//! side; `board_rs_names_the_same_pins` below checks that the two agree:
//! every pin, its Arduino number, the PWM channel on each bridge input and
//! the two USARTs).

use plant_model::Side;

/// An MCU pin: IO port letter and bit, with its Arduino Mega number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Pin {
    pub port: char,
    pub bit: u8,
    pub arduino: u8,
}

impl Pin {
    /// Data-space address of the pin's PIN register (ATmega2560 datasheet,
    /// register summary): ports A-G in the low IO space, H-L in extended IO.
    pub fn pin_register(&self) -> u16 {
        match self.port {
            'A' => 0x20,
            'B' => 0x23,
            'C' => 0x26,
            'D' => 0x29,
            'E' => 0x2C,
            'F' => 0x2F,
            'G' => 0x32,
            'H' => 0x100,
            'J' => 0x103,
            'K' => 0x106,
            'L' => 0x109,
            p => panic!("the ATmega2560 has no port {p}"),
        }
    }

    /// Whether a level change on this pin can start something in the
    /// ATmega2560 by itself, however the firmware configures it: an external
    /// interrupt (INT0-7), a pin-change interrupt (PCINT0-23), an input
    /// capture (ICP1/3/4/5), a counter or asynchronous clock input
    /// (T0/1/3/4/5, TOSC1/2), a USART clock input (XCK0-3), SPI or TWI. The
    /// analog comparator's inputs are separate ([`Pin::is_comparator_input`]).
    pub fn can_interrupt(&self) -> bool {
        match (self.port, self.bit) {
            ('B', _) | ('K', _) => true, // PCINT0-7, PCINT16-23 (and SPI on B0-3)
            ('D', 0..=7) => true,        // INT0-3, XCK1, ICP1, T1, T0
            ('E', 0) | ('E', 2) | ('E', 4..=7) => true, // PCINT8, XCK0, INT4-7, T3, ICP3
            ('G', 3) | ('G', 4) => true, // TOSC2, TOSC1
            ('H', 2) | ('H', 7) => true, // XCK2, T4
            ('J', 0..=6) => true,        // PCINT9-15, XCK3
            ('L', 0..=2) => true,        // ICP4, ICP5, T5
            _ => false,
        }
    }

    /// AIN0 (PE2) or AIN1 (PE3): the analog comparator can interrupt or
    /// capture on it when ACSR enables that.
    pub fn is_comparator_input(&self) -> bool {
        matches!((self.port, self.bit), ('E', 2) | ('E', 3))
    }
}

/// Which timer channel can drive a pin with PWM.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum PwmSource {
    Timer2(char),
    Timer4(char),
}

/// One H-bridge input: its pin and its PWM channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct BridgeInput {
    pub pin: Pin,
    pub pwm: PwmSource,
}

/// One motor's two DRV8833 inputs: IN1 high drives the robot forward.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct MotorWiring {
    pub forward: BridgeInput,
    pub reverse: BridgeInput,
}

/// One encoder's two channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct EncoderWiring {
    pub a: Pin,
    pub b: Pin,
}

/// The battery-level LEDs (thesis `Nivel_Bateria`), each lit by a high pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct LedWiring {
    pub green: Pin,
    pub blue: Pin,
    pub red: Pin,
}

/// The whole robot's wiring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Wiring {
    pub left_motor: MotorWiring,
    pub right_motor: MotorWiring,
    pub left_encoder: EncoderWiring,
    pub right_encoder: EncoderWiring,
    /// USART carrying the Bluetooth (HC-05) link.
    pub bluetooth_uart: u8,
    /// USART carrying the debug/telemetry link (USB serial).
    pub debug_uart: u8,
    pub battery_leds: LedWiring,
}

const fn pin(port: char, bit: u8, arduino: u8) -> Pin {
    Pin { port, bit, arduino }
}

/// Henrytwo as the thesis wires it (Annex A): encoders on D2-D5, the DRV8833
/// on D6-D9. `Adelante` drives D7 with the right wheel's PID and D9 with the
/// left's; `Inercia_Stop_Ad` brakes with D6 and D8: so D7/D6 are the right
/// motor's forward/reverse inputs and D9/D8 the left's.
pub const HENRYTWO: Wiring = Wiring {
    right_motor: MotorWiring {
        forward: BridgeInput {
            pin: pin('H', 4, 7),
            pwm: PwmSource::Timer4('B'),
        },
        reverse: BridgeInput {
            pin: pin('H', 3, 6),
            pwm: PwmSource::Timer4('A'),
        },
    },
    left_motor: MotorWiring {
        forward: BridgeInput {
            pin: pin('H', 6, 9),
            pwm: PwmSource::Timer2('B'),
        },
        reverse: BridgeInput {
            pin: pin('H', 5, 8),
            pwm: PwmSource::Timer4('C'),
        },
    },
    left_encoder: EncoderWiring {
        a: pin('E', 4, 2),
        b: pin('G', 5, 4),
    },
    right_encoder: EncoderWiring {
        a: pin('E', 5, 3),
        b: pin('E', 3, 5),
    },
    bluetooth_uart: 1,
    debug_uart: 0,
    // D10 green, D11 blue, D12 red (firmware/src/battery.rs).
    battery_leds: LedWiring {
        green: pin('B', 4, 10),
        blue: pin('B', 5, 11),
        red: pin('B', 6, 12),
    },
};

impl Wiring {
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

    /// All four bridge inputs, in Arduino pin order (D6..D9).
    pub fn bridge_inputs(&self) -> [BridgeInput; 4] {
        let mut v = [
            self.right_motor.reverse,
            self.right_motor.forward,
            self.left_motor.reverse,
            self.left_motor.forward,
        ];
        v.sort_by_key(|b| b.pin.arduino);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn battery_leds_share_one_port() {
        let l = HENRYTWO.battery_leds;
        assert!([l.blue.port, l.red.port].iter().all(|p| *p == l.green.port));
    }

    #[test]
    fn bridge_inputs_are_all_on_port_h_and_distinct() {
        let inputs = HENRYTWO.bridge_inputs();
        let arduino: Vec<u8> = inputs.iter().map(|b| b.pin.arduino).collect();
        assert_eq!(arduino, vec![6, 7, 8, 9]);
        assert!(inputs.iter().all(|b| b.pin.port == 'H'));
    }

    /// The thesis wires A to INT4/INT5 (D2, D3) and B to D4 (PG5) and D5
    /// (PE3, AIN1): the bench may raise B lazily only because of that.
    #[test]
    fn encoder_a_interrupts_and_b_cannot() {
        for side in [Side::Left, Side::Right] {
            let e = HENRYTWO.encoder(side);
            assert!(e.a.can_interrupt(), "{side:?} A");
            assert!(!e.b.can_interrupt(), "{side:?} B");
        }
        assert!(HENRYTWO.encoder(Side::Right).b.is_comparator_input());
        assert_eq!(HENRYTWO.encoder(Side::Left).b.pin_register(), 0x32); // PING
        assert_eq!(HENRYTWO.encoder(Side::Right).b.pin_register(), 0x2C); // PINE
    }

    /// One pin field of board.rs's `Pins`: its doc line
    /// `/// D<n> (P<port><bit>, ALT...): role` and its type `Pin<P<port><bit>, ..>`.
    #[derive(Debug)]
    struct BoardPin {
        doc_arduino: u8,
        doc_pin: String,
        doc_alt: Vec<String>,
        type_pin: String,
    }

    /// The pin fields of the firmware's board.rs, by field name.
    fn board_pins(text: &str) -> std::collections::BTreeMap<String, BoardPin> {
        let mut out = std::collections::BTreeMap::new();
        let mut doc: Option<&str> = None;
        for line in text.lines().map(str::trim) {
            if let Some(d) = line.strip_prefix("/// ") {
                doc = Some(d);
                continue;
            }
            let field = line
                .strip_prefix("pub ")
                .and_then(|l| l.split_once(": Pin<"))
                .filter(|(name, _)| !name.contains(' '));
            if let (Some((name, ty)), Some(d)) = (field, doc) {
                // "D6 (PH3, OC4A): ..." ("A0 (PF0, ADC0)" is analog: no D number).
                let (head, _) = d.split_once("):").expect("a pin's doc names it");
                let (num, pins) = head.split_once(" (").expect("D<n> (P..");
                let mut parts = pins.split(", ").map(str::to_string);
                let doc_pin = parts.next().unwrap();
                out.insert(
                    name.to_string(),
                    BoardPin {
                        doc_arduino: num
                            .strip_prefix('D')
                            .map_or(u8::MAX, |n| n.parse().unwrap()),
                        doc_pin,
                        doc_alt: parts.collect(),
                        type_pin: ty.split(',').next().unwrap().to_string(),
                    },
                );
            }
            doc = None;
        }
        out
    }

    fn port_bit(p: &Pin) -> String {
        format!("P{}{}", p.port, p.bit)
    }

    fn pwm_name(p: PwmSource) -> String {
        match p {
            PwmSource::Timer2(c) => format!("OC2{c}"),
            PwmSource::Timer4(c) => format!("OC4{c}"),
        }
    }

    /// The firmware's board.rs and this table name the same pins: each
    /// signal's field in `Pins` has the table's port and bit in its type and
    /// its doc, and the table's Arduino number; each bridge input's doc and
    /// `DriveMotors` (right forward, right reverse, left forward, left
    /// reverse) name the table's PWM channel; the Bluetooth and debug links
    /// are on the table's USARTs.
    #[test]
    fn board_rs_names_the_same_pins() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../firmware/src/board.rs");
        let text = std::fs::read_to_string(path).expect("firmware/src/board.rs");
        let board = board_pins(&text);
        let w = HENRYTWO;
        let pins = [
            ("left_encoder_a", w.left_encoder.a),
            ("left_encoder_b", w.left_encoder.b),
            ("right_encoder_a", w.right_encoder.a),
            ("right_encoder_b", w.right_encoder.b),
            ("right_forward", w.right_motor.forward.pin),
            ("right_reverse", w.right_motor.reverse.pin),
            ("left_forward", w.left_motor.forward.pin),
            ("left_reverse", w.left_motor.reverse.pin),
            ("led_green", w.battery_leds.green),
            ("led_blue", w.battery_leds.blue),
            ("led_red", w.battery_leds.red),
        ];
        for (name, pin) in pins {
            let b = board
                .get(name)
                .unwrap_or_else(|| panic!("board.rs has no pin {name}: {board:#?}"));
            assert_eq!(b.type_pin, port_bit(&pin), "{name}: type");
            assert_eq!(b.doc_pin, port_bit(&pin), "{name}: doc");
            assert_eq!(b.doc_arduino, pin.arduino, "{name}: Arduino number");
        }
        let bridge = [
            ("right_forward", w.right_motor.forward),
            ("right_reverse", w.right_motor.reverse),
            ("left_forward", w.left_motor.forward),
            ("left_reverse", w.left_motor.reverse),
        ];
        for (name, input) in bridge {
            assert!(
                board[name].doc_alt.contains(&pwm_name(input.pwm)),
                "{name}: board.rs says {:?}, the table {}",
                board[name].doc_alt,
                pwm_name(input.pwm)
            );
        }
        let drive = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("pub type DriveMotors = Motors<"))
            .expect("board.rs defines DriveMotors");
        let channels: Vec<String> = drive
            .trim_end_matches(">;")
            .split(", ")
            .map(str::to_uppercase)
            .collect();
        let table: Vec<String> = bridge.iter().map(|(_, i)| pwm_name(i.pwm)).collect();
        assert_eq!(channels, table, "DriveMotors<RF, RR, LF, LR>");
        for (name, uart) in [
            ("bluetooth_rx", w.bluetooth_uart),
            ("bluetooth_tx", w.bluetooth_uart),
            ("debug_rx", w.debug_uart),
            ("debug_tx", w.debug_uart),
        ] {
            let dir = if name.ends_with("rx") { "RXD" } else { "TXD" };
            assert!(
                board[name].doc_alt.contains(&format!("{dir}{uart}")),
                "{name}: board.rs says {:?}, the table USART{uart}",
                board[name].doc_alt
            );
        }
    }
}
