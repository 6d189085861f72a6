//! Quadrature encoder geometry: from a wheel angle to the encoder's state and levels.
//!
//! The magnetic encoder on each motor shaft gives 6 edges per motor revolution on channel A
//! and as many on channel B, a quarter period apart: 12 quadrature states per motor
//! revolution, `12 * 100.37 = 1204.44` per wheel turn (602.22 A edges, the thesis'
//! "counts per wheel revolution"). One state spans `dq = 2 pi / (2 * 6 * 100.37)` wheel
//! radians; four states make one period of A (two A edges).
//!
//! - State index: `q = floor(angle / dq + 0.5)`. The wheel starts at angle 0, the middle of
//!   state 0, so there is no transition at time 0. A boundary belongs to the state above it.
//! - Levels: A high when `q mod 4` is 0 or 1, B high when `q mod 4` is 1 or 2 (Euclidean
//!   remainder, so negative `q` work the same).
//! - With this, increasing angle gives at each A edge either (A high, B low) or (A low,
//!   B high), which the thesis' decoder (on every A change: `+1` if A differs from B, else
//!   `-1`) counts as `+1`. Both wheels count up when the robot drives forward (the real
//!   robot's wiring makes it so).
//! - Net signed A edges since the start: `floor((q + 2) / 2) - 1` (`q = 0 -> 0`, `2 -> 1`,
//!   `4 -> 2`, `-1 -> -1`).
//!
//! A `reversed` encoder sees the negated wheel angle (for fault injection: a swapped A/B
//! pair).

use std::f64::consts::PI;

use crate::units::Radians;

/// One wheel's encoder: state size and direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoder {
    state_angle: f64,
    reversed: bool,
}

impl Encoder {
    /// An encoder behind a gearbox of `gear_ratio` with `a_edges_per_motor_rev` edges on
    /// channel A per motor revolution.
    pub fn new(gear_ratio: f64, a_edges_per_motor_rev: u32, reversed: bool) -> Self {
        Encoder {
            state_angle: 2.0 * PI / (2.0 * f64::from(a_edges_per_motor_rev) * gear_ratio),
            reversed,
        }
    }

    /// `dq`: wheel angle spanned by one quadrature state.
    pub fn state_angle(&self) -> Radians {
        Radians(self.state_angle)
    }

    /// Whether this encoder counts backwards.
    pub fn is_reversed(&self) -> bool {
        self.reversed
    }

    /// The quadrature state index `q` at wheel angle `angle`.
    pub fn quadrature_index(&self, angle: Radians) -> i64 {
        let seen = if self.reversed { -angle.0 } else { angle.0 };
        // Saturating conversion; 2^63 states are ~10^16 wheel turns.
        (seen / self.state_angle + 0.5).floor() as i64
    }
}

/// Levels `(A, B)` of the encoder in quadrature state `q`.
pub fn levels(q: i64) -> (bool, bool) {
    let phase = q.rem_euclid(4);
    (phase <= 1, phase == 1 || phase == 2)
}

/// Net signed A edges from state 0 to state `q`.
pub fn net_a_edges(q: i64) -> i64 {
    (q + 2).div_euclid(2) - 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use rstest::rstest;

    /// The level table of the module docs.
    #[rstest]
    #[case(0, (true, false))]
    #[case(1, (true, true))]
    #[case(2, (false, true))]
    #[case(3, (false, false))]
    #[case(4, (true, false))]
    #[case(-1, (false, false))]
    #[case(-2, (false, true))]
    #[case(-3, (true, true))]
    fn level_table(#[case] q: i64, #[case] expected: (bool, bool)) {
        assert_eq!(levels(q), expected);
    }

    /// The A-edge count formula on the values of the module docs and around them.
    #[rstest]
    #[case(0, 0)]
    #[case(1, 0)]
    #[case(2, 1)]
    #[case(3, 1)]
    #[case(4, 2)]
    #[case(-1, -1)]
    #[case(-2, -1)]
    #[case(-3, -2)]
    #[case(-4, -2)]
    fn a_edge_formula(#[case] q: i64, #[case] edges: i64) {
        assert_eq!(net_a_edges(q), edges);
    }

    /// Decoding the level sequence the way the thesis firmware does (on each A change, +1 if
    /// A != B else -1) gives `net_a_edges`, forwards and backwards, from any start.
    #[test]
    fn thesis_decoder_agrees_with_formula() {
        for start in -9..9 {
            for dir in [1i64, -1] {
                let mut count = 0;
                let mut q = start;
                let mut prev = levels(q);
                for _ in 0..50 {
                    q += dir;
                    let (a, b) = levels(q);
                    assert!(
                        (a != prev.0) ^ (b != prev.1),
                        "exactly one channel changes per state"
                    );
                    if a != prev.0 {
                        count += if a != b { 1 } else { -1 };
                    }
                    prev = (a, b);
                    assert_eq!(count, net_a_edges(q) - net_a_edges(start));
                }
                if dir > 0 {
                    assert_eq!(count, 25, "forward counts up");
                } else {
                    assert_eq!(count, -25, "backward counts down");
                }
            }
        }
    }

    /// 12 states per motor revolution; 1204.44 per wheel turn; no transition at angle 0; a
    /// reversed encoder counts the other way.
    #[test]
    fn geometry_matches_the_robot() {
        let enc = Encoder::new(100.37, 6, false);
        let per_turn = 2.0 * PI / enc.state_angle().0;
        assert!((per_turn - 1204.44).abs() < 1e-9);
        assert_eq!(enc.quadrature_index(Radians(0.0)), 0);
        assert_eq!(enc.quadrature_index(Radians(0.49 * enc.state_angle().0)), 0);
        assert_eq!(enc.quadrature_index(Radians(0.5 * enc.state_angle().0)), 1);
        assert_eq!(
            enc.quadrature_index(Radians(-0.51 * enc.state_angle().0)),
            -1
        );
        let rev = Encoder::new(100.37, 6, true);
        assert_eq!(rev.quadrature_index(Radians(2.0 * PI)), -1204);
        assert_eq!(enc.quadrature_index(Radians(2.0 * PI)), 1204);
    }
}
