//! The plant's randomness: a seeded SplitMix64 generator and a keyed hash, with no
//! dependency and only integer arithmetic, so the same seed gives the same draws on every
//! machine.
//!
//! Each random effect draws from its own *stream* (the robot's seed mixed with a fixed
//! stream number), so switching one effect on does not change another's draws. Draws are
//! made per unit of the effect's own progress (a stretch of floor travelled, an encoder
//! pulse), never per call of [`crate::Robot::advance_to`], so how often the bench advances
//! the plant does not change what is drawn.
//!
//! The generator is public because the rest of the workspace draws from it too (the gap
//! diagnosis' synthetic runs and resampling, the bench's fault dice): one definition of
//! SplitMix64, so the same seed means the same bits everywhere. Its API:
//!
//! * [`SplitMix64::new`] (a plant stream), [`SplitMix64::from_seed`] (a bare seed),
//!   [`SplitMix64::next_u64`], [`SplitMix64::next_unit`],
//!   [`SplitMix64::next_standard_normal`];
//! * [`mix`], SplitMix64's output function, and [`unit`], 64 bits to `[0, 1)`, for
//!   counter-based draws (the `i`-th output of a stream is `mix((i + 1)·γ + state)`).
//!
//! Every value it gives is pinned: changing one changes every seeded run of the workspace.

/// Stream numbers: one per random effect and side.
pub(crate) mod stream {
    /// `floor_noise`, rolling.
    pub const FLOOR_NOISE: u64 = 1;
    /// `floor_noise`, turning on the spot.
    pub const FLOOR_NOISE_TURNING: u64 = 2;
    /// `encoder_missed_counts`, plus the side index.
    pub const MISSED_COUNTS: u64 = 16;
    /// `encoder_glitches`, plus the side index.
    pub const GLITCHES: u64 = 32;
}

/// γ, SplitMix64's increment: 2⁶⁴ divided by the golden ratio, made odd.
pub const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output function: a bijective mix of all 64 bits.
pub fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A uniform number in `[0, 1)` from 64 random bits (the top 53).
pub fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 / (1u64 << 53) as f64
}

/// A keyed hash: the same `(seed, stream, index)` always gives the same uniform number in
/// `[0, 1)`. Used where a random property belongs to a place rather than to a moment (an
/// encoder pulse that is missed is missed each time the shaft passes it).
pub(crate) fn hash_unit(seed: u64, stream: u64, index: i64) -> f64 {
    let key = mix(seed ^ mix(stream.wrapping_mul(GOLDEN)));
    unit(mix(key ^ (index as u64).wrapping_mul(GOLDEN)))
}

/// SplitMix64 (Steele, Lea, Flood 2014): a 64-bit state advanced by a constant and mixed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// The generator of `stream` for the robot seeded with `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        SplitMix64 {
            state: mix(seed ^ mix(stream.wrapping_mul(GOLDEN))),
        }
    }

    /// A generator from a bare seed, with no stream: its state is `seed ^ γ` (so that seed 0
    /// does not start from state 0). The seeding of the gap diagnosis' draws and of the
    /// bench's fault dice.
    pub fn from_seed(seed: u64) -> Self {
        SplitMix64 {
            state: seed ^ GOLDEN,
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GOLDEN);
        mix(self.state)
    }

    /// Uniform in `[0, 1)`.
    pub fn next_unit(&mut self) -> f64 {
        unit(self.next_u64())
    }

    /// A standard normal draw, approximated by the Irwin-Hall sum of twelve uniforms minus
    /// six: mean 0, variance 1, tails cut at 6 sigma. Sums and no transcendental functions, so
    /// it is bit-identical on every machine (a Box-Muller draw would depend on the platform's
    /// `ln` and `cos`).
    pub fn next_standard_normal(&mut self) -> f64 {
        let mut sum = 0.0;
        for _ in 0..12 {
            sum += self.next_unit();
        }
        sum - 6.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same seed and stream give the same sequence; another seed or stream another one.
    #[test]
    fn seeded_and_separate_streams() {
        let draw = |seed, stream| {
            let mut g = SplitMix64::new(seed, stream);
            (0..4).map(|_| g.next_u64()).collect::<Vec<_>>()
        };
        assert_eq!(draw(7, 1), draw(7, 1));
        assert_ne!(draw(7, 1), draw(8, 1));
        assert_ne!(draw(7, 1), draw(7, 2));
        assert_eq!(hash_unit(3, 16, -5), hash_unit(3, 16, -5));
        assert_ne!(hash_unit(3, 16, -5), hash_unit(3, 16, 5));
    }

    /// Pinned values: a change of the generator shows up here (and would change every
    /// seeded run).
    #[test]
    fn pinned_sequence() {
        let mut g = SplitMix64::new(0, 0);
        let first = g.next_u64();
        assert_eq!(first, mix(mix(0).wrapping_add(GOLDEN)));
        assert!((0.0..1.0).contains(&unit(first)));
    }

    /// `from_seed` draws what the gap diagnosis and the bench's dice drew when each had its
    /// own copy of SplitMix64 (values computed outside Rust): their seeded outputs rest on it.
    #[test]
    fn from_seed_is_pinned() {
        let draw = |seed| {
            let mut g = SplitMix64::from_seed(seed);
            [g.next_u64(), g.next_u64(), g.next_u64()]
        };
        assert_eq!(
            draw(0),
            [
                0x6e78_9e6a_a1b9_65f4,
                0x06c4_5d18_8009_454f,
                0xf88b_b8a8_724c_81ec
            ]
        );
        assert_eq!(
            draw(7),
            [
                0xec77_9c36_93f8_8501,
                0xfed9_eeb4_936d_e39d,
                0x6f9f_b04b_092b_d30a
            ]
        );
    }

    /// The normal approximation has mean 0 and variance 1 (to sampling error).
    #[test]
    fn normal_draws_have_unit_variance() {
        let mut g = SplitMix64::new(11, 1);
        let n = 40_000;
        let draws: Vec<f64> = (0..n).map(|_| g.next_standard_normal()).collect();
        let mean = draws.iter().sum::<f64>() / f64::from(n);
        let var = draws.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / f64::from(n - 1);
        assert!(mean.abs() < 0.02, "mean {mean}");
        assert!((var - 1.0).abs() < 0.03, "variance {var}");
    }
}
