//! DRV8833 H-bridge, one per motor: two input duties in, an averaged drive state out.
//!
//! # Truth table (DRV8833 datasheet, one bridge)
//!
//! | IN1 | IN2 | outputs          | motor                          |
//! |-----|-----|------------------|--------------------------------|
//! | 0   | 0   | both high-Z      | coast (fast decay)             |
//! | 1   | 0   | OUT1 H, OUT2 L   | forward                        |
//! | 0   | 1   | OUT1 L, OUT2 H   | reverse                        |
//! | 1   | 1   | both low         | brake (slow decay, shorted)    |
//!
//! The thesis firmware drives one input with PWM and holds the other low: forward with
//! `IN1 = PWM, IN2 = 0`, reverse with `IN1 = 0, IN2 = PWM`. During the on-time the motor is
//! driven, during the off-time both inputs are low and it coasts (fast decay). With
//! `IN1 = 1, IN2 = PWM` the off-time brakes instead (slow decay, forward at `1 - duty`).
//!
//! # Averaged model (the choice made here)
//!
//! The PWM runs at 31.37 kHz (period 32 us) against mechanical time constants of 55-69 ms, a
//! ratio of about 2000: the wheel cannot follow the ripple, so the plant uses the average over
//! a PWM period. Assuming both inputs of a bridge start their high time together (same timer,
//! same mode), a period with duties `d1`, `d2` splits into
//!
//! - `min(d1, d2)`: both high, brake;
//! - `|d1 - d2|`: one high, driven (forward if `d1 > d2`);
//! - `1 - max(d1, d2)`: both low, coast.
//!
//! The [`DriveState`] keeps the signed driven fraction `d1 - d2` in `[-1, 1]` and the braking
//! fraction; the motor model turns them into a speed target and a time constant. Current
//! ripple, the bridge's dead time and its on-resistance are not modelled: the motor fit
//! includes whatever they did on the real robot.

use crate::Duty;

/// What the motor does while the driven part of the period is off.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decay {
    /// Off-time coasts (both inputs low): the motor current decays fast through the diodes.
    Fast,
    /// Some or all of the off-time brakes (both inputs high): the motor is shorted.
    Slow,
}

/// The averaged state of one bridge over a PWM period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriveState {
    drive: f64,
    brake: f64,
}

impl DriveState {
    /// Both inputs low: the motor coasts.
    pub const COAST: DriveState = DriveState {
        drive: 0.0,
        brake: 0.0,
    };

    /// The averaged state for input duties `in1`, `in2` (see the module docs).
    pub fn from_inputs(in1: Duty, in2: Duty) -> DriveState {
        let (d1, d2) = (in1.get(), in2.get());
        DriveState {
            drive: d1 - d2,
            brake: d1.min(d2),
        }
    }

    /// Signed fraction of the period during which the motor is driven: positive forward
    /// (`IN1` high, `IN2` low), negative reverse. In `[-1, 1]`.
    pub fn drive(&self) -> f64 {
        self.drive
    }

    /// Fraction of the period during which both inputs are high and the motor is shorted.
    pub fn brake_fraction(&self) -> f64 {
        self.brake
    }

    /// Fraction of the period during which both inputs are low and the motor coasts.
    pub fn coast_fraction(&self) -> f64 {
        1.0 - self.drive.abs() - self.brake
    }

    /// How the off-time behaves.
    pub fn decay(&self) -> Decay {
        if self.brake > 0.0 {
            Decay::Slow
        } else {
            Decay::Fast
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use rstest::rstest;

    fn duty(x: f64) -> Duty {
        Duty::new(x).unwrap()
    }

    /// The DRV8833 truth table and its PWM uses map to the drive, brake and coast fractions
    /// the module docs give.
    #[rstest]
    #[case::coast(0.0, 0.0, 0.0, 0.0, 1.0, Decay::Fast)]
    #[case::forward_full(1.0, 0.0, 1.0, 0.0, 0.0, Decay::Fast)]
    #[case::reverse_full(0.0, 1.0, -1.0, 0.0, 0.0, Decay::Fast)]
    #[case::brake(1.0, 1.0, 0.0, 1.0, 0.0, Decay::Slow)]
    #[case::forward_pwm_fast_decay(0.8, 0.0, 0.8, 0.0, 0.2, Decay::Fast)]
    #[case::reverse_pwm_fast_decay(0.0, 0.6, -0.6, 0.0, 0.4, Decay::Fast)]
    #[case::forward_slow_decay(1.0, 0.3, 0.7, 0.3, 0.0, Decay::Slow)]
    #[case::partial_brake(0.5, 0.5, 0.0, 0.5, 0.5, Decay::Slow)]
    fn truth_table(
        #[case] in1: f64,
        #[case] in2: f64,
        #[case] drive: f64,
        #[case] brake: f64,
        #[case] coast: f64,
        #[case] decay: Decay,
    ) {
        let state = DriveState::from_inputs(duty(in1), duty(in2));
        assert_relative_eq!(state.drive(), drive, epsilon = 1e-12);
        assert_relative_eq!(state.brake_fraction(), brake, epsilon = 1e-12);
        assert_relative_eq!(state.coast_fraction(), coast, epsilon = 1e-12);
        assert_eq!(state.decay(), decay);
    }
}
