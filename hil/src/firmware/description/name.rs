//! What names a test a run drives, and the shape a test is expected to
//! drive: the thesis' four tests ([`Test`], defined by the protocol) or a
//! test of the firmware's own that a test description names.

use henrytwo_protocol::Test;

/// A test a run drives: one of the thesis' tests (its name keeps its shape
/// and selector), or one of the firmware's own, named by its test
/// description. Written as its name (`"umbmark-cw"`, `"forward-then-left"`).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum TestName {
    Thesis(Test),
    Own(String),
}

/// The longest name a test may have (it is a file stem and a JUnit case).
pub const MAX_NAME_LEN: usize = 40;

impl TestName {
    /// The name as files and command lines spell it.
    pub fn name(&self) -> &str {
        match self {
            TestName::Thesis(t) => t.name(),
            TestName::Own(n) => n,
        }
    }

    /// The thesis' test, when it is one.
    pub fn thesis(&self) -> Option<Test> {
        match self {
            TestName::Thesis(t) => Some(*t),
            TestName::Own(_) => None,
        }
    }

    /// `s` as a test name: a thesis test's name means that test; any other
    /// name of 1-40 lower-case letters, digits, `-` and `_` (starting with a
    /// letter) is a test of the firmware's own. Err: what is allowed.
    pub fn parse(s: &str) -> Result<Self, String> {
        if let Some(t) = Test::from_name(s) {
            return Ok(TestName::Thesis(t));
        }
        let ok = !s.is_empty()
            && s.len() <= MAX_NAME_LEN
            && s.starts_with(|c: char| c.is_ascii_lowercase())
            && s.chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_');
        if ok {
            Ok(TestName::Own(s.to_string()))
        } else {
            Err(format!(
                "a test name is 1 to {MAX_NAME_LEN} of a-z, 0-9, '-' and '_', starting with a letter \
                 (the thesis' tests: umbmark-cw, umbmark-ccw, line, triangle)"
            ))
        }
    }
}

impl From<Test> for TestName {
    fn from(t: Test) -> Self {
        TestName::Thesis(t)
    }
}

impl PartialEq<Test> for TestName {
    fn eq(&self, other: &Test) -> bool {
        self.thesis() == Some(*other)
    }
}

impl std::fmt::Display for TestName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for TestName {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        TestName::parse(s)
    }
}

impl serde::Serialize for TestName {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for TestName {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        TestName::parse(&s).map_err(|why| serde::de::Error::custom(format!("test = {s:?}: {why}")))
    }
}

/// What a test drives: legs, each followed by a spin turn while turns
/// remain (the thesis' shapes, and a described test's `shape`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Shape {
    pub legs: usize,
    pub turns: usize,
    /// Each turn's commanded angle, degrees, positive counter-clockwise.
    pub turn_deg: f64,
    /// Each leg's length when the test says it (else the run's leg).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub leg_mm: Option<f64>,
}

impl Shape {
    /// The thesis test's shape.
    pub fn of(test: Test) -> Self {
        let (legs, turns, turn_deg) = test.shape();
        Shape {
            legs,
            turns,
            turn_deg,
            leg_mm: None,
        }
    }

    /// Where the robot ends, in the start frame (x along the first leg, y
    /// to the left), driving it exactly with legs of `leg_mm` (unless the
    /// shape has its own): leg, turn, leg, turn, ...
    pub fn ideal_end(&self, leg_mm: f64) -> (f64, f64) {
        let leg = self.leg_mm.unwrap_or(leg_mm);
        let (mut x, mut y, mut th) = (0.0f64, 0.0f64, 0.0f64);
        for k in 0..self.legs.max(self.turns) {
            if k < self.legs {
                x += leg * th.cos();
                y += leg * th.sin();
            }
            if k < self.turns {
                th += self.turn_deg.to_radians();
            }
        }
        // The thesis' closed shapes end at the start: no rounding residue.
        let tidy = |v: f64| if v.abs() < 1e-9 { 0.0 } else { v };
        (tidy(x), tidy(y))
    }

    /// Why `legs` legs and `turns` turns of `turn_deg` each (signed, as
    /// measured) are not this shape; None when they are. A turn is of the
    /// shape when it spins the shape's way and reaches at least half its
    /// angle (a spin the other way, or a brake pulse, is not the turn).
    pub fn differs(&self, legs: usize, turns: &[f64]) -> Option<String> {
        if legs != self.legs || turns.len() != self.turns {
            return Some(format!(
                "drove {legs} legs and {} turns where the test's shape is {} legs and {} turns",
                turns.len(),
                self.legs,
                self.turns
            ));
        }
        let want = self.turn_deg;
        turns
            .iter()
            .position(|&a| {
                want != 0.0 && (a.signum() != want.signum() || a.abs() < want.abs() / 2.0)
            })
            .map(|k| {
                format!(
                    "turn {} turned {:+.1} deg where the test's shape turns {:+.1} deg",
                    k + 1,
                    turns[k],
                    want
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thesis_names_keep_their_tests_and_others_are_the_firmwares_own() {
        assert_eq!(TestName::parse("line"), Ok(TestName::Thesis(Test::Line)));
        assert_eq!(
            TestName::parse("forward-then-left"),
            Ok(TestName::Own("forward-then-left".into()))
        );
        for bad in ["", "Left", "1st", "a b", &"x".repeat(41)] {
            assert!(TestName::parse(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn an_ideal_end_drives_the_shape_exactly() {
        for t in Test::ALL {
            let (x, y) = Shape::of(t).ideal_end(400.0);
            assert_eq!((x, y), t.ideal_end(400.0), "{t:?}");
        }
        let left = Shape {
            legs: 2,
            turns: 1,
            turn_deg: 90.0,
            leg_mm: Some(500.0),
        };
        let (x, y) = left.ideal_end(2000.0);
        assert!(
            (x - 500.0).abs() < 1e-9 && (y - 500.0).abs() < 1e-9,
            "{x} {y}"
        );
    }

    #[test]
    fn a_shape_differs_in_counts_and_in_a_turns_direction() {
        let s = Shape {
            legs: 1,
            turns: 1,
            turn_deg: 90.0,
            leg_mm: None,
        };
        assert_eq!(s.differs(1, &[88.0]), None);
        assert!(s
            .differs(2, &[88.0])
            .unwrap()
            .contains("drove 2 legs and 1 turns"));
        assert!(s.differs(1, &[]).is_some());
        assert!(s
            .differs(1, &[-90.0])
            .unwrap()
            .contains("turn 1 turned -90.0"));
        assert!(s.differs(1, &[30.0]).is_some());
    }
}
