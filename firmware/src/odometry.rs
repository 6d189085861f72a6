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

/// Counts one wheel turns in a spin in place of `angle_deg` about the axle's
/// centre: the wheel's arc `A * b / 2` over its distance per count
/// `c * MM_PER_COUNT`, rounded up (the thesis compares `abs(count) >= 612`
/// and `>= 815.5`, which with b = 130 mm and c = 1 are these rounded-up
/// values). Computed in `f32`.
pub const fn spin_target_counts(angle_deg: f32, wheelbase_mm: f32, c: f32) -> i32 {
    let arc_mm = angle_deg * (core::f32::consts::PI / 180.0) * (wheelbase_mm / 2.0);
    ceil_to_i32(arc_mm / (c * MM_PER_COUNT))
}

// b = 130 mm: 90 degrees -> 611.6 -> 612; 120 degrees -> 815.51 -> 816,
// which is also what `abs(long) >= 815.5` accepts first.
const _: () = assert!(spin_target_counts(90.0, 130.0, 1.0) == 612);
const _: () = assert!(spin_target_counts(120.0, 130.0, 1.0) == 816);

/// Fixed-point 1.0 of the leg weights (2^15).
pub const WEIGHT_ONE: i32 = 1 << 15;

/// Weight of one count of a wheel with correction factor `c` in the leg's
/// stop rule (fixed point, [`WEIGHT_ONE`] = 1.0), rounded to nearest.
pub const fn leg_weight(c: f32) -> i32 {
    let w = c * WEIGHT_ONE as f32;
    if w.is_nan() || w <= 0.0 {
        0
    } else {
        (w + 0.5) as i32
    }
}

/// Target of a leg: it ends when
/// `wL * dL + wR * dR >= ceil(2 * leg_mm / MM_PER_COUNT * 2^15)`, i.e. when
/// the mean corrected wheel distance `(cL dL + cR dR) / 2 * MM_PER_COUNT`
/// reaches `leg_mm` (up to the rounding of c to 2^-15). Fits an `i32` for
/// legs up to 5 000 mm (the protocol's maximum).
pub const fn leg_target(leg_mm: f32) -> i32 {
    ceil_to_i32(2.0 * leg_mm / MM_PER_COUNT * WEIGHT_ONE as f32)
}

/// Progress of a leg: `wL * dL + wR * dR` (in `i64`: no overflow).
pub const fn leg_progress(w_left: i32, w_right: i32, d_left: i32, d_right: i32) -> i64 {
    w_left as i64 * d_left as i64 + w_right as i64 * d_right as i64
}

/// How far ahead (counts) to arm a wheel's trip during a leg with `remaining`
/// weighted progress still to go: `ceil(remaining / (2 w))`, at least 1.
/// Before either wheel moves that far, the sum cannot reach the target:
/// `wL (aL - 1) + wR (aR - 1) < remaining / 2 + remaining / 2`.
pub const fn leg_trip_ahead(remaining: i64, w: i32) -> i32 {
    if w <= 0 || remaining <= 0 {
        return 1;
    }
    let two_w = 2 * w as i64;
    let a = (remaining + two_w - 1) / two_w;
    if a > i32::MAX as i64 {
        i32::MAX
    } else if a < 1 {
        1
    } else {
        a as i32
    }
}

// With c = 1 a leg stops at the same count sum as the integer rule:
// 2 m -> 23962 counts together.
const _: () = {
    let t = leg_target(2000.0);
    assert!(t > 23961 * (1 << 15) && t <= 23962 * (1 << 15));
    assert!(leg_weight(1.0) == 1 << 15);
    assert!(leg_target(5000.0) < i32::MAX);
    let w = leg_weight(1.0);
    assert!(leg_progress(w, w, 11981, 11981) == 23962 * (1 << 15));
    assert!(leg_trip_ahead(t as i64, w) == 11981);
    assert!(leg_trip_ahead(1, w) == 1 && leg_trip_ahead(0, w) == 1);
};
