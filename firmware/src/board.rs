//! The Henrytwo robot on its Arduino Mega 2560: the clock and every pin the
//! robot wires, named once (Arduino number, port bit, role).
//!
//! Timer and baud values elsewhere are derived from [`CPU_HZ`] (stated in
//! `robot.rs`, which the host-side logic shares); no other file states the
//! clock.

use avr_device::atmega2560::{PORTB, PORTD, PORTE, PORTF, PORTG, PORTH, TC2, TC4};

use crate::hal::gpio::{Input, Pin, PB4, PB5, PB6, PD2, PD3, PE0, PE1, PE3, PE4, PE5, PF0, PG5, PH3, PH4, PH5, PH6};
use crate::hal::pwm::{self, Oc2b, Oc4a, Oc4b, Oc4c};
use crate::hal::usart::Baud;
use crate::motors::{HBridge, Motors};

pub use crate::robot::CPU_HZ;

/// HC-05 Bluetooth module on USART1 (configured for 9600 baud).
pub const BLUETOOTH_BAUD: Baud = Baud::new(CPU_HZ, 9600);
/// Debug/USB serial on USART0, 9600 baud like the thesis' `Serial.begin(9600)`.
pub const DEBUG_BAUD: Baud = Baud::new(CPU_HZ, 9600);

/// Left encoder channel A pin (D2, PE4).
pub type LeftEncoderA = PE4;
/// Left encoder channel B pin (D4, PG5).
pub type LeftEncoderB = PG5;
/// Right encoder channel A pin (D3, PE5).
pub type RightEncoderA = PE5;
/// Right encoder channel B pin (D5, PE3).
pub type RightEncoderB = PE3;

/// Every pin of the robot, in its reset state (input, no pull-up).
pub struct Pins {
    /// D2 (PE4, INT4): left encoder channel A; every edge interrupts.
    pub left_encoder_a: Pin<PE4, Input>,
    /// D4 (PG5): left encoder channel B; read in the INT4 handler for direction.
    pub left_encoder_b: Pin<PG5, Input>,
    /// D3 (PE5, INT5): right encoder channel A; every edge interrupts.
    pub right_encoder_a: Pin<PE5, Input>,
    /// D5 (PE3): right encoder channel B; read in the INT5 handler for direction.
    pub right_encoder_b: Pin<PE3, Input>,
    /// D6 (PH3, OC4A): DRV8833 input, right motor reverse.
    pub right_reverse: Pin<PH3, Input>,
    /// D7 (PH4, OC4B): DRV8833 input, right motor forward.
    pub right_forward: Pin<PH4, Input>,
    /// D8 (PH5, OC4C): DRV8833 input, left motor reverse.
    pub left_reverse: Pin<PH5, Input>,
    /// D9 (PH6, OC2B): DRV8833 input, left motor forward.
    pub left_forward: Pin<PH6, Input>,
    /// D0 (PE0, RXD0): debug serial receive (USB); taken over by USART0.
    pub debug_rx: Pin<PE0, Input>,
    /// D1 (PE1, TXD0): debug serial transmit (USB); taken over by USART0.
    pub debug_tx: Pin<PE1, Input>,
    /// D19 (PD2, RXD1): HC-05 TX -> MCU receive; taken over by USART1.
    pub bluetooth_rx: Pin<PD2, Input>,
    /// D18 (PD3, TXD1): MCU transmit -> HC-05 RX; taken over by USART1.
    pub bluetooth_tx: Pin<PD3, Input>,
    /// A0 (PF0, ADC0): battery voltage through a divider (analog input).
    pub battery_sense: Pin<PF0, Input>,
    /// D10 (PB4, OC2A, used as a plain output): green battery LED.
    pub led_green: Pin<PB4, Input>,
    /// D11 (PB5, OC1A, used as a plain output): blue battery LED.
    pub led_blue: Pin<PB5, Input>,
    /// D12 (PB6, OC1B, used as a plain output): red battery LED.
    pub led_red: Pin<PB6, Input>,
}

impl Pins {
    /// Hands out the pins; the port peripherals are taken by value so that no
    /// other code can create them again.
    pub fn new(_portb: PORTB, _portd: PORTD, _porte: PORTE, _portf: PORTF, _portg: PORTG, _porth: PORTH) -> Self {
        // SAFETY: the ports are consumed here, so each pin is created exactly
        // once for the life of the program.
        unsafe {
            Pins {
                left_encoder_a: Pin::new(),
                left_encoder_b: Pin::new(),
                right_encoder_a: Pin::new(),
                right_encoder_b: Pin::new(),
                right_reverse: Pin::new(),
                right_forward: Pin::new(),
                left_reverse: Pin::new(),
                left_forward: Pin::new(),
                debug_rx: Pin::new(),
                debug_tx: Pin::new(),
                bluetooth_rx: Pin::new(),
                bluetooth_tx: Pin::new(),
                battery_sense: Pin::new(),
                led_green: Pin::new(),
                led_blue: Pin::new(),
                led_red: Pin::new(),
            }
        }
    }
}

/// The robot's motors as wired (thesis `Adelante`, `Inercia_Stop_Ad`):
/// right forward D7 (OC4B), right reverse D6 (OC4A), left forward D9 (OC2B),
/// left reverse D8 (OC4C). The thesis build drives these compiled-in
/// channels; the robust build takes its wiring at run time
/// ([`crate::driver`], whose factory wiring is this one).
pub type DriveMotors = Motors<Oc4b, Oc4a, Oc2b, Oc4c>;

/// Makes D6..D9 outputs driving low, starts timers 4 and 2 in 8-bit
/// phase-correct PWM at clock/1 (31 372.55 Hz at 16 MHz, as the thesis sets
/// TCCR4B/TCCR2B), and wires the channels to the two H-bridges (all duties 0).
pub fn drive_motors<M6, M7, M8, M9>(
    tc4: TC4,
    tc2: TC2,
    d6_right_reverse: Pin<PH3, M6>,
    d7_right_forward: Pin<PH4, M7>,
    d8_left_reverse: Pin<PH5, M8>,
    d9_left_forward: Pin<PH6, M9>,
) -> DriveMotors {
    let t4 = pwm::timer4(
        tc4,
        d6_right_reverse.into_output_low(),
        d7_right_forward.into_output_low(),
        d8_left_reverse.into_output_low(),
    );
    let oc2b = pwm::timer2(tc2, d9_left_forward.into_output_low());
    Motors { right: HBridge::new(t4.b, t4.a), left: HBridge::new(oc2b, t4.c) }
}
