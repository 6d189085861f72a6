//! Faults the bench switches on and off at exact times (fault injection).
//!
//! Each fault changes the plant's dynamics from the moment it is set (after
//! [`crate::Robot::advance_to`] to that moment). Motor faults change the encoder's timing, so
//! the bench re-plans both wheels' transitions after setting one; a slip burst and a battery
//! override are set the same way. The bench's own injection point (between the plant and the
//! pins: encoder lines, a bridge's inputs, the link) is `hil::inject`; these are the faults of
//! the physics.
//!
//! | call | encoder | pose |
//! |---|---|---|
//! | [`MotorFault::Stall`] | the shaft is blocked with the wheel: no edges while stalled | the wheel does not turn: the robot pivots about it or stops |
//! | [`MotorFault::Disconnected`] | the motor coasts down (coast time constant), then no edges | as the wheel: it rolls out and stops |
//! | [`MotorFault::LoadStep`] | steady speed lower (open loop) or more duty for the same speed (closed loop) | follows the wheel |
//! | [`crate::Robot::set_slip_burst`] | unchanged: the wheel turns as before | the ground sees `1 - slip` of that wheel's travel |
//! | [`crate::Robot::set_battery_voltage_override`] | every driven wheel's steady speed scales with the voltage | follows the wheels |

use serde::{Deserialize, Serialize};

use crate::Error;

/// A fault of one motor (and its wheel).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotorFault {
    /// No fault.
    #[default]
    None,
    /// The wheel is blocked: its speed is forced to 0 (at once) while stalled, whatever the
    /// bridge does; the motor draws its stall current. Clearing the fault lets it start from
    /// rest.
    Stall,
    /// The bridge no longer drives the motor (a broken wire): it coasts whatever the inputs
    /// are, as with both inputs low.
    Disconnected,
    /// An extra load torque opposing the drive, as a fraction of the motor's stall torque at
    /// full duty and the fit voltage: the dead band widens by that duty, so the steady speed
    /// at a given duty drops by `K / (d_ref - d0) * torque_fraction` (see [`crate::motor`]),
    /// and a coasting wheel stops sooner.
    LoadStep {
        /// Load torque / stall torque at full duty, in `[0, 1]`.
        torque_fraction: f64,
    },
}

impl MotorFault {
    /// Checks the fault's parameters.
    pub fn validate(&self) -> Result<(), Error> {
        match *self {
            MotorFault::LoadStep { torque_fraction }
                if !(torque_fraction.is_finite() && (0.0..=1.0).contains(&torque_fraction)) =>
            {
                Err(Error::InvalidFault {
                    what: "LoadStep torque_fraction",
                    value: torque_fraction,
                    allowed: "a fraction of the stall torque must lie in [0, 1]",
                })
            }
            _ => Ok(()),
        }
    }

    /// The load as a duty (0 unless [`MotorFault::LoadStep`]).
    pub(crate) fn load_duty(&self) -> f64 {
        match *self {
            MotorFault::LoadStep { torque_fraction } => torque_fraction,
            _ => 0.0,
        }
    }
}
