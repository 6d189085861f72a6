//! The robot's tests: the one definition, by their selector bytes.

/// The tests, numbered like the thesis' single-byte selectors: the one
/// definition of the robot's tests, for the firmware that drives them and for
/// every host that starts, runs or analyses them.
///
/// With the `serde` feature a test is written as its [`Test::name`]
/// (`"umbmark-cw"`), as the bench's files and outputs spell it.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
#[repr(u8)]
pub enum Test {
    /// UMBmark clockwise: 4 legs, 4 spin turns to the right.
    UmbmarkCw = 2,
    /// UMBmark counter-clockwise: 4 legs, 4 spin turns to the left.
    UmbmarkCcw = 3,
    /// Straight line: 1 leg.
    Line = 4,
    /// Triangular path: 3 legs, 3 spin turns to the left.
    Triangle = 5,
}

impl Test {
    /// Every test, in selector order.
    pub const ALL: [Test; 4] = [
        Test::UmbmarkCw,
        Test::UmbmarkCcw,
        Test::Line,
        Test::Triangle,
    ];

    /// The test selected by `b` (2..=5).
    pub const fn from_u8(b: u8) -> Option<Test> {
        Some(match b {
            2 => Test::UmbmarkCw,
            3 => Test::UmbmarkCcw,
            4 => Test::Line,
            5 => Test::Triangle,
            _ => return None,
        })
    }

    /// The thesis' single-byte selector (also the `START_TEST` argument).
    pub const fn command_byte(self) -> u8 {
        self as u8
    }

    /// The name hosts use for it on command lines and in files.
    pub const fn name(self) -> &'static str {
        match self {
            Test::UmbmarkCw => "umbmark-cw",
            Test::UmbmarkCcw => "umbmark-ccw",
            Test::Line => "line",
            Test::Triangle => "triangle",
        }
    }

    /// The test named `name` (see [`Test::name`]).
    pub fn from_name(name: &str) -> Option<Test> {
        Test::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Straight legs driven.
    pub const fn legs(self) -> usize {
        match self {
            Test::UmbmarkCw | Test::UmbmarkCcw => 4,
            Test::Line => 1,
            Test::Triangle => 3,
        }
    }

    /// Spin turns, one after each leg (none on the line).
    pub const fn turns(self) -> usize {
        match self {
            Test::Line => 0,
            t => t.legs(),
        }
    }

    /// The commanded angle of each turn, degrees, positive counter-clockwise
    /// (0 for the line).
    pub const fn turn_deg(self) -> f64 {
        match self {
            Test::UmbmarkCw => -90.0,
            Test::UmbmarkCcw => 90.0,
            Test::Line => 0.0,
            Test::Triangle => 120.0,
        }
    }

    /// (legs, turns, turn angle in degrees, positive counter-clockwise).
    pub const fn shape(self) -> (usize, usize, f64) {
        (self.legs(), self.turns(), self.turn_deg())
    }

    /// Where an ideal robot ends, in the start frame (`x` along the first
    /// leg, `y` to the left), in the unit of `leg`: back at the start, or for
    /// the line one leg ahead.
    pub const fn ideal_end(self, leg: f64) -> (f64, f64) {
        match self {
            Test::Line => (leg, 0.0),
            _ => (0.0, 0.0),
        }
    }
}

/// A name that is not a [`Test::name`].
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct UnknownTest;

impl core::fmt::Display for UnknownTest {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unknown test: use umbmark-cw, umbmark-ccw, line or triangle")
    }
}

impl core::error::Error for UnknownTest {}

impl core::str::FromStr for Test {
    type Err = UnknownTest;
    fn from_str(s: &str) -> Result<Self, UnknownTest> {
        Test::from_name(s).ok_or(UnknownTest)
    }
}
