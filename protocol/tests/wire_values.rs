//! Every wire value decodes to exactly its documented meaning and nothing
//! else does (README.md next to this crate lists them byte by byte), the
//! parameters' names are the ones host tools print, and the parser reports
//! its own state. Each table here is the documentation's, written out, so a
//! dropped or swapped match arm fails.

use henrytwo_protocol::frame::{Parser, START};
use henrytwo_protocol::message::{CommandId, Fault, Status, Test, REPLY_FLAG};
use henrytwo_protocol::param::Param;

/// `from_u8` gives exactly the listed value for each listed byte and None
/// for every other byte.
fn decodes_exactly<T: PartialEq + std::fmt::Debug + Copy>(
    from_u8: fn(u8) -> Option<T>,
    table: &[(u8, T)],
) {
    for b in 0..=u8::MAX {
        let want = table.iter().find(|(k, _)| *k == b).map(|(_, v)| *v);
        assert_eq!(from_u8(b), want, "byte {b:#04x}");
    }
}

#[test]
fn status_codes() {
    decodes_exactly(
        Status::from_u8,
        &[
            (0, Status::Ok),
            (1, Status::BadCrc),
            (2, Status::UnknownCommand),
            (3, Status::Truncated),
            (4, Status::OutOfRange),
            (5, Status::Busy),
            (6, Status::BadLength),
            (7, Status::UnknownParam),
        ],
    );
}

#[test]
fn command_ids_their_arguments_and_replies() {
    let table = [
        (0x01, CommandId::Ping, 0),
        (0x10, CommandId::StartTest, 1),
        (0x11, CommandId::Stop, 0),
        (0x20, CommandId::GetState, 0),
        (0x21, CommandId::GetTelemetry, 0),
        (0x30, CommandId::SetParam, 5),
        (0x31, CommandId::GetParam, 1),
    ];
    let ids: Vec<(u8, CommandId)> = table.iter().map(|(b, c, _)| (*b, *c)).collect();
    decodes_exactly(CommandId::from_u8, &ids);
    for (b, c, args) in table {
        assert_eq!(c.arg_len(), args, "{c:?} arguments");
        assert_eq!(c.reply_id(), b + REPLY_FLAG, "{c:?} reply id");
    }
}

#[test]
fn test_selectors() {
    decodes_exactly(
        Test::from_u8,
        &[
            (2, Test::UmbmarkCw),
            (3, Test::UmbmarkCcw),
            (4, Test::Line),
            (5, Test::Triangle),
        ],
    );
}

#[test]
fn fault_codes() {
    decodes_exactly(
        Fault::from_u8,
        &[
            (0, Fault::None),
            (1, Fault::StallLeft),
            (2, Fault::StallRight),
            (3, Fault::SegmentTimeout),
            (4, Fault::WrongWayLeft),
            (5, Fault::WrongWayRight),
            (6, Fault::WatchdogReset),
            (7, Fault::EncoderInconsistent),
        ],
    );
}

/// The names host tools print and accept, one per parameter, in id order.
#[test]
fn parameter_names() {
    let names: Vec<&str> = Param::ALL.iter().map(|p| p.name()).collect();
    assert_eq!(
        names,
        [
            "c_left",
            "c_right",
            "wheelbase_mm",
            "leg_length_mm",
            "turn_umbmark_deg",
            "turn_triangle_deg",
            "setpoint_left",
            "setpoint_right",
            "kp_left",
            "ki_left",
            "kd_left",
            "kp_right",
            "ki_right",
            "kd_right",
            "stall_timeout_ms",
            "stall_duty",
            "mm_per_count_left",
            "mm_per_count_right",
            "counts_per_wheel_rev",
            "driver_kind",
            "left_pin1",
            "left_pin2",
            "left_pin3",
            "right_pin1",
            "right_pin2",
            "right_pin3",
            "brake_coast_ms",
            "brake_pulse_ms",
            "stop_lead_ms",
            "stall_progress_counts",
            "wrong_way_counts",
        ]
    );
}

/// The parser's accessors: the timeout it was built with, the time of the
/// last byte, and idle only between frames (not inside one, not while
/// discarding after an error).
#[test]
fn parser_reports_its_state() {
    let mut p = Parser::new(37);
    assert_eq!(p.timeout(), 37);
    assert!(p.is_idle());
    let _ = p.push(START, 1234);
    assert_eq!(p.last_byte_at(), 1234);
    assert!(!p.is_idle() && p.in_frame());
    // LEN 0: a framing error, then discarding until START or silence.
    let _ = p.push(0, 1240);
    assert_eq!(p.last_byte_at(), 1240);
    assert!(!p.is_idle() && !p.in_frame());
    let _ = p.poll(1240 + 37);
    assert!(p.is_idle());
}
