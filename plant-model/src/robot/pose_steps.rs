//! Stepping the ground: the pose is integrated on a fixed grid of [`MAX_POSE_STEP`]
//! instants (and at the wheels' turning points when backlash needs them), so the pose is the
//! same however the bench advances the plant.

use super::wheel::Wheel;
use super::MAX_POSE_STEP;
use crate::ground::Ground;
use crate::side::{PerSide, Side};
use crate::units::Seconds;

/// The index `k` (an integer) of the last instant `k * MAX_POSE_STEP` of the pose grid at or
/// before `t`.
fn pose_grid_index(t: Seconds) -> f64 {
    let step = MAX_POSE_STEP.0;
    let mut k = (t.0 / step).floor().max(0.0);
    // The division rounds: make sure the instant is not after `t`, and the next one is.
    while k > 0.0 && k * step > t.0 {
        k -= 1.0;
    }
    while (k + 1.0) * step <= t.0 {
        k += 1.0;
    }
    k
}

/// The last instant of the pose grid at or before `t`.
pub(super) fn pose_grid_at_or_before(t: Seconds) -> Seconds {
    Seconds(pose_grid_index(t) * MAX_POSE_STEP.0)
}

/// Steps `ground` from `from` to `to` under the wheels' current segments: at the pose grid's
/// instants in between, at the wheels' turning points when the ground needs them
/// (backlash), and at `to`.
pub(super) fn integrate(ground: &mut Ground, wheels: &PerSide<Wheel>, from: Seconds, to: Seconds) {
    if to <= from {
        return;
    }
    let mut turns = [to; 4];
    let mut n = 0;
    if ground.needs_turning_points() {
        for side in Side::BOTH {
            for t in wheels.get(side).segment.turning_points(from, to) {
                turns[n] = t;
                n += 1;
            }
        }
        turns[..n].sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let step = MAX_POSE_STEP.0;
    let mut k = pose_grid_index(from) + 1.0;
    let mut turn = 0;
    let mut at = from;
    while at < to {
        let next_turn = if turn < n { turns[turn].0 } else { to.0 };
        let next = Seconds((k * step).min(next_turn).min(to.0));
        ground.step(PerSide {
            left: wheels.left.angle_at(next),
            right: wheels.right.angle_at(next),
        });
        at = next;
        while k * step <= at.0 {
            k += 1.0;
        }
        while turn < n && turns[turn] <= at {
            turn += 1;
        }
    }
}
