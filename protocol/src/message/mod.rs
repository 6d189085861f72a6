//! Messages: commands (host to firmware), replies and notifications
//! (firmware to host).
//!
//! - Command payload: `[id, args...]`, `id` in 0x01..=0x3F.
//! - Reply payload: `[id | 0x80, status, data...]`. A frame the firmware
//!   could not attribute to a known command (bad CRC, bad length, truncated,
//!   unknown command id) is answered with id [`FRAME_ERROR_ID`] (0xFF).
//! - Notification payload: `[id, status, data...]` with `id` >= 0xC0 and
//!   status [`Status::Ok`]; the firmware sends them unasked.
//!
//! # Files
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | the ids' constants, [`Reply`]: a reply or notification split |
//! | `command.rs` | [`CommandId`] and [`Command`]: ids, argument lengths, decoding and encoding |
//! | `codes.rs` | the state, phase and fault codes: [`RunState`], [`Phase`], [`Fault`] |
//! | `data.rs` | the data blocks of replies and notifications: [`StateReport`], [`Telemetry`], [`FaultNotice`], [`TestDoneNotice`] |
//! | `bytes.rs` | little-endian values read and written at an offset |

mod bytes;
mod codes;
mod command;
mod data;

pub use crate::status::Status;
pub use crate::test_kind::{Test, UnknownTest};
use bytes::put;
pub use codes::{Fault, Phase, RunState};
pub use command::{Command, CommandId};
pub use data::{FaultNotice, StateReport, Telemetry, TestDoneNotice};

/// Protocol version reported by [`Command::Ping`].
pub const VERSION: u8 = 1;
/// Bit set in a reply's id (the command id it answers, plus this bit).
pub const REPLY_FLAG: u8 = 0x80;
/// Reply id for frames that cannot be attributed to a known command.
pub const FRAME_ERROR_ID: u8 = 0xFF;
/// Notification: a test ran to its end.
pub const NOTIFY_TEST_DONE: u8 = 0xC0;
/// Notification: a fault stopped the motors.
pub const NOTIFY_FAULT: u8 = 0xC1;

/// A reply or notification payload, split.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Reply<'a> {
    /// Reply id (command id | 0x80), [`FRAME_ERROR_ID`] or a notification id.
    pub id: u8,
    /// Result code.
    pub status: Status,
    /// The data after the status byte.
    pub data: &'a [u8],
}

impl<'a> Reply<'a> {
    /// Splits a firmware payload; `None` if shorter than 2 bytes or the
    /// status code is unknown.
    pub fn decode(payload: &'a [u8]) -> Option<Reply<'a>> {
        let (&id, rest) = payload.split_first()?;
        let (&status, data) = rest.split_first()?;
        Some(Reply {
            id,
            status: Status::from_u8(status)?,
            data,
        })
    }

    /// Writes `[id, status, data...]` to `out`; returns its length.
    pub fn encode(&self, out: &mut [u8]) -> Option<usize> {
        put(out, 0, &[self.id, self.status as u8])?;
        put(out, 2, self.data)?;
        Some(2 + self.data.len())
    }
}
