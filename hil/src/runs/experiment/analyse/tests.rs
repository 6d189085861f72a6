//! The debounce and the segment rules.

use super::*;

/// A motion event at `cycle`, the robot at the origin (the rules read
/// only the motion and the cycle).
pub(in crate::runs::experiment) fn at(motion: Motion, cycle: u64) -> MotionEvent {
    MotionEvent {
        motion,
        at: Snapshot {
            cycle,
            x_mm: 0.0,
            y_mm: 0.0,
            theta_rad: 0.0,
            left_count: None,
            right_count: None,
            left_edges: 0,
            right_edges: 0,
            left_mm: 0.0,
            right_mm: 0.0,
        },
    }
}

const MS: u64 = 16_000;

/// A leg with a 1 us stale level (both inputs low while the firmware
/// writes the second) is one leg; a stop of a PWM period or more is two.
#[test]
fn a_level_shorter_than_a_pwm_period_does_not_split_a_leg() {
    let stale = 510; // one period of the 31.37 kHz PWM
    let leg = |gap: u64| {
        vec![
            at(Motion::Forward, 0),
            at(Motion::Stopped, 1000 * MS),
            at(Motion::Forward, 1000 * MS + gap),
            at(Motion::Stopped, 2000 * MS),
        ]
    };
    let n = |m: &[MotionEvent]| segments(&debounced(m, stale), 30 * MS).len();
    assert_eq!(n(&leg(16)), 1);
    assert_eq!(n(&leg(509)), 1);
    assert_eq!(n(&leg(510 + 30 * MS)), 2);
}

/// A control period with one wheel at zero inside a leg is the same leg;
/// a turn goes on through the phase with one motor cut.
#[test]
fn a_leg_goes_on_through_a_period_with_one_wheel_at_zero() {
    let m = vec![
        at(Motion::Forward, 0),
        at(Motion::OneWheel, 500 * MS),
        at(Motion::Forward, 515 * MS),
        at(Motion::Stopped, 2000 * MS),
        at(Motion::SpinCw, 4000 * MS),
        at(Motion::OneWheel, 4500 * MS),
        at(Motion::Stopped, 4600 * MS),
    ];
    let s = segments(&debounced(&m, 510), 30 * MS);
    assert_eq!(s.len(), 2, "{s:?}");
    assert_eq!((s[0].start, s[0].stop), (0, 3));
    assert_eq!((s[1].start, s[1].stop), (4, 6));
}
