//! The segments of each test: legs and spin turns, alternating, numbered
//! together from 0 (leg 0, turn 1, leg 2, ...).
//!
//! | test | selector | segments |
//! |---|---|---|
//! | UMBmark CW | 2 | 4 x (leg, spin right by the UMBmark angle) |
//! | UMBmark CCW | 3 | 4 x (leg, spin left by the UMBmark angle) |
//! | straight line | 4 | 1 leg |
//! | triangle | 5 | 3 x (leg, spin left by the triangle angle) |

use henrytwo_protocol::Test;

/// Direction of a spin in place, seen from above.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Spin {
    /// Clockwise (turning right): left wheel forward, right wheel backward.
    Cw,
    /// Counter-clockwise (turning left): left backward, right forward.
    Ccw,
}

impl Spin {
    /// Whether the (left, right) wheel turns forward.
    pub const fn forward(self) -> (bool, bool) {
        match self {
            Spin::Cw => (true, false),
            Spin::Ccw => (false, true),
        }
    }
}

/// One segment of a test.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Segment {
    /// A straight leg of the leg length.
    Leg,
    /// A spin in place; `triangle` selects the triangle angle instead of the
    /// UMBmark one.
    Turn {
        /// Direction.
        spin: Spin,
        /// Uses the triangle's angle.
        triangle: bool,
    },
}

/// Number of segments of `test`.
pub const fn segment_count(test: Test) -> u8 {
    match test {
        Test::Line => 1,
        Test::UmbmarkCw | Test::UmbmarkCcw => 8,
        Test::Triangle => 6,
    }
}

/// Segment `index` of `test`, or `None` after the last.
pub const fn segment(test: Test, index: u8) -> Option<Segment> {
    if index >= segment_count(test) {
        return None;
    }
    if index.is_multiple_of(2) {
        return Some(Segment::Leg);
    }
    Some(match test {
        Test::UmbmarkCw => Segment::Turn { spin: Spin::Cw, triangle: false },
        Test::UmbmarkCcw => Segment::Turn { spin: Spin::Ccw, triangle: false },
        Test::Triangle => Segment::Turn { spin: Spin::Ccw, triangle: true },
        // A line has one segment, a leg.
        Test::Line => Segment::Leg,
    })
}

const _: () = {
    assert!(matches!(segment(Test::Line, 0), Some(Segment::Leg)));
    assert!(segment(Test::Line, 1).is_none());
    assert!(matches!(segment(Test::UmbmarkCw, 7), Some(Segment::Turn { spin: Spin::Cw, triangle: false })));
    assert!(segment(Test::UmbmarkCw, 8).is_none());
    assert!(matches!(segment(Test::Triangle, 5), Some(Segment::Turn { spin: Spin::Ccw, triangle: true })));
    assert!(matches!(segment(Test::Triangle, 4), Some(Segment::Leg)));
};
