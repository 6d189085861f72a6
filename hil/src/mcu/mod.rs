//! The MCU side: simavr and what the bench models of the MCU itself.
//!
//! | where | what |
//! |---|---|
//! | `chip/` | each MCU as data ([`chip::Chip`]): names, memory, ports, every pin and what it can do, vectors, timers, USARTs |
//! | `sim/` | simavr, the only FFI ([`sim::Avr`], its memory, IRQs, callbacks); `sim/sys.rs` the one OS call. Every `unsafe` line of the crate is here |
//! | `pwm.rs`, `pwm/` | the bench's datasheet-exact model of the timers the board's PWM pins are on (simavr gets phase-correct PWM wrong) |
//! | `supply.rs` | the MCU's supply and its brown-out detector, which simavr does not model |
//! | `clock.rs` | emulated time: a CPU clock and cycle counts, with exact conversions |
//!
//! Nothing here knows the robot: the board (`crate::board`) says which pin
//! is what, and the bench (`crate::bench`) wires the MCU to the plant.

pub mod chip;
pub mod clock;
pub mod pwm;
#[allow(unsafe_code)]
pub mod sim;
pub mod supply;
