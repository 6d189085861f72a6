//! Distance from encoder counts (thesis `Desplazamiento`) and the stop rule of
//! a straight leg.

use crate::robot::MM_PER_COUNT;

/// Sum of the two wheels' count deltas at which a leg of `leg_mm` millimetres
/// is complete: the mean wheel distance `(dL + dR) / 2 * MM_PER_COUNT` reaches
/// `leg_mm` exactly when `dL + dR >= ceil(2 * leg_mm / MM_PER_COUNT)`.
///
/// Computed in `f32` as `2.0 * leg_mm / MM_PER_COUNT` then rounded up.
/// A length that is not positive (or NaN) gives 0: the leg ends at once.
/// Saturates at `i32::MAX`.
pub const fn leg_target_count_sum(leg_mm: f32) -> i32 {
    ceil_to_i32(2.0 * leg_mm / MM_PER_COUNT)
}

/// Mean distance travelled by the two wheels, in millimetres, as the thesis
/// computes it: `(Constante * dR + Constante * dL) / 2`.
pub const fn mean_distance_mm(d_left: i32, d_right: i32) -> f32 {
    (MM_PER_COUNT * d_right as f32 + MM_PER_COUNT * d_left as f32) / 2.0
}

/// `ceil(x)` for `x > 0`, 0 for everything else, saturating at `i32::MAX`.
const fn ceil_to_i32(x: f32) -> i32 {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    // 2^31 as f32; anything at or above it does not fit.
    if x >= 2_147_483_648.0 {
        return i32::MAX;
    }
    let t = x as i32;
    if (t as f32) < x {
        t + 1
    } else {
        t
    }
}

// 2 m: 4000 / 0.1669339526 = 23961.57 -> 23962 counts (both wheels together).
const _: () = assert!(leg_target_count_sum(2000.0) == 23962);
const _: () = assert!(leg_target_count_sum(0.0) == 0);
const _: () = assert!(leg_target_count_sum(-5.0) == 0);
const _: () = assert!(leg_target_count_sum(f32::NAN) == 0);
const _: () = assert!(leg_target_count_sum(1.0e30) == i32::MAX);
// An exact multiple stays put: 2 * 0.5 * MM_PER_COUNT / MM_PER_COUNT.
const _: () = assert!(ceil_to_i32(3.0) == 3 && ceil_to_i32(3.0001) == 4 && ceil_to_i32(0.2) == 1);
