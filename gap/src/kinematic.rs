//! A fast, exact wheel-level kinematic model of the endpoint tests with named effects.
//!
//! # What the firmware does (from [`crate::Firmware`])
//!
//! * **Leg**: with [`StraightLegs::SpeedSetpoints`] the count rates are held at the
//!   set-points, so `nL/nR = ρ = set_L/set_R`, and the leg ends when
//!   `(cL·nL + cR·nR)/2 · m_fw = L` (`m_fw` the firmware's mm per count); with
//!   [`StraightLegs::CorrectedOdometry`] `cL·nL = cR·nR = L/m_fw`.
//! * **Spin** of angle A: each wheel is cut when it reaches `A·b_fw/2 / (c·m_fw)` counts
//!   (left backward and right forward for a left turn). The wheels run at their set-point
//!   rates (corrected odometry: at equal corrected speeds), so one may finish first; the
//!   other then pivots alone. Both phases are integrated exactly.
//!
//! # What the robot does (the effects; [`KinematicModel::parameters`])
//!
//! * counts become wheel travel with the actual distance per count: mean `m_ref/Es`, left
//!   `·2/(Ed+1)`, right `·2Ed/(Ed+1)` (Ed = D_R/D_L, Es = L_calc/L_actual, `m_ref` the
//!   reference's mm per count); the wheelbase is `Eb·b_ref`;
//! * every sub-segment with wheel travels (dL, dR) is an exact arc: heading change
//!   `(dR − dL)/b`, centre travel `(dR + dL)/2`, no small-angle approximation;
//! * `turn_slip` s: in spins the differential (rotating) part of the wheel travel keeps
//!   `1 − s`, the common (translating) part is kept, as the plant library's `turn_slip`
//!   (`fraction`): each spin turns `(1 − s)` of what the wheels' travel implies;
//! * `coast` c: after each spin the robot keeps turning by c degrees in the direction of the
//!   turn, and after each leg it runs on straight by `c·b/2` (c in radians): the wheels
//!   coast by the same distance `s` after every cut-off, since they are cut at the same
//!   set-point speed (the plant library's `coast` has `s = r·w0·τ` per wheel, so
//!   `c = (s_L + s_R)/b`: "extra rotation proportional to the speed at cut-off");
//! * `toe` φ: the wheels' mean rolling direction is turned by φ against the robot's axis (a
//!   thrust angle; with the plant library's toe-in angles, `φ = (φ_R − φ_L)/2`, equal toe-in
//!   on both sides cancels). A straight leg then *crabs*: it moves along heading + φ
//!   without changing heading. Its signature is not a curvature: a single line ends `L·sin φ`
//!   to the side (like Ed's `L·β/2`), but a closed polygon with exact turns cancels it (the
//!   sideways shifts of the legs add up to zero), while Ed's heading change carries from leg
//!   to leg. It is direction-independent. Spins are taken as unaffected (the wheels scrub;
//!   the rotation changes by cos φ − 1, second order);
//! * `floor_noise` σ: each leg's heading changes by an extra `N(0, σ²·ℓ)` (ℓ the leg's
//!   length in metres, σ in degrees per √m: a heading random walk), spread uniformly along
//!   the leg. Run `i` of an experiment draws from its own stream seeded by
//!   `(experiment.seed, i)`, so predictions are smooth in σ (common random numbers).
//!
//! With equal set-points, unit correction factors and `m_fw = m_ref`, `b_fw = b_ref`, it
//! reproduces [`calib::forward`] exactly (tested).

use std::f64::consts::PI;

use plant_model::{Millimetres, Radians, World};

use crate::effects::{
    EffectParams, ParamKind, ParamSpec, Unsupported, BACKLASH, BATTERY_SAG, CASTOR_DRAG, COAST,
    DEAD_BAND, DISTANCE_SCALE, ENCODER_GLITCHES, ENCODER_MISSED_COUNTS, FLOOR_NOISE,
    MOTOR_GAIN_ASYMMETRY, STRAIGHT_SLIP, TOE, TURN_SLIP, WHEELBASE_RATIO, WHEEL_DIAMETER_RATIO,
};
use crate::model::{
    check_params, Experiment, Model, ModelError, RunEndpoint, StraightLegs, TestKind,
};
use crate::rng::Rng;

/// The robot's pose in the start frame, mm and rad: the plant's own type, since the start
/// frame of a test is the plant's [`World`] frame.
type Pose = plant_model::Pose<World>;

/// The kinematic model (no motor dynamics; see the module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct KinematicModel;

/// The parameters of [`KinematicModel`].
pub fn kinematic_parameters() -> Vec<ParamSpec> {
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
            "D_R/D_L: curves every leg (left when > 1)",
        ),
        ParamSpec::new(
            WHEELBASE_RATIO,
            "Eb",
            "1",
            (0.8, 1.25),
            1.0,
            0.03,
            Systematic,
            "actual wheelbase / reference: every spin turns by 1/Eb of its target",
        ),
        ParamSpec::new(
            DISTANCE_SCALE,
            "Es",
            "1",
            (0.9, 1.1),
            1.0,
            0.02,
            Systematic,
            "odometry distance / actual distance: legs are L/Es long, spins 1/Es too large",
        ),
        ParamSpec::new(
            TURN_SLIP,
            "slip",
            "1",
            (0.0, 0.3),
            0.0,
            0.03,
            Systematic,
            "fraction of each spin's rotation lost",
        ),
        ParamSpec::new(
            COAST,
            "coast",
            "deg",
            (0.0, 10.0),
            0.0,
            1.5,
            Systematic,
            "rotation after the motors are cut at the end of each spin",
        ),
        ParamSpec::new(
            TOE,
            "toe",
            "deg",
            (-5.0, 5.0),
            0.0,
            0.7,
            Systematic,
            "crab angle of straight legs (left positive): legs shift sideways, heading kept",
        ),
        ParamSpec::new(
            FLOOR_NOISE,
            "σ_floor",
            "deg/√m",
            (0.0, 5.0),
            0.0,
            0.4,
            Stochastic,
            "heading random walk along the legs, standard deviation after 1 m",
        ),
    ]
}

/// The library's effects the kinematic model cannot represent.
pub fn kinematic_unsupported() -> Vec<Unsupported> {
    let u = |name: &str, reason: &str| Unsupported {
        name: name.to_owned(),
        reason: reason.to_owned(),
    };
    vec![
        u(
            MOTOR_GAIN_ASYMMETRY,
            "needs motor dynamics: under per-wheel speed control a gain difference only shows in \
             the start-up transient of each segment (a heading kick); use the RPM time series",
        ),
        u(
            DEAD_BAND,
            "needs the PWM-to-speed map: it changes the start-up transient and the lowest \
             reachable speed, not the kinematics at the set-points",
        ),
        u(
            BATTERY_SAG,
            "needs the voltage-to-speed map: under speed control it changes transients and the \
             saturation margin, which the kinematics does not have",
        ),
        u(
            ENCODER_MISSED_COUNTS,
            "kinematically a wheel that loses a fraction of its counts is a larger wheel on that \
             side: it is aliased onto wheel_diameter_ratio and distance_scale and cannot be \
             separated by endpoints; the RPM time series against a reference encoder can",
        ),
        u(
            CASTOR_DRAG,
            "needs forces (lateral drag at the castor bends the path depending on speed and \
             the castor's swivel state); the kinematic model has none",
        ),
        u(
            STRAIGHT_SLIP,
            "in straight legs it is a shorter (mean slip) and curved (slip difference) leg with \
             spins untouched: at the kinematic level distance_scale and wheel_diameter_ratio \
             with a compensating wheelbase_ratio; not modelled separately",
        ),
        u(
            ENCODER_GLITCHES,
            "bouncing edges move nothing; what the firmware makes of them depends on its \
             decoder's latency, which only the bench (real firmware, exact edges) has",
        ),
        u(
            BACKLASH,
            "lost motion when a wheel reverses at the start of a spin: at the kinematic level a \
             constant angle lost per turn, i.e. a negative coast; not modelled separately",
        ),
    ]
}

impl Model for KinematicModel {
    fn name(&self) -> String {
        "kinematic".to_owned()
    }

    fn parameters(&self) -> Vec<ParamSpec> {
        kinematic_parameters()
    }

    fn unsupported(&self) -> Vec<Unsupported> {
        kinematic_unsupported()
    }

    fn predict(
        &self,
        params: &EffectParams,
        exp: &Experiment,
    ) -> Result<Vec<RunEndpoint>, ModelError> {
        check_params(&self.name(), &kinematic_parameters(), params)?;
        let phys = Physics::new(params, exp)?;
        let mut out = Vec::with_capacity(exp.runs);
        for run in 0..exp.runs {
            let mut rng = Rng::for_run(exp.seed, run as u64);
            out.push(phys.run(exp, &mut rng));
        }
        Ok(out)
    }
}

struct Physics {
    /// Actual mm per count, left and right.
    k_l: f64,
    k_r: f64,
    /// Actual wheelbase, mm.
    b: f64,
    slip: f64,
    coast_rad: f64,
    toe_rad: f64,
    /// rad per √m.
    noise: f64,
}

impl Physics {
    fn new(p: &EffectParams, exp: &Experiment) -> Result<Self, ModelError> {
        let fw = &exp.firmware;
        let r = &exp.reference;
        let positive = [
            ("reference wheelbase_mm", r.wheelbase_mm),
            ("reference mm_per_count", r.mm_per_count),
            ("firmware wheelbase_mm", fw.wheelbase_mm),
            ("firmware mm_per_count", fw.mm_per_count),
            ("firmware c_left", fw.c_left),
            ("firmware c_right", fw.c_right),
        ];
        for (what, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(ModelError::InvalidExperiment(format!(
                    "{what} must be a positive number, got {v}"
                )));
            }
        }
        if !(fw.leg_mm.is_finite() && fw.leg_mm >= 0.0) {
            return Err(ModelError::InvalidExperiment(format!(
                "leg_mm must be ≥ 0, got {}",
                fw.leg_mm
            )));
        }
        let ed = p.get_or(WHEEL_DIAMETER_RATIO, 1.0);
        let es = p.get_or(DISTANCE_SCALE, 1.0);
        let mean = r.mm_per_count / es;
        Ok(Physics {
            k_l: mean * 2.0 / (ed + 1.0),
            k_r: mean * 2.0 * ed / (ed + 1.0),
            b: r.wheelbase_mm * p.get_or(WHEELBASE_RATIO, 1.0),
            slip: p.get_or(TURN_SLIP, 0.0),
            coast_rad: p.get_or(COAST, 0.0).to_radians(),
            toe_rad: p.get_or(TOE, 0.0).to_radians(),
            noise: p.get_or(FLOOR_NOISE, 0.0).to_radians(),
        })
    }

    /// Exact arc for wheel travels (dL, dR), with an extra heading change spread along it and
    /// the travel direction offset by `toe`.
    fn arc(&self, p: Pose, d_l: f64, d_r: f64, extra: f64, toe: f64) -> Pose {
        let dtheta = (d_r - d_l) / self.b + extra;
        let ds = (d_r + d_l) / 2.0;
        let t = p.theta().0 + toe;
        let (dx, dy) = if dtheta.abs() < 1e-12 {
            (ds * t.cos(), ds * t.sin())
        } else {
            let r = ds / dtheta;
            (
                r * ((t + dtheta).sin() - t.sin()),
                r * (t.cos() - (t + dtheta).cos()),
            )
        };
        Pose::new(
            Millimetres(p.x().0 + dx),
            Millimetres(p.y().0 + dy),
            Radians(p.theta().0 + dtheta),
        )
    }

    /// A spin sub-segment: turn slip keeps `1 − s` of the differential (rotating) part of the
    /// wheel travel, the common (translating) part is kept.
    fn spin_arc(&self, p: Pose, d_l: f64, d_r: f64) -> Pose {
        let common = (d_l + d_r) / 2.0;
        let diff = (d_r - d_l) / 2.0 * (1.0 - self.slip);
        self.arc(p, common - diff, common + diff, 0.0, 0.0)
    }

    fn leg(&self, p: Pose, exp: &Experiment, rng: &mut Rng) -> Pose {
        let fw = &exp.firmware;
        let l = fw.leg_mm;
        let (n_l, n_r) = match fw.straight_legs {
            StraightLegs::SpeedSetpoints => {
                let rho = fw.setpoint_ratio();
                let n_r = 2.0 * l / (fw.mm_per_count * (fw.c_left * rho + fw.c_right));
                (rho * n_r, n_r)
            }
            StraightLegs::CorrectedOdometry => (
                l / (fw.mm_per_count * fw.c_left),
                l / (fw.mm_per_count * fw.c_right),
            ),
        };
        let (d_l, d_r) = (n_l * self.k_l, n_r * self.k_r);
        let extra = if self.noise > 0.0 {
            let metres = ((d_l + d_r) / 2.0).abs() / 1000.0;
            self.noise * metres.sqrt() * rng.normal()
        } else {
            0.0
        };
        let q = self.arc(p, d_l, d_r, extra, self.toe_rad);
        // Coasting after the cut-off: both wheels run on by the distance that turns a spin by
        // the coast angle.
        let run_on = self.coast_rad * self.b / 2.0;
        if run_on > 0.0 {
            self.arc(q, run_on, run_on, 0.0, self.toe_rad)
        } else {
            q
        }
    }

    fn spin(&self, p: Pose, exp: &Experiment, angle_rad: f64, sign: f64) -> Pose {
        let fw = &exp.firmware;
        let half_arc = angle_rad * fw.wheelbase_mm / 2.0;
        let n_l = half_arc / (fw.c_left * fw.mm_per_count);
        let n_r = half_arc / (fw.c_right * fw.mm_per_count);
        // Count rates of the two wheels while both run.
        let (r_l, r_r) = match fw.straight_legs {
            StraightLegs::SpeedSetpoints => (fw.setpoint_ratio(), 1.0),
            StraightLegs::CorrectedOdometry => (1.0 / fw.c_left, 1.0 / fw.c_right),
        };
        let t1 = (n_l / r_l).min(n_r / r_r);
        let (a_l, a_r) = (r_l * t1, r_r * t1);
        // Left turn: left wheel backward, right forward.
        let (s_l, s_r) = (-sign, sign);
        let mut q = self.spin_arc(p, s_l * a_l * self.k_l, s_r * a_r * self.k_r);
        let (b_l, b_r) = (n_l - a_l, n_r - a_r);
        if b_l > 1e-12 || b_r > 1e-12 {
            q = self.spin_arc(
                q,
                s_l * b_l.max(0.0) * self.k_l,
                s_r * b_r.max(0.0) * self.k_r,
            );
        }
        Pose::new(q.x(), q.y(), Radians(q.theta().0 + sign * self.coast_rad))
    }

    fn run(&self, exp: &Experiment, rng: &mut Rng) -> RunEndpoint {
        let test = exp.test;
        let turn = test.turn_deg(&exp.firmware).to_radians();
        let sign = test.turn_sign();
        let mut p = Pose::origin();
        for _ in 0..test.legs() {
            p = self.leg(p, exp, rng);
            if test != TestKind::Line {
                p = self.spin(p, exp, turn, sign);
            }
        }
        let commanded_heading = sign * turn * test.legs() as f64;
        // The commanded end: exact legs and exact turns ((L, 0) for the line, the start for
        // a closed polygon).
        let (mut cx, mut cy) = (0.0, 0.0);
        for k in 0..test.legs() {
            let h = sign * turn * k as f64;
            cx += exp.firmware.leg_mm * h.cos();
            cy += exp.firmware.leg_mm * h.sin();
        }
        let (x, y) = (p.x().0 - cx, p.y().0 - cy);
        RunEndpoint {
            x_cm: x / 10.0,
            y_cm: y / 10.0,
            theta_rad: wrap(p.theta().0 - commanded_heading),
        }
    }
}

/// Angle wrapped to (−π, π].
pub(crate) fn wrap(a: f64) -> f64 {
    let mut w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w -= 2.0 * PI;
    }
    w
}
