//! The first-order motor model with dead band (see [the motor module](super) for the formula
//! and where the numbers come from).

use serde::{Deserialize, Serialize};

use super::{Modifiers, Relaxation};
use crate::bridge::DriveState;
use crate::check::{check_duty, check_physical, GAIN_THESIS_RPM, TIME_CONSTANT_S, VOLTAGE_V};
use crate::units::{RadPerSec, Seconds, ThesisRpm, Volts};
use crate::Error;

/// Parameters of the first-order model with dead band (see the [`motor`](super) module docs
/// for the formula and where the numbers come from).
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

    /// `omega_ss(d)` of the [`motor`](super) module docs.
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

    /// Target and time constant for one bridge state (see the [`motor`](super) module
    /// docs).
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
    /// `speed` (see the [`motor`](super) module docs).
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

    pub(super) fn validate(&self, prefix: &str) -> Result<(), Error> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Duty;
    use approx::assert_relative_eq;

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
}
