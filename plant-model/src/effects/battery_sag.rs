//! `battery_sag`: the battery's voltage falls with its state of charge and under load.
//!
//! ```text
//! V = V_oc(SoC) - R_int I
//! V_oc(SoC) = V_empty + (V_full - V_empty) SoC            (linear; a LiPo's curve is flatter
//!                                                          in the middle, steeper at the ends)
//! SoC(t) = SoC_0 - Q(t) / C,   Q = charge drawn since time 0
//! I = I_idle + sum over motors of |d| (V - sign(d) ke omega) / R_m
//! ```
//!
//! Each bridge connects its motor to the battery for the driven fraction `|d|` of the PWM
//! period, when the motor takes `(V - e) / R_m` with `e = ke omega` its back EMF (`ke` at the
//! wheel follows from the fitted motor line, [`crate::motor::FirstOrderMotor::back_emf_v_per_rad_s`]);
//! coasting and braking draw nothing. A stalled or dead-banded motor (omega = 0) takes its
//! full `|d| V / R_m`. `I` depends on `V`, so `V` is solved from the line above in closed form.
//!
//! # Keeping the plant exact
//!
//! The voltage is piecewise constant: it is recomputed every `update_interval_s` (at
//! `k * update_interval_s`, `k = 1, 2, ...`) from the state of charge and the load at that
//! instant, and the wheels' motions are re-planned there; those times are what
//! [`crate::Robot::next_internal_change`] announces. The charge is integrated in closed form
//! (`integral of omega dt` is the wheel angle) at each input change and each update, never per
//! call of `advance_to`, so it does not depend on how the bench steps the plant.
//!
//! # Signature
//!
//! At a fixed duty (open loop) the robot slows as the charge drops, and more under load than
//! idle; under speed control the controller hides it until the duty saturates. Applied to
//! the steady speeds through `V / V_fit` ([`crate::motor`]).
//!
//! # Keys
//!
//! | key | unit | meaning |
//! |---|---|---|
//! | `open_circuit_full_v` | V | V_oc at SoC 1 (2S LiPo: 8.4) |
//! | `open_circuit_empty_v` | V | V_oc at SoC 0 (2S LiPo: about 6.6 at 3.3 V per cell) |
//! | `capacity_mah` | mAh | C (the thesis' pack: 1000) |
//! | `initial_charge_fraction` | 1 | SoC at plant time 0, in `[0, 1]` |
//! | `internal_resistance_ohm` | ohm | R_int, pack + wiring + bridge |
//! | `motor_resistance_ohm` | ohm | R_m, one motor's winding |
//! | `idle_current_a` | A | electronics (MCU board, Bluetooth, encoders, LEDs) |
//! | `update_interval_s` | s | optional, default 0.05: how often V is recomputed |

use serde::{Deserialize, Serialize};

use crate::check::{check_between, check_physical, Bounds, TIME_CONSTANT_S, VOLTAGE_V};
use crate::effects::key;
use crate::Error;

/// Default of `update_interval_s`.
pub const DEFAULT_UPDATE_INTERVAL_S: f64 = 0.05;

/// Parameters of `[effects.battery_sag]` (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatterySag {
    /// Open-circuit voltage when full, V.
    pub open_circuit_full_v: f64,
    /// Open-circuit voltage when empty, V.
    pub open_circuit_empty_v: f64,
    /// Capacity, mAh.
    pub capacity_mah: f64,
    /// State of charge at plant time 0, in `[0, 1]`.
    pub initial_charge_fraction: f64,
    /// Internal resistance (pack, wiring, bridge), ohm.
    pub internal_resistance_ohm: f64,
    /// Winding resistance of one motor, ohm.
    pub motor_resistance_ohm: f64,
    /// Current of everything but the motors, A.
    pub idle_current_a: f64,
    /// How often the voltage is recomputed, s.
    #[serde(default = "default_interval")]
    pub update_interval_s: f64,
}

fn default_interval() -> f64 {
    DEFAULT_UPDATE_INTERVAL_S
}

impl BatterySag {
    /// Checks the parameters; `prefix` is `effects.battery_sag`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        check_physical(
            &key(prefix, "open_circuit_full_v"),
            self.open_circuit_full_v,
            VOLTAGE_V,
            "open-circuit voltage when full",
        )?;
        check_between(
            &key(prefix, "open_circuit_empty_v"),
            self.open_circuit_empty_v,
            (0.0, self.open_circuit_full_v),
            "it must lie between 0 and open_circuit_full_v",
            "open-circuit voltage when empty, V",
        )?;
        check_physical(
            &key(prefix, "capacity_mah"),
            self.capacity_mah,
            Bounds {
                low: 1.0,
                high: 1e6,
                unit: "mAh",
            },
            "capacity",
        )?;
        check_between(
            &key(prefix, "initial_charge_fraction"),
            self.initial_charge_fraction,
            (0.0, 1.0),
            "a state of charge must lie in [0, 1]",
            "state of charge at the start",
        )?;
        check_physical(
            &key(prefix, "internal_resistance_ohm"),
            self.internal_resistance_ohm,
            Bounds {
                low: 0.0,
                high: 100.0,
                unit: "ohm",
            },
            "internal resistance of pack and wiring",
        )?;
        check_physical(
            &key(prefix, "motor_resistance_ohm"),
            self.motor_resistance_ohm,
            Bounds {
                low: 0.01,
                high: 1000.0,
                unit: "ohm",
            },
            "winding resistance of one motor",
        )?;
        check_physical(
            &key(prefix, "idle_current_a"),
            self.idle_current_a,
            Bounds {
                low: 0.0,
                high: 10.0,
                unit: "A",
            },
            "current of the electronics",
        )?;
        check_physical(
            &key(prefix, "update_interval_s"),
            self.update_interval_s,
            TIME_CONSTANT_S,
            "how often the voltage is recomputed",
        )?;
        Ok(())
    }

    /// `V_oc` at state of charge `soc`.
    pub fn open_circuit_v(&self, soc: f64) -> f64 {
        self.open_circuit_empty_v + (self.open_circuit_full_v - self.open_circuit_empty_v) * soc
    }
}

/// One motor's load on the battery.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MotorLoad {
    /// Signed driven fraction of the PWM period (0 when disconnected).
    pub drive: f64,
    /// Back-EMF constant, V per wheel rad/s.
    pub back_emf: f64,
    /// Wheel speed now, rad/s.
    pub speed: f64,
    /// Wheel angle change since the charge was last accounted, rad.
    pub angle_change: f64,
}

/// The battery's state under `battery_sag`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SagState {
    params: BatterySag,
    /// Charge drawn since time 0, coulombs.
    charge_c: f64,
    /// Time up to which `charge_c` is accounted.
    accounted_to: f64,
    /// Updates done (the next is at `(updates + 1) * interval`).
    updates: u64,
}

impl SagState {
    pub(crate) fn new(params: BatterySag) -> Self {
        SagState {
            params,
            charge_c: 0.0,
            accounted_to: 0.0,
            updates: 0,
        }
    }

    /// Time of the next voltage update.
    pub(crate) fn next_update(&self) -> f64 {
        (self.updates + 1) as f64 * self.params.update_interval_s
    }

    /// Counts one update as done.
    pub(crate) fn count_update(&mut self) {
        self.updates += 1;
    }

    /// Skips the updates due at or before `now` (after an override, which suspends them).
    pub(crate) fn skip_updates_to(&mut self, now: f64) {
        while self.next_update() <= now {
            self.updates += 1;
        }
    }

    /// Time up to which the charge is accounted.
    pub(crate) fn accounted_to(&self) -> f64 {
        self.accounted_to
    }

    /// State of charge now (as accounted), in `[0, 1]`.
    pub(crate) fn charge_fraction(&self) -> f64 {
        let capacity_c = self.params.capacity_mah * 3.6;
        (self.params.initial_charge_fraction - self.charge_c / capacity_c).clamp(0.0, 1.0)
    }

    /// Adds the charge drawn from `accounted_to` to `now` at terminal voltage `volts` (constant
    /// over that interval) by `loads` (whose drives were constant over it).
    pub(crate) fn account(&mut self, now: f64, volts: f64, loads: &[MotorLoad]) {
        let dt = now - self.accounted_to;
        if dt <= 0.0 {
            return;
        }
        let mut charge = self.params.idle_current_a * dt;
        for load in loads {
            let d = load.drive;
            if d != 0.0 {
                charge += d.abs() * (volts * dt - d.signum() * load.back_emf * load.angle_change)
                    / self.params.motor_resistance_ohm;
            }
        }
        self.charge_c += charge;
        self.accounted_to = now;
    }

    /// The terminal voltage under `loads` now: `V = V_oc - R_int I(V)` solved for `V`.
    pub(crate) fn terminal_voltage(&self, loads: &[MotorLoad]) -> f64 {
        let p = &self.params;
        let r = p.internal_resistance_ohm;
        let mut numerator = p.open_circuit_v(self.charge_fraction()) - r * p.idle_current_a;
        let mut denominator = 1.0;
        for load in loads {
            let d = load.drive;
            numerator +=
                r * d.abs() * d.signum() * load.back_emf * load.speed / p.motor_resistance_ohm;
            denominator += r * d.abs() / p.motor_resistance_ohm;
        }
        (numerator / denominator).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::test_support::{drive, symmetric};
    use crate::side::Side;
    use crate::units::Seconds;
    use crate::Robot;

    fn sag(capacity_mah: f64) -> BatterySag {
        BatterySag {
            open_circuit_full_v: 8.4,
            open_circuit_empty_v: 6.6,
            capacity_mah,
            initial_charge_fraction: 0.9,
            internal_resistance_ohm: 0.2,
            motor_resistance_ohm: 10.0,
            idle_current_a: 0.15,
            update_interval_s: 0.05,
        }
    }

    /// Signature: at a fixed duty the robot slows as the charge drops (a tiny 20 mAh pack
    /// makes it visible in seconds); the voltage is `V_oc(SoC) - R_int I` and changes only at
    /// the announced update times; idle, the voltage stays near `V_oc`.
    #[test]
    fn slows_the_robot_as_the_charge_drops() {
        let config = symmetric(|c| c.effects.battery_sag = Some(sag(20.0)));
        let mut robot = Robot::new(&config, 0).unwrap();
        let idle = robot.battery_voltage().0;
        assert!((idle - (8.22 - 0.2 * 0.15)).abs() < 1e-9, "idle {idle}");
        assert_eq!(robot.next_internal_change(), Some(Seconds(0.05)));
        drive(&mut robot, 0.9, 0.9);
        let mut speeds = Vec::new();
        let mut volts = Vec::new();
        for k in 1..=6 {
            robot.advance_to(Seconds(f64::from(k) * 5.0)).unwrap();
            speeds.push(robot.wheel_speed(Side::Left).0);
            volts.push(robot.battery_voltage().0);
        }
        for w in speeds.windows(2) {
            assert!(w[1] < w[0], "slower as the charge drops: {speeds:?}");
        }
        for w in volts.windows(2) {
            assert!(w[1] < w[0], "voltage falls: {volts:?}");
        }
        let soc = robot.battery_charge_fraction().unwrap();
        assert!(soc < 0.6, "20 mAh pack drained: SoC {soc}");
        // Under load the terminal voltage is below the open-circuit one by R_int I.
        let v_oc = sag(20.0).open_circuit_v(soc);
        assert!(robot.battery_voltage().0 < v_oc - 0.05);
        // Piecewise constant: between two update times the voltage does not move.
        let t0 = robot.now();
        let v0 = robot.battery_voltage();
        let next = robot.next_internal_change().unwrap();
        assert!(next > t0);
        robot.advance_to(Seconds(0.5 * (t0.0 + next.0))).unwrap();
        assert_eq!(robot.battery_voltage(), v0);
    }

    /// The charge drawn does not depend on how the plant is stepped: one long advance and
    /// many irregular ones give the same state of charge and the same wheel angle bit for bit.
    #[test]
    fn charge_does_not_depend_on_the_stepping() {
        let config = symmetric(|c| c.effects.battery_sag = Some(sag(5.0)));
        let run = |times: &[f64]| {
            let mut robot = Robot::new(&config, 0).unwrap();
            drive(&mut robot, 0.8, -0.7);
            for &t in times {
                robot.advance_to(Seconds(t)).unwrap();
            }
            (
                robot.battery_charge_fraction(),
                robot.wheel_angle(Side::Right),
            )
        };
        let one = run(&[3.0]);
        let many: Vec<f64> = (1..=3000).map(|k| f64::from(k) * 1e-3).collect();
        assert_eq!(run(&many), one);
        assert_eq!(run(&[0.0123, 0.05, 0.05, 1.7, 2.999, 3.0]), one);
    }
}
