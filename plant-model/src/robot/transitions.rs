//! The bench's question: when do a wheel's encoder levels change next? Asked of the
//! wheel's present motion, and across the plant's announced internal changes on a copy of
//! the dynamics advanced to each.

use super::crossing::Resolution;
use super::{Robot, TRANSITION_HORIZON};
use crate::encoder::Watch;
use crate::side::Side;
use crate::units::{Seconds, TimeGrid};

impl Robot {
    /// The earliest time after [`Robot::now`] at which the encoder levels of `side` change
    /// under the current inputs, or `None` if they do not change within
    /// [`TRANSITION_HORIZON`] (ask again after the next input change, or after advancing).
    ///
    /// The answer takes the announced internal changes ([`Robot::next_internal_change`])
    /// into account: the search continues past each on a copy of the dynamics advanced to it.
    ///
    /// # Guarantee
    ///
    /// With `t_next` the answer and no input change or fault before it:
    /// - `advance_to(t)` for any `t` from `t_next` up to the following transition (one state
    ///   is about 210 us at the top speed of the nominal robot, 24.5 rad/s; a glitch of the
    ///   `encoder_glitches` effect is as short as its width at the wheel's speed) leaves
    ///   [`Robot::encoder_levels`] changed in exactly one channel, and without encoder
    ///   effects [`Robot::quadrature_index`] changed by exactly one. So the bench may round
    ///   `t_next` up to its next emulated cycle (62.5 ns).
    /// - There is a time `t_lo` with `t_next - t_lo <= max(1e-12 s, one f64 step of t_next)`
    ///   at which the levels have not changed yet: `advance_to(t_next - 1e-9)` leaves them
    ///   unchanged.
    ///
    /// Both hold bit for bit because the answer is found by bisection on the very function
    /// `advance_to` evaluates (the wheel's closed-form angle, through the encoder's level
    /// function), after Newton's method has located the boundary crossing. The angle is split
    /// at the speed's zero crossing (a wheel driven against its motion turns round) and at a
    /// Coulomb stop, so a boundary reached only after turning back is found too; boundaries
    /// where no level changes (a missed pulse) are skipped.
    pub fn next_encoder_transition(&self, side: Side) -> Option<Seconds> {
        self.next_encoder_transition_watching(side, Watch::Both)
    }

    /// [`Robot::next_encoder_transition`] for the channels in `watch` only. Watching A
    /// alone, a search that meets only missed pulses for [`crate::encoder::WATCH_A_STATES`]
    /// states returns the time it got there, at which nothing on A changes.
    pub fn next_encoder_transition_watching(&self, side: Side, watch: Watch) -> Option<Seconds> {
        self.search_transition(side, watch, Resolution::Continuous)
    }

    /// [`Robot::next_encoder_transition_watching`] for a reader that samples the levels on
    /// `grid` (the bench: at its CPU cycles): the index `k` of the first instant after now
    /// at which the levels differ, found without solving for the time to
    /// [`TRANSITION_RESOLUTION`](super::TRANSITION_RESOLUTION). Exact on the grid: the levels
    /// at `grid.time(k)` differ from now's, and at `grid.time(k - 1)` (if after now) they do
    /// not. Now must be an instant of the grid, or the answer may be an instant before now's
    /// next.
    pub fn next_encoder_transition_on(
        &self,
        side: Side,
        watch: Watch,
        grid: TimeGrid,
    ) -> Option<u64> {
        self.search_transition(side, watch, Resolution::Grid(grid))
            .map(|t| grid.index_at_or_after(t))
    }

    /// [`Robot::next_encoder_transition_on`] as if the robot had been advanced to instant
    /// `after` of the grid with its inputs unchanged: the transition after that one, for a
    /// reader that plans several ahead. `after` must lie from now up to the next internal
    /// change ([`Robot::next_internal_change`]); the answer is the one
    /// [`Robot::next_encoder_transition_on`] gives once the robot is there.
    pub fn next_encoder_transition_on_after(
        &self,
        side: Side,
        watch: Watch,
        grid: TimeGrid,
        after: u64,
    ) -> Option<u64> {
        let start = grid.time(after);
        debug_assert!(start >= self.dynamics.now, "plans ahead only");
        debug_assert!(
            self.dynamics
                .next_internal_change()
                .is_none_or(|c| start <= c),
            "plans beyond the next internal change"
        );
        self.search_transition_from(side, watch, Resolution::Grid(grid), start)
            .map(|t| grid.index_at_or_after(t))
    }

    fn search_transition(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
    ) -> Option<Seconds> {
        self.search_transition_from(side, watch, resolution, self.dynamics.now)
    }

    /// The search from `start` (from now up to the next internal change).
    fn search_transition_from(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
        start: Seconds,
    ) -> Option<Seconds> {
        let wheel = self.dynamics.wheels.get(side);
        let from = wheel.levels(start);
        let end = start + TRANSITION_HORIZON;
        let change = self.dynamics.next_internal_change().filter(|&c| c < end);
        if let Some(t) =
            wheel.next_transition(start, change.unwrap_or(end), from, watch, resolution)
        {
            return Some(t);
        }
        let change = change?;
        if wheel.rests_whatever_the_voltage(start) {
            return None;
        }
        self.search_transition_past(side, watch, resolution, from, change, end)
    }

    /// The search past the internal change at `change` (the levels there `from`), up to
    /// `end`: on a copy of the dynamics advanced to each change in turn.
    #[cold]
    fn search_transition_past(
        &self,
        side: Side,
        watch: Watch,
        resolution: Resolution,
        from: (bool, bool),
        change: Seconds,
        end: Seconds,
    ) -> Option<Seconds> {
        let mut dynamics = self.dynamics.clone();
        dynamics.advance_to(change);
        let mut at = change;
        loop {
            let change = dynamics.next_internal_change().filter(|&c| c < end);
            let until = change.unwrap_or(end);
            let wheel = dynamics.wheels.get(side);
            if let Some(t) = wheel.next_transition(at, until, from, watch, resolution) {
                return Some(t);
            }
            let change = change?;
            if wheel.rests_whatever_the_voltage(at) {
                return None;
            }
            dynamics.advance_to(change);
            at = change;
        }
    }
}
