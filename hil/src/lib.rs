//! Hardware-in-the-loop bench for the firmware of differential-drive robots
//! on AVR microcontrollers (reference robot: Henrytwo, an ATmega2560), as a
//! library and as the `hil` command line.
//!
//! The firmware's real ELF runs inside simavr; the plant model
//! (`plant-model`) drives the MCU's encoder pins at the exact cycles at which
//! the physics says the edges happen, and sees the H-bridge inputs through the
//! bench's own model of the PWM timers, wired as the robot's board says.
//! Nothing in a run reads the host's clock: the same ELF, files and seed give
//! the same run, bit for bit.
//!
//! The crate is read as rooms, each depending only on those above it in
//! this table:
//!
//! | room | what |
//! |---|---|
//! | [`mcu`] | the MCU side: simavr (the only FFI), the PWM timers' model, supply, cycle time |
//! | [`board`] | which MCU pin each robot signal is on, as data |
//! | [`firmware`] | the firmware under test: its ELF, bench variables, what it is told, its protocol, test descriptions |
//! | [`bench`](mod@bench) | one MCU wired to the plant on one event queue: drivers, edges, UARTs, power, faults, hangs, the gdb stub |
//! | [`output`] | files written whole, VCD traces, JUnit XML |
//! | [`runs`] | one pipeline per kind of run: experiments, the line, faults and scenarios, golden runs, timing, fuzzing, the gap, `hil bench` |
//! | [`clients`] | programs that drive a bench: the harness for your own tests, the operator's station |
//! | [`paths`] | default locations of the firmware ELFs and the fixtures |
//!
//! The `hil` command line (`src/cli/`) sits on top of all of them.
//!
//! # Your own firmware tests
//!
//! [`clients::harness`] is the bench for a `cargo test` of your own: build it from a
//! robot config, a board file and an ELF, send bytes over the Bluetooth
//! UART, run until a condition holds (a frame or bytes from the firmware, a
//! motor or pin state, a firmware variable, a pose: a scenario file's
//! [`runs::scenario::Condition`]s), inject a fault ([`bench::Action`]) and assert
//! on the plant:
//!
//! ```
//! use hil::clients::harness::{
//!     Action, Command, Condition, EncoderFault, Harness, Side, Test, NOTIFY_TEST_DONE,
//! };
//!
//! # fn main() -> Result<(), hil::clients::harness::HarnessError> {
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
//! A condition that does not hold in time is a [`clients::harness::HarnessError::Timeout`]
//! naming it, the window and what the bench saw instead. `examples/firmware-test/`
//! is a crate of such tests; `hil test FILE...` runs the same conditions from
//! scenario files ([`runs::scenario`]).

#![deny(unsafe_code)]

pub mod bench;
pub mod board;
pub mod clients;
pub mod firmware;
pub mod mcu;
pub mod output;
pub mod paths;
pub mod runs;
