//! Hardware-in-the-loop bench for the firmware of differential-drive robots
//! on an ATmega2560 (reference robot: Henrytwo), as a library and as the
//! `hil` command line.
//!
//! The firmware's real ELF runs inside simavr ([`sim`]); the plant model
//! (`plant-model`) drives the MCU's encoder pins at the exact cycles at which
//! the physics says the edges happen, and sees the H-bridge inputs through the
//! bench's own model of the PWM timers ([`pwm`]), wired as the robot's
//! [`board`] says. [`bench`] ties them together on one event queue; [`line`] is
//! the straight-line test. [`station`] is the operator's side: the protocol
//! client for real and emulated robots, `hil serve` and the `hil ui` page.
//! Nothing in a run reads the host's clock: the same ELF, files and seed give
//! the same run, bit for bit.
//!
//! # Your own firmware tests
//!
//! [`harness`] is the bench for a `cargo test` of your own: build it from a
//! robot config, a board file and an ELF, send bytes over the Bluetooth
//! UART, run until a condition holds (a frame or bytes from the firmware, a
//! motor or pin state, a firmware variable, a pose: a scenario file's
//! [`scenario::Condition`]s), inject a fault ([`bench::Action`]) and assert
//! on the plant:
//!
//! ```
//! use hil::harness::{
//!     Action, Command, Condition, EncoderFault, Harness, Side, Test, NOTIFY_TEST_DONE,
//! };
//!
//! # fn main() -> Result<(), hil::harness::HarnessError> {
//! // The robust build on Henrytwo: the robot config and the board are the
//! // defaults (.robot(path), .board(path) for your own), seed 0.
//! let mut h = Harness::builder()
//!     .firmware(hil::paths::firmware_elf("robust"))
//!     .seed(0)
//!     .build()?;
//!
//! // A PING over the Bluetooth UART (h.send(&bytes) sends raw bytes): its
//! // reply is frame 0x81, within 50 ms of robot time.
//! h.boot()?;
//! h.command(&Command::Ping);
//! h.run_until(&Condition::frame(0x81), 0.05)?;
//!
//! // A 300 mm line, up to its TEST_DONE notice: the robot 300 mm on, to 1 %.
//! h.start(Test::Line, 300.0)?;
//! h.run_until(&Condition::frame(NOTIFY_TEST_DONE), 10.0)?;
//! let pose = h.pose();
//! assert!((pose.x().0.hypot(pose.y().0) - 300.0).abs() <= 3.0);
//!
//! // Another line, and the left encoder's cable off half a second into it:
//! // the firmware cuts both motors within 250 ms.
//! h.start(Test::Line, 600.0)?;
//! h.run_until(&Condition::driving_forward(0.05), 3.0)?;
//! h.run_for(0.5)?;
//! h.inject(Action::Encoder { side: Side::Left, fault: EncoderFault::Dropout });
//! h.run_until(&Condition::motors_off(), 0.25)?;
//! assert_eq!(h.motor_duty(), [0.0, 0.0]);
//! # Ok(()) }
//! ```
//!
//! A condition that does not hold in time is a [`harness::HarnessError::Timeout`]
//! naming it, the window and what the bench saw instead. `examples/firmware-test/`
//! is a crate of such tests; `hil test FILE...` runs the same conditions from
//! scenario files ([`scenario`]).

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
pub mod harness;
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
