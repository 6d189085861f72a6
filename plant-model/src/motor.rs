//! Motor + gearbox + wheel under load: from the bridge's averaged drive state to the wheel's
//! speed and angle.
//!
//! A [`MotorModel`] is an enum so that fitted models of other kinds can be added as variants
//! (the config names the variant with `model = "..."`). Whatever the model, over an interval
//! of constant input it yields a [`Relaxation`] (target speed and time constant), and the
//! wheel's motion over that interval is the closed-form [`Segment`]. This is what lets the
//! plant answer "when is the next encoder transition?" exactly instead of by sampling.
//!
//! # The first-order model with dead band ([`FirstOrderMotor`])
//!
//! With `d` the signed driven fraction of the PWM period (`DriveState::drive`, `d1 - d2`),
//! `V` the battery voltage and all speeds in thesis "RPM" (true wheel RPM / 6, see
//! [`ThesisRpm`]):
//!
//! ```text
//! omega_ss(d) = sign(d) * K * max(0, |d| - d0) / (d_ref - d0) * V / V_fit
//! ```
//!
//! - `K` (`gain_thesis_rpm`) is the thesis' first-order gain: right 25.0, left 22.0. The thesis
//!   fitted it on the **mean** of its five step responses (PWM 170, 190, 210, 230, 250 out of
//!   255), so `K` is the steady speed at the mean duty `d_ref = 210/255`
//!   (`reference_duty`), not a gain per unit duty. Check: the mean of the five steady levels
//!   is 24.98 (right) and 21.81 (left).
//! - `d0` (`dead_band_duty`): the steady levels are not proportional to the duty: 14.4 at
//!   170/255 but 38.7 at 250/255 on the right wheel (a ratio of 2.7 for a duty ratio of 1.47).
//!   The motor needs a minimum duty to overcome friction under load. A line through the levels
//!   meets zero at `d0`: 129.24/255 = 0.5068 (right) and 147.79/255 = 0.5796 (left). The fit is
//!   least squares over **all five** levels with the line pinned at `(d_ref, K)`; because the
//!   duties are symmetric about 210, the least-squares line through all five passes through
//!   their centroid `(210/255, mean level)`, which is the thesis' own `(d_ref, K)` to within
//!   1 % (mean levels 24.98 and 21.81 against K = 25.0 and 22.0); so this fit and the thesis'
//!   gain agree. Dropping 170/255 (fitting 190..250) would
//!   match 250/255 better but discard the level nearest the firmware's speed set points
//!   (14.47 and 15.0). The levels are the mean of the three printed steady rows (samples
//!   127-129) of `motor_step_*.csv`. `tests/motor_fit.rs` recomputes `d0` from the CSVs and
//!   prints the residual per level (model minus measured, thesis RPM):
//!
//!   | PWM | right measured | right residual | left measured | left residual |
//!   |-----|----------------|----------------|---------------|---------------|
//!   | 170 | 14.360 | -1.743 (-12.1 %) |  9.583 | -1.729 (-18.0 %) |
//!   | 190 | 17.697 | +1.112 (+6.3 %)  | 13.633 | +1.294 (+9.5 %)  |
//!   | 210 | 23.207 | +1.793 (+7.7 %)  | 19.880 | +2.120 (+10.7 %) |
//!   | 230 | 30.930 | +0.261 (+0.8 %)  | 28.387 | +0.686 (+2.4 %)  |
//!   | 250 | 38.700 | -1.317 (-3.4 %)  | 37.570 | -1.425 (-3.8 %)  |
//!
//!   The measured curve bends (its slope grows from 0.17 to 0.39 thesis RPM per count); a
//!   line cannot follow it. Near the set points the line's slope (0.31 right, 0.35 left) is
//!   about twice the measured local slope, which matters for closed-loop behaviour; a fitted
//!   curve is a later model variant.
//! - `V / V_fit`: the steady speed scales with the battery voltage relative to the voltage
//!   of the fit (`fit_voltage_v`, the nominal 7.4 V of the 2S pack).
//!
//! The wheel's speed relaxes to `omega_ss` with the time constant `tau` (`tau_s`: right
//! 0.0685 s, left 0.055 s, the thesis' 63.2 % fits). When the motor is not driven beyond the
//! dead band (`|d| <= d0`, including `d = 0`) the target is 0 and the time constant is a mix
//! of the coast and brake constants weighted by the fractions of the period spent coasting and
//! braking: `1 / tau = b / tau_brake + (1 - b) / tau_coast`, `b` the braking fraction
//! (`coast_tau_s`, default `tau_s`; `brake_tau_s`, default `tau_s / 3`). Decay relaxes to 0
//! and so never reverses the wheel; only a drive of the other sign does.
//!
//! The motion over an interval of constant input, from speed `w0` and angle `a0`:
//!
//! ```text
//! omega(t) = w_ss + (w0 - w_ss) e^(-t/tau)
//! angle(t) = a0 + w_ss t + (w0 - w_ss) tau (1 - e^(-t/tau))
//! ```
//!
//! # What effects and faults change ([`Modifiers`])
//!
//! The effects library ([`crate::effects`]) and the faults ([`crate::MotorFault`]) act on the
//! motor through three numbers, each neutral by default:
//!
//! - a gain ratio `g` (`motor_gain_asymmetry`) multiplies `omega_ss`;
//! - a friction duty `f` (`dead_band`, `castor_drag`, a `LoadStep` fault): a load torque
//!   expressed as the duty that would balance it, i.e. as a fraction of the stall torque at
//!   full duty. In steady state a load torque and a dead band are the same thing (a DC motor's
//!   `w_ss = (d V kt / R - tau_load) / (kt ke / R)` is a line in `d` offset by
//!   `tau_load R / (kt V)`), so while driven it widens the dead band:
//!   `omega_ss = sign(d) g K max(0, |d| - d0 - f) / (d_ref - d0) V / V_fit`. While not driven
//!   it is a Coulomb deceleration `c = g K f / (d_ref - d0) V / V_fit / tau` (the same offset
//!   over the same time constant), so the wheel stops in finite time,
//!   `t_stop = tau_d ln(1 + |w0| / (c tau_d))`, and stays stopped (first order with an offset,
//!   still closed form; [`Relaxation::stops_at_zero`]);
//! - a coast time constant (`coast`): replaces `coast_tau_s` while coasting.
//!
//! With all three neutral the motion is bit for bit the base model's.

use serde::{Deserialize, Serialize};

use crate::bridge::DriveState;
use crate::check::{check_duty, check_physical, GAIN_THESIS_RPM, TIME_CONSTANT_S, VOLTAGE_V};
use crate::units::{RadPerSec, Radians, Seconds, ThesisRpm, Volts};
use crate::Error;

/// A motor + gearbox + loaded-wheel model, selected in the config by `model = "..."`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum MotorModel {
    /// First-order response with a dead band (see the module docs).
    FirstOrder(FirstOrderMotor),
}

impl MotorModel {
    /// The speed target and time constant while the bridge is in `drive` and the battery is
    /// at `battery`.
    pub fn relaxation(&self, drive: DriveState, battery: Volts) -> Relaxation {
        match self {
            MotorModel::FirstOrder(motor) => motor.relaxation(drive, battery),
        }
    }

    /// The speed target and time constant while the bridge is in `drive`, the battery is at
    /// `battery`, the effects and faults in `modifiers` apply and the wheel turns at `speed`
    /// (the sign of the speed says which way friction acts).
    pub fn relaxation_with(
        &self,
        drive: DriveState,
        battery: Volts,
        modifiers: &Modifiers,
        speed: RadPerSec,
    ) -> Relaxation {
        match self {
            MotorModel::FirstOrder(motor) => {
                motor.relaxation_with(drive, battery, modifiers, speed)
            }
        }
    }

    /// Back-EMF constant at the wheel, volts per wheel rad/s, for a motor whose gain is scaled
    /// by `gain_ratio`: the voltage the motor generates when its wheel turns at 1 rad/s.
    pub fn back_emf_v_per_rad_s(&self, gain_ratio: f64) -> f64 {
        match self {
            MotorModel::FirstOrder(motor) => motor.back_emf_v_per_rad_s(gain_ratio),
        }
    }

    /// Checks the parameters; `prefix` is the config section (e.g. `motor.left`), used to name
    /// keys in errors.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        match self {
            MotorModel::FirstOrder(motor) => motor.validate(prefix),
        }
    }
}

/// What the effects and faults change in a motor's response (see the module docs); the
/// default changes nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modifiers {
    /// Multiplies the steady speed (`motor_gain_asymmetry`).
    pub gain_ratio: f64,
    /// Load torque as a duty, i.e. as a fraction of the stall torque at full duty
    /// (`dead_band`, `castor_drag`, a `LoadStep` fault); widens the dead band while driven,
    /// decelerates by Coulomb friction while not.
    pub friction_duty: f64,
    /// Time constant while coasting, replacing the motor's own (`coast`).
    pub coast_tau: Option<Seconds>,
}

impl Default for Modifiers {
    fn default() -> Self {
        Modifiers {
            gain_ratio: 1.0,
            friction_duty: 0.0,
            coast_tau: None,
        }
    }
}

/// Parameters of the first-order model with dead band (see the module docs for the formula
/// and where the numbers come from).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FirstOrderMotor {
    /// `K`: steady wheel speed at `reference_duty` and `fit_voltage_v`, in thesis "RPM".
    pub gain_thesis_rpm: f64,
    /// `d_ref`: the duty at which the steady speed is `K` (the thesis: 210/255, the mean duty
    /// of its five step responses).
    pub reference_duty: f64,
    /// `d0`: the duty below which the loaded motor does not turn.
    pub dead_band_duty: f64,
    /// `tau`: time constant while driven, seconds.
    pub tau_s: f64,
    /// Time constant while coasting (both inputs low), seconds; `tau_s` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coast_tau_s: Option<f64>,
    /// Time constant while braking (both inputs high), seconds; `tau_s / 3` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub brake_tau_s: Option<f64>,
    /// Battery voltage at which `K` was measured, volts.
    pub fit_voltage_v: f64,
}

/// Reference duty of the thesis fits: the mean of its step-response duties 170..250 of 255.
pub const THESIS_REFERENCE_DUTY: f64 = 210.0 / 255.0;

impl FirstOrderMotor {
    /// The left motor as fitted from the thesis (gain 22.0, tau 0.055 s, dead band fitted
    /// from `motor_step_left.csv`).
    pub fn henrytwo_left() -> Self {
        FirstOrderMotor {
            gain_thesis_rpm: 22.0,
            reference_duty: THESIS_REFERENCE_DUTY,
            dead_band_duty: 0.5796,
            tau_s: 0.055,
            coast_tau_s: None,
            brake_tau_s: None,
            fit_voltage_v: 7.4,
        }
    }

    /// The right motor as fitted from the thesis (gain 25.0, tau 0.0685 s, dead band fitted
    /// from `motor_step_right.csv`).
    pub fn henrytwo_right() -> Self {
        FirstOrderMotor {
            gain_thesis_rpm: 25.0,
            reference_duty: THESIS_REFERENCE_DUTY,
            dead_band_duty: 0.5068,
            tau_s: 0.0685,
            coast_tau_s: None,
            brake_tau_s: None,
            fit_voltage_v: 7.4,
        }
    }

    /// Time constant while coasting.
    pub fn coast_tau(&self) -> Seconds {
        Seconds(self.coast_tau_s.unwrap_or(self.tau_s))
    }

    /// Time constant while braking.
    pub fn brake_tau(&self) -> Seconds {
        Seconds(self.brake_tau_s.unwrap_or(self.tau_s / 3.0))
    }

    /// `omega_ss(d)` of the module docs.
    pub fn steady_speed(&self, drive: f64, battery: Volts) -> RadPerSec {
        let excess = (drive.abs() - self.dead_band_duty).max(0.0);
        let rpm = drive.signum() * self.gain_thesis_rpm * excess
            / (self.reference_duty - self.dead_band_duty)
            * (battery.0 / self.fit_voltage_v);
        if excess > 0.0 {
            ThesisRpm(rpm).into()
        } else {
            RadPerSec::ZERO
        }
    }

    /// Target and time constant for one bridge state (see the module docs).
    pub fn relaxation(&self, drive: DriveState, battery: Volts) -> Relaxation {
        self.relaxation_with(drive, battery, &Modifiers::default(), RadPerSec::ZERO)
    }

    /// Steady wheel speed per unit of duty beyond the dead band at the fit voltage, rad/s:
    /// `K / (d_ref - d0)`.
    pub fn slope_rad_s_per_duty(&self) -> f64 {
        RadPerSec::from(ThesisRpm(self.gain_thesis_rpm)).0
            / (self.reference_duty - self.dead_band_duty)
    }

    /// Back-EMF constant at the wheel, V per wheel rad/s: the steady line rises by
    /// `g K / (d_ref - d0)` per unit of duty at `V_fit`, and a DC motor's rises by
    /// `V / ke`, so `ke = V_fit (d_ref - d0) / (g K)` (0.149 V s/rad for the right motor:
    /// `plant_model::identify`'s physical fit gives `kt` = 1.487e-3 V s/rad at the motor shaft,
    /// 0.149 at the wheel).
    pub fn back_emf_v_per_rad_s(&self, gain_ratio: f64) -> f64 {
        self.fit_voltage_v / (gain_ratio * self.slope_rad_s_per_duty())
    }

    /// Target and time constant for one bridge state under `modifiers`, the wheel turning at
    /// `speed` (see the module docs).
    pub fn relaxation_with(
        &self,
        drive: DriveState,
        battery: Volts,
        modifiers: &Modifiers,
        speed: RadPerSec,
    ) -> Relaxation {
        let d = drive.drive();
        let excess = (d.abs() - self.dead_band_duty - modifiers.friction_duty).max(0.0);
        if excess > 0.0 {
            let rpm = d.signum() * modifiers.gain_ratio * self.gain_thesis_rpm * excess
                / (self.reference_duty - self.dead_band_duty)
                * (battery.0 / self.fit_voltage_v);
            return Relaxation {
                target: ThesisRpm(rpm).into(),
                tau: Seconds(self.tau_s),
                stops_at_zero: false,
            };
        }
        let brake = drive.brake_fraction();
        let coast = modifiers.coast_tau.unwrap_or(self.coast_tau());
        let rate = brake / self.brake_tau().0 + (1.0 - brake) / coast.0;
        let tau = 1.0 / rate;
        if modifiers.friction_duty > 0.0 && speed.0 != 0.0 {
            let decel = modifiers.gain_ratio
                * self.slope_rad_s_per_duty()
                * modifiers.friction_duty
                * (battery.0 / self.fit_voltage_v)
                / self.tau_s;
            return Relaxation {
                target: RadPerSec(-speed.0.signum() * decel * tau),
                tau: Seconds(tau),
                stops_at_zero: true,
            };
        }
        Relaxation {
            target: RadPerSec::ZERO,
            tau: Seconds(tau),
            stops_at_zero: false,
        }
    }

    fn validate(&self, prefix: &str) -> Result<(), Error> {
        let key = |name: &str| format!("{prefix}.{name}");
        check_physical(
            &key("gain_thesis_rpm"),
            self.gain_thesis_rpm,
            GAIN_THESIS_RPM,
            "steady wheel speed at the reference duty",
        )?;
        check_duty(&key("reference_duty"), self.reference_duty)?;
        check_duty(&key("dead_band_duty"), self.dead_band_duty)?;
        if self.dead_band_duty >= self.reference_duty {
            return Err(Error::DeadBandNotBelowReference {
                dead_band_key: key("dead_band_duty"),
                dead_band: self.dead_band_duty,
                reference_key: key("reference_duty"),
                reference: self.reference_duty,
            });
        }
        let tau = |name: &str, value: f64, meaning| {
            check_physical(&key(name), value, TIME_CONSTANT_S, meaning)
        };
        tau("tau_s", self.tau_s, "time constant while driven")?;
        if let Some(t) = self.coast_tau_s {
            tau("coast_tau_s", t, "time constant while coasting")?;
        }
        if let Some(t) = self.brake_tau_s {
            tau("brake_tau_s", t, "time constant while braking")?;
        }
        check_physical(
            &key("fit_voltage_v"),
            self.fit_voltage_v,
            VOLTAGE_V,
            "battery voltage of the fit",
        )?;
        Ok(())
    }
}

/// First-order relaxation towards a target speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxation {
    /// The speed approached.
    pub target: RadPerSec,
    /// The time constant of the approach.
    pub tau: Seconds,
    /// The target is a Coulomb friction offset, not a drive: the wheel stops where the speed
    /// reaches 0 and stays there instead of turning round.
    pub stops_at_zero: bool,
}

impl Relaxation {
    /// Relaxation towards `target` with time constant `tau`, turning round if the target has
    /// the other sign.
    pub fn towards(target: RadPerSec, tau: Seconds) -> Self {
        Relaxation {
            target,
            tau,
            stops_at_zero: false,
        }
    }
}

/// The wheel's motion over an interval of constant input, in closed form (module docs).
///
/// Evaluated at absolute plant times `t >= start`. Evaluating the same segment at the same
/// time always gives the same bits, which is what makes encoder transition times found on a
/// segment consistent with the states reached by advancing to them.
///
/// A relaxation that [stops at zero](Relaxation::stops_at_zero) holds the angle it reached
/// from the stop time on ([`Segment::stop_time`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    start: Seconds,
    angle0: f64,
    speed0: f64,
    target: f64,
    tau: f64,
    /// Time at which the wheel stops for good (infinite if it does not).
    stop: f64,
    /// The angle from `stop` on.
    angle_stop: f64,
}

impl Segment {
    /// Motion from `angle`, `speed` at time `start` under `relaxation`.
    pub fn new(start: Seconds, angle: Radians, speed: RadPerSec, relaxation: Relaxation) -> Self {
        let mut segment = Segment {
            start,
            angle0: angle.0,
            speed0: speed.0,
            target: relaxation.target.0,
            tau: relaxation.tau.0,
            stop: f64::INFINITY,
            angle_stop: angle.0,
        };
        if relaxation.stops_at_zero {
            if segment.speed0 == 0.0 {
                segment.target = 0.0;
            } else if let Some(tz) = segment.zero_crossing() {
                segment.angle_stop = segment.angle_at(tz).0;
                segment.stop = tz.0;
            }
        }
        segment
    }

    /// A wheel held still at `angle` from `start` on (a stalled wheel).
    pub fn held(start: Seconds, angle: Radians) -> Self {
        Segment::new(
            start,
            angle,
            RadPerSec::ZERO,
            Relaxation::towards(RadPerSec::ZERO, Seconds(1.0)),
        )
    }

    /// The time at which the wheel stops for good under Coulomb friction, if it does.
    pub fn stop_time(&self) -> Option<Seconds> {
        self.stop.is_finite().then_some(Seconds(self.stop))
    }

    /// Time at which the segment starts.
    pub fn start(&self) -> Seconds {
        self.start
    }

    /// The relaxation the segment follows.
    pub fn relaxation(&self) -> Relaxation {
        Relaxation {
            target: RadPerSec(self.target),
            tau: Seconds(self.tau),
            stops_at_zero: self.stop.is_finite(),
        }
    }

    /// The largest wheel speed (rad/s, unsigned) of the segment: the speed goes from its
    /// start value towards the target without overshoot (and stops at zero under Coulomb
    /// friction).
    pub fn speed_bound(&self) -> f64 {
        self.speed0.abs().max(self.target.abs())
    }

    /// True when the wheel is still and will stay so.
    pub fn is_at_rest(&self) -> bool {
        self.speed0 == 0.0 && self.target == 0.0
    }

    /// True when the wheel is still at `t` and will stay so.
    pub fn is_at_rest_from(&self, t: Seconds) -> bool {
        self.is_at_rest() || t.0 >= self.stop
    }

    /// Wheel angle at time `t` (`t >= start`).
    pub fn angle_at(&self, t: Seconds) -> Radians {
        if t.0 >= self.stop {
            return Radians(self.angle_stop);
        }
        let dt = t.0 - self.start.0;
        // 1 - e^(-dt/tau), accurate for small dt too.
        let settled = -(-dt / self.tau).exp_m1();
        self.angle_with(dt, settled)
    }

    /// The angle at `t` (`t >= start`) with the exponential it took, `e^(-(t - start)/tau)
    /// - 1` (NaN from the stop time on, where none is taken): the angle is
    /// [`Segment::angle_at`]'s, bit for bit, and the exponential lets [`Segment::around`]
    /// expand the motion about `t` without another.
    pub(crate) fn evaluate(&self, t: Seconds) -> (Radians, f64) {
        if t.0 >= self.stop {
            return (Radians(self.angle_stop), f64::NAN);
        }
        let dt = t.0 - self.start.0;
        let decay_m1 = (-dt / self.tau).exp_m1();
        (self.angle_with(dt, -decay_m1), decay_m1)
    }

    /// The angle `dt` after the start, with `settled = 1 - e^(-dt/tau)`.
    fn angle_with(&self, dt: f64, settled: f64) -> Radians {
        Radians(self.angle0 + self.target * dt + (self.speed0 - self.target) * self.tau * settled)
    }

    /// The motion about `a` (before the stop time), from [`Segment::evaluate`]'s answer there:
    /// cheap to evaluate near `a`, equal to the segment's closed form to rounding.
    pub(crate) fn around(&self, a: Seconds, (angle, decay_m1): (Radians, f64)) -> Around {
        debug_assert!(a.0 < self.stop, "expanded at or past the stop time");
        Around {
            angle: angle.0,
            target: self.target,
            transient: (self.speed0 - self.target) * (1.0 + decay_m1),
            tau: self.tau,
        }
    }

    /// Wheel speed at time `t` (`t >= start`).
    pub fn speed_at(&self, t: Seconds) -> RadPerSec {
        if t.0 >= self.stop {
            return RadPerSec::ZERO;
        }
        let dt = t.0 - self.start.0;
        RadPerSec(self.target + (self.speed0 - self.target) * (-dt / self.tau).exp())
    }

    /// The time after `start` at which the speed passes through zero, if it does: only when
    /// the wheel turns one way and is driven the other. The angle is monotone on each side of
    /// this time. (A wheel slowed by Coulomb friction stops there instead:
    /// [`Segment::stop_time`].)
    pub fn speed_reversal(&self) -> Option<Seconds> {
        if self.stop.is_finite() {
            None
        } else {
            self.zero_crossing()
        }
    }

    fn zero_crossing(&self) -> Option<Seconds> {
        if self.speed0 != 0.0 && self.target != 0.0 && self.speed0.signum() != self.target.signum()
        {
            // w_ss + (w0 - w_ss) e^(-t/tau) = 0  =>  t = tau ln(1 - w0 / w_ss)
            Some(Seconds(
                self.start.0 + self.tau * (-self.speed0 / self.target).ln_1p(),
            ))
        } else {
            None
        }
    }

    /// The times in `(from, to)` at which the direction of motion changes or the motion ends
    /// (speed reversal, Coulomb stop): the angle is monotone between them.
    pub fn turning_points(&self, from: Seconds, to: Seconds) -> impl Iterator<Item = Seconds> {
        [self.speed_reversal(), self.stop_time()]
            .into_iter()
            .flatten()
            .filter(move |&t| t > from && t < to)
    }
}

/// A [`Segment`] expanded about a time `a`: angle and speed at `a + u`, with `e^(-u/tau)`
/// from a short series when `u` is small against `tau` (the usual case: the next encoder
/// edge is a fraction of a millisecond away, the time constants tens of milliseconds). For
/// solving where the angle reaches a value; the answer is then checked on the closed form.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Around {
    angle: f64,
    target: f64,
    /// The speed's distance from its target at `a`.
    transient: f64,
    tau: f64,
}

impl Around {
    /// Angle (rad) and speed (rad/s) at `a + u`.
    pub(crate) fn state(&self, u: f64) -> (f64, f64) {
        let decay_m1 = expm1_near_zero(-u / self.tau);
        (
            self.angle + self.target * u - self.transient * self.tau * decay_m1,
            self.target + self.transient * (1.0 + decay_m1),
        )
    }

    /// The angular acceleration (rad/s^2) at `a + u`, given the speed there.
    pub(crate) fn acceleration(&self, speed: f64) -> f64 {
        (self.target - speed) / self.tau
    }
}

/// `e^x - 1`: a series for `|x| <= 1/32` (error below 1e-16 relative), the library's beyond.
fn expm1_near_zero(x: f64) -> f64 {
    if x.abs() <= 1.0 / 32.0 {
        // Horner on x + x^2/2 + ... + x^8/8!; the next term is below 2^-45 x.
        x * (1.0
            + x * (1.0 / 2.0
                + x * (1.0 / 6.0
                    + x * (1.0 / 24.0
                        + x * (1.0 / 120.0
                            + x * (1.0 / 720.0 + x * (1.0 / 5040.0 + x * (1.0 / 40320.0))))))))
    } else {
        x.exp_m1()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Duty;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    fn fwd(duty: f64) -> DriveState {
        DriveState::from_inputs(Duty::new(duty).unwrap(), Duty::OFF)
    }

    const V: Volts = Volts(7.4);

    /// At the reference duty the steady speed is the thesis gain K, converted to rad/s; at
    /// twice the voltage it doubles; in reverse it is negated.
    #[test]
    fn gain_is_the_speed_at_the_reference_duty() {
        let m = FirstOrderMotor::henrytwo_right();
        let at_ref = m.steady_speed(THESIS_REFERENCE_DUTY, V);
        assert_relative_eq!(at_ref.to_thesis_rpm().0, 25.0, epsilon = 1e-12);
        assert_relative_eq!(
            m.steady_speed(THESIS_REFERENCE_DUTY, Volts(14.8)).0,
            2.0 * at_ref.0,
            epsilon = 1e-12
        );
        assert_eq!(m.steady_speed(-THESIS_REFERENCE_DUTY, V), -at_ref);
    }

    /// Inside the dead band there is no drive: target 0, coast time constant; with both
    /// inputs high the brake time constant (tau / 3 by default).
    #[test]
    fn dead_band_coasts_and_both_high_brakes() {
        let m = FirstOrderMotor::henrytwo_left();
        let r = m.relaxation(fwd(0.5), V);
        assert_eq!(r.target, RadPerSec::ZERO);
        assert_relative_eq!(r.tau.0, 0.055, epsilon = 1e-15);
        let brake = DriveState::from_inputs(Duty::FULL, Duty::FULL);
        let r = m.relaxation(brake, V);
        assert_eq!(r.target, RadPerSec::ZERO);
        assert_relative_eq!(r.tau.0, 0.055 / 3.0, epsilon = 1e-15);
    }

    /// The closed form agrees with a fine RK4 integration of
    /// `d omega/dt = (w_ss - omega)/tau, d angle/dt = omega`, for driving, reversing through
    /// zero, coasting and braking.
    #[test]
    fn closed_form_matches_numerical_integration() {
        let m = FirstOrderMotor::henrytwo_right();
        let cases = [
            (0.0, fwd(0.98)),
            (
                20.0,
                DriveState::from_inputs(Duty::OFF, Duty::new(0.9).unwrap()),
            ),
            (-15.0, DriveState::COAST),
            (24.0, DriveState::from_inputs(Duty::FULL, Duty::FULL)),
        ];
        for (w0, drive) in cases {
            let relax = m.relaxation(drive, V);
            let seg = Segment::new(Seconds(0.5), Radians(1.0), RadPerSec(w0), relax);
            let (w_ss, tau) = (relax.target.0, relax.tau.0);
            let f = |w: f64| (w_ss - w) / tau;
            let (mut w, mut a) = (w0, 1.0);
            let h = 1e-5;
            for step in 1..=30_000 {
                let k1w = f(w);
                let k2w = f(w + 0.5 * h * k1w);
                let k3w = f(w + 0.5 * h * k2w);
                let k4w = f(w + h * k3w);
                let (k1a, k2a, k3a, k4a) = (w, w + 0.5 * h * k1w, w + 0.5 * h * k2w, w + h * k3w);
                w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
                a += h / 6.0 * (k1a + 2.0 * k2a + 2.0 * k3a + k4a);
                if step % 1000 == 0 {
                    let t = Seconds(0.5 + h * f64::from(step));
                    assert_relative_eq!(seg.speed_at(t).0, w, epsilon = 1e-9);
                    assert_relative_eq!(seg.angle_at(t).0, a, epsilon = 1e-9);
                }
            }
        }
    }

    /// The reversal time is where the closed-form speed is zero.
    #[test]
    fn speed_reversal_is_a_zero_of_the_speed() {
        let m = FirstOrderMotor::henrytwo_left();
        let reverse = DriveState::from_inputs(Duty::OFF, Duty::FULL);
        let seg = Segment::new(
            Seconds(2.0),
            Radians::ZERO,
            RadPerSec(20.0),
            m.relaxation(reverse, V),
        );
        let tz = seg.speed_reversal().unwrap();
        assert!(tz > Seconds(2.0));
        assert!(seg.speed_at(tz).0.abs() < 1e-12);
        assert!(seg.speed_at(tz - Seconds(1e-6)).0 > 0.0);
        assert!(seg.speed_at(tz + Seconds(1e-6)).0 < 0.0);
    }

    /// The short series for `e^x - 1` is the library's to rounding over its whole range
    /// (|x| <= 1/32), where the next term it drops is below 2^-45 x: a wrong coefficient
    /// anywhere up to the x^7 term is off by more than 1e-15 relative somewhere.
    #[test]
    fn series_for_expm1_is_the_library_to_rounding() {
        for i in -256..=256 {
            let x = f64::from(i) / (256.0 * 32.0);
            let (series, library) = (expm1_near_zero(x), x.exp_m1());
            assert!(
                (series - library).abs() <= 1e-15 * library.abs(),
                "x = {x}: series {series}, library {library}"
            );
        }
        // Beyond the series' range it is the library's.
        assert_eq!(expm1_near_zero(0.5), 0.5f64.exp_m1());
    }

    /// The expansion about `a` gives the closed form's angle and speed at `a + u`, for
    /// steps where the series serves (u much shorter than tau) and where it does not.
    #[test]
    fn expansion_about_a_time_is_the_closed_form() {
        let m = FirstOrderMotor::henrytwo_left();
        let seg = Segment::new(
            Seconds(0.1),
            Radians(2.0),
            RadPerSec(-3.0),
            m.relaxation(fwd(0.8), V),
        );
        let a = Seconds(0.13);
        let around = seg.around(a, seg.evaluate(a));
        for u in [0.0, 1e-4, 1.5e-3, 0.02, 0.2] {
            let (angle, speed) = around.state(u);
            let t = Seconds(a.0 + u);
            assert_relative_eq!(angle, seg.angle_at(t).0, max_relative = 1e-13);
            assert_relative_eq!(speed, seg.speed_at(t).0, max_relative = 1e-13);
        }
    }

    proptest! {
        /// Coasting or braking from any speed never reverses the wheel: the speed keeps its
        /// sign and shrinks, for any mix of brake and coast time.
        #[test]
        fn decay_never_reverses(w0 in -40.0f64..40.0, brake in 0.0f64..=1.0, dt in 0.0f64..5.0) {
            let m = FirstOrderMotor::henrytwo_right();
            let drive = DriveState::from_inputs(Duty::new(brake).unwrap(), Duty::new(brake).unwrap());
            let seg = Segment::new(Seconds::ZERO, Radians::ZERO, RadPerSec(w0), m.relaxation(drive, V));
            let w = seg.speed_at(Seconds(dt)).0;
            prop_assert!(w * w0 >= 0.0);
            prop_assert!(w.abs() <= w0.abs());
            prop_assert!(seg.speed_reversal().is_none());
        }
    }
}
