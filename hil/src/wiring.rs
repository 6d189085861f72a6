//! The wiring table: which MCU pin each signal of the robot is on.
//!
//! Parts (the plant's encoders and H-bridge inputs) know only their own
//! signals; this table is the one place that names MCU pins, as the robot's
//! board does (firmware/src/board.rs names the same pins from the firmware's
//! side; a test checks that the two agree on the symbols the bench reads).

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
}
