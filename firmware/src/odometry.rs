//! Distance from encoder counts (thesis `Desplazamiento`) and the stop rules
//! of a straight leg and a spin turn, for any wheel geometry: every function
//! takes the distance per count it works with (the robust build's come from
//! its settings, the thesis build's is the thesis' `Constante`).

/// Sum of the two wheels' count deltas at which a leg of `leg_mm` millimetres
/// is complete with `mm_per_count` on both wheels: the mean wheel distance
/// `(dL + dR) / 2 * mm_per_count` reaches `leg_mm` exactly when
/// `dL + dR >= ceil(2 * leg_mm / mm_per_count)`.
///
/// Computed in `f32` as `2.0 * leg_mm / mm_per_count` then rounded up.
/// A length that is not positive (or NaN) gives 0: the leg ends at once.
/// Saturates at `i32::MAX`.
pub const fn leg_target_count_sum(leg_mm: f32, mm_per_count: f32) -> i32 {
    ceil_to_i32(2.0 * leg_mm / mm_per_count)
}

/// Mean distance travelled by the two wheels, in millimetres, as the thesis
/// computes it: `(Constante * dR + Constante * dL) / 2`.
pub const fn mean_distance_mm(d_left: i32, d_right: i32, mm_per_count: f32) -> f32 {
    (mm_per_count * d_right as f32 + mm_per_count * d_left as f32) / 2.0
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

/// `ceil(x)` for `x > 0`, 0 for everything else, saturating at `i64::MAX`.
const fn ceil_to_i64(x: f32) -> i64 {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    // 2^63 as f32.
    if x >= 9_223_372_036_854_775_808.0 {
        return i64::MAX;
    }
    let t = x as i64;
    if (t as f32) < x {
        t + 1
    } else {
        t
    }
}

/// Counts one wheel turns in a spin in place of `angle_deg` about the axle's
/// centre: the wheel's arc `A * b / 2` over its distance per count
/// `c * mm_per_count`, rounded up (the thesis compares `abs(count) >= 612`
/// and `>= 815.5`, which with b = 130 mm, c = 1 and its 0.16693 mm per count
/// are these rounded-up values). Computed in `f32`.
pub const fn spin_target_counts(angle_deg: f32, wheelbase_mm: f32, c: f32, mm_per_count: f32) -> i32 {
    let arc_mm = angle_deg * (core::f32::consts::PI / 180.0) * (wheelbase_mm / 2.0);
    ceil_to_i32(arc_mm / (c * mm_per_count))
}

/// Fixed-point 1.0 of the leg weights (2^15).
pub const WEIGHT_ONE: i32 = 1 << 15;

/// Distance per count the leg's weights are relative to: the larger of the
/// two wheels', so no weight exceeds `c * WEIGHT_ONE` (the same value when
/// both wheels are alike, and then each weight is exactly `c`'s).
pub const fn leg_reference_mm(mm_per_count_left: f32, mm_per_count_right: f32) -> f32 {
    if mm_per_count_left > mm_per_count_right {
        mm_per_count_left
    } else {
        mm_per_count_right
    }
}

/// Weight of one count of a wheel with correction factor `c` and distance
/// per count `mm_per_count` in the leg's stop rule, relative to the leg's
/// `reference_mm` ([`leg_reference_mm`]): `c * mm_per_count / reference_mm`
/// in fixed point ([`WEIGHT_ONE`] = 1.0), rounded to nearest. The ratio is
/// taken first, so a wheel at the reference weighs exactly `c`.
pub const fn leg_weight(c: f32, mm_per_count: f32, reference_mm: f32) -> i32 {
    let w = c * (mm_per_count / reference_mm) * WEIGHT_ONE as f32;
    if w.is_nan() || w <= 0.0 {
        0
    } else {
        (w + 0.5) as i32
    }
}

/// Target of a leg: it ends when
/// `wL * dL + wR * dR >= ceil(2 * leg_mm / reference_mm * 2^15)`, i.e. when
/// the mean corrected wheel distance `(cL mL dL + cR mR dR) / 2` reaches
/// `leg_mm` (up to the rounding of the weights to 2^-15). In `i64`: with
/// 0.001 mm per count a 5 000 mm leg (the protocol's limits,
/// `henrytwo_protocol::limits`) is 3.3e11.
pub const fn leg_target(leg_mm: f32, reference_mm: f32) -> i64 {
    ceil_to_i64(2.0 * leg_mm / reference_mm * WEIGHT_ONE as f32)
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

// Geometry-free properties of the rounding.
const _: () = assert!(ceil_to_i32(3.0) == 3 && ceil_to_i32(3.0001) == 4 && ceil_to_i32(0.2) == 1);
const _: () = assert!(ceil_to_i32(0.0) == 0 && ceil_to_i32(-5.0) == 0 && ceil_to_i32(f32::NAN) == 0);
const _: () = assert!(ceil_to_i32(1.0e30) == i32::MAX && ceil_to_i64(1.0e30) == i64::MAX);
const _: () = assert!(ceil_to_i64(3.0) == 3 && ceil_to_i64(3.0001) == 4 && ceil_to_i64(-1.0) == 0);
const _: () = assert!(leg_trip_ahead(1, WEIGHT_ONE) == 1 && leg_trip_ahead(0, WEIGHT_ONE) == 1);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Settings;
    use henrytwo_protocol::limits;

    /// Henrytwo's distance per count (both wheels alike).
    fn henrytwo_mm() -> f32 {
        let m = Settings::DEFAULT.mm_per_count;
        assert_eq!(m.left, m.right);
        m.left
    }

    /// Another robot: 0.567 mm per count, 360 counts per wheel turn.
    const OTHER_MM: f32 = 0.567;

    #[test]
    fn henrytwo_legs_and_turns_stop_at_the_thesis_counts() {
        let m = henrytwo_mm();
        // 4000 / 0.1669339526 = 23961.57 -> 23962 counts, both wheels together.
        assert_eq!(leg_target_count_sum(2000.0, m), 23962);
        assert_eq!(leg_target_count_sum(0.0, m), 0);
        assert_eq!(leg_target_count_sum(-5.0, m), 0);
        assert_eq!(leg_target_count_sum(f32::NAN, m), 0);
        assert_eq!(leg_target_count_sum(1.0e30, m), i32::MAX);
        // b = 130 mm: 90 degrees -> 611.6 -> 612; 120 degrees -> 815.51 -> 816,
        // which is also what the thesis' `abs(long) >= 815.5` accepts first.
        let b = Settings::DEFAULT.wheelbase_mm;
        assert_eq!(spin_target_counts(90.0, b, 1.0, m), 612);
        assert_eq!(spin_target_counts(120.0, b, 1.0, m), 816);
    }

    #[test]
    fn henrytwo_weighted_leg_stops_where_the_count_sum_does() {
        let m = henrytwo_mm();
        let r = leg_reference_mm(m, m);
        let t = leg_target(2000.0, r);
        assert!(t > 23961 * (1 << 15) && t <= 23962 * (1 << 15), "{t}");
        let w = leg_weight(1.0, m, r);
        assert_eq!(w, 1 << 15);
        assert_eq!(leg_progress(w, w, 11981, 11981), 23962 * (1 << 15));
        assert_eq!(leg_trip_ahead(t, w), 11981);
        assert!(leg_target(5000.0, r) < i32::MAX as i64);
    }

    #[test]
    fn another_geometry_sets_the_leg_and_turn_targets() {
        // 4000 / 0.567 = 7054.67 -> 7055 counts together.
        assert_eq!(leg_target_count_sum(2000.0, OTHER_MM), 7055);
        let r = leg_reference_mm(OTHER_MM, OTHER_MM);
        let t = leg_target(2000.0, r);
        assert!(t > 7054 * (1 << 15) && t <= 7055 * (1 << 15), "{t}");
        // 90 degrees on b = 180 mm: a 141.37 mm arc / 0.567 = 249.3 -> 250.
        assert_eq!(spin_target_counts(90.0, 180.0, 1.0, OTHER_MM), 250);
        assert!((mean_distance_mm(100, 300, OTHER_MM) - 113.4).abs() < 1e-4);
    }

    #[test]
    fn wheels_with_different_distances_per_count_weigh_their_counts_by_them() {
        // Left 0.5 mm, right 0.4 mm per count: the left is the reference.
        let r = leg_reference_mm(0.5, 0.4);
        assert_eq!(r, leg_reference_mm(0.4, 0.5));
        let (wl, wr) = (leg_weight(1.0, 0.5, r), leg_weight(1.0, 0.4, r));
        assert_eq!(wl, 1 << 15);
        assert_eq!(wr, (0.8f32 * (1 << 15) as f32 + 0.5) as i32);
        // A 500 mm leg: 1000 left counts (500 mm) and 1250 right ones (500 mm);
        // the right weight rounds down a little, so it takes 1251.
        let t = leg_target(500.0, r);
        assert!(leg_progress(wl, wr, 1000, 1249) < t);
        assert!(leg_progress(wl, wr, 1000, 1251) >= t);
    }

    #[test]
    fn a_fine_encoder_on_a_long_leg_does_not_overflow() {
        // The finest encoder on the longest leg the protocol accepts: 0.001 mm
        // per count, 5000 mm, 10^7 counts together.
        let (leg_mm, mm) = (limits::LEG_LENGTH_MM.max, limits::MM_PER_COUNT.min);
        assert_eq!((leg_mm, mm), (5000.0, 0.001));
        let t = leg_target(leg_mm, mm);
        assert!(t > i32::MAX as i64);
        let w = leg_weight(1.0, mm, mm);
        assert!(leg_progress(w, w, 4_999_000, 4_999_000) < t);
        assert!(leg_progress(w, w, 5_000_100, 5_000_100) >= t);
    }

    /// A wheel whose factor, distance per count or reference is negative or
    /// not a number weighs nothing (never a negative count weight).
    #[test]
    fn a_negative_or_nan_weight_is_zero() {
        assert_eq!(leg_weight(-1.0, 0.1, 0.1), 0);
        assert_eq!(leg_weight(1.0, -0.2, 0.1), 0);
        assert_eq!(leg_weight(1.0, 0.1, -0.1), 0);
        assert_eq!(leg_weight(f32::NAN, 0.1, 0.1), 0);
        assert_eq!(leg_weight(1.0, 0.1, 0.1), WEIGHT_ONE);
    }

    /// A trip armed `ceil(remaining / 2w)` counts ahead, exactly when that
    /// divides, at least 1, at most `i32::MAX`; a wheel of no weight (or
    /// nothing left to go) is armed one count ahead instead of dividing by 0.
    #[test]
    fn a_trip_is_armed_half_the_remaining_progress_ahead() {
        let w = WEIGHT_ONE;
        assert_eq!(leg_trip_ahead(10 * w as i64, w), 5);
        assert_eq!(leg_trip_ahead(10 * w as i64 + 1, w), 6);
        assert_eq!(leg_trip_ahead(1000, 0), 1);
        assert_eq!(leg_trip_ahead(-7, w), 1);
        assert_eq!(leg_trip_ahead(i64::MAX / 2, 1), i32::MAX);
    }
}
