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
//!
//! # Imperfections ([`Imperfections`]: the `encoder_missed_counts` and `encoder_glitches`
//! effects)
//!
//! Both are functions of the shaft angle, not of time, so the levels stay a function of the
//! wheel angle and [`crate::Robot::next_encoder_transition`] stays exact. Work in the
//! *position* `s = angle / dq + 0.5` (in the encoder's sense), so that `q = floor(s)` and
//! the boundary between states `n - 1` and `n` is at `s = n`. At boundary `n` channel A
//! changes if `n mod 4` is 0 (rising, forward) or 2 (falling), B if it is 1 or 3.
//!
//! - **Missed pulse**: A pulse `m` (A high over states `4m` and `4m + 1`) is missing with
//!   probability `p_miss`, drawn once per pulse from the robot's seed: A stays low, both its
//!   edges are gone (two counts lost; B keeps toggling, so the direction stays decodable). A
//!   boundary with no level change is *silent*: no transition is reported there.
//! - **Glitch**: after a boundary `n` whose edge is real, with probability `p_glitch`, the
//!   channel that changed falls back to its old level over `s` in `[n + w, n + 2w)`: three
//!   edges where there was one (`w` the glitch width in states). Its duration in time is
//!   `w` states at the wheel's speed: 0.5 motor degrees (`w` = 1/60) last 9.5 us at the thesis'
//!   set-point speed. A decoder that sees all three edges counts the same net total.
//!
//! The bench has its own injection point between the plant and the pins
//! (`hil::inject::EncoderFault`: dropouts, stuck lines, swapped lines, missed pairs at high
//! rates). These effects are the plant's: a flaw of the encoder itself, present in every
//! run of the robot that has it, at the same shaft positions for a given seed.

use std::f64::consts::PI;

use crate::rng::{hash_unit, stream};
use crate::units::Radians;

/// Flaws of one encoder (see the module docs); the default has none.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Imperfections {
    /// The robot's seed.
    pub seed: u64,
    /// Index of the side (0 left, 1 right), so the two encoders draw differently.
    pub side_index: u64,
    /// Probability that an A pulse is missing.
    pub missed_pulse_fraction: f64,
    /// Probability that a real edge is followed by a glitch.
    pub glitch_fraction: f64,
    /// Glitch width `w`, in quadrature states (one state is 30 motor degrees here).
    pub glitch_width_states: f64,
}

/// One wheel's encoder: state size, direction and flaws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoder {
    state_angle: f64,
    reversed: bool,
    flaws: Imperfections,
}

impl Encoder {
    /// An encoder behind a gearbox of `gear_ratio` with `a_edges_per_motor_rev` edges on
    /// channel A per motor revolution.
    pub fn new(gear_ratio: f64, a_edges_per_motor_rev: u32, reversed: bool) -> Self {
        Encoder {
            state_angle: 2.0 * PI / (2.0 * f64::from(a_edges_per_motor_rev) * gear_ratio),
            reversed,
            flaws: Imperfections::default(),
        }
    }

    /// The same encoder with `flaws`.
    pub fn with_imperfections(mut self, flaws: Imperfections) -> Self {
        self.flaws = flaws;
        self
    }

    /// Whether the encoder has any flaw (missed pulses or glitches).
    pub fn is_flawed(&self) -> bool {
        self.flaws.missed_pulse_fraction > 0.0 || self.flaws.glitch_fraction > 0.0
    }

    /// The position `s = angle / dq + 0.5` in the encoder's sense (module docs).
    pub fn position(&self, angle: Radians) -> f64 {
        let seen = if self.reversed { -angle.0 } else { angle.0 };
        seen / self.state_angle + 0.5
    }

    /// Whether A pulse `m` is missing.
    fn missed(&self, pulse: i64) -> bool {
        let p = self.flaws.missed_pulse_fraction;
        p > 0.0
            && hash_unit(
                self.flaws.seed,
                stream::MISSED_COUNTS + self.flaws.side_index,
                pulse,
            ) < p
    }

    /// Whether a level changes at boundary `n` (`n - 1` to `n`), ignoring glitches, and
    /// whether that channel is A.
    fn edge_at(&self, n: i64) -> (bool, bool) {
        let is_a = n.rem_euclid(2) == 0;
        let real = !is_a || !self.missed(n.div_euclid(4));
        (real, is_a)
    }

    /// Whether a glitch follows the boundary `n`.
    fn glitch_at(&self, n: i64) -> bool {
        let p = self.flaws.glitch_fraction;
        p > 0.0
            && self.edge_at(n).0
            && hash_unit(self.flaws.seed, stream::GLITCHES + self.flaws.side_index, n) < p
    }

    /// Levels `(A, B)` in state `q`, with missed pulses but without glitches.
    fn state_levels(&self, q: i64) -> (bool, bool) {
        let (a, b) = levels(q);
        (a && !self.missed(q.div_euclid(4)), b)
    }

    /// Levels `(A, B)` at position `s`, flaws included.
    pub fn levels_at(&self, s: f64) -> (bool, bool) {
        let floor = s.floor();
        let n = floor as i64;
        let (mut a, mut b) = self.state_levels(n);
        if self.glitch_at(n) {
            let w = self.flaws.glitch_width_states;
            if s >= floor + w && s < floor + 2.0 * w {
                if n.rem_euclid(2) == 0 {
                    a = !a;
                } else {
                    b = !b;
                }
            }
        }
        (a, b)
    }

    /// The boundaries (positions where a level may change) within state `n`, ascending:
    /// `n` itself and, after a glitching edge, `n + w` and `n + 2w`.
    fn boundaries_of(&self, n: i64) -> impl Iterator<Item = f64> {
        let floor = n as f64;
        let w = self.flaws.glitch_width_states;
        let glitch = self.glitch_at(n);
        [
            Some(floor),
            glitch.then_some(floor + w),
            glitch.then_some(floor + 2.0 * w),
        ]
        .into_iter()
        .flatten()
    }

    /// The first boundary crossed from position `s` moving up (`upward`) or down at which
    /// the watched levels become different from `from`: moving up, the levels change when
    /// the position reaches it (`s' >= boundary`); moving down, when it falls below it
    /// (`s' < boundary`). Silent boundaries are skipped. Watching channel A alone, the
    /// search gives up after [`WATCH_A_STATES`] states (every pulse missed) and returns the
    /// boundary it reached: a change of nothing, which a caller treats as a check-point.
    pub fn next_level_change(&self, s: f64, upward: bool, from: (bool, bool), watch: Watch) -> f64 {
        if !self.is_flawed() {
            // No silent boundaries and no glitches: the boundaries are the integers, and
            // four states in a row show every level pair, so the change comes within four.
            let n0 = s.floor() as i64;
            for k in 1..=4 {
                let (n, region) = if upward {
                    (n0 + k, n0 + k)
                } else {
                    (n0 + 1 - k, n0 - k)
                };
                if watch.differs(levels(region), from) {
                    return n as f64;
                }
            }
        }
        self.next_level_change_stepping(s, upward, from, watch)
    }

    /// [`Encoder::next_level_change`] by stepping through the boundaries of each state,
    /// flaws included.
    fn next_level_change_stepping(
        &self,
        s: f64,
        upward: bool,
        from: (bool, bool),
        watch: Watch,
    ) -> f64 {
        let n0 = s.floor() as i64;
        let limit = match watch {
            Watch::Both => i64::MAX,
            Watch::A => WATCH_A_STATES,
        };
        if upward {
            let mut last = s;
            for n in n0..n0.saturating_add(limit) {
                for b in self.boundaries_of(n) {
                    if b > s {
                        if watch.differs(self.levels_at(b), from) {
                            return b;
                        }
                        last = b;
                    }
                }
            }
            last
        } else {
            let mut last = s;
            for n in (n0.saturating_sub(limit)..=n0).rev() {
                let mut bounds = [0.0; 3];
                let mut len = 0;
                for b in self.boundaries_of(n) {
                    bounds[len] = b;
                    len += 1;
                }
                for i in (0..len).rev() {
                    let b = bounds[i];
                    if b > s {
                        continue;
                    }
                    // The region below `b`: from the boundary before it.
                    let below = match i {
                        0 => self.region_start_below(n),
                        _ => bounds[i - 1],
                    };
                    if watch.differs(self.levels_at(below), from) {
                        return b;
                    }
                    last = b;
                }
            }
            last
        }
    }

    /// The start of the last region of state `n - 1`.
    fn region_start_below(&self, n: i64) -> f64 {
        self.boundaries_of(n - 1).last().unwrap_or((n - 1) as f64)
    }

    /// Net signed A edges counted by the thesis' decoder over the boundaries crossed going
    /// from state `from` to state `to` (glitches excluded: a glitch once passed nets zero).
    pub fn decoded_between(&self, from: i64, to: i64) -> i64 {
        let mut count = 0;
        if to > from {
            for n in (from + 1)..=to {
                let (real, is_a) = self.edge_at(n);
                if real && is_a {
                    count += 1;
                }
            }
        } else {
            for n in (to + 1)..=from {
                let (real, is_a) = self.edge_at(n);
                if real && is_a {
                    count -= 1;
                }
            }
        }
        count
    }

    /// Net signed steps counted by a decoder of all four edges over the states crossed
    /// going from state `from` to state `to`, missed pulses included (glitches excluded: a
    /// glitch once passed nets zero).
    pub fn all_decoded_between(&self, from: i64, to: i64) -> i64 {
        let step =
            |(a, b): (bool, bool), (na, nb): (bool, bool)| i64::from(na ^ b) - i64::from(a ^ nb);
        let mut count = 0;
        if to > from {
            for n in (from + 1)..=to {
                count += step(self.state_levels(n - 1), self.state_levels(n));
            }
        } else {
            for n in (to + 1)..=from {
                count += step(self.state_levels(n), self.state_levels(n - 1));
            }
        }
        count
    }

    /// The decoder's count at position `s` relative to its count at the start of state
    /// `floor(s)`: -1 inside the glitch after a rising-going A boundary, else 0.
    pub fn glitch_count_offset(&self, s: f64) -> i64 {
        let floor = s.floor();
        let n = floor as i64;
        let w = self.flaws.glitch_width_states;
        if n.rem_euclid(2) == 0 && self.glitch_at(n) && s >= floor + w && s < floor + 2.0 * w {
            -1
        } else {
            0
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
        // Saturating conversion; 2^63 states are ~10^16 wheel turns.
        self.position(angle).floor() as i64
    }
}

/// Which channels a transition search watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Watch {
    /// A and B: every level change.
    Both,
    /// Channel A alone: for a reader who samples B only when it needs it (the bench raises
    /// B lazily when nothing can interrupt on it).
    A,
}

impl Watch {
    fn differs(self, now: (bool, bool), from: (bool, bool)) -> bool {
        match self {
            Watch::Both => now != from,
            Watch::A => now.0 != from.0,
        }
    }
}

/// How many states a search watching channel A alone looks through before it returns a
/// check-point (A changes every second state unless pulses are missed).
pub const WATCH_A_STATES: i64 = 256;

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

    /// A four-edge decoder counts every state crossed, signed; around a missing A pulse
    /// the two B edges net zero (four counts lost), and the count is the same whichever
    /// way the states are crossed.
    #[test]
    fn all_edges_decoded_between_states() {
        let e = Encoder::new(100.0, 6, false);
        assert_eq!(e.all_decoded_between(0, 37), 37);
        assert_eq!(e.all_decoded_between(37, -5), -42);
        let flawed = e.with_imperfections(Imperfections {
            seed: 3,
            missed_pulse_fraction: 0.5,
            ..Imperfections::default()
        });
        let missing = (0..10).filter(|&m| flawed.missed(m)).count() as i64;
        assert!(missing > 0 && missing < 10, "{missing}");
        assert_eq!(flawed.all_decoded_between(-1, 39), 40 - 4 * missing);
        assert_eq!(flawed.all_decoded_between(39, -1), -(40 - 4 * missing));
    }

    /// Without flaws the next change is found without stepping through the states' regions,
    /// at the boundary stepping finds: from inside a state and from a boundary, both ways,
    /// for every pair of levels it could be asked about.
    #[test]
    fn flawless_shortcut_agrees_with_stepping() {
        for reversed in [false, true] {
            let enc = Encoder::new(100.37, 6, reversed);
            assert!(!enc.is_flawed());
            for k in -40..40 {
                for s in [k as f64, k as f64 + 0.25, k as f64 + 0.999_999] {
                    for from in [(false, false), (false, true), (true, false), (true, true)] {
                        for upward in [true, false] {
                            for watch in [Watch::A, Watch::Both] {
                                assert_eq!(
                                    enc.next_level_change(s, upward, from, watch),
                                    enc.next_level_change_stepping(s, upward, from, watch),
                                    "s {s}, from {from:?}, upward {upward}, {watch:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// Watching A alone finds the first boundary at which A changes: the same one as
    /// stepping through every level change (A and B), with missed pulses and glitches.
    #[rstest]
    #[case(0.0, 0.0)]
    #[case(0.3, 0.0)]
    #[case(0.0, 0.25)]
    #[case(0.5, 0.5)]
    fn watching_a_skips_b_only(#[case] missed: f64, #[case] glitches: f64) {
        let enc = Encoder::new(100.37, 6, false).with_imperfections(Imperfections {
            seed: 11,
            side_index: 1,
            missed_pulse_fraction: missed,
            glitch_fraction: glitches,
            glitch_width_states: 0.2,
        });
        for k in 0..400 {
            let s = -50.0 + k as f64 * 0.2537;
            for upward in [true, false] {
                let from = enc.levels_at(s);
                let a_only = enc.next_level_change(s, upward, from, Watch::A);
                // Step through every change until A differs.
                let mut at = s;
                let mut levels = from;
                let expected = loop {
                    let b = enc.next_level_change(at, upward, levels, Watch::Both);
                    let next = if upward {
                        enc.levels_at(b)
                    } else {
                        enc.levels_at(b - 1e-9)
                    };
                    if next.0 != from.0 {
                        break b;
                    }
                    at = if upward { b } else { b - 1e-9 };
                    levels = next;
                };
                assert!(
                    (a_only - expected).abs() < 1e-6,
                    "s {s} up {upward}: A-only {a_only} vs stepped {expected}"
                );
            }
        }
    }

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
