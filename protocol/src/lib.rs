//! The framed command protocol of the Henrytwo robot, shared by the firmware
//! (ATmega2560, `no_std`) and its hosts (the bench, a PC tool).
//!
//! One frame is `START, LEN, payload[LEN], CRC` (see [`frame`]): `LEN` counts
//! the payload bytes (1 to [`MAX_PAYLOAD`]) and `CRC` is CRC-8/SMBUS
//! (polynomial 0x07, see [`crc`]) over `LEN` and the payload. The first
//! payload byte names the message (see [`message`]): a command from the host,
//! the reply to it (the command's id with bit 7 set, then a [`Status`] byte),
//! or a notification the firmware sends on its own. Run-time parameters and
//! their ranges are in [`param`], the ranges by name in [`limits`]. Every
//! multi-byte value is little-endian.
//!
//! Bytes outside a frame that are not [`START`] reach the application as
//! [`Event::Raw`]: the firmware keeps accepting the thesis' single-byte test
//! selectors (2, 3, 4, 5) that way.
//!
//! Nothing here reads a clock: the [`Parser`]'s inter-byte timeout works on
//! times the caller passes in, in whatever unit the caller chooses.
//!
//! `README.md` next to this crate documents the protocol byte by byte.

#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod crc;
pub mod frame;
pub mod limits;
pub mod message;
pub mod param;
pub mod status;
pub mod test_kind;

pub use crc::crc8;
pub use frame::{
    encode_frame, EncodeError, Event, FrameError, Parser, MAX_FRAME, MAX_PAYLOAD, START,
};
pub use message::{
    Command, CommandId, Fault, FaultNotice, Phase, Reply, RunState, StateReport, Status, Telemetry,
    Test, TestDoneNotice, FRAME_ERROR_ID, NOTIFY_FAULT, NOTIFY_TEST_DONE, REPLY_FLAG, VERSION,
};
pub use param::{DriverKind, Param, Range, NO_PIN};
