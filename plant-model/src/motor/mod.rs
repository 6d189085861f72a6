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
//! [`ThesisRpm`](crate::ThesisRpm)):
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
//!
//! # Files
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`MotorModel`], the [`Modifiers`] effects and faults apply, the [`Relaxation`] a model yields |
//! | `first_order.rs` | [`FirstOrderMotor`]: the first-order model with dead band, the thesis' two motors |
//! | `segment.rs` | [`Segment`]: the wheel's closed-form motion over an interval of constant input |

mod first_order;
mod segment;

use serde::{Deserialize, Serialize};

use crate::bridge::DriveState;
use crate::units::{RadPerSec, Seconds, Volts};
use crate::Error;
pub use first_order::{FirstOrderMotor, THESIS_REFERENCE_DUTY};
pub(crate) use segment::Around;
pub use segment::Segment;

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
