//! The robot moves as a differential drive should: straight on equal wheels, curving towards
//! the slower wheel, turning on the spot when the wheels turn opposite ways, with exact arcs
//! at constant wheel speeds; advancing in one long step or many short ones gives the same
//! result; time never runs backwards; the same calls give the same bits.

mod common;

use approx::assert_relative_eq;
use common::{duty, symmetric_config};
use plant_model::{Error, Millimetres, Robot, RobotConfig, Seconds, Side};
use rstest::rstest;

fn drive(robot: &mut Robot, left: (f64, f64), right: (f64, f64)) {
    robot.set_bridge(Side::Left, duty(left.0), duty(left.1));
    robot.set_bridge(Side::Right, duty(right.0), duty(right.1));
}

/// Identical wheels and motors driven alike roll straight along +x: y and theta stay exactly
/// 0 and x is the distance each wheel rolled; backwards the same along -x.
#[rstest]
#[case::forward((0.9, 0.0), 1.0)]
#[case::backward((0.0, 0.9), -1.0)]
fn equal_wheels_drive_straight(#[case] input: (f64, f64), #[case] sign: f64) {
    let mut robot = Robot::new(&symmetric_config(), 1).unwrap();
    drive(&mut robot, input, input);
    robot.advance_to(Seconds(1.5)).unwrap();
    let pose = robot.pose();
    assert_eq!(pose.y().0, 0.0);
    assert_eq!(pose.theta().0, 0.0);
    let rolled = robot.distance_travelled(Side::Left);
    assert_eq!(rolled, robot.distance_travelled(Side::Right));
    assert!(sign * rolled.0 > 200.0, "rolled {rolled}");
    assert_relative_eq!(pose.x().0, rolled.0, epsilon = 1e-9);
}

/// With the right wheel faster the robot curves left (heading and y grow); with the left
/// faster it curves right.
#[rstest]
#[case::right_faster_turns_left((0.75, 0.0), (0.95, 0.0), 1.0)]
#[case::left_faster_turns_right((0.95, 0.0), (0.75, 0.0), -1.0)]
#[case::backing_right_faster((0.0, 0.75), (0.0, 0.95), -1.0)]
fn unequal_speeds_curve_towards_the_slower_wheel(
    #[case] left: (f64, f64),
    #[case] right: (f64, f64),
    #[case] turn: f64,
) {
    let mut robot = Robot::new(&symmetric_config(), 1).unwrap();
    drive(&mut robot, left, right);
    robot.advance_to(Seconds(0.5)).unwrap();
    let pose = robot.pose();
    assert!(turn * pose.theta().0 > 0.1, "heading {}", pose.theta());
    let forward = robot.distance_travelled(Side::Left).0.signum();
    assert!(turn * forward * pose.y().0 > 1.0, "y {}", pose.y());
    // Heading is the difference of the wheel arcs over the wheelbase.
    let dl = robot.distance_travelled(Side::Left).0;
    let dr = robot.distance_travelled(Side::Right).0;
    assert_relative_eq!(pose.theta().0, (dr - dl) / 130.0, epsilon = 1e-12);
}

/// Opposite drives of equal size spin the robot on the spot: counter-clockwise when the right
/// wheel goes forward; the midpoint between the wheels stays at the origin.
#[rstest]
#[case::counter_clockwise((0.0, 0.9), (0.9, 0.0), 1.0)]
#[case::clockwise((0.9, 0.0), (0.0, 0.9), -1.0)]
fn spin_in_place_rotates_without_translating(
    #[case] left: (f64, f64),
    #[case] right: (f64, f64),
    #[case] turn: f64,
) {
    let mut robot = Robot::new(&symmetric_config(), 1).unwrap();
    drive(&mut robot, left, right);
    robot.advance_to(Seconds(2.0)).unwrap();
    let pose = robot.pose();
    assert!(pose.x().0.abs() < 1e-9 && pose.y().0.abs() < 1e-9, "{pose}");
    assert!(
        turn * pose.theta().0 > std::f64::consts::TAU,
        "more than a turn: {pose}"
    );
    let arc = robot.distance_travelled(Side::Right).0;
    assert_relative_eq!(pose.theta().0, 2.0 * arc / 130.0, epsilon = 1e-12);
}

/// At constant wheel speeds (long after the last input change) the path is a circle of radius
/// `b/2 * (s_r + s_l) / (s_r - s_l)`: the pose after another second matches the circle.
#[test]
fn constant_speeds_trace_the_exact_circle() {
    let mut robot = Robot::new(&symmetric_config(), 1).unwrap();
    drive(&mut robot, (0.8, 0.0), (1.0, 0.0));
    robot.advance_to(Seconds(5.0)).unwrap();
    let start = robot.pose();
    let (l0, r0) = (
        robot.distance_travelled(Side::Left).0,
        robot.distance_travelled(Side::Right).0,
    );
    robot.advance_to(Seconds(6.0)).unwrap();
    let (sl, sr) = (
        robot.distance_travelled(Side::Left).0 - l0,
        robot.distance_travelled(Side::Right).0 - r0,
    );
    let radius = 65.0 * (sr + sl) / (sr - sl);
    let dtheta = (sr - sl) / 130.0;
    let th = start.theta().0;
    let centre = (
        start.x().0 - radius * th.sin(),
        start.y().0 + radius * th.cos(),
    );
    let end = robot.pose();
    assert_relative_eq!(end.theta().0, th + dtheta, epsilon = 1e-9);
    assert_relative_eq!(
        end.x().0,
        centre.0 + radius * (th + dtheta).sin(),
        epsilon = 1e-6
    );
    assert_relative_eq!(
        end.y().0,
        centre.1 - radius * (th + dtheta).cos(),
        epsilon = 1e-6
    );
}

fn with_backlash() -> RobotConfig {
    let mut config = RobotConfig::default();
    config.effects.backlash = Some(plant_model::effects::Backlash {
        left_wheel_deg: 2.0,
        right_wheel_deg: 3.0,
    });
    config
}

/// One long `advance_to` is subdivided internally on a fixed grid: advancing in 1 ms, in
/// irregular steps, or asking for the pose on the way gives the same wheel states and the
/// same pose, bit for bit (with backlash too, whose steps also split at reversals).
#[rstest]
#[case::nominal(RobotConfig::default())]
#[case::backlash(with_backlash())]
fn long_advance_equals_many_short_ones(#[case] config: RobotConfig) {
    let script = |robot: &mut Robot, times: &[f64], look: bool| {
        drive(robot, (0.95, 0.0), (0.7, 0.0));
        for &t in times {
            if t > 0.5 && robot.now().0 <= 0.5 {
                robot.advance_to(Seconds(0.5)).unwrap();
                drive(robot, (0.0, 0.9), (0.6, 0.0));
            }
            robot.advance_to(Seconds(t)).unwrap();
            if look {
                let _ = robot.pose();
            }
        }
    };
    let mut one = Robot::new(&config, 3).unwrap();
    script(&mut one, &[0.8], false);
    let mut fine = Robot::new(&config, 3).unwrap();
    let ms: Vec<f64> = (1..=800).map(|k| f64::from(k) / 1000.0).collect();
    script(&mut fine, &ms, true);
    let mut odd = Robot::new(&config, 3).unwrap();
    script(
        &mut odd,
        &[0.0001, 0.0123, 0.2, 0.20001, 0.5, 0.6377, 0.8],
        true,
    );
    for other in [&fine, &odd] {
        for side in Side::BOTH {
            assert_eq!(one.wheel_angle(side), other.wheel_angle(side));
            assert_eq!(one.quadrature_index(side), other.quadrature_index(side));
        }
        assert_eq!(one.pose(), other.pose());
    }
    // And the pose between grid instants is the last instant's plus the arc since.
    let mut between = Robot::new(&config, 3).unwrap();
    script(&mut between, &[0.7995], true);
    let mut direct = Robot::new(&config, 3).unwrap();
    script(&mut direct, &[0.79, 0.7995], false);
    assert_eq!(between.pose(), direct.pose());
}

/// With backlash a pose step also ends where a wheel reverses: the gear play is taken up
/// from the shaft's extreme, not from the grid instants either side of it. One wheel driven
/// forward, then reversed; while the shaft comes back through the play the wheel stays where
/// the extreme left it, so the robot (pivoting on the other wheel) has turned by the shaft's
/// furthest arc over the wheelbase. Stepping over the reversal would lose the last 1e-5 rad
/// or so of it (2e-6 rad of heading).
#[test]
fn backlash_takes_up_the_play_from_the_reversal() {
    let config = with_backlash();
    let mut robot = Robot::new(&config, 3).unwrap();
    drive(&mut robot, (0.9, 0.0), (0.0, 0.0));
    robot.advance_to(Seconds(0.3003)).unwrap();
    drive(&mut robot, (0.0, 0.9), (0.0, 0.0));
    // The shaft's extreme, sampled every microsecond (off by under 1e-9 rad of arc).
    let mut furthest = f64::MIN;
    let mut t = robot.now().0;
    while t < 0.345 {
        t += 1e-6;
        robot.advance_to(Seconds(t)).unwrap();
        furthest = furthest.max(robot.distance_travelled(Side::Left).0);
    }
    // Past the extreme, and not yet through the play (2 degrees of a 16 mm wheel: 0.56 mm).
    let back = furthest - robot.distance_travelled(Side::Left).0;
    assert!(back > 0.1 && back < 0.5, "{back} mm back from the extreme");
    let heading = robot.pose().theta().0;
    let expected = -furthest / config.geometry.wheelbase_mm;
    assert!(
        (heading - expected).abs() < 1e-9,
        "heading {heading} rad, the shaft's furthest arc over the wheelbase {expected} rad"
    );
}

/// Asking to go back in time is an error that leaves the plant as it was; going to `now`
/// again does nothing.
#[test]
fn time_only_moves_forward() {
    let mut robot = Robot::new(&RobotConfig::default(), 0).unwrap();
    drive(&mut robot, (0.9, 0.0), (0.9, 0.0));
    robot.advance_to(Seconds(0.5)).unwrap();
    let before = robot.pose();
    let err = robot.advance_to(Seconds(0.4)).unwrap_err();
    assert!(matches!(err, Error::TimeWentBackwards { .. }), "{err}");
    assert!(robot.advance_to(Seconds(f64::NAN)).is_err());
    assert_eq!(robot.now(), Seconds(0.5));
    assert_eq!(robot.pose(), before);
    robot.advance_to(Seconds(0.5)).unwrap();
    assert_eq!(robot.pose(), before);
}

/// The same calls give bit-identical results (no clock, no hidden state); the seed is kept.
#[test]
fn deterministic() {
    let run = || {
        let mut robot = Robot::new(&RobotConfig::default(), 42).unwrap();
        drive(&mut robot, (0.9, 0.0), (0.8, 0.0));
        robot.advance_to(Seconds(0.7)).unwrap();
        drive(&mut robot, (0.0, 0.0), (1.0, 1.0));
        robot.advance_to(Seconds(1.0)).unwrap();
        robot
    };
    let (a, b) = (run(), run());
    assert_eq!(a.pose(), b.pose());
    assert_eq!(a.seed(), 42);
    assert_eq!(
        a.next_encoder_transition(Side::Left),
        b.next_encoder_transition(Side::Left)
    );
}

/// Braking (both inputs high) stops a wheel faster than coasting, and neither reverses it.
#[test]
fn brake_stops_faster_than_coast() {
    let mut robot = Robot::new(&symmetric_config(), 0).unwrap();
    drive(&mut robot, (1.0, 0.0), (1.0, 0.0));
    robot.advance_to(Seconds(0.5)).unwrap();
    drive(&mut robot, (0.0, 0.0), (1.0, 1.0));
    let at = |r: &Robot| {
        (
            r.distance_travelled(Side::Left),
            r.distance_travelled(Side::Right),
        )
    };
    let (l0, r0) = at(&robot);
    robot.advance_to(Seconds(1.5)).unwrap();
    let (l1, r1) = at(&robot);
    let coast: Millimetres = l1 - l0;
    let brake: Millimetres = r1 - r0;
    assert!(brake.0 > 0.0 && coast.0 > 0.0);
    assert_relative_eq!(coast.0 / brake.0, 3.0, epsilon = 1e-5);
    assert!(robot.wheel_speed(Side::Left).0 >= 0.0 && robot.wheel_speed(Side::Right).0 >= 0.0);
}

/// Speeds are reported in rad/s and in thesis RPM, consistently.
#[test]
fn speed_in_both_units() {
    let mut robot = Robot::new(&RobotConfig::default(), 0).unwrap();
    drive(&mut robot, (0.9, 0.0), (0.9, 0.0));
    robot.advance_to(Seconds(1.0)).unwrap();
    let w = robot.wheel_speed(Side::Right);
    assert_relative_eq!(
        robot.wheel_speed_thesis_rpm(Side::Right).0 * std::f64::consts::PI / 5.0,
        w.0,
        epsilon = 1e-12
    );
}
