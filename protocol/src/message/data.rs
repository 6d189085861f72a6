//! The data blocks of the replies to `GET_STATE` and `GET_TELEMETRY` and of the two
//! notifications, with their fixed lengths and byte layouts.

use super::bytes::{f32_at, put, u16_at, u32_at};

/// Data of the [`CommandId::GetState`](super::CommandId::GetState) reply (7 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct StateReport {
    /// [`RunState`](super::RunState) code.
    pub state: u8,
    /// [`Phase`](super::Phase) code.
    pub phase: u8,
    /// Running or last test (2..=5), 0 before the first.
    pub test: u8,
    /// Index of the current segment (legs and turns numbered together from 0).
    pub segment: u8,
    /// [`Fault`](super::Fault) code.
    pub fault: u8,
    /// Tests completed since reset.
    pub tests_done: u16,
}

impl StateReport {
    /// Encoded length.
    pub const LEN: usize = 7;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let d = self.tests_done.to_le_bytes();
        [
            self.state,
            self.phase,
            self.test,
            self.segment,
            self.fault,
            d[0],
            d[1],
        ]
    }

    /// Decodes reply data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(StateReport {
            state: b[0],
            phase: b[1],
            test: b[2],
            segment: b[3],
            fault: b[4],
            tests_done: u16_at(b, 5)?,
        })
    }
}

/// Data of the [`CommandId::GetTelemetry`](super::CommandId::GetTelemetry) reply (24 bytes).
#[derive(Clone, Copy, PartialEq, Debug, Default)]
pub struct Telemetry {
    /// Left encoder count since reset (`HT_LEFT_COUNT`).
    pub left_count: i32,
    /// Right encoder count since reset.
    pub right_count: i32,
    /// Last measured left speed, thesis "RPM".
    pub speed_left: f32,
    /// Last measured right speed, thesis "RPM".
    pub speed_right: f32,
    /// Last left duty, 0..=255.
    pub duty_left: u8,
    /// Last right duty, 0..=255.
    pub duty_right: u8,
    /// Control ticks (15 ms) since reset.
    pub ticks: u32,
    /// Last battery reading, ADC counts 0..=1023.
    pub battery_adc: u16,
}

impl Telemetry {
    /// Encoded length.
    pub const LEN: usize = 24;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let mut b = [0u8; Self::LEN];
        let _ = put(&mut b, 0, &self.left_count.to_le_bytes());
        let _ = put(&mut b, 4, &self.right_count.to_le_bytes());
        let _ = put(&mut b, 8, &self.speed_left.to_le_bytes());
        let _ = put(&mut b, 12, &self.speed_right.to_le_bytes());
        let _ = put(&mut b, 16, &[self.duty_left, self.duty_right]);
        let _ = put(&mut b, 18, &self.ticks.to_le_bytes());
        let _ = put(&mut b, 22, &self.battery_adc.to_le_bytes());
        b
    }

    /// Decodes reply data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(Telemetry {
            left_count: u32_at(b, 0)? as i32,
            right_count: u32_at(b, 4)? as i32,
            speed_left: f32_at(b, 8)?,
            speed_right: f32_at(b, 12)?,
            duty_left: b[16],
            duty_right: b[17],
            ticks: u32_at(b, 18)?,
            battery_adc: u16_at(b, 22)?,
        })
    }
}

/// Data of the [`NOTIFY_FAULT`](super::NOTIFY_FAULT) notification (12 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct FaultNotice {
    /// [`Fault`](super::Fault) code.
    pub fault: u8,
    /// The test that was running (2..=5).
    pub test: u8,
    /// Its segment index.
    pub segment: u8,
    /// [`Phase`](super::Phase) code at the fault (1 leg, 2 turn).
    pub phase: u8,
    /// Left count relative to the segment's start.
    pub left: i32,
    /// Right count relative to the segment's start.
    pub right: i32,
}

impl FaultNotice {
    /// Encoded length.
    pub const LEN: usize = 12;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let mut b = [0u8; Self::LEN];
        let _ = put(
            &mut b,
            0,
            &[self.fault, self.test, self.segment, self.phase],
        );
        let _ = put(&mut b, 4, &self.left.to_le_bytes());
        let _ = put(&mut b, 8, &self.right.to_le_bytes());
        b
    }

    /// Decodes notification data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(FaultNotice {
            fault: b[0],
            test: b[1],
            segment: b[2],
            phase: b[3],
            left: u32_at(b, 4)? as i32,
            right: u32_at(b, 8)? as i32,
        })
    }
}

/// Data of the [`NOTIFY_TEST_DONE`](super::NOTIFY_TEST_DONE) notification (3 bytes).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct TestDoneNotice {
    /// The test that ended (2..=5).
    pub test: u8,
    /// Tests completed since reset, this one included.
    pub tests_done: u16,
}

impl TestDoneNotice {
    /// Encoded length.
    pub const LEN: usize = 3;

    /// The encoded bytes.
    pub fn to_bytes(&self) -> [u8; Self::LEN] {
        let d = self.tests_done.to_le_bytes();
        [self.test, d[0], d[1]]
    }

    /// Decodes notification data; `None` if the length is wrong.
    pub fn decode(b: &[u8]) -> Option<Self> {
        if b.len() != Self::LEN {
            return None;
        }
        Some(TestDoneNotice {
            test: b[0],
            tests_done: u16_at(b, 1)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{encode_frame, Event, Parser, MAX_FRAME};
    use crate::message::{CommandId, Reply, Status};

    #[test]
    fn data_blocks_round_trip() {
        let s = StateReport {
            state: 2,
            phase: 2,
            test: 3,
            segment: 5,
            fault: 0,
            tests_done: 0x1234,
        };
        assert_eq!(s.to_bytes(), [2, 2, 3, 5, 0, 0x34, 0x12]);
        assert_eq!(StateReport::decode(&s.to_bytes()), Some(s));
        let t = Telemetry {
            left_count: -5,
            right_count: 70_000,
            speed_left: 15.25,
            speed_right: -0.0,
            duty_left: 200,
            duty_right: 7,
            ticks: 0xDEADBEEF,
            battery_adc: 1023,
        };
        assert_eq!(Telemetry::decode(&t.to_bytes()), Some(t));
        assert_eq!(&t.to_bytes()[0..4], &[0xFB, 0xFF, 0xFF, 0xFF]);
        let f = FaultNotice {
            fault: 1,
            test: 2,
            segment: 4,
            phase: 1,
            left: 3,
            right: -700,
        };
        assert_eq!(FaultNotice::decode(&f.to_bytes()), Some(f));
        let d = TestDoneNotice {
            test: 5,
            tests_done: 9,
        };
        assert_eq!(TestDoneNotice::decode(&d.to_bytes()), Some(d));
        assert_eq!(StateReport::decode(&[0; 6]), None);
        assert_eq!(Telemetry::decode(&[0; 25]), None);
    }

    /// A host's view: encode a reply frame, parse it back byte by byte.
    #[test]
    fn reply_through_the_parser() {
        let data = StateReport {
            state: 1,
            phase: 0,
            test: 4,
            segment: 0,
            fault: 0,
            tests_done: 1,
        }
        .to_bytes();
        let mut payload = [0u8; 32];
        let n = Reply {
            id: CommandId::GetState.reply_id(),
            status: Status::Ok,
            data: &data,
        }
        .encode(&mut payload)
        .unwrap();
        let mut frame = [0u8; MAX_FRAME];
        let m = encode_frame(&payload[..n], &mut frame).unwrap();
        let mut p = Parser::new(50);
        let mut got = None;
        for (i, &b) in frame[..m].iter().enumerate() {
            assert_eq!(p.poll(i as u32), None);
            if let Some(Event::Frame(f)) = p.push(b, i as u32) {
                let r = Reply::decode(f).unwrap();
                got = Some((r.id, r.status, StateReport::decode(r.data).unwrap()));
            }
        }
        assert_eq!(
            got,
            Some((0xA0, Status::Ok, StateReport::decode(&data).unwrap()))
        );
    }
}
