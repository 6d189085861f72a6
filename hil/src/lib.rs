//! Hardware-in-the-loop bench for the Henrytwo robot.
//!
//! The firmware's real ELF runs inside simavr ([`sim`]); the plant model
//! (`plant-model`) drives the MCU's encoder pins at the exact cycles at which
//! the physics says the edges happen, and sees the H-bridge inputs through the
//! bench's own model of the PWM timers ([`pwm`]), wired as the robot's
//! [`board`] says. [`bench`] ties them together on one event queue; [`line`] is
//! the straight-line test. [`station`] is the operator's side: the protocol
//! client for real and emulated robots, `hil serve` and the `hil ui` page.

#![deny(unsafe_code)]

pub mod bench;
pub mod board;
pub mod calibrate;
pub mod description;
pub mod elf;
pub mod experiment;
pub mod experiments;
pub mod faults;
pub mod firmware_params;
pub mod fuzz;
pub mod fwvars;
pub mod gap_bench;
pub mod gdb;
pub mod golden;
pub mod hang;
pub mod inject;
pub mod junit;
pub mod line;
pub mod link;
pub mod output;
pub mod paths;
pub mod perf;
pub mod pwm;
pub mod report;
pub mod scenario;
#[allow(unsafe_code)]
pub mod sim;
pub mod station;
pub mod supply;
#[allow(unsafe_code)]
mod sys;
pub mod time;
pub mod timing;
pub mod vcd;
pub mod wiring;

/// The experiments' former path (`hil::umbmark::Plan`), kept for callers.
pub use experiments as umbmark;
