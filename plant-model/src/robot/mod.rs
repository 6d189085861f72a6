//! The whole plant: two bridges, two motors, two wheels with encoders, the battery, the
//! floor, the pose; the effects of the robot's config and the faults the bench sets.
//!
//! # How the bench drives it
//!
//! ```text
//! loop {
//!     t = min(next_encoder_transition(Left), next_encoder_transition(Right),
//!             next_internal_change(), next firmware event)
//!     advance_to(t rounded up to an emulated cycle)
//!     raise the encoder levels that changed; on a PWM register write: set_bridge(...);
//!     at a scheduled fault: set_motor_fault(...), set_slip_burst(...), ...
//!     re-plan a wheel after its transition; both after an input change, a fault or an
//!     internal change
//! }
//! ```
//!
//! Time is the plant's own: it starts at 0 and moves only through [`Robot::advance_to`]; no
//! host clock is read, and the random effects draw from seeded streams per stretch of floor
//! or per encoder pulse (a SplitMix64 stream per effect), so the same calls give the same results bit for bit
//! and the same seed the same floor however the plant is stepped.
//!
//! # Two halves
//!
//! - **Dynamics** (what the encoders see): per wheel, the motor's motion since its last
//!   change, one closed-form [`Segment`]; the battery voltage; the faults. It changes only at
//!   input changes, at faults, and at the internal changes [`Robot::next_internal_change`]
//!   announces (the battery's piecewise-constant voltage under `battery_sag`).
//! - **Ground** (what the floor sees): from the shaft angles to the pose,
//!   through backlash, wheel sizes, slip, toe and floor noise. Nothing here feeds back into
//!   the dynamics, so no ground effect can move an encoder edge.
//!
//! # Exactness
//!
//! A wheel's angle at any time is its segment evaluated at that time, never a sum of small
//! steps, so [`Robot::next_encoder_transition`] and [`Robot::advance_to`] see the same angle
//! function; the encoder's levels are a function of that angle ([`crate::encoder`]). The pose
//! is integrated from the wheel-angle increments by exact arcs over steps of at most
//! [`MAX_POSE_STEP`] (the arc is exact while the ratio of the wheel speeds is constant; over
//! 1 ms with 55-69 ms time constants the error is far below a micrometre), split at internal
//! changes and, with backlash, at every reversal of a wheel.
//!
//! # Files
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`Robot`]: made from a config, its inputs, faults and battery override, [`Robot::advance_to`]; the time constants of the search and the pose |
//! | `transitions.rs` | [`Robot::next_encoder_transition`] and its variants, across the plant's internal changes |
//! | `readings.rs` | encoder levels and counts, wheel speeds and angles, the distance rolled, [`Robot::pose`] |
//! | `wheel.rs` | one side: inputs, motor, fault, encoder, its closed-form motion, the transition search on it |
//! | `crossing.rs` | the first time (or grid instant) a monotone condition holds: the search's last step |
//! | `dynamics.rs` | both wheels and the battery, with the battery's changes at their announced times |
//! | `pose_steps.rs` | stepping the ground on the pose grid |

mod crossing;
mod dynamics;
mod pose_steps;
mod readings;
mod transitions;
mod wheel;

use std::cell::Cell;

use crate::bridge::DriveState;
use crate::config::RobotConfig;
use crate::effects::battery_sag::SagState;
use crate::encoder::{Encoder, Imperfections};
use crate::fault::MotorFault;
use crate::ground::{effective_radius_mm, Ground};
use crate::motor::{Modifiers, Segment};
use crate::side::{PerSide, Side};
use crate::units::{Radians, Seconds, Volts};
use crate::Duty;
use crate::Error;
use dynamics::{Battery, Dynamics};
use pose_steps::{integrate, pose_grid_at_or_before};
use wheel::{Wheel, NO_MEMO};

/// How far ahead [`Robot::next_encoder_transition`] looks. A wheel that will not change its
/// encoder state within this time (at rest, or creeping to a stop short of the next state)
/// gets `None`; ask again after the next input change or after advancing this far.
pub const TRANSITION_HORIZON: Seconds = Seconds(10.0);

/// Longest step of the pose integration; [`Robot::advance_to`] subdivides longer intervals.
pub const MAX_POSE_STEP: Seconds = Seconds(1e-3);

/// How far the ground may lag behind the wheels before [`Robot::advance_to`] steps it (on
/// the grid of [`MAX_POSE_STEP`] all the same, so the pose does not depend on it).
const POSE_BATCH: Seconds = Seconds(8e-3);

/// Resolution of [`Robot::next_encoder_transition`]: the time returned is at most this much
/// (or one `f64` step of the time, if that is larger) after a time at which the encoder state
/// has not changed yet.
pub const TRANSITION_RESOLUTION: Seconds = Seconds(1e-12);

/// The simulated robot: the plant the bench drives.
#[derive(Debug, Clone)]
pub struct Robot {
    config: RobotConfig,
    seed: u64,
    dynamics: Dynamics,
    ground: Ground,
    /// The time the ground has been stepped to: the last instant of the pose grid (multiples
    /// of [`MAX_POSE_STEP`]) or change of the motion, whichever is later, up to now.
    pose_time: Seconds,
    /// The thesis decoder's count per side, kept for flawed encoders.
    decoded: PerSide<Decoded>,
    /// Per side, whether the firmware counts every edge of both channels
    /// (an xor wiring) rather than A's: what [`Robot::counted_edges`] gives.
    all_edges_counted: PerSide<bool>,
}

/// The decoders' net counts at quadrature state `q`: A edges (the
/// thesis'), every edge (a four-edge decoder).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Decoded {
    q: i64,
    count: i64,
    all: i64,
}

impl Robot {
    /// The robot of `config` at rest at the origin of [`World`](crate::World), bridges
    /// coasting, time 0. `seed` seeds the random effects (`floor_noise`,
    /// `encoder_missed_counts`, `encoder_glitches`); without them nothing is random.
    pub fn new(config: &RobotConfig, seed: u64) -> Result<Robot, Error> {
        config.validate()?;
        let effects = &config.effects;
        let ground = Ground::new(config, seed);
        let battery = match &effects.battery_sag {
            Some(sag) => {
                let state = SagState::new(sag.clone());
                let idle = state.terminal_voltage(&[]);
                Battery {
                    modelled: Volts(idle),
                    sag: Some(state),
                    override_v: None,
                }
            }
            None => Battery {
                modelled: Volts(config.battery.voltage_v),
                sag: None,
                override_v: None,
            },
        };
        let make_wheel = |side: Side, index: u64| {
            let flaws = Imperfections {
                seed,
                side_index: index,
                missed_pulse_fraction: effects
                    .encoder_missed_counts
                    .as_ref()
                    .map_or(0.0, |e| e.fraction(side)),
                glitch_fraction: effects
                    .encoder_glitches
                    .as_ref()
                    .map_or(0.0, |e| e.fraction(side)),
                glitch_width_states: effects.encoder_glitches.as_ref().map_or(0.0, |e| {
                    e.width_states(config.encoder.a_edges_per_motor_rev)
                }),
            };
            let encoder = Encoder::new(
                config.encoder.gear_ratio,
                config.encoder.a_edges_per_motor_rev,
                config.encoder.reversed(side),
            )
            .with_imperfections(flaws);
            let mut friction_duty = effects.dead_band.as_ref().map_or(0.0, |e| e.extra(side));
            if let Some(castor) = &effects.castor_drag {
                let wheelbase = config.geometry.wheelbase_mm
                    * effects
                        .wheelbase_ratio
                        .as_ref()
                        .map_or(1.0, |e| e.actual_over_nominal_ratio);
                friction_duty +=
                    castor.friction_duty(side, wheelbase, effective_radius_mm(config, side));
            }
            let gain_ratio = effects
                .motor_gain_asymmetry
                .as_ref()
                .map_or(1.0, |e| e.ratio(side));
            let modifiers = Modifiers {
                gain_ratio,
                friction_duty,
                coast_tau: effects.coast.as_ref().map(|c| c.tau(side)),
            };
            let motor = config.motor.get(side).clone();
            let mut wheel = Wheel {
                back_emf: motor.back_emf_v_per_rad_s(gain_ratio),
                motor,
                modifiers,
                fault: MotorFault::None,
                encoder,
                in1: Duty::OFF,
                in2: Duty::OFF,
                segment: Segment::held(Seconds::ZERO, Radians::ZERO),
                memo: Cell::new(NO_MEMO),
            };
            wheel.replan(Seconds::ZERO, battery.voltage());
            wheel
        };
        let wheels = PerSide {
            left: make_wheel(Side::Left, 0),
            right: make_wheel(Side::Right, 1),
        };
        Ok(Robot {
            config: config.clone(),
            seed,
            dynamics: Dynamics {
                now: Seconds::ZERO,
                wheels,
                battery,
            },
            ground,
            pose_time: Seconds::ZERO,
            decoded: PerSide::default(),
            all_edges_counted: PerSide::default(),
        })
    }

    /// The config the robot was made from.
    pub fn config(&self) -> &RobotConfig {
        &self.config
    }

    /// The seed given to [`Robot::new`].
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Plant time.
    pub fn now(&self) -> Seconds {
        self.dynamics.now
    }

    /// Battery voltage the motors see now: the override if set, else the constant
    /// `battery.voltage_v`, or the `battery_sag` model's voltage at its last update.
    pub fn battery_voltage(&self) -> Volts {
        self.dynamics.voltage()
    }

    /// State of charge under `battery_sag` (as of the last input change or update), in
    /// `[0, 1]`; `None` without the effect.
    pub fn battery_charge_fraction(&self) -> Option<f64> {
        self.dynamics
            .battery
            .sag
            .as_ref()
            .map(SagState::charge_fraction)
    }

    /// Sets the H-bridge inputs of `side` from now on (advance to the time of the change
    /// first). Both inputs are duties of PWM signals assumed to start their high time
    /// together; `in1` high alone drives the wheel forward (see [`crate::bridge`]). Setting the
    /// inputs a bridge already has changes nothing. Only this wheel's motion changes (the
    /// battery's voltage follows the load at its next update, not at once).
    pub fn set_bridge(&mut self, side: Side, in1: Duty, in2: Duty) {
        let wheel = self.dynamics.wheels.get(side);
        if (wheel.in1, wheel.in2) == (in1, in2) {
            return;
        }
        self.settle_pose();
        self.dynamics.account();
        let (now, volts) = (self.dynamics.now, self.dynamics.voltage());
        let wheel = self.dynamics.wheels.get_mut(side);
        wheel.in1 = in1;
        wheel.in2 = in2;
        wheel.replan(now, volts);
    }

    /// The bridge inputs `(in1, in2)` of `side`.
    pub fn bridge_inputs(&self, side: Side) -> (Duty, Duty) {
        let wheel = self.dynamics.wheels.get(side);
        (wheel.in1, wheel.in2)
    }

    /// The averaged bridge state of `side` (from its inputs, whatever the motor's fault).
    pub fn drive_state(&self, side: Side) -> DriveState {
        let (in1, in2) = self.bridge_inputs(side);
        DriveState::from_inputs(in1, in2)
    }

    /// Sets a fault of `side`'s motor from now on (advance to its time first); re-plan both
    /// wheels' transitions afterwards. See [`MotorFault`] for what each does to the encoder
    /// and the pose. An invalid fault (a load outside `[0, 1]`) is refused and changes
    /// nothing.
    pub fn set_motor_fault(&mut self, side: Side, fault: MotorFault) -> Result<(), Error> {
        fault.validate()?;
        if self.dynamics.wheels.get(side).fault == fault {
            return Ok(());
        }
        self.settle_pose();
        self.dynamics.account();
        let (now, volts) = (self.dynamics.now, self.dynamics.voltage());
        let wheel = self.dynamics.wheels.get_mut(side);
        wheel.fault = fault;
        wheel.replan(now, volts);
        Ok(())
    }

    /// The motor fault of `side`.
    pub fn motor_fault(&self, side: Side) -> MotorFault {
        self.dynamics.wheels.get(side).fault
    }

    /// From now on the ground sees `1 - slip_fraction` of `side`'s wheel travel (a patch of
    /// oil, a wheel lifted over a bump): the encoder is unaffected (the wheel turns as
    /// before), the pose curves towards the slipping side. `0` ends the burst; `1` is a wheel
    /// spinning in place. A fraction outside `[0, 1]` is refused.
    pub fn set_slip_burst(&mut self, side: Side, slip_fraction: f64) -> Result<(), Error> {
        if !(slip_fraction.is_finite() && (0.0..=1.0).contains(&slip_fraction)) {
            return Err(Error::InvalidFault {
                what: "slip_fraction",
                value: slip_fraction,
                allowed: "a slip fraction must lie in [0, 1]",
            });
        }
        self.settle_pose();
        self.ground.set_burst(side, slip_fraction);
        Ok(())
    }

    /// The slip burst of `side` (0 when none).
    pub fn slip_burst(&self, side: Side) -> f64 {
        self.ground.burst(side)
    }

    /// Forces the battery voltage the motors see (a brown-out scenario) from now on, or
    /// gives it back to the model with `None`; re-plan both wheels afterwards. Every driven
    /// wheel's steady speed scales with the voltage ([`crate::motor`]); the encoders follow.
    /// While an override is set the `battery_sag` model keeps counting the charge but does
    /// not change the voltage, and [`Robot::next_internal_change`] is `None`. A negative or
    /// non-finite voltage is refused.
    pub fn set_battery_voltage_override(&mut self, volts: Option<Volts>) -> Result<(), Error> {
        if let Some(v) = volts {
            if !(v.0.is_finite() && v.0 >= 0.0) {
                return Err(Error::InvalidFault {
                    what: "battery voltage override (V)",
                    value: v.0,
                    allowed: "a voltage must be finite and not negative",
                });
            }
        }
        if self.dynamics.battery.override_v == volts {
            return Ok(());
        }
        self.settle_pose();
        self.dynamics.account();
        self.dynamics.battery.override_v = volts;
        if volts.is_none() {
            let now = self.dynamics.now.0;
            if let Some(sag) = &mut self.dynamics.battery.sag {
                sag.skip_updates_to(now);
            }
            if let Some(v) = self.dynamics.sag_voltage() {
                self.dynamics.battery.modelled = v;
            }
        }
        self.dynamics.replan_all();
        Ok(())
    }

    /// The battery voltage override, if set.
    pub fn battery_voltage_override(&self) -> Option<Volts> {
        self.dynamics.battery.override_v
    }

    /// The next time after [`Robot::now`] at which the plant's own dynamics change without
    /// an input change: under `battery_sag`, the next voltage update (every
    /// `update_interval_s`); otherwise (or while the voltage is overridden) `None`.
    ///
    /// The bench schedules it as an event: `advance_to` it, then re-plan both wheels.
    /// `advance_to` applies the change at exactly this time even when asked to go past it,
    /// and [`Robot::next_encoder_transition`] already looks across it, so a transition
    /// planned before it stays right; re-planning after it is cheap and keeps the plan
    /// simple.
    pub fn next_internal_change(&self) -> Option<Seconds> {
        self.dynamics.next_internal_change()
    }

    /// Moves the plant to time `t` under the current inputs: wheel angles and speeds in closed
    /// form, internal changes at their exact times, the pose by arcs on a fixed grid of
    /// [`MAX_POSE_STEP`] (see [`Robot::pose`]).
    ///
    /// `t == now` does nothing. `t < now` (or a `t` that is not finite) is an error,
    /// [`Error::TimeWentBackwards`], and leaves the plant unchanged.
    pub fn advance_to(&mut self, t: Seconds) -> Result<(), Error> {
        if !t.0.is_finite() || t < self.dynamics.now {
            return Err(Error::TimeWentBackwards {
                now: self.dynamics.now,
                requested: t,
            });
        }
        while let Some(change) = self.dynamics.next_internal_change().filter(|&c| c <= t) {
            self.dynamics.now = change;
            self.settle_pose();
            self.dynamics.apply_internal_change();
        }
        self.dynamics.now = t;
        // The steps fall on the grid whenever they are taken: take them in batches.
        let grid = pose_grid_at_or_before(t);
        if grid.0 - self.pose_time.0 >= POSE_BATCH.0 {
            integrate(
                &mut self.ground,
                &self.dynamics.wheels,
                self.pose_time,
                grid,
            );
            self.pose_time = grid;
        }
        self.sync_decoded();
        Ok(())
    }

    /// Steps the ground to now, before the motion changes.
    fn settle_pose(&mut self) {
        let now = self.dynamics.now;
        integrate(&mut self.ground, &self.dynamics.wheels, self.pose_time, now);
        self.pose_time = now;
    }

    /// Brings the decoder counts of flawed encoders to the current states.
    fn sync_decoded(&mut self) {
        for side in Side::BOTH {
            let wheel = self.dynamics.wheels.get(side);
            if !wheel.encoder.is_flawed() {
                continue;
            }
            let q = wheel
                .encoder
                .quadrature_index(Radians(wheel.angle_at(self.dynamics.now)));
            let decoded = self.decoded.get_mut(side);
            decoded.count += wheel.encoder.decoded_between(decoded.q, q);
            decoded.all += wheel.encoder.all_decoded_between(decoded.q, q);
            decoded.q = q;
        }
    }
}
