//! `toe`: the wheels are not parallel to the robot's axis (the thesis' photo of Henrytwo
//! shows visibly misaligned wheels).
//!
//! Each wheel rolls along its own plane, turned by its toe angle `phi` against the robot's
//! forward axis; toe-in (positive) turns the front of the wheel towards the centre line. A
//! wheel that rolls `d` wants to move its contact point by `d (cos phi, -+ sin phi)`: `cos phi`
//! of it forward, `sin phi` sideways. Two wheels with different sideways wishes cannot both
//! have them: the tyres scrub. With equal lateral friction at both wheels and a free
//! castor (no lateral force), the robot moves by the rigid motion that fits both wishes in
//! the least-squares sense, which is also the quasi-static force balance of the scrubbing
//! tyres (equal and opposite lateral forces, no yaw moment from them):
//!
//! ```text
//! forward = (d_L cos phi_L + d_R cos phi_R) / 2
//! heading = (d_R cos phi_R - d_L cos phi_L) / b
//! lateral = (d_R sin phi_R - d_L sin phi_L) / 2      (to the robot's left)
//! ```
//!
//! # Signature (worked out)
//!
//! - **Straight leg, equal toe-in on both sides**: the sideways wishes cancel; the leg is
//!   straight and `cos phi` short (second order: 0.14 % at 3 degrees).
//! - **Straight leg, one wheel toed (or unequal toe)**: the lateral components do not
//!   cancel and the robot *crabs*: it moves along a direction turned by
//!   `(phi_R - phi_L) / 2` from its heading, without turning. A single line ends
//!   `L sin((phi_R - phi_L)/2)` to the side; the heading changes only through the `cos`
//!   terms, at second order (`(cos phi_R - cos phi_L) L / b`). In a closed square the
//!   sideways shifts of the four legs turn with the heading and cancel: toe alone leaves a
//!   UMBmark closed (it only rotates the square), while a line test shows it. This is what
//!   tells it from Ed, whose heading change carries from leg to leg.
//! - **Spin turn with toe-in**: the wheels move in opposite directions, so their sideways
//!   wishes now add: the axle midpoint drifts sideways by `sin phi` of the wheel travel,
//!   along a circle of radius `b/2 sin phi` (about 1.1 mm at 2 degrees): small.
//! - The encoders see none of it (the wheels turn as before).
//!
//! A castor that resisted lateral motion (one that cannot swivel) would turn the crab into
//! a yaw about the castor; a free castor, as modelled here, does not.
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `left_deg` | degrees | toe-in of the left wheel (negative: toe-out), within +-20 |
//! | `right_deg` | degrees | toe-in of the right wheel |

use serde::{Deserialize, Serialize};

use crate::check::check_between;
use crate::effects::key;
use crate::side::Side;
use crate::Error;

/// Parameters of `[effects.toe]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Toe {
    /// Toe-in of the left wheel, degrees.
    pub left_deg: f64,
    /// Toe-in of the right wheel, degrees.
    pub right_deg: f64,
}

impl Toe {
    /// Checks the parameters; `prefix` is `effects.toe`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        let check = |name: &str, value: f64| {
            check_between(
                &key(prefix, name),
                value,
                (-20.0, 20.0),
                "a toe angle must lie within +-20 degrees",
                "toe-in of the wheel, degrees",
            )
        };
        check("left_deg", self.left_deg)?;
        check("right_deg", self.right_deg)
    }

    /// The rolling direction of `side`'s wheel in the robot's frame, `(forward, left)`
    /// components of a unit step: left `(cos, -sin)`, right `(cos, sin)` of its toe-in.
    pub fn rolling_direction(&self, side: Side) -> (f64, f64) {
        match side {
            Side::Left => {
                let phi = self.left_deg.to_radians();
                (phi.cos(), -phi.sin())
            }
            Side::Right => {
                let phi = self.right_deg.to_radians();
                (phi.cos(), phi.sin())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{run, symmetric};

    fn with(left: f64, right: f64) -> crate::RobotConfig {
        symmetric(|c| {
            c.effects.toe = Some(Toe {
                left_deg: left,
                right_deg: right,
            })
        })
    }

    /// Signature: one toed-in right wheel makes a straight leg crab to the left at half the
    /// toe angle with the heading unchanged to second order; equal toe-in on both sides
    /// keeps the leg straight and `cos phi` short; a spin turn with toe-in drifts the centre
    /// by `b/2 sin phi` at most; the encoders do not notice.
    #[test]
    fn crabs_a_straight_leg_without_turning_it() {
        let phi = 2.0f64;
        let plain = run(&symmetric(|_| {}), 0, 0.9, 0.9, 2.0, 0.3);
        let one = run(&with(0.0, phi), 0, 0.9, 0.9, 2.0, 0.3);
        let pose = one.pose();
        let travel = plain.pose().x().0;
        let crab = (0.5 * phi).to_radians();
        // Second-order heading from the cos term: (cos phi - 1) d / b for a wheel travel d.
        let heading = (phi.to_radians().cos() - 1.0) * travel / 130.0;
        assert!((pose.theta().0 - heading).abs() < 1e-9, "{pose}");
        // The crab, plus the drift of that slowly growing heading (half its end value).
        let lateral = travel * (crab.sin() + 0.5 * heading);
        assert!(
            (pose.y().0 - lateral).abs() < 0.01 * lateral,
            "{pose} vs y = {lateral}"
        );
        assert_eq!(one.a_edges(Side::Right), plain.a_edges(Side::Right));

        let both = run(&with(phi, phi), 0, 0.9, 0.9, 2.0, 0.3).pose();
        assert!(both.y().0.abs() < 1e-9 && both.theta().0.abs() < 1e-12);
        assert!((both.x().0 / travel - phi.to_radians().cos()).abs() < 1e-9);

        let spin = run(&with(phi, phi), 0, -0.9, 0.9, 1.0, 0.3).pose();
        assert!(spin.distance_from_origin().0 <= 2.0 * 65.0 * phi.to_radians().sin() + 1e-9);
        assert!(spin.distance_from_origin().0 > 0.1);
    }
}
