//! The parts of the Arduino AVR core (1.6.x and later, `wiring.c`, `Print.cpp`,
//! `HardwareSerial.cpp`) the thesis firmware relies on, for the thesis build:
//! - [`time`]: timer 0 as Arduino's `init()` sets it (fast PWM, clk/64,
//!   overflow interrupt) with `millis()`, `micros()` and `delay()` computed
//!   exactly as Arduino computes them;
//! - [`print`]: `Serial.print`/`println` of strings, integers and floats
//!   (two decimals), byte by byte through a blocking write that waits, like
//!   `HardwareSerial::write`, while 63 bytes are queued.
//!
//! `analogRead` is `hal::adc::Adc::read_blocking`, `analogWrite` on the motor
//! pins is `hal::pwm` (same semantics: 0 low, 255 high, else PWM) and the
//! LEDs are plain digital writes (`battery::Leds`).

pub mod print;
pub mod time;
