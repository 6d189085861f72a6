//! The result code of every reply, shared by the message layer and the parameter ranges.

/// Result code of a reply (second payload byte).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Status {
    /// Done.
    Ok = 0,
    /// The frame's CRC did not match.
    BadCrc = 1,
    /// The command id is not known.
    UnknownCommand = 2,
    /// The frame stopped arriving (inter-byte timeout).
    Truncated = 3,
    /// A parameter value or a test id is outside its range.
    OutOfRange = 4,
    /// Refused while a test runs.
    Busy = 5,
    /// `LEN` is 0 or above 32, or the payload's length does not fit the command.
    BadLength = 6,
    /// The parameter id is not known.
    UnknownParam = 7,
}

impl Status {
    /// The status with code `b`.
    pub const fn from_u8(b: u8) -> Option<Status> {
        Some(match b {
            0 => Status::Ok,
            1 => Status::BadCrc,
            2 => Status::UnknownCommand,
            3 => Status::Truncated,
            4 => Status::OutOfRange,
            5 => Status::Busy,
            6 => Status::BadLength,
            7 => Status::UnknownParam,
            _ => return None,
        })
    }
}

impl From<crate::frame::FrameError> for Status {
    fn from(e: crate::frame::FrameError) -> Status {
        match e {
            crate::frame::FrameError::BadLength => Status::BadLength,
            crate::frame::FrameError::BadCrc => Status::BadCrc,
            crate::frame::FrameError::Truncated => Status::Truncated,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_round_trip() {
        for b in 0..=255u8 {
            if let Some(s) = Status::from_u8(b) {
                assert_eq!(s as u8, b);
            }
        }
        assert_eq!(Status::from_u8(8), None);
    }
}
