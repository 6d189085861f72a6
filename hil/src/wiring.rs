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
}
