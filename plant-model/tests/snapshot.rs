//! A fixed script of bridge inputs on the nominal robot gives a fixed trajectory: any change
//! to the physics shows up as a reviewed snapshot diff.

use std::fmt::Write;

use plant_model::{Duty, Robot, RobotConfig, Seconds, Side};

/// Bridge inputs `(in1, in2)` as 8-bit compare values (of 255).
type Inputs = (u8, u8);

/// From each time on: the left and right bridge inputs.
const SCRIPT: [(f64, Inputs, Inputs); 7] = [
    (0.0, (200, 0), (200, 0)),     // straight-ish (the motors differ)
    (1.0, (150, 0), (230, 0)),     // left just past its dead band: curve left
    (1.5, (0, 220), (220, 0)),     // spin counter-clockwise
    (2.0, (255, 255), (255, 255)), // brake
    (2.3, (0, 240), (0, 240)),     // reverse
    (3.0, (0, 0), (0, 0)),         // coast
    (3.5, (0, 0), (0, 0)),         // end
];

/// The pose, encoder counts and wheel speeds at each step of the script.
#[test]
fn scripted_run() {
    let mut robot = Robot::new(&RobotConfig::default(), 0).unwrap();
    let mut table = String::from(
        "     t        x_mm        y_mm    theta_rad  edges_L  edges_R   rpm_L    rpm_R\n",
    );
    for (t, left, right) in SCRIPT {
        robot.advance_to(Seconds(t)).unwrap();
        let pose = robot.pose();
        writeln!(
            table,
            "{t:>6.3} {:>11.4} {:>11.4} {:>12.6} {:>8} {:>8} {:>7.3} {:>8.3}",
            pose.x().0,
            pose.y().0,
            pose.theta().0,
            robot.a_edges(Side::Left),
            robot.a_edges(Side::Right),
            robot.wheel_speed_thesis_rpm(Side::Left).0,
            robot.wheel_speed_thesis_rpm(Side::Right).0,
        )
        .unwrap();
        robot.set_bridge(Side::Left, Duty::from_pwm8(left.0), Duty::from_pwm8(left.1));
        robot.set_bridge(
            Side::Right,
            Duty::from_pwm8(right.0),
            Duty::from_pwm8(right.1),
        );
    }
    // An absolute snapshot folder: found even when insta cannot ask cargo for the workspace.
    insta::with_settings!({
        snapshot_path => concat!(env!("CARGO_MANIFEST_DIR"), "/tests/snapshots"),
    }, {
        insta::assert_snapshot!(table);
    });
}
