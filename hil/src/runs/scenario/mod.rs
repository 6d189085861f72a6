//! Scenario files: faults for `hil run --scenario FILE` and `hil faults
//! --scenario FILE`, and the user's own expectations for `hil test FILE...`,
//! in TOML (or JSON, by the `.json` extension).
//!
//! ```toml
//! name = "left encoder off, then a slip"
//! test = "line"        # for `hil faults` and `hil test`; `hil run` takes the test it is given
//! leg_mm = 2000.0      # for `hil faults` and `hil test`
//! limit_s = 25.0       # for `hil faults` and `hil test`
//! firmware = "robust"  # for `hil test` (robust or thesis; --firmware / --elf override)
//! seed = 0             # for `hil test` (--seed overrides)
//!
//! [[fault]]
//! trigger = { at = "time", s = 3.0 }
//! action = { action = "encoder", side = "left", fault = { kind = "dropout" } }
//!
//! [[fault]]
//! trigger = { at = "turn_start", n = 3 }
//! action = { action = "slip_burst", side = "left", slip = 0.3 }
//! duration_s = 1.5     # then the fault ends (or `undo` runs, when given)
//!
//! [[expect]]
//! name = "motors off after the dropout"
//! after = { event = "fault", n = 1 }   # when fault 1's action was applied
//! within_ms = 250.0                    # the window; without it, up to the end of the run
//! that = { on = "motor", side = "both", state = "off" }
//!
//! [[expect]]
//! after = { event = "end" }
//! that = { on = "pose", distance_mm = 2000.0, tol_pct = 1.0 }
//! ```
//!
//! Triggers: `time` (`s` since reset), `turn_start` / `leg_start` (`n`,
//! 1-based), `host_byte` (`n`-th byte from the host on the Bluetooth link).
//! Actions are [`crate::bench::Action`]'s, tagged by `action`: `encoder`,
//! `encoder_glitch`, `link`, `motor_disconnected`, `motor`, `slip_burst`,
//! `battery_volts`, `reset`, `host_send`. Every value is checked before
//! anything runs; times (`s`, `duration_s`, `limit_s`) are at most a day of
//! robot time ([`MAX_ROBOT_TIME_S`]), far beyond any run and far below the
//! 64-bit cycle counter, so no fault waits forever or wraps round. A fault
//! whose trigger the run never reaches is named in the run's warnings.
//!
//! An `[[expect]]` waits for its condition (`that`) from its event (`after`)
//! on, for `within_ms` of robot time (or to the end of the run): it passes
//! when the condition holds at some point of that window, or, with
//! `throughout = true`, at every point of it. Events: `start` (the test's
//! start command; the default), `end` (the run's last cycle), `time` (`s`
//! since reset), `fault` (`n`: when the file's `n`-th `[[fault]]` was
//! applied), `leg_start` / `turn_start` (`n`, 1-based, from the H-bridge).
//! Conditions, tagged by `on` ([`Condition`]):
//!
//! | `on` | fields | holds when |
//! |---|---|---|
//! | `uart` | `text` or `bytes`, `usart` (default: the board's command link), `dir` (`tx` the firmware's, default; `rx` the host's) | the pattern arrived complete inside the window |
//! | `frame` | `id`, optional `status`, `data` (a prefix), `usart` | the firmware sent a framed reply or notice (protocol/README.md) with that id |
//! | `motor` | `side` (`left`, `right`, `both`), `state` (`off`, `coast`, `brake`, `forward`, `reverse`), optional `duty_min`, `duty_max` (0-1) | the bridge inputs give that state (and drive duty) |
//! | `pin` | `pin` (`D13`, `A0`), `level` (`high`, `low`) | the MCU pin reads that level |
//! | `var` | `symbol` (an ELF data symbol), `type` (`u8` ... `i32`, `f32`), `eq`, `ne`, `min`, `max` | the firmware variable compares so |
//! | `pose` | `x_mm`, `y_mm`, `distance_mm` (from the origin) with `tol_mm` or `tol_pct`; `heading_deg` with `tol_deg` | the plant's pose (origin and heading 0 where the robot stood at reset) is that close |
//!
//! Conditions are judged on the bench's own state at exact cycles, never on
//! wall-clock time: firmware variables, pins and bridge inputs at the run
//! loop's checks (every [`crate::bench::CHECK_PERIOD_S`] of robot time, the
//! same cycles in every run), UART bytes at the cycle each one completed,
//! the pose at the plant's own steps ([`eval`]).
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | [`Scenario`], [`ScenarioError`] |
//! | `load.rs` | reading and checking a file: one error line, naming what, where and the range |
//! | `faults.rs` | [`FaultEntry`]: a `[[fault]]` and its checks |
//! | `expect.rs` | [`Expectation`], [`Anchor`], [`Condition`]: an `[[expect]]` and its checks |
//! | `eval.rs` | the [`eval::Watch`] a run carries, and the verdict on each expectation |

use std::path::PathBuf;

use serde::Deserialize;
use thiserror::Error;

use crate::bench::inject::EncoderFault;
use crate::bench::{Action, ScheduledFault};
use crate::runs::experiment::TestName;

pub mod eval;
mod expect;
mod faults;
pub(crate) mod judge;
mod load;
#[cfg(test)]
mod tests;

pub use self::expect::{
    Anchor, Condition, Direction, Expectation, Level, MotorSides, MotorState, VarType,
};
pub use self::faults::FaultEntry;
pub use self::load::MAX_ROBOT_TIME_S;

#[derive(Debug, Error)]
pub enum ScenarioError {
    #[error("cannot read the scenario {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the scenario {path} does not parse: {message} (the module docs of hil::runs::scenario show the layout)")]
    Parse { path: PathBuf, message: String },
    #[error("the scenario {path}, fault {index}: {message}")]
    Invalid {
        path: PathBuf,
        /// 1-based, in file order.
        index: usize,
        message: String,
    },
    /// An `[[expect]]` out of its range, or naming what the file lacks.
    #[error("the scenario {path}, expect {index}: {message}")]
    Expect {
        path: PathBuf,
        /// 1-based, in file order.
        index: usize,
        message: String,
    },
    #[error("the scenario {path} has no [[fault]]: add at least one")]
    Empty { path: PathBuf },
    /// A top-level value (`leg_mm`, `limit_s`) out of its range.
    #[error("the scenario {path}: {message}")]
    Field { path: PathBuf, message: String },
}

/// A scenario file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    /// A thesis test, or (with a test description) one of the firmware's own.
    pub test: Option<TestName>,
    #[serde(default)]
    pub leg_mm: Option<f64>,
    #[serde(default)]
    pub limit_s: Option<f64>,
    /// Start with a framed command instead of the raw selector byte.
    #[serde(default)]
    pub framed: bool,
    /// The build `hil test` runs (`robust` or `thesis`), unless told otherwise.
    #[serde(default)]
    pub firmware: Option<String>,
    /// The plant's seed for `hil test`, unless told otherwise.
    #[serde(default)]
    pub seed: Option<u64>,
    /// A file of expectations alone needs no fault.
    #[serde(rename = "fault", default)]
    pub faults: Vec<FaultEntry>,
    #[serde(rename = "expect", default)]
    pub expect: Vec<Expectation>,
}

impl Scenario {
    /// The faults, as the bench schedules them.
    pub fn scheduled(&self) -> Vec<ScheduledFault> {
        self.faults.iter().map(FaultEntry::scheduled).collect()
    }

    /// Refuses a fault on a line `board` does not wire, naming the fault:
    /// channel B of a one-channel encoder, stuck, swapped with A or
    /// glitched, is on no pin, so the run would change nothing the firmware
    /// sees and read as if it had shrugged the fault off.
    pub fn check_wiring(&self, board: &crate::board::Board) -> Result<(), String> {
        for (k, f) in self.faults.iter().enumerate() {
            let on_b = match &f.action {
                Action::Encoder {
                    side,
                    fault: EncoderFault::StuckB { .. } | EncoderFault::Swapped,
                } => Some(*side),
                Action::EncoderGlitch {
                    side,
                    channel: crate::bench::inject::Channel::B,
                    ..
                } => Some(*side),
                _ => None,
            };
            let Some(side) = on_b else { continue };
            let (wiring, name) = match side {
                plant_model::Side::Left => (board.left_encoder, "left"),
                plant_model::Side::Right => (board.right_encoder, "right"),
            };
            if wiring.b.is_none() {
                return Err(format!(
                    "[[fault]] {} ({}): the board's {name} encoder has channel A alone (a \
                     one-channel encoder), its channel B on no pin; give a fault of channel A \
                     (stuck_a, dropout, miss_pairs, a glitch on A)",
                    k + 1,
                    f.action.name()
                ));
            }
        }
        Ok(())
    }
}
