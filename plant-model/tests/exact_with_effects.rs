//! With every effect on, the plant stays exact and event-consistent: the bench loop sees one
//! level change per planned transition and a decoder count equal to `a_edges`; the planned
//! times agree with a brute-force scan, even when the battery's voltage changes before them
//! and nobody re-plans; and the ground effects do not move a single encoder edge.

mod common;

use common::{all_effects_config, duty};
use plant_model::effects::{
    Backlash, DistanceScale, FloorNoise, StraightSlip, Toe, TurnSlip, WheelDiameterRatio,
    WheelbaseRatio,
};
use plant_model::{Robot, RobotConfig, Seconds, Side};

/// One emulated AVR cycle at 16 MHz.
const CYCLE: f64 = 62.5e-9;

/// From each time on: the signed drives of the left and right wheels.
const SCRIPT: [(f64, f64, f64); 6] = [
    (0.0, 0.9, 0.85),
    (0.7, 0.0, 0.0),
    (0.75, -0.8, 0.8),
    (1.2, 0.0, 0.0),
    (1.25, -0.9, -0.9),
    (1.9, 1.0, 1.0),
];

fn set(robot: &mut Robot, left: f64, right: f64) {
    for (side, d) in [(Side::Left, left), (Side::Right, right)] {
        if d >= 0.0 {
            robot.set_bridge(side, duty(d), duty(0.0));
        } else {
            robot.set_bridge(side, duty(0.0), duty(-d));
        }
    }
}

/// Runs the bench loop over [`SCRIPT`] until `end`; returns the transition times of each
/// side. Re-plans a wheel after its transition and both after an input change; after an
/// internal change too when `replan_internal`.
fn bench_loop(config: &RobotConfig, end: f64, replan_internal: bool) -> [Vec<f64>; 2] {
    let mut robot = Robot::new(config, 17).unwrap();
    let mut times = [Vec::new(), Vec::new()];
    let mut next_input = 0;
    let mut planned = [None, None];
    let mut levels = Side::BOTH.map(|s| robot.encoder_levels(s));
    let mut counts = Side::BOTH.map(|s| robot.a_edges(s));
    while robot.now().0 < end {
        let input_at = SCRIPT.get(next_input).map_or(end, |s| s.0);
        let internal_at = if replan_internal {
            robot.next_internal_change().map_or(f64::INFINITY, |t| t.0)
        } else {
            f64::INFINITY
        };
        let (edge_at, _) = planned
            .iter()
            .enumerate()
            .filter_map(|(i, t): (usize, &Option<Seconds>)| t.map(|t| (t.0, i)))
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        if edge_at < input_at.min(internal_at) {
            let t = ((edge_at / CYCLE).ceil() * CYCLE).min(input_at.min(internal_at));
            robot.advance_to(Seconds(t)).unwrap();
            // Every wheel whose transition fell in this cycle.
            for (i, side) in Side::BOTH.into_iter().enumerate() {
                let Some(due) = planned[i].filter(|d| d.0 <= t) else {
                    continue;
                };
                let now = robot.encoder_levels(side);
                let was = levels[i];
                assert!(
                    (now.0 != was.0) ^ (now.1 != was.1),
                    "{side}: one channel at {due}"
                );
                if now.0 != was.0 {
                    counts[i] += if now.0 != now.1 { 1 } else { -1 };
                }
                levels[i] = now;
                times[i].push(due.0);
                planned[i] = robot.next_encoder_transition(side);
            }
        } else if internal_at <= input_at {
            robot.advance_to(Seconds(internal_at)).unwrap();
            planned = Side::BOTH.map(|s| robot.next_encoder_transition(s));
        } else {
            robot.advance_to(Seconds(input_at)).unwrap();
            if let Some(&(_, left, right)) = SCRIPT.get(next_input) {
                set(&mut robot, left, right);
            }
            next_input += 1;
            planned = Side::BOTH.map(|s| robot.next_encoder_transition(s));
        }
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            assert_eq!(
                robot.encoder_levels(side),
                levels[i],
                "{side}: no unplanned change"
            );
            assert_eq!(counts[i], robot.a_edges(side), "{side}: decoder = a_edges");
        }
    }
    times
}

/// Every effect on, the bench's loop: one channel per planned transition, the decoder's
/// count always `a_edges`, no level change the plan did not announce; with or without
/// re-planning at the battery's internal changes, the same transitions (the plan already
/// looks across them).
#[test]
fn bench_loop_with_every_effect() {
    let config = all_effects_config();
    let replanned = bench_loop(&config, 2.3, true);
    let planned_once = bench_loop(&config, 2.3, false);
    assert!(
        replanned[0].len() > 3000,
        "{} transitions",
        replanned[0].len()
    );
    assert_eq!(replanned, planned_once);
}

/// The ground effects (wheel sizes, slips, floor, backlash, toe) leave every encoder edge
/// where it was.
#[test]
fn ground_effects_do_not_move_encoder_edges() {
    let plain = RobotConfig::default();
    let mut ground = plain.clone();
    let e = &mut ground.effects;
    e.wheel_diameter_ratio = Some(WheelDiameterRatio {
        right_over_left_ratio: 1.03,
    });
    e.wheelbase_ratio = Some(WheelbaseRatio {
        actual_over_nominal_ratio: 0.95,
    });
    e.distance_scale = Some(DistanceScale {
        odometry_over_actual_ratio: 1.02,
    });
    e.turn_slip = Some(TurnSlip { fraction: 0.05 });
    e.straight_slip = Some(StraightSlip {
        left_fraction: 0.02,
        right_fraction: 0.01,
    });
    e.floor_noise = Some(FloorNoise {
        heading_deg_per_sqrt_m: 2.0,
        lateral_mm_per_sqrt_m: 5.0,
        turn_heading_deg_per_sqrt_m: Some(3.0),
        stretch_mm: 20.0,
    });
    e.backlash = Some(Backlash {
        left_wheel_deg: 2.0,
        right_wheel_deg: 1.0,
    });
    e.toe = Some(Toe {
        left_deg: 2.0,
        right_deg: -1.0,
    });
    assert_eq!(
        bench_loop(&ground, 2.3, true),
        bench_loop(&plain, 2.3, true)
    );
}

/// First time after `now` at which the levels of `side` differ, by stepping a copy of the
/// robot `step` at a time and bisecting the step where they changed.
fn brute_force(robot: &Robot, side: Side, step: f64, window: f64) -> Option<f64> {
    let from = robot.encoder_levels(side);
    let now = robot.now().0;
    let levels_at = |t: f64| {
        let mut probe = robot.clone();
        probe.advance_to(Seconds(t)).unwrap();
        probe.encoder_levels(side)
    };
    let mut scan = robot.clone();
    let mut prev = now;
    let mut k = 1.0;
    while prev < now + window {
        let t = now + k * step;
        scan.advance_to(Seconds(t)).unwrap();
        if scan.encoder_levels(side) != from {
            let (mut lo, mut hi) = (prev, t);
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if levels_at(mid) != from {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = t;
        k += 1.0;
    }
    None
}

/// At states along a run with every effect on (a battery update every 10 ms, so most
/// answers lie past one), the planned transition equals a brute-force scan of the levels in
/// 0.5 us steps (glitches last about 5 us here).
#[test]
fn planned_transitions_agree_with_brute_force() {
    let mut config = all_effects_config();
    if let Some(sag) = &mut config.effects.battery_sag {
        sag.update_interval_s = 0.01;
    }
    if let Some(g) = &mut config.effects.encoder_glitches {
        g.left_fraction = 0.3;
        g.right_fraction = 0.3;
    }
    let mut robot = Robot::new(&config, 5).unwrap();
    set(&mut robot, 0.9, -0.7);
    let mut checked = 0;
    for k in 0..40 {
        robot
            .advance_to(Seconds(0.05 + 0.0137 * f64::from(k)))
            .unwrap();
        if k == 20 {
            set(&mut robot, 0.0, 0.0);
        }
        for side in Side::BOTH {
            let exact = robot.next_encoder_transition(side).map(|t| t.0);
            let scanned = brute_force(&robot, side, 0.5e-6, 0.02);
            match (exact, scanned) {
                (Some(e), Some(s)) => {
                    assert!((e - s).abs() <= 1e-9, "{side} at {k}: {e} vs {s}");
                    checked += 1;
                }
                (Some(e), None) => assert!(e > robot.now().0 + 0.02, "scan missed {e}"),
                (None, Some(s)) => panic!("{side} at {k}: none planned, scan found {s}"),
                (None, None) => {}
            }
        }
    }
    assert!(checked > 40, "{checked} checked");
}
