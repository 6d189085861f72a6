//! Where a monotone condition first holds: the first time, to [`TRANSITION_RESOLUTION`],
//! or the first instant of a sampling grid. The transition search locates an encoder
//! boundary by Newton's method, then settles the answer here on the closed form itself, so
//! that it agrees bit for bit with advancing the plant.

use super::TRANSITION_RESOLUTION;
use crate::units::{Seconds, TimeGrid};

/// How finely a transition time is wanted.
#[derive(Debug, Clone, Copy)]
pub(super) enum Resolution {
    /// To [`TRANSITION_RESOLUTION`].
    Continuous,
    /// The first instant of the grid.
    Grid(TimeGrid),
}

impl Resolution {
    /// How closely Newton's method must locate the crossing first.
    pub(super) fn tolerance(self) -> f64 {
        match self {
            Resolution::Continuous => TRANSITION_RESOLUTION.0,
            // A twentieth of a step: the grid search then checks one or two instants.
            Resolution::Grid(grid) => 0.05 / grid.hz() as f64,
        }
    }
}

/// The first time in `[a, b]` at which `crossed` holds, to [`TRANSITION_RESOLUTION`], given
/// that it does not at `a`, does at `b`, is monotone between, and changes near `guess`:
/// a bracket widening around the guess, then bisection on `crossed` itself, so the answer
/// agrees exactly with evaluating the segment.
pub(super) fn first_crossed_near(
    a: Seconds,
    b: Seconds,
    guess: Seconds,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let mut lo = a;
    let mut hi;
    let mut eps = TRANSITION_RESOLUTION.0;
    loop {
        let above = Seconds((guess.0 + eps).min(b.0));
        if crossed(above) {
            hi = above;
            break;
        }
        lo = Seconds(lo.0.max(above.0));
        eps *= 4.0;
    }
    let mut eps = TRANSITION_RESOLUTION.0;
    loop {
        let below = Seconds((guess.0 - eps).max(lo.0));
        if !crossed(below) {
            lo = below;
            break;
        }
        hi = Seconds(hi.0.min(below.0));
        eps *= 4.0;
    }
    while hi.0 - lo.0 > TRANSITION_RESOLUTION.0 {
        let mid = Seconds(lo.0 + 0.5 * (hi.0 - lo.0));
        if mid <= lo || mid >= hi {
            break;
        }
        if crossed(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The first instant of `grid` in `[a, b]` at which `crossed` holds, under the same
/// conditions as [`first_crossed_near`]; the first instant after `b` if none in it does (the
/// crossing fell within the last step before `b`). Galloping from the instant after
/// `guess`, then bisection: with a good guess, two evaluations.
pub(super) fn first_crossed_on_grid(
    grid: TimeGrid,
    a: Seconds,
    b: Seconds,
    guess: Seconds,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let first = grid.index_at_or_after(a);
    let last = grid.index_at_or_after(b);
    let k = grid.index_at_or_after(guess).clamp(first, last);
    first_crossed_from(grid, first, last, k, crossed)
}

/// [`first_crossed_on_grid`] with the indices of `a`, `b` and the guess (clamped to them)
/// worked out: `first`, `last`, `k`.
fn first_crossed_from(
    grid: TimeGrid,
    first: u64,
    last: u64,
    k: u64,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let holds = |k: u64| k >= last || crossed(grid.time(k));
    if holds(k) {
        // Every instant below `k` is below `last`: there `holds` is `crossed`.
        return first_crossed_below(grid, first, k, crossed);
    }
    // Invariant of the bisection: !holds(lo), holds(hi).
    let mut lo = k;
    let mut step = 1;
    let hi = loop {
        let above = (lo + step).min(last);
        if holds(above) {
            break above;
        }
        lo = above;
        step *= 2;
    };
    bisect(grid, lo, hi, &holds)
}

/// The first instant from `first` to `hi` at which `crossed` holds, given that it holds at
/// `hi` (and, being monotone, from there on): a search down from `hi`.
pub(super) fn first_crossed_below(
    grid: TimeGrid,
    first: u64,
    mut hi: u64,
    crossed: &impl Fn(Seconds) -> bool,
) -> Seconds {
    let holds = |k: u64| crossed(grid.time(k));
    let mut step = 1;
    let lo = loop {
        if hi == first {
            return grid.time(first);
        }
        let below = hi.saturating_sub(step).max(first);
        if !holds(below) {
            break below;
        }
        hi = below;
        step *= 2;
    };
    bisect(grid, lo, hi, &holds)
}

/// Bisection to the first instant that holds, given `!holds(lo)` and `holds(hi)`.
fn bisect(grid: TimeGrid, mut lo: u64, mut hi: u64, holds: &impl Fn(u64) -> bool) -> Seconds {
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if holds(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    grid.time(hi)
}
