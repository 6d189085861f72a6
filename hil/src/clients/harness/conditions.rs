//! Short ways to write the scenario [`Condition`]s a test waits for, in Rust
//! (a scenario file writes the same conditions in TOML: `hil::runs::scenario`).

use crate::firmware::link::{CommandId, FrameId};
use crate::runs::scenario::{Condition, Direction, Level, MotorSides, MotorState};

impl Condition {
    /// The firmware sent a frame with this id on the command link:
    /// `Condition::frame(FrameId::TestDone)`, `Condition::frame(FrameId::Reply(CommandId::Ping))`
    /// (a raw byte, `Condition::frame(0x81)`, is the same id).
    pub fn frame(id: impl Into<FrameId>) -> Self {
        Condition::Frame {
            usart: None,
            id: id.into().byte(),
            status: None,
            data: None,
        }
    }

    /// The firmware replied to `command` on the command link, with any status.
    pub fn reply_to(command: CommandId) -> Self {
        Self::frame(FrameId::Reply(command))
    }

    /// The firmware sent these bytes, back to back, on the command link.
    pub fn sent(bytes: &[u8]) -> Self {
        Condition::Uart {
            usart: None,
            text: None,
            bytes: Some(bytes.to_vec()),
            dir: Direction::Tx,
        }
    }

    /// The firmware sent this text on the command link.
    pub fn sent_text(text: &str) -> Self {
        Condition::Uart {
            usart: None,
            text: Some(text.into()),
            bytes: None,
            dir: Direction::Tx,
        }
    }

    /// The motors of `side` are in `state` (any duty).
    pub fn motors(side: MotorSides, state: MotorState) -> Self {
        Condition::Motor {
            side,
            state,
            duty_min: None,
            duty_max: None,
        }
    }

    /// Both motors off (coasting or braking).
    pub fn motors_off() -> Self {
        Self::motors(MotorSides::Both, MotorState::Off)
    }

    /// Both motors driven forward at `duty_min` of the period or more (0-1).
    pub fn driving_forward(duty_min: f64) -> Self {
        Condition::Motor {
            side: MotorSides::Both,
            state: MotorState::Forward,
            duty_min: Some(duty_min),
            duty_max: None,
        }
    }

    /// The MCU pin (`"D13"`, `"A0"`) reads `level`.
    pub fn pin(name: &str, level: Level) -> Self {
        Condition::Pin {
            pin: name.into(),
            level,
        }
    }

    /// The robot stands `distance_mm` from where it was at reset, within
    /// `tol_pct` per cent of it.
    pub fn distance_within_pct(distance_mm: f64, tol_pct: f64) -> Self {
        Condition::Pose {
            x_mm: None,
            y_mm: None,
            distance_mm: Some(distance_mm),
            heading_deg: None,
            tol_mm: None,
            tol_pct: Some(tol_pct),
            tol_deg: None,
        }
    }
}
