//! The bench for a user's own `cargo test`: build it from a robot, a board,
//! an ELF and, for a firmware without the bench interface, its test
//! description (each a file or a value), talk to the firmware over its
//! serial links, start its tests, run until a condition holds, inject a
//! fault, look at the plant and assert.
//!
//! The crate docs ([`crate`]) show a worked example; `examples/firmware-test/`
//! is a crate of such tests.
//!
//! A [`Harness`] is a [`Bench`] with the host's side played by the test:
//! nothing happens between calls, and every call runs in robot time (the
//! same inputs and seed give the same run, bit for bit, however the test
//! splits it into calls). The conditions are a scenario file's
//! ([`Condition`], the table in [`crate::runs::scenario`]), judged at the run
//! loop's checks (every [`crate::bench::CHECK_PERIOD_S`] of robot time);
//! the faults are the bench's [`Action`]s. Errors are [`HarnessError`]s,
//! one line each, so a test can end in `?` or `.unwrap()` and still say
//! what went wrong; the `assert_` methods panic at the test's line with
//! what the bench saw.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | [`Harness`]: running, the host's side, what the test looks at |
//! | `builder.rs` | [`HarnessBuilder`]: the inputs, files or values ([`Source`]), the seed |
//! | `start.rs` | boot and start: through the description, the protocol or the thesis build's selector |
//! | `asserts.rs` | `#[track_caller]` asserts naming what was seen |
//! | `conditions.rs` | short constructors of [`Condition`] (`Condition::frame`, `Condition::motors_off`, ...) |
//! | `vars.rs` | [`Var`]: firmware variables read as their Rust types |
//! | `until.rs` | a condition judged live, for [`Harness::run_until`] |
//! | `error.rs` | [`HarnessError`] |

use std::sync::Arc;

use crate::bench::Bench;
use crate::runs::scenario::judge::motor_state;

mod asserts;
mod builder;
mod conditions;
mod error;
mod start;
mod until;
mod vars;

pub use self::builder::{HarnessBuilder, Source};
pub use self::error::HarnessError;
pub use self::start::IntoTestName;
pub use self::vars::Var;
// What a test names, re-exported from where each is defined, so that a
// test crate needs `hil::clients::harness` alone.
pub use crate::bench::inject::{Channel, EncoderFault, LinkFault};
pub use crate::bench::{Action, ScheduledFault, Trigger};
pub use crate::board::Board;
pub use crate::firmware::description::{Description, TestName};
pub use crate::firmware::elf::Firmware;
pub use crate::firmware::link::{frame, Command, CommandId, FrameId, Param, Received};
pub use crate::runs::experiment::{Test, TestRun};
pub use crate::runs::scenario::{Condition, Direction, Level, MotorSides, MotorState, VarType};
pub use henrytwo_protocol::{NOTIFY_FAULT, NOTIFY_TEST_DONE, REPLY_FLAG, VERSION};
pub use plant_model::{Millimetres, MotorFault, Pose, Radians, RobotConfig, Side, World};

/// A bench under a test's control (see the module docs).
pub struct Harness {
    bench: Bench,
    robot: RobotConfig,
    description: Option<Arc<Description>>,
    /// The test [`Harness::start`] started last, for [`Harness::run_until_done`].
    started: Option<start::Started>,
    /// Booted: ready for a test ([`Harness::boot`]).
    ready: bool,
}

impl Harness {
    /// Start describing a harness: `Harness::builder().firmware(elf).build()?`.
    pub fn builder() -> HarnessBuilder {
        HarnessBuilder::default()
    }

    /// Send bytes to the firmware on the board's command link (the
    /// Bluetooth UART), paced at its baud rate from now on.
    pub fn send(&mut self, bytes: &[u8]) {
        let uart = self.bench.board().command_uart.usart;
        self.bench.send(uart, bytes);
    }

    /// Send bytes (or text: `b"g"`) to the firmware on USART `usart` (0-3,
    /// or [`crate::bench::USB_SERIAL`] on an MCU with USB), paced at the
    /// board's baud rate for it.
    pub fn send_to(&mut self, usart: u8, bytes: &[u8]) {
        self.bench.send(usart, bytes);
    }

    /// What the firmware sent on USART `usart` since reset, as text (an
    /// invalid byte as U+FFFD): a sketch's `Serial.print`s.
    pub fn text(&self, usart: u8) -> String {
        String::from_utf8_lossy(self.bench.uart_output(usart)).into_owned()
    }

    /// Send a command of the framed protocol (`protocol/README.md`).
    pub fn command(&mut self, command: &Command) {
        self.send(&frame(command));
    }

    /// Send `command` and run until its reply comes, for at most
    /// `within_s` of robot time: the reply, whatever its status (an error
    /// reply is the firmware's answer, not the harness's error).
    pub fn request(&mut self, command: &Command, within_s: f64) -> Result<Received, HarnessError> {
        check_time("request within_s", within_s)?;
        let before = self.output().len();
        self.command(command);
        let id = FrameId::Reply(command.id());
        self.run_until(&Condition::frame(id), within_s)?;
        Ok(crate::firmware::link::replies(&self.output()[before..])
            .into_iter()
            .find(|r| r.frame_id() == id)
            .expect("the reply the wait just saw"))
    }

    /// The value of `param` in the firmware, by GET_PARAM (within 100 ms
    /// of robot time); an error reply is [`HarnessError::Refused`].
    pub fn param(&mut self, param: Param) -> Result<f32, HarnessError> {
        let reply = self.request(&Command::GetParam(param), 0.1)?;
        match reply.data.get(1..5) {
            Some(b) if reply.ok => Ok(f32::from_le_bytes(b.try_into().expect("4 bytes"))),
            _ => Err(HarnessError::Refused {
                command: format!("GET_PARAM {param:?}"),
                reply: format!("{reply:?}"),
            }),
        }
    }

    /// Set `param` to `value` by SET_PARAM (its reply within 100 ms of
    /// robot time): the value the firmware stored; an error reply (out of
    /// range, ...) is [`HarnessError::Refused`].
    pub fn set_param(&mut self, param: Param, value: f32) -> Result<f32, HarnessError> {
        let reply = self.request(&Command::SetParam(param, value), 0.1)?;
        match reply.data.get(1..5) {
            Some(b) if reply.ok => Ok(f32::from_le_bytes(b.try_into().expect("4 bytes"))),
            _ => Err(HarnessError::Refused {
                command: format!("SET_PARAM {param:?} = {value}"),
                reply: format!("{reply:?}"),
            }),
        }
    }

    /// Run for `seconds` of robot time (more than 0, at most a day).
    pub fn run_for(&mut self, seconds: f64) -> Result<(), HarnessError> {
        check_time("run_for seconds", seconds)?;
        Ok(self.bench.run_for(seconds)?)
    }

    /// Run until `condition` holds, for at most `within_s` of robot time
    /// (more than 0, at most a day): Ok(the robot time it held at), else
    /// [`HarnessError::Timeout`] with what was seen instead. Bytes and
    /// frames count from now on; a state (motors, pin, variable, pose) may
    /// already hold at the first check. The plant is at the current cycle
    /// on return.
    pub fn run_until(&mut self, condition: &Condition, within_s: f64) -> Result<f64, HarnessError> {
        check_time("run_until within_s", within_s)?;
        let mut probe = until::Probe::new(condition, &self.bench)
            .map_err(|message| HarnessError::Condition { message })?;
        let from_s = self.bench.robot_time_s();
        if self.bench.run_until(within_s, |b| probe.holds(b))? {
            return Ok(self.bench.robot_time_s());
        }
        Err(HarnessError::Timeout {
            what: probe.what(),
            within_s,
            from_s,
            to_s: self.bench.robot_time_s(),
            seen: probe.seen,
        })
    }

    /// Apply a fault now (its robot time is in [`Harness::applied`] once
    /// the bench has run on).
    pub fn inject(&mut self, action: Action) {
        let now = self.bench.robot_time_s();
        self.bench.schedule(Trigger::Time { s: now }, action, None);
    }

    /// Arm a fault for later: at a robot time, a leg's or turn's start, a
    /// host byte; undone after its duration when it has one.
    pub fn schedule(&mut self, fault: ScheduledFault) {
        self.bench.schedule(fault.trigger, fault.action, fault.undo);
    }

    /// The faults applied so far: (robot time s, action).
    pub fn applied(&self) -> Vec<(f64, Action)> {
        let clock = self.bench.clock();
        self.bench
            .core()
            .applied()
            .iter()
            .map(|(c, a)| (clock.seconds(*c).0, a.clone()))
            .collect()
    }

    /// Robot time since reset, in seconds.
    pub fn robot_time_s(&self) -> f64 {
        self.bench.robot_time_s()
    }

    /// The plant's pose: millimetres and radians, the origin and heading 0
    /// where the robot stood at reset, x along its first heading.
    pub fn pose(&self) -> Pose<World> {
        self.bench.core().robot().pose()
    }

    /// Each motor's drive duty from its bridge inputs, (left, right), a
    /// fraction of the PWM period: positive forward, negative reverse, 0
    /// when not driven.
    pub fn motor_duty(&self) -> [f64; 2] {
        [Side::Left, Side::Right].map(|s| until::drive_duty(&self.bench, s))
    }

    /// The state of `side`'s motor from its bridge inputs.
    pub fn motor_state(&self, side: Side) -> MotorState {
        let (a, b) = self.bench.core().robot().bridge_inputs(side);
        motor_state((a.get(), b.get())).0
    }

    /// Every frame the firmware sent on the command link so far, decoded
    /// (bytes outside frames skipped).
    pub fn frames(&self) -> Vec<Received> {
        crate::firmware::link::replies(self.output())
    }

    /// The bytes the firmware sent on the command link so far.
    pub fn output(&self) -> &[u8] {
        self.bench
            .uart_output(self.bench.board().command_uart.usart)
    }

    /// The firmware variable `symbol` (an ELF data symbol of `T`'s size),
    /// read as `T`: `h.var::<u8>("HT_FAULT")?`, `h.var::<i32>("leftCount")?`.
    pub fn var<T: Var>(&self, symbol: &str) -> Result<T, HarnessError> {
        let addr = self.bench.firmware().variable(symbol, T::TYPE.size())?;
        Ok(T::from_bytes(until::read_bytes(&self.bench, addr, T::TYPE)))
    }

    /// The test description the harness runs the firmware by, if any.
    pub fn description(&self) -> Option<&Description> {
        self.description.as_deref()
    }

    /// The robot config the plant runs.
    pub fn robot(&self) -> &RobotConfig {
        &self.robot
    }

    /// The bench underneath, for what the harness does not cover (pins,
    /// traces, the MCU).
    pub fn bench(&self) -> &Bench {
        &self.bench
    }

    pub fn bench_mut(&mut self) -> &mut Bench {
        &mut self.bench
    }
}

fn check_time(what: &'static str, value: f64) -> Result<(), HarnessError> {
    if value.is_finite() && value > 0.0 && value <= crate::runs::scenario::MAX_ROBOT_TIME_S {
        Ok(())
    } else {
        Err(HarnessError::Time { what, value })
    }
}
