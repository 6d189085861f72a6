//! Left and right.

use std::fmt;

use serde::{Deserialize, Serialize};

/// One side of the robot, seen from behind it looking forward.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The left wheel and motor.
    Left,
    /// The right wheel and motor.
    Right,
}

impl Side {
    /// Both sides, left first.
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// The side's place in [`Side::BOTH`] (left 0, right 1): the index of
    /// its entry in a per-side array.
    pub const fn index(self) -> usize {
        match self {
            Side::Left => 0,
            Side::Right => 1,
        }
    }

    /// The lower-case name used in config keys (`left`, `right`).
    pub const fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One value per side.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerSide<T> {
    /// The left side's value.
    pub left: T,
    /// The right side's value.
    pub right: T,
}

impl<T> PerSide<T> {
    /// The value of `side`.
    pub fn get(&self, side: Side) -> &T {
        match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        }
    }

    /// The value of `side`, mutable.
    pub fn get_mut(&mut self, side: Side) -> &mut T {
        match side {
            Side::Left => &mut self.left,
            Side::Right => &mut self.right,
        }
    }

    /// Applies `f` to each side's value.
    pub fn map<U>(self, mut f: impl FnMut(Side, T) -> U) -> PerSide<U> {
        PerSide {
            left: f(Side::Left, self.left),
            right: f(Side::Right, self.right),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_is_the_place_in_both() {
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            assert_eq!(side.index(), i);
        }
    }

    /// Scenario files and the bench's JSON name sides `left` and `right`.
    #[test]
    fn serde_names_are_the_lower_case_names() {
        #[derive(Serialize, Deserialize)]
        struct S {
            side: Side,
        }
        for side in Side::BOTH {
            let text = toml::to_string(&S { side }).unwrap();
            assert_eq!(text.trim(), format!("side = \"{}\"", side.name()));
            assert_eq!(toml::from_str::<S>(&text).unwrap().side, side);
        }
    }
}
