//! What the floor sees: from the motor shafts' angles to the robot's pose.
//!
//! The encoders measure the motor shafts; everything between a shaft and the floor lives
//! here and never feeds back into the wheel dynamics, so none of it can change the encoder
//! timing. One pose step, with the shafts' angle increments as input:
//!
//! 1. **Backlash** ([`crate::effects::backlash`]): the wheel angle follows the shaft angle
//!    through the gear play.
//! 2. **Wheel arcs**: wheel angle increment times the effective radius (the configured
//!    diameter with `wheel_diameter_ratio` and `distance_scale` applied).
//! 3. **Slip** ([`crate::effects::turn_slip`], [`crate::effects::straight_slip`], and the
//!    bench's slip bursts): the arcs split into a common part `v = (d_L + d_R)/2` and a
//!    differential part `u = (d_R - d_L)/2`; left `(1 - s_L) v - (1 - s_t) u`, right
//!    `(1 - s_R) v + (1 - s_t) u`; then a burst keeps `1 - burst` of its side.
//! 4. **Kinematics** with the effective wheelbase (`wheelbase_ratio`) and the wheels'
//!    rolling directions ([`crate::effects::toe`]): forward travel, heading change, sideways
//!    crab.
//! 5. **Floor noise** ([`crate::effects::floor_noise`]): heading and lateral noise for the
//!    floor crossed, rolling and turning on the spot.
//! 6. The pose moves along the exact arc (plus the crab, if any).
//!
//! With no effect on, each step computes exactly what the nominal model did (the same
//! operations in the same order), so nominal runs keep their bits.

use crate::config::RobotConfig;
use crate::effects::backlash::follow;
use crate::effects::floor_noise::FloorState;
use crate::pose::{Pose, World};
use crate::side::{PerSide, Side};
use crate::units::{Millimetres, Radians};

/// Slip fractions kept: `(1 - s)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Slip {
    turn_keep: f64,
    straight_keep: PerSide<f64>,
}

/// The floor side of the plant (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ground {
    pose: Pose<World>,
    /// Shaft angle (in wheel radians) at the last step.
    shaft: PerSide<f64>,
    /// Wheel angle after the gear play, at the last step.
    wheel: PerSide<f64>,
    /// Gear play, wheel radians, if `backlash` is on.
    play: Option<PerSide<f64>>,
    radius_mm: PerSide<f64>,
    wheelbase_mm: f64,
    slip: Option<Slip>,
    /// Slip burst per side (0: none).
    burst: PerSide<f64>,
    /// Rolling directions `(forward, left)` if `toe` is on.
    toe: Option<PerSide<(f64, f64)>>,
    floor: Option<FloorState>,
}

impl Ground {
    /// The floor of `config`'s robot at the origin, wheels at angle 0.
    pub(crate) fn new(config: &RobotConfig, seed: u64) -> Self {
        let effects = &config.effects;
        let radius_mm = PerSide {
            left: effective_radius_mm(config, Side::Left),
            right: effective_radius_mm(config, Side::Right),
        };
        let wheelbase_mm = config.geometry.wheelbase_mm
            * effects
                .wheelbase_ratio
                .as_ref()
                .map_or(1.0, |e| e.actual_over_nominal_ratio);
        let slip = (effects.turn_slip.is_some() || effects.straight_slip.is_some()).then(|| {
            let turn = effects.turn_slip.as_ref().map_or(0.0, |e| e.fraction);
            let straight = |side| {
                effects
                    .straight_slip
                    .as_ref()
                    .map_or(0.0, |e| e.fraction(side))
            };
            Slip {
                turn_keep: 1.0 - turn,
                straight_keep: PerSide {
                    left: 1.0 - straight(Side::Left),
                    right: 1.0 - straight(Side::Right),
                },
            }
        });
        let play = effects.backlash.as_ref().map(|b| PerSide {
            left: b.play_rad(Side::Left),
            right: b.play_rad(Side::Right),
        });
        // Engaged forwards: the shaft leads the wheel by half the play.
        let wheel = play.map_or(PerSide::default(), |p| PerSide {
            left: -0.5 * p.left,
            right: -0.5 * p.right,
        });
        Ground {
            pose: Pose::origin(),
            shaft: PerSide::default(),
            wheel,
            play,
            radius_mm,
            wheelbase_mm,
            slip,
            burst: PerSide::default(),
            toe: effects.toe.as_ref().map(|t| PerSide {
                left: t.rolling_direction(Side::Left),
                right: t.rolling_direction(Side::Right),
            }),
            floor: effects
                .floor_noise
                .as_ref()
                .map(|f| FloorState::new(f, seed)),
        }
    }

    pub(crate) fn pose(&self) -> Pose<World> {
        self.pose
    }

    /// Effective rolling radius of `side`, mm.
    pub(crate) fn radius_mm(&self, side: Side) -> f64 {
        *self.radius_mm.get(side)
    }

    /// Whether pose steps must split at every reversal of a wheel (backlash is on).
    pub(crate) fn needs_turning_points(&self) -> bool {
        self.play.is_some()
    }

    /// Sets the share of `side`'s travel the ground loses (a slip burst), from now on.
    pub(crate) fn set_burst(&mut self, side: Side, slip: f64) {
        *self.burst.get_mut(side) = slip;
    }

    /// The slip burst of `side`.
    pub(crate) fn burst(&self, side: Side) -> f64 {
        *self.burst.get(side)
    }

    /// One pose step: the shafts are now at `shaft` (wheel radians).
    pub(crate) fn step(&mut self, shaft: PerSide<f64>) {
        let mut arc = [0.0; 2];
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let now = *shaft.get(side);
            let radius = *self.radius_mm.get(side);
            arc[i] = match &self.play {
                None => radius * (now - *self.shaft.get(side)),
                Some(play) => {
                    let before = *self.wheel.get(side);
                    let after = follow(before, now, *play.get(side));
                    *self.wheel.get_mut(side) = after;
                    radius * (after - before)
                }
            };
            *self.shaft.get_mut(side) = now;
        }
        let [mut left, mut right] = arc;
        if let Some(slip) = &self.slip {
            let v = 0.5 * (left + right);
            let u = 0.5 * (right - left);
            left = slip.straight_keep.left * v - slip.turn_keep * u;
            right = slip.straight_keep.right * v + slip.turn_keep * u;
        }
        if self.burst.left != 0.0 {
            left *= 1.0 - self.burst.left;
        }
        if self.burst.right != 0.0 {
            right *= 1.0 - self.burst.right;
        }
        let (forward, mut dtheta, mut lateral) = match &self.toe {
            None => (
                0.5 * (right + left),
                (right - left) / self.wheelbase_mm,
                0.0,
            ),
            Some(dir) => {
                let (lf, ll) = (left * dir.left.0, left * dir.left.1);
                let (rf, rl) = (right * dir.right.0, right * dir.right.1);
                (
                    0.5 * (rf + lf),
                    (rf - lf) / self.wheelbase_mm,
                    0.5 * (rl + ll),
                )
            }
        };
        if let Some(floor) = &mut self.floor {
            let (heading, shift) =
                floor.advance(0.5 * (left + right).abs(), 0.5 * (right - left).abs());
            dtheta += heading;
            lateral += shift;
        }
        if lateral != 0.0 {
            self.pose
                .move_with_crab(Millimetres(forward), Millimetres(lateral), Radians(dtheta));
        } else if left != 0.0 || right != 0.0 {
            self.pose
                .move_along_arc(Millimetres(forward), Radians(dtheta));
        }
    }
}

/// The rolling radius of `side`: half the configured diameter, times the Ed factor of that
/// side and `1 / Es`.
pub(crate) fn effective_radius_mm(config: &RobotConfig, side: Side) -> f64 {
    let effects = &config.effects;
    let mut radius = 0.5 * config.wheel_diameter_mm(side);
    if let Some(ed) = &effects.wheel_diameter_ratio {
        radius *= *ed.diameter_factors().get(side);
    }
    if let Some(es) = &effects.distance_scale {
        radius *= es.diameter_factor();
    }
    radius
}
