//! The bench for a user's own `cargo test`: build it from a robot config, a
//! board file and an ELF, talk to the firmware over its Bluetooth UART, run
//! until a condition holds, inject a fault, look at the plant and assert.
//!
//! The crate docs ([`crate`]) show a worked example; `examples/firmware-test/`
//! is a crate of such tests.
//!
//! A [`Harness`] is a [`Bench`] with the host's side played by the test:
//! nothing happens between calls, and every call runs in robot time (the
//! same files and seed give the same run, bit for bit, however the test
//! splits it into calls). The conditions are a scenario file's
//! ([`Condition`], the table in [`crate::runs::scenario`]), judged at the run
//! loop's checks (every [`crate::bench::CHECK_PERIOD_S`] of robot time);
//! the faults are the bench's [`Action`]s. Errors are [`HarnessError`]s,
//! one line each, so a test can end in `?` or `.unwrap()` and still say
//! what went wrong.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | [`Harness`]: running, the host's side, what the test looks at |
//! | `builder.rs` | [`HarnessBuilder`]: the files, the seed |
//! | `conditions.rs` | short constructors of [`Condition`] (`Condition::frame`, `Condition::motors_off`, ...) |
//! | `until.rs` | a condition judged live, for [`Harness::run_until`] |
//! | `error.rs` | [`HarnessError`] |

use plant_model::RobotConfig;

use crate::bench::Bench;
use crate::runs::scenario::judge::motor_state;

mod builder;
mod conditions;
mod error;
mod until;

pub use self::builder::HarnessBuilder;
pub use self::error::HarnessError;
// What a test names, re-exported from where each is defined, so that a
// test crate needs `hil::clients::harness` alone.
pub use crate::bench::inject::{Channel, EncoderFault, LinkFault};
pub use crate::bench::{Action, ScheduledFault, Trigger};
pub use crate::firmware::link::{frame, Command, Param, Received};
pub use crate::runs::experiment::Test;
pub use crate::runs::scenario::{Condition, Direction, Level, MotorSides, MotorState, VarType};
pub use henrytwo_protocol::{NOTIFY_FAULT, NOTIFY_TEST_DONE, REPLY_FLAG, VERSION};
pub use plant_model::{MotorFault, Pose, Side, World};

/// A bench under a test's control (see the module docs).
pub struct Harness {
    bench: Bench,
    robot: RobotConfig,
}

impl Harness {
    /// Start describing a harness: `Harness::builder().firmware(elf).build()?`.
    pub fn builder() -> HarnessBuilder {
        HarnessBuilder::default()
    }

    /// Run until the firmware reports idle after reset (`HT_STATE` = 1,
    /// within 2 s of robot time): ready for a command. Needs the bench
    /// interface of this repository's builds.
    pub fn boot(&mut self) -> Result<(), HarnessError> {
        if !self.bench.is_idle() {
            crate::runs::start::wait_ready(&mut self.bench, None)?;
        }
        Ok(())
    }

    /// Start `test` as `hil run` does: boot if not yet idle, set the leg
    /// length (10 to 5000 mm), tell a firmware that takes parameters the
    /// robot's geometry over the protocol, then send the start command (a
    /// framed START_TEST to a firmware that speaks the protocol, else the
    /// thesis build's selector byte). Returns at once: run the test with
    /// [`Harness::run_until`].
    pub fn start(&mut self, test: Test, leg_mm: f64) -> Result<(), HarnessError> {
        let r = Param::LegLengthMm.range();
        if Param::LegLengthMm.check(leg_mm as f32).is_err() || !leg_mm.is_finite() {
            return Err(HarnessError::Leg {
                leg_mm,
                min: r.min,
                max: r.max,
            });
        }
        self.boot()?;
        let vars = *self.bench.vars()?;
        self.bench.write_f32(vars.leg_length_mm, leg_mm as f32);
        let (params, _, _) = crate::firmware::params::plan(
            self.bench.firmware(),
            &self.robot,
            self.bench.board(),
            crate::firmware::params::Tell::Robot,
            &[],
        );
        // A firmware that speaks the framed protocol gets a framed start: its
        // raw selector byte counts only after 50 ms of quiet on the line,
        // which a test that just sent a command does not leave.
        let framed = crate::firmware::params::takes_params(self.bench.firmware());
        crate::runs::start::start_test(&mut self.bench, &params, framed, test);
        Ok(())
    }

    /// Send bytes to the firmware on the board's command link (the
    /// Bluetooth UART), paced at its baud rate from now on.
    pub fn send(&mut self, bytes: &[u8]) {
        let uart = self.bench.board().command_uart.usart;
        self.bench.send(uart, bytes);
    }

    /// Send a command of the framed protocol (`protocol/README.md`).
    pub fn command(&mut self, command: &Command) {
        self.send(&frame(command));
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

    /// The firmware variable `symbol` (an ELF data symbol of `ty`'s size).
    pub fn var(&self, symbol: &str, ty: VarType) -> Result<f64, HarnessError> {
        let addr = self.bench.firmware().variable(symbol, ty.size())?;
        Ok(until::read_var(&self.bench, addr, ty))
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
