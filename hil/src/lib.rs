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
//! robot, a board, an ELF and, for a firmware without the bench interface (an Arduino
//! sketch), its test description, each a file or a value; send bytes or commands,
//! start a test, run until a condition holds (a frame or bytes from the firmware, a
//! motor or pin state, a firmware variable, a pose: a scenario file's
//! [`runs::scenario::Condition`]s), inject a fault ([`bench::Action`]) and assert
//! on the plant:
//!
//! ```
//! use hil::clients::harness::{
//!     Action, CommandId, Condition, EncoderFault, FrameId, Harness, Side, Test,
//! };
//!
//! # fn main() -> Result<(), hil::clients::harness::HarnessError> {
//! // The robust build on Henrytwo: the robot config and the board are the
//! // defaults (.robot(..), .board(..) for your own, a path or a value), seed 0.
//! let mut h = Harness::builder()
//!     .firmware(hil::paths::firmware_elf("robust"))
//!     .seed(0)
//!     .build()?;
//!
//! // A PING over the Bluetooth UART: its reply within 50 ms of robot time.
//! h.boot()?;
//! let reply = h.request(&hil::clients::harness::Command::Ping, 0.05)?;
//! assert_eq!(reply.frame_id(), FrameId::Reply(CommandId::Ping));
//!
//! // A 300 mm line (its leg told over the protocol), up to its TEST_DONE
//! // notice: the robot 300 mm on, to 1 %.
//! h.start(Test::Line, 300.0)?;
//! h.assert_within(&Condition::frame(FrameId::TestDone), 10.0);
//! h.assert_distance(300.0, 3.0);
//! assert!(h.pose().x() > hil::clients::harness::Millimetres(290.0));
//!
//! // Another line, and the left encoder's cable off half a second into it:
//! // the firmware cuts both motors within 250 ms and sets its fault code.
//! h.start(Test::Line, 600.0)?;
//! h.run_until(&Condition::driving_forward(0.05), 3.0)?;
//! h.run_for(0.5)?;
//! h.inject(Action::Encoder { side: Side::Left, fault: EncoderFault::Dropout });
//! h.assert_within(&Condition::motors_off(), 0.25);
//! assert_ne!(h.var::<u8>("HT_FAULT")?, 0);
//! # Ok(()) }
//! ```
//!
//! A described sketch starts the same way, through its description (no
//! variable of the bench's own builds needed):
//!
//! ```
//! use hil::clients::harness::{Harness, RobotConfig};
//!
//! # fn main() -> Result<(), hil::clients::harness::HarnessError> {
//! let root = hil::paths::workspace_root();
//! let robot = RobotConfig::load(root.join("fixtures/robots/uno-l298n.toml")).unwrap();
//! let mut h = Harness::builder()
//!     .tests(root.join("fixtures/arduino/uno-l298n/tests.toml")) // names its ELF
//!     .board(root.join("fixtures/boards/uno-l298n.toml"))
//!     .robot(robot) // a value: edit it first if the test needs to
//!     .build()?;
//! h.start("leg-and-spin", None)?; // boots on "uno-l298n ready", sends 'g' on Serial
//! h.run_until_done(60.0)?;        // its end: the text "done"
//! assert!(h.text(0).contains("done"));
//! assert!(h.var::<i32>("rightCount")? > 2821); // its 1 m leg and the spin
//! # Ok(()) }
//! ```
//!
//! A condition that does not hold in time is a [`clients::harness::HarnessError::Timeout`]
//! naming it, the window and what the bench saw instead; the `assert_` methods panic with
//! the same, at the test's line. `examples/firmware-test/` is a crate of such tests;
//! `hil test FILE...` runs the same conditions from scenario files ([`runs::scenario`]).

#![deny(unsafe_code)]

pub mod bench;
pub mod board;
pub mod clients;
pub mod firmware;
pub mod mcu;
pub mod output;
pub mod paths;
pub mod runs;
