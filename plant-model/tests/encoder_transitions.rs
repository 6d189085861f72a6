//! `next_encoder_transition` is exact and consistent with `advance_to`: it agrees with a
//! brute-force scan of the encoder state for random input histories (including a wheel driven
//! against its motion, which turns round), and stepping from transition to transition the way
//! the bench does yields one state change per step and a level sequence that the thesis'
//! decoder counts to exactly `a_edges`.

mod common;

use common::duty;
use plant_model::encoder::Watch;
use plant_model::{Robot, RobotConfig, Seconds, Side, TimeGrid};
use proptest::prelude::*;

/// One emulated AVR cycle at 16 MHz.
const CYCLE: f64 = 62.5e-9;

fn robot_with(reversed: bool) -> Robot {
    let mut config = RobotConfig::default();
    config.encoder.reversed_left = reversed;
    config.encoder.reversed_right = reversed;
    Robot::new(&config, 7).unwrap()
}

/// The robot after `history` on `side` (bridge inputs, each held for its time in s), then
/// `last` held for `settle` s.
fn robot_after(
    reversed: bool,
    side: Side,
    history: &[((f64, f64), f64)],
    last: (f64, f64),
    settle: f64,
) -> Robot {
    let mut robot = robot_with(reversed);
    let mut t = 0.0;
    for &((in1, in2), dt) in history {
        robot.set_bridge(side, duty(in1), duty(in2));
        t += dt;
        robot.advance_to(Seconds(t)).unwrap();
    }
    robot.set_bridge(side, duty(last.0), duty(last.1));
    robot.advance_to(Seconds(t + settle)).unwrap();
    robot
}

fn q_at(robot: &Robot, side: Side, t: f64) -> i64 {
    let mut probe = robot.clone();
    probe.advance_to(Seconds(t)).unwrap();
    probe.quadrature_index(side)
}

/// First time after `now` (to 1e-12 s) at which the state differs, by stepping a copy of the
/// robot forward `step` at a time and bisecting the step where the state changed; `None` if
/// it does not change before `now + window`.
fn brute_force_transition(robot: &Robot, side: Side, step: f64, window: f64) -> Option<f64> {
    let q0 = robot.quadrature_index(side);
    let now = robot.now().0;
    let mut scan = robot.clone();
    let mut prev = now;
    let mut k = 1.0;
    while prev < now + window {
        let t = now + k * step;
        scan.advance_to(Seconds(t)).unwrap();
        if scan.quadrature_index(side) != q0 {
            let (mut lo, mut hi) = (prev, t);
            while hi - lo > 1e-12 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if q_at(robot, side, mid) != q0 {
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

/// Checks the documented guarantee at one answer.
fn check_guarantee(robot: &Robot, side: Side, t_next: f64) {
    let q0 = robot.quadrature_index(side);
    let now = robot.now().0;
    assert!(t_next > now);
    for t in [t_next, t_next + CYCLE] {
        let q = q_at(robot, side, t);
        assert_eq!(
            (q - q0).abs(),
            1,
            "one state further at {t} (t_next {t_next})"
        );
    }
    if t_next - 1e-9 > now {
        assert_eq!(
            q_at(robot, side, t_next - 1e-9),
            q0,
            "unchanged just before"
        );
    }
}

fn inputs() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        (0.0f64..=1.0).prop_map(|d| (d, 0.0)),
        (0.0f64..=1.0).prop_map(|d| (0.0, d)),
        Just((0.0, 0.0)),
        Just((1.0, 1.0)),
        Just((1.0, 0.0)),
        Just((0.0, 1.0)),
        (0.0f64..=1.0, 0.0f64..=1.0),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// After a random history of bridge inputs, for a random new input, the answer equals the
    /// brute-force first change to 1e-9 s and keeps the guarantee; `None` only if the scan
    /// sees no change either.
    #[test]
    fn agrees_with_brute_force(
        history in prop::collection::vec((inputs(), 0.0f64..0.25), 0..4),
        last in inputs(),
        left in any::<bool>(),
        reversed in any::<bool>(),
        settle in 0.0f64..0.01,
    ) {
        let side = if left { Side::Left } else { Side::Right };
        let robot = robot_after(reversed, side, &history, last, settle);

        let window = 0.3;
        let exact = robot.next_encoder_transition(side).map(|s| s.0);
        let scanned = brute_force_transition(&robot, side, 10e-6, window);
        match (exact, scanned) {
            (Some(e), Some(s)) => {
                prop_assert!((e - s).abs() <= 1e-9, "exact {e} vs scanned {s}");
                check_guarantee(&robot, side, e);
            }
            (Some(e), None) => {
                prop_assert!(e > robot.now().0 + window, "scan missed {e}");
                check_guarantee(&robot, side, e);
            }
            (None, Some(s)) => prop_assert!(false, "exact found nothing, scan found {s}"),
            (None, None) => {}
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// On a grid (the bench's 16 MHz cycles), after a random history that leaves the robot on
    /// a grid instant: the answer is the first instant with the levels changed (they differ
    /// there and not one instant before) and the continuous answer rounded up to the grid,
    /// watching both channels or A alone.
    #[test]
    fn grid_answer_is_exact_on_the_grid(
        history in prop::collection::vec((inputs(), 1u64..4_000_000), 0..4),
        last in inputs(),
        left in any::<bool>(),
        reversed in any::<bool>(),
        settle in 0u64..160_000,
        watch_a in any::<bool>(),
    ) {
        let grid = TimeGrid::new(16_000_000);
        let side = if left { Side::Left } else { Side::Right };
        let watch = if watch_a { Watch::A } else { Watch::Both };
        let mut robot = robot_with(reversed);
        let mut k = 0;
        for ((in1, in2), dk) in history {
            robot.set_bridge(side, duty(in1), duty(in2));
            k += dk;
            robot.advance_to(grid.time(k)).unwrap();
        }
        robot.set_bridge(side, duty(last.0), duty(last.1));
        k += settle;
        robot.advance_to(grid.time(k)).unwrap();

        let on_grid = robot.next_encoder_transition_on(side, watch, grid);
        let continuous = robot.next_encoder_transition_watching(side, watch);
        prop_assert_eq!(on_grid, continuous.map(|t| grid.index_at_or_after(t)));
        if let Some(next) = on_grid {
            prop_assert!(next > k);
            let levels = |i: u64| {
                let mut probe = robot.clone();
                probe.advance_to(grid.time(i)).unwrap();
                probe.encoder_levels(side)
            };
            let from = robot.encoder_levels(side);
            let differs = |l: (bool, bool)| if watch_a { l.0 != from.0 } else { l != from };
            prop_assert!(differs(levels(next)), "unchanged at the answer {next}");
            if next - 1 > k {
                prop_assert!(!differs(levels(next - 1)), "changed before the answer {next}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// Planning transitions ahead on the grid gives the ones found by advancing to each and
    /// searching again, watching both channels or A alone, with or without a battery that
    /// sags (whose steps the plan must not run past).
    #[test]
    fn planning_ahead_equals_stepping(
        (in1, in2) in inputs(),
        left in any::<bool>(),
        watch_a in any::<bool>(),
        settle in 0u64..1_600_000,
        sag in any::<bool>(),
    ) {
        let grid = TimeGrid::new(16_000_000);
        let side = if left { Side::Left } else { Side::Right };
        let watch = if watch_a { Watch::A } else { Watch::Both };
        let mut config = RobotConfig::default();
        if sag {
            config.effects.battery_sag = Some(plant_model::effects::BatterySag {
                open_circuit_full_v: 8.4,
                open_circuit_empty_v: 6.6,
                capacity_mah: 1000.0,
                initial_charge_fraction: 0.8,
                internal_resistance_ohm: 0.2,
                motor_resistance_ohm: 10.0,
                idle_current_a: 0.15,
                update_interval_s: 0.05,
            });
        }
        let mut robot = Robot::new(&config, 5).unwrap();
        robot.set_bridge(side, duty(in1), duty(in2));
        robot.advance_to(grid.time(settle)).unwrap();

        let mut stepped = robot.clone();
        let Some(first) = stepped.next_encoder_transition_on(side, watch, grid) else {
            return Ok(());
        };
        let limit = robot.next_internal_change().map(|t| grid.index_at_or_after(t));
        let mut planned = vec![first];
        while planned.len() < 12 {
            let after = *planned.last().unwrap();
            if limit.is_some_and(|l| after >= l) {
                break;
            }
            match robot.next_encoder_transition_on_after(side, watch, grid, after) {
                Some(k) => planned.push(k),
                None => break,
            }
        }
        for pair in planned.windows(2) {
            stepped.advance_to(grid.time(pair[0])).unwrap();
            prop_assert_eq!(stepped.next_encoder_transition_on(side, watch, grid), Some(pair[1]));
        }
    }
}

/// Builds the state in which turning round matters: a wheel spun up, left to coast almost to
/// a stop (so it is within a state or so of stopping), then driven the other way.
fn almost_stopped_then_reversed(
    side: Side,
    reversed: bool,
    spin: f64,
    coast: f64,
    back: f64,
) -> Robot {
    let mut robot = robot_with(reversed);
    robot.set_bridge(side, duty(spin), duty(0.0));
    robot.advance_to(Seconds(0.2)).unwrap();
    robot.set_bridge(side, duty(0.0), duty(0.0));
    robot.advance_to(Seconds(0.2 + coast)).unwrap();
    robot.set_bridge(side, duty(0.0), duty(back));
    robot
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Near a stop, driven backwards: the next change is either the forward boundary reached
    /// just before turning round or the backward one after it; either way the answer equals
    /// the brute-force scan and keeps the guarantee.
    #[test]
    fn agrees_with_brute_force_when_turning_round(
        spin in 0.7f64..=1.0,
        coast in 0.15f64..0.6,
        back in 0.6f64..=1.0,
        left in any::<bool>(),
        reversed in any::<bool>(),
    ) {
        let side = if left { Side::Left } else { Side::Right };
        let robot = almost_stopped_then_reversed(side, reversed, spin, coast, back);
        let exact = robot.next_encoder_transition(side).expect("driven: it moves").0;
        let scanned = brute_force_transition(&robot, side, 2e-6, 0.3).expect("within 0.3 s");
        prop_assert!((exact - scanned).abs() <= 1e-9, "exact {exact} vs scanned {scanned}");
        check_guarantee(&robot, side, exact);
    }
}

/// Both kinds of turning-round case occur in the generator's range: the state changes
/// forward first for some coasting times, backward first for others.
#[test]
fn turning_round_cases_cover_both_directions() {
    let mut seen = [false; 2];
    for i in 0..60 {
        let coast = 0.15 + 0.0075 * f64::from(i);
        let robot = almost_stopped_then_reversed(Side::Right, false, 0.9, coast, 0.8);
        let q0 = robot.quadrature_index(Side::Right);
        let t = robot.next_encoder_transition(Side::Right).unwrap();
        let q = q_at(&robot, Side::Right, t.0);
        let turned = robot.wheel_speed(Side::Right).0 > 0.0 && q < q0;
        seen[usize::from(turned)] = true;
    }
    assert_eq!(seen, [true, true]);
}

/// A wheel spinning forward and then driven full reverse slows, stops and turns back; the
/// transition just past the turning point (the state entered last on the way up is left again
/// on the way down) is found, not skipped.
#[test]
fn finds_the_transition_after_turning_round() {
    let mut robot = robot_with(false);
    let side = Side::Right;
    robot.set_bridge(side, duty(1.0), duty(0.0));
    robot.advance_to(Seconds(0.3)).unwrap();
    robot.set_bridge(side, duty(0.0), duty(1.0));
    let mut turned = false;
    let mut last_q = robot.quadrature_index(side);
    let mut last_dir = 1;
    while robot.now().0 < 1.0 {
        let t = robot.next_encoder_transition(side).unwrap();
        let brute = brute_force_transition(&robot, side, 5e-6, 0.2).unwrap();
        assert!((t.0 - brute).abs() < 1e-9, "{} vs {brute}", t.0);
        robot.advance_to(t).unwrap();
        let q = robot.quadrature_index(side);
        let dir = q - last_q;
        assert_eq!(dir.abs(), 1);
        if dir != last_dir {
            assert!(!turned, "turns round once");
            turned = true;
        }
        last_q = q;
        last_dir = dir;
    }
    assert!(turned);
    assert!(robot.wheel_speed(side).0 < 0.0);
}

/// A wheel at rest under coast or brake has no transition; a coasting wheel creeping to a
/// stop short of the next boundary has none either.
#[test]
fn no_transition_when_nothing_will_move() {
    let mut robot = robot_with(false);
    assert_eq!(robot.next_encoder_transition(Side::Left), None);
    robot.set_bridge(Side::Left, duty(1.0), duty(1.0));
    assert_eq!(robot.next_encoder_transition(Side::Left), None);
    // Inside the dead band: no drive.
    robot.set_bridge(Side::Left, duty(0.5), duty(0.0));
    assert_eq!(robot.next_encoder_transition(Side::Left), None);
    // Spin up, then coast for long enough that the remaining travel is below one state.
    robot.set_bridge(Side::Left, duty(1.0), duty(0.0));
    robot.advance_to(Seconds(0.2)).unwrap();
    robot.set_bridge(Side::Left, duty(0.0), duty(0.0));
    robot.advance_to(Seconds(2.0)).unwrap();
    assert_eq!(robot.next_encoder_transition(Side::Left), None);
}

/// The bench loop: advance to each next transition rounded up to a 62.5 ns cycle, forward
/// then backward. Every step changes the state by one, exactly one channel toggles, and the
/// thesis decoder (on each A change: +1 if A != B, else -1) run on the levels counts exactly
/// `a_edges`, positive forward and negative backward, for both wheels and both encoder senses.
#[test]
fn bench_loop_decodes_to_a_edges() {
    for reversed in [false, true] {
        let mut robot = robot_with(reversed);
        let mut counts = [0i64; 2];
        let mut levels = [
            robot.encoder_levels(Side::Left),
            robot.encoder_levels(Side::Right),
        ];
        let script = [
            (0.0, 0.9, 0.0),
            (0.6, 0.0, 0.0),
            (0.9, 0.0, 0.95),
            (1.6, 1.0, 1.0),
        ];
        let mut next_change = 1;
        robot.set_bridge(Side::Left, duty(script[0].1), duty(script[0].2));
        robot.set_bridge(Side::Right, duty(script[0].1), duty(script[0].2));
        let mut forward_edges = None;
        while robot.now().0 < 2.2 {
            let change_at = script.get(next_change).map_or(2.2, |s| s.0);
            let edge_at = Side::BOTH
                .iter()
                .filter_map(|&s| robot.next_encoder_transition(s))
                .fold(f64::INFINITY, |a, t| a.min(t.0));
            if edge_at < change_at {
                let cycles = (edge_at / CYCLE).ceil();
                robot.advance_to(Seconds(cycles * CYCLE)).unwrap();
            } else {
                robot.advance_to(Seconds(change_at)).unwrap();
                if let Some(&(_, in1, in2)) = script.get(next_change) {
                    if next_change == 2 {
                        forward_edges = Some(robot.a_edges(Side::Right));
                    }
                    robot.set_bridge(Side::Left, duty(in1), duty(in2));
                    robot.set_bridge(Side::Right, duty(in1), duty(in2));
                }
                next_change += 1;
            }
            for (i, side) in Side::BOTH.into_iter().enumerate() {
                let (a, b) = robot.encoder_levels(side);
                let (pa, pb) = levels[i];
                assert!(!(a != pa && b != pb), "never both channels at once");
                if a != pa {
                    counts[i] += if a != b { 1 } else { -1 };
                }
                levels[i] = (a, b);
                assert_eq!(counts[i], robot.a_edges(side), "{side} reversed={reversed}");
            }
        }
        let sign = if reversed { -1 } else { 1 };
        let forward = forward_edges.unwrap();
        assert!(sign * forward > 500, "drove forward: {forward} edges");
        assert!(
            sign * robot.a_edges(Side::Right) < sign * forward,
            "then came back"
        );
        assert!(
            robot.wheel_speed(Side::Right).0 < 0.0 || robot.wheel_speed(Side::Right).0.abs() < 1e-3
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Within `encoder_travel_time_bound` of any instant, the encoder position moves less
    /// than the states asked for: after a random history, sampled over the bound from a
    /// random instant (a wheel speeding up, slowing down, turning round or coasting to a
    /// stop).
    #[test]
    fn travel_time_bound_holds(
        history in prop::collection::vec((inputs(), 0.0f64..0.25), 0..4),
        last in inputs(),
        left in any::<bool>(),
        reversed in any::<bool>(),
        settle in 0.0f64..0.05,
        states in 0.25f64..2.0,
    ) {
        let side = if left { Side::Left } else { Side::Right };
        let robot = robot_after(reversed, side, &history, last, settle);
        let bound = robot.encoder_travel_time_bound(side, states).0;
        prop_assert!(bound > 0.0);
        let span = bound.min(0.5);
        let state_angle = robot.encoder(side).state_angle().0;
        let from = robot.wheel_angle(side).0;
        let mut probe = robot.clone();
        for k in 1..=200 {
            probe.advance_to(Seconds(robot.now().0 + span * k as f64 / 200.0)).unwrap();
            let moved = (probe.wheel_angle(side).0 - from).abs() / state_angle;
            prop_assert!(moved < states, "moved {moved} states within the bound ({bound} s)");
        }
    }
}
