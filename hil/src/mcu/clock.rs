//! Emulated time: a CPU clock and cycle counts, with exact conversions.
//!
//! The bench keeps time in CPU cycles (an integer, exact). The plant keeps time
//! in seconds (`f64`); conversions go through [`Clock`] only, so the rounding
//! rule is written once: an event the plant places at time `t` happens at the
//! first cycle at or after `t`.

use plant_model::{Seconds, TimeGrid};

/// A CPU clock frequency in hertz.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Clock {
    hz: u32,
}

impl Clock {
    /// The Arduino Mega's 16 MHz crystal.
    pub const MEGA_16MHZ: Clock = Clock { hz: 16_000_000 };

    pub const fn new(hz: u32) -> Self {
        Self { hz }
    }

    pub const fn hz(self) -> u32 {
        self.hz
    }

    /// The cycles as the plant's time grid: one rounding rule for both.
    pub const fn grid(self) -> TimeGrid {
        TimeGrid::new(self.hz)
    }

    /// Seconds elapsed at `cycles`.
    pub fn seconds(self, cycles: u64) -> Seconds {
        self.grid().time(cycles)
    }

    /// The first cycle at or after `t` (0 for t <= 0).
    pub fn cycle_at_or_after(self, t: Seconds) -> u64 {
        self.grid().index_at_or_after(t)
    }

    /// Cycles in `t` seconds, rounded to the nearest cycle.
    pub fn cycles_in(self, t: Seconds) -> u64 {
        (t.0 * self.hz as f64).round().max(0.0) as u64
    }

    /// Cycles in `ms` milliseconds (exact for the clocks we use).
    pub const fn cycles_per_ms(self) -> u64 {
        self.hz as u64 / 1000
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_at_or_after_never_precedes_the_time() {
        let clock = Clock::MEGA_16MHZ;
        for i in 0..10_000u64 {
            let t = Seconds(i as f64 * 1.234_567e-4);
            let c = clock.cycle_at_or_after(t);
            assert!(clock.seconds(c).0 >= t.0, "cycle {c} precedes {t:?}");
            if c > 0 {
                assert!(clock.seconds(c - 1).0 < t.0, "cycle {c} is not the first");
            }
        }
    }

    #[test]
    fn whole_seconds_are_exact() {
        let clock = Clock::MEGA_16MHZ;
        assert_eq!(clock.cycle_at_or_after(Seconds(1.0)), 16_000_000);
        assert_eq!(clock.seconds(8_000_000).0, 0.5);
    }
}
