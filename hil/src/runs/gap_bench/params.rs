//! The bench's effect parameters: one number per effect of the plant's library, named as
//! [`gap::effects`] names them, and how each becomes an `[effects.<name>]` table of the
//! robot config.
//!
//! The library's effects have several keys each (left and right, a width, a pack's
//! voltages); the diagnosis searches one number per effect. Effects with two sides take a
//! signed value, positive on the left side and negative on the right (a left dead band of
//! 0.12 is `+0.12`, a right one `-0.12`), so that the search is 1-D and the neutral value 0
//! sits in the middle of the range; the other keys are fixed at typical values, written in
//! [`apply`].

use gap::effects::{
    Effect, EffectParams, ParamKind, ParamSpec, BACKLASH, BATTERY_SAG, CASTOR_DRAG, COAST,
    DEAD_BAND, DISTANCE_SCALE, ENCODER_GLITCHES, ENCODER_MISSED_COUNTS, FLOOR_NOISE,
    MOTOR_GAIN_ASYMMETRY, STRAIGHT_SLIP, TOE, TURN_SLIP, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO,
};
use gap::model::ModelError;
use plant_model::effects as fx;
use plant_model::motor::MotorModel;
use plant_model::RobotConfig;

/// A glitch's width, degrees of motor-shaft angle: a short bounce, well inside a
/// quadrature state of the nominal encoder (60°).
const GLITCH_WIDTH_MOTOR_DEG: f64 = 5.0;
/// The castor's contact, as a fraction of the wheelbase off the centre line.
const CASTOR_OFFSET_OF_WHEELBASE: f64 = 0.25;
/// A wheel's stall torque at full duty (the identify module's physical fit, see
/// `plant_model::effects::castor_drag`), N m.
const WHEEL_STALL_TORQUE_NM: f64 = 0.11;
/// The pack of the battery effect: a constant open-circuit voltage (the robot's own, so
/// that a zero internal resistance is the nominal robot), a large capacity (a test does not
/// drain it), one motor's winding resistance and the electronics' current.
const MOTOR_RESISTANCE_OHM: f64 = 10.0;
const IDLE_CURRENT_A: f64 = 0.1;

/// Every effect of the plant's library, as the bench applies it (see the module docs).
pub fn bench_parameters() -> Vec<ParamSpec> {
    use ParamKind::{Stochastic, Systematic};
    vec![
        ParamSpec::new(
            WHEEL_DIAMETER_RATIO,
            "Ed",
            "1",
            (0.9, 1.1),
            1.0,
            0.01,
            Systematic,
            "D_R/D_L (right_over_left_ratio)",
        ),
        ParamSpec::new(
            WHEELBASE_RATIO,
            "Eb",
            "1",
            (0.8, 1.25),
            1.0,
            0.03,
            Systematic,
            "actual wheelbase / nominal (actual_over_nominal_ratio)",
        ),
        ParamSpec::new(
            DISTANCE_SCALE,
            "Es",
            "1",
            (0.9, 1.1),
            1.0,
            0.02,
            Systematic,
            "odometry distance / actual (odometry_over_actual_ratio)",
        ),
        ParamSpec::new(
            TURN_SLIP,
            "slip",
            "1",
            (0.0, 0.3),
            0.0,
            0.03,
            Systematic,
            "fraction of each spin's rotation the ground does not see",
        ),
        ParamSpec::new(
            STRAIGHT_SLIP,
            "sslip",
            "1",
            (-0.2, 0.2),
            0.0,
            0.01,
            Systematic,
            "travel lost in straight legs, left wheel (+) or right (−)",
        ),
        ParamSpec::new(
            COAST,
            "coast",
            "s",
            (0.0, 0.3),
            0.0,
            0.03,
            Systematic,
            "coast time constant added to both motors' own",
        ),
        ParamSpec::new(
            TOE,
            "toe",
            "deg",
            (-5.0, 5.0),
            0.0,
            0.7,
            Systematic,
            "crab angle (φ_R − φ_L)/2, left positive: right wheel toed in, left out",
        ),
        ParamSpec::new(
            FLOOR_NOISE,
            "σ_floor",
            "deg/√m",
            (0.0, 5.0),
            0.0,
            0.4,
            Stochastic,
            "heading random walk along the legs (heading_deg_per_sqrt_m)",
        ),
        ParamSpec::new(
            MOTOR_GAIN_ASYMMETRY,
            "gain",
            "1",
            (-0.3, 0.3),
            0.0,
            0.05,
            Systematic,
            "left gain ratio 1 + g/2, right 1 − g/2",
        ),
        ParamSpec::new(
            DEAD_BAND,
            "dead",
            "duty",
            (-0.3, 0.3),
            0.0,
            0.05,
            Systematic,
            "extra dead band of the left motor (+) or the right (−)",
        ),
        ParamSpec::new(
            BATTERY_SAG,
            "R_int",
            "ohm",
            (0.0, 20.0),
            0.0,
            2.0,
            Systematic,
            "internal resistance of the pack (open-circuit voltage the robot's own)",
        ),
        ParamSpec::new(
            ENCODER_MISSED_COUNTS,
            "miss",
            "1",
            (-0.2, 0.2),
            0.0,
            0.01,
            Systematic,
            "share of A pulses lost, left encoder (+) or right (−)",
        ),
        ParamSpec::new(
            ENCODER_GLITCHES,
            "glitch",
            "1",
            (-0.5, 0.5),
            0.0,
            0.05,
            Systematic,
            "share of edges that bounce (5° of motor shaft), left (+) or right (−)",
        ),
        ParamSpec::new(
            CASTOR_DRAG,
            "castor",
            "N",
            (-3.0, 3.0),
            0.0,
            0.3,
            Systematic,
            "drag at a castor b/4 left of the centre line (+) or right (−)",
        ),
        ParamSpec::new(
            BACKLASH,
            "play",
            "deg",
            (0.0, 20.0),
            0.0,
            2.0,
            Systematic,
            "gear play of both wheels, degrees of wheel angle",
        ),
    ]
}

/// The other name of a library effect's value, when the plant makes the same robot under
/// two names: turn slip `s` keeps `1 − s` of each differential arc, a wheelbase `Eb` times
/// the nominal turns the robot by `1/Eb` of it, and the ground computes the same pose from
/// either (to rounding; nothing there feeds back into the encoders). So `turn_slip = s` is
/// `wheelbase_ratio = 1/(1 − s)`, and no test of any shape can tell them apart on the
/// bench's candidates (they differ only where another effect reads the wheelbase: the
/// castor's lever, the floor noise's turning share). None when the value has no equal
/// inside the other's range of [`bench_parameters`] (a wheelbase below nominal would be a
/// negative slip).
pub fn equivalent(effect: &str, value: f64) -> Option<(&'static str, f64)> {
    let (other, v) = match effect {
        TURN_SLIP => (WHEELBASE_RATIO, 1.0 / (1.0 - value)),
        WHEELBASE_RATIO => (TURN_SLIP, 1.0 - 1.0 / value),
        _ => return None,
    };
    bench_parameters()
        .iter()
        .any(|s| s.name == other && (s.lower..=s.upper).contains(&v) && v.is_finite())
        .then_some((other, v))
}

/// `value` split into (left, right) by its sign: positive on the left.
fn sided(value: f64) -> (f64, f64) {
    if value >= 0.0 {
        (value, 0.0)
    } else {
        (0.0, -value)
    }
}

/// `nominal` with the effects `params` switched on (unset or neutral ones left as the
/// nominal robot has them). The caller has checked the values against
/// [`bench_parameters`].
pub fn apply(nominal: &RobotConfig, params: &EffectParams) -> Result<RobotConfig, ModelError> {
    let mut c = nominal.clone();
    let specs = bench_parameters();
    for (name, v) in params.iter() {
        if specs.iter().any(|s| s.name == name && s.neutral == v) {
            continue;
        }
        let Some(effect) = Effect::from_name(name) else {
            return Err(ModelError::UnknownParameter {
                model: "bench".to_owned(),
                name: name.to_owned(),
                known: specs
                    .iter()
                    .map(|s| s.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        let e = &mut c.effects;
        match effect {
            Effect::WheelDiameterRatio => {
                e.wheel_diameter_ratio = Some(fx::WheelDiameterRatio {
                    right_over_left_ratio: v,
                })
            }
            Effect::WheelbaseRatio => {
                e.wheelbase_ratio = Some(fx::WheelbaseRatio {
                    actual_over_nominal_ratio: v,
                })
            }
            Effect::DistanceScale => {
                e.distance_scale = Some(fx::DistanceScale {
                    odometry_over_actual_ratio: v,
                })
            }
            Effect::TurnSlip => e.turn_slip = Some(fx::TurnSlip { fraction: v }),
            Effect::StraightSlip => {
                let (l, r) = sided(v);
                e.straight_slip = Some(fx::StraightSlip {
                    left_fraction: l,
                    right_fraction: r,
                })
            }
            Effect::Coast => {
                // The effect replaces each motor's coast time constant: the motor's own plus
                // the extra, and the motor's own key cleared (the config takes one or the
                // other).
                let own = |m: &mut MotorModel| {
                    let MotorModel::FirstOrder(m) = m;
                    let t = m.coast_tau().0;
                    m.coast_tau_s = None;
                    t + v
                };
                let left_tau_s = own(&mut c.motor.left);
                let right_tau_s = own(&mut c.motor.right);
                c.effects.coast = Some(fx::Coast {
                    left_tau_s,
                    right_tau_s,
                })
            }
            Effect::Toe => {
                e.toe = Some(fx::Toe {
                    left_deg: -v,
                    right_deg: v,
                })
            }
            Effect::FloorNoise => {
                e.floor_noise = Some(fx::FloorNoise {
                    heading_deg_per_sqrt_m: v,
                    lateral_mm_per_sqrt_m: 0.0,
                    turn_heading_deg_per_sqrt_m: Some(0.0),
                    stretch_mm: fx::floor_noise::DEFAULT_STRETCH_MM,
                })
            }
            Effect::MotorGainAsymmetry => {
                e.motor_gain_asymmetry = Some(fx::MotorGainAsymmetry {
                    left_gain_ratio: 1.0 + v / 2.0,
                    right_gain_ratio: 1.0 - v / 2.0,
                })
            }
            Effect::DeadBand => {
                let (l, r) = sided(v);
                e.dead_band = Some(fx::DeadBand {
                    extra_left_duty: l,
                    extra_right_duty: r,
                })
            }
            Effect::BatterySag => {
                e.battery_sag = Some(fx::BatterySag {
                    open_circuit_full_v: nominal.battery.voltage_v,
                    open_circuit_empty_v: nominal.battery.voltage_v,
                    capacity_mah: 1e5,
                    initial_charge_fraction: 1.0,
                    internal_resistance_ohm: v,
                    motor_resistance_ohm: MOTOR_RESISTANCE_OHM,
                    idle_current_a: IDLE_CURRENT_A,
                    update_interval_s: fx::battery_sag::DEFAULT_UPDATE_INTERVAL_S,
                })
            }
            Effect::EncoderMissedCounts => {
                let (l, r) = sided(v);
                e.encoder_missed_counts = Some(fx::EncoderMissedCounts {
                    left_fraction: l,
                    right_fraction: r,
                })
            }
            Effect::EncoderGlitches => {
                let (l, r) = sided(v);
                e.encoder_glitches = Some(fx::EncoderGlitches {
                    left_fraction: l,
                    right_fraction: r,
                    width_motor_deg: GLITCH_WIDTH_MOTOR_DEG,
                })
            }
            Effect::CastorDrag => {
                let side = if v >= 0.0 { 1.0 } else { -1.0 };
                e.castor_drag = Some(fx::CastorDrag {
                    force_n: v.abs(),
                    lateral_offset_mm: side
                        * CASTOR_OFFSET_OF_WHEELBASE
                        * nominal.geometry.wheelbase_mm,
                    wheel_stall_torque_nm: WHEEL_STALL_TORQUE_NM,
                })
            }
            Effect::Backlash => {
                e.backlash = Some(fx::Backlash {
                    left_wheel_deg: v,
                    right_wheel_deg: v,
                })
            }
        }
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The robot a spin, a straight leg and a spin the other way leave: both wheels
    /// driven from `duties` for 0.6 s each, then 0.4 s coasting.
    fn end_pose(config: &RobotConfig) -> plant_model::Pose<plant_model::World> {
        use plant_model::{Duty, Seconds, Side};
        let mut robot = plant_model::Robot::new(config, 7).expect("a valid config");
        let signed = |d: f64| {
            let duty = Duty::new(d.abs()).expect("a duty");
            if d >= 0.0 {
                (duty, Duty::OFF)
            } else {
                (Duty::OFF, duty)
            }
        };
        let mut t = 0.0;
        for (l, r) in [(-0.7, 0.7), (0.6, 0.65), (0.8, -0.5), (0.0, 0.0)] {
            for (side, d) in [(Side::Left, l), (Side::Right, r)] {
                let (a, b) = signed(d);
                robot.set_bridge(side, a, b);
            }
            t += 0.6;
            robot.advance_to(Seconds(t)).expect("a run");
        }
        robot.pose()
    }

    /// Turn slip and the wheelbase it is equivalent to make the same robot: the same end
    /// pose after spins both ways and a curved leg (to rounding), while a slip 10 % off
    /// the equivalent value is visibly elsewhere. Values outside the other's range have no
    /// equivalent, and other effects none at all.
    #[test]
    fn turn_slip_and_its_equivalent_wheelbase_make_the_same_robot() {
        let nominal = RobotConfig::default();
        let slip = 0.06;
        let (other, eb) = equivalent(TURN_SLIP, slip).expect("an equivalent wheelbase");
        assert_eq!(other, WHEELBASE_RATIO);
        let back = equivalent(WHEELBASE_RATIO, eb).expect("and back");
        assert_eq!(back.0, TURN_SLIP);
        assert!((back.1 - slip).abs() < 1e-12, "{back:?}");
        let with = |name: &str, v: f64| {
            end_pose(&apply(&nominal, &EffectParams::new().with(name, v)).expect("a known effect"))
        };
        let (a, b) = (with(TURN_SLIP, slip), with(WHEELBASE_RATIO, eb));
        let off = with(TURN_SLIP, 1.1 * slip);
        let apart = |p: &plant_model::Pose<plant_model::World>,
                     q: &plant_model::Pose<plant_model::World>| {
            (p.x().0 - q.x().0).hypot(p.y().0 - q.y().0) + (p.theta().0 - q.theta().0).abs()
        };
        assert!(apart(&a, &b) < 1e-9, "{a:?} vs {b:?}");
        assert!(apart(&a, &off) > 1e-2, "{a:?} vs {off:?}");
        assert!(apart(&a, &with(TURN_SLIP, 0.0)) > 1.0);
        assert_eq!(equivalent(WHEELBASE_RATIO, 0.9), None);
        assert_eq!(equivalent(TURN_SLIP, 0.25), None);
        assert_eq!(equivalent(DEAD_BAND, 0.1), None);
    }

    /// Every library effect is a parameter, and each non-neutral value switches on exactly
    /// its own table, valid for the plant.
    #[test]
    fn every_effect_is_a_parameter_and_switches_on_its_table() {
        let specs = bench_parameters();
        let mut names: Vec<&str> = specs.iter().map(|s| s.name.as_str()).collect();
        names.sort_unstable();
        let mut all = gap::ALL_EFFECTS.to_vec();
        all.sort_unstable();
        assert_eq!(names, all);
        let nominal = RobotConfig::default();
        for s in &specs {
            let v = (s.neutral + s.scale).min(s.upper);
            let c = apply(&nominal, &EffectParams::new().with(&s.name, v)).expect("a known effect");
            assert_eq!(c.effects.enabled(), vec![s.name.as_str()], "{}", s.name);
            c.effects
                .validate()
                .unwrap_or_else(|e| panic!("{}: {e}", s.name));
            plant_model::Robot::new(&c, 1).unwrap_or_else(|e| panic!("{}: {e}", s.name));
            let neutral = apply(&nominal, &EffectParams::new().with(&s.name, s.neutral))
                .expect("a known effect");
            assert!(neutral.effects.is_empty(), "{}", s.name);
        }
    }
}
