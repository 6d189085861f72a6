//! The codes of the state the firmware reports: what it is doing ([`RunState`]), in which
//! part of a test ([`Phase`]), and the fault that stopped it ([`Fault`]).

/// `HT_STATE` / the state byte of [`StateReport`](super::StateReport).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum RunState {
    /// Reset until initialised.
    Booting = 0,
    /// Ready for a command.
    Idle = 1,
    /// Driving a leg or a turn.
    Driving = 2,
    /// Braking and waiting between segments.
    Braking = 3,
}

impl RunState {
    /// The state with wire value `b`, or None for a value no firmware sends.
    pub const fn from_u8(b: u8) -> Option<RunState> {
        Some(match b {
            0 => RunState::Booting,
            1 => RunState::Idle,
            2 => RunState::Driving,
            3 => RunState::Braking,
            _ => return None,
        })
    }
}

/// `HT_PHASE` / the phase byte of [`StateReport`](super::StateReport).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Phase {
    /// No test running.
    Idle = 0,
    /// Driving a straight leg.
    Leg = 1,
    /// Spinning in place.
    Turn = 2,
    /// Braking pulses and waits after a segment.
    Braking = 3,
    /// Stopped by a fault (see [`Fault`]); idle otherwise.
    Fault = 4,
}

impl Phase {
    /// The phase with wire value `b`, or None for a value no firmware sends.
    pub const fn from_u8(b: u8) -> Option<Phase> {
        Some(match b {
            0 => Phase::Idle,
            1 => Phase::Leg,
            2 => Phase::Turn,
            3 => Phase::Braking,
            4 => Phase::Fault,
            _ => return None,
        })
    }
}

/// `HT_FAULT` / the fault byte of [`StateReport`](super::StateReport) and
/// [`FaultNotice`](super::FaultNotice).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Hash)]
#[repr(u8)]
pub enum Fault {
    /// No fault since the last test start.
    None = 0,
    /// Left wheel driven at or above the stall duty without advancing 3
    /// counts in the commanded direction within the stall timeout (its count
    /// nearly still).
    StallLeft = 1,
    /// Right wheel, likewise.
    StallRight = 2,
    /// A leg or turn took more than 4 times its nominal time plus 2 s.
    SegmentTimeout = 3,
    /// The left wheel moved more than 64 counts against its commanded
    /// direction during a segment.
    WrongWayLeft = 4,
    /// The right wheel, likewise.
    WrongWayRight = 5,
    /// The last reset was a watchdog reset (reported at boot).
    WatchdogReset = 6,
    /// A wheel (either; the notice's counts show which one stopped
    /// advancing) driven at or above the stall duty whose count moved back
    /// and forth (3 or more counts, tick by tick) without advancing 3 counts
    /// in the commanded direction within the stall timeout: edges arrive but
    /// do not add up, e.g. encoder channel B stuck.
    EncoderInconsistent = 7,
}

impl Fault {
    /// The fault with code `b`.
    pub const fn from_u8(b: u8) -> Option<Fault> {
        Some(match b {
            0 => Fault::None,
            1 => Fault::StallLeft,
            2 => Fault::StallRight,
            3 => Fault::SegmentTimeout,
            4 => Fault::WrongWayLeft,
            5 => Fault::WrongWayRight,
            6 => Fault::WatchdogReset,
            7 => Fault::EncoderInconsistent,
            _ => return None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::message::FaultNotice;

    #[test]
    fn run_state_and_phase_decode_exactly_their_wire_values() {
        let states = [
            RunState::Booting,
            RunState::Idle,
            RunState::Driving,
            RunState::Braking,
        ];
        let phases = [
            Phase::Idle,
            Phase::Leg,
            Phase::Turn,
            Phase::Braking,
            Phase::Fault,
        ];
        for b in 0..=u8::MAX {
            assert_eq!(
                RunState::from_u8(b),
                states.iter().copied().find(|s| *s as u8 == b)
            );
            assert_eq!(
                Phase::from_u8(b),
                phases.iter().copied().find(|p| *p as u8 == b)
            );
        }
    }

    #[test]
    fn fault_codes_round_trip() {
        let mut known = 0;
        for b in 0..=255u8 {
            if let Some(f) = Fault::from_u8(b) {
                assert_eq!(f as u8, b);
                known += 1;
            }
        }
        assert_eq!(known, 8);
        assert_eq!(Fault::from_u8(7), Some(Fault::EncoderInconsistent));
        assert_eq!(Fault::from_u8(8), None);
        let f = FaultNotice {
            fault: Fault::EncoderInconsistent as u8,
            test: 4,
            segment: 0,
            phase: 1,
            left: 2100,
            right: 75,
        };
        assert_eq!(f.to_bytes()[0], 7);
        assert_eq!(FaultNotice::decode(&f.to_bytes()), Some(f));
    }
}
