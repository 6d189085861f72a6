//! Physics of the Henrytwo differential-drive robot, for the hardware-in-the-loop bench.
//!
//! Pure: no simulator, no registers, no clock. The bench sets the H-bridge inputs, advances
//! the plant in time and asks when each wheel's encoder changes state next; the plant answers
//! from closed-form solutions, so edges land at exact times instead of on a sampling grid.
//!
//! # Robot
//!
//! Two DC gear motors (100.37:1) with magnetic encoders (6 channel-A edges per motor
//! revolution, 602.22 per wheel turn, channel B in quadrature), 32 mm wheels, 130 mm
//! wheelbase, one DRV8833 bridge per motor at 31.37 kHz from a 7.4 V 2S LiPo. Parameters live
//! in a [`RobotConfig`] (TOML, `fixtures/robots/henrytwo-ideal.toml` is the nominal robot).
//!
//! # From PWM duty to wheel speed
//!
//! 1. **Bridge** ([`bridge`]): the two input duties `(in1, in2)` of a bridge are averaged over
//!    the PWM period (31.37 kHz against 55-69 ms mechanical time constants). The motor sees
//!    the signed driven fraction `d = in1 - in2` (forward when `in1` carries the PWM and
//!    `in2 = 0`, as the thesis firmware drives it) and the fraction of the period spent
//!    braking (both inputs high); the rest coasts.
//! 2. **Motor** ([`motor`]): the steady wheel speed, in the thesis' "RPM" (true wheel RPM / 6),
//!    is `omega_ss(d) = sign(d) * K * max(0, |d| - d0) / (d_ref - d0) * V_bat / V_fit`.
//!    `K` is the thesis' fitted gain (right 25.0, left 22.0). The thesis fitted it on the
//!    *mean* of its five step responses (PWM 170..250 of 255), so `K` is the steady speed at
//!    the mean duty `d_ref = 210/255`, not a gain per unit of duty. The dead band `d0` is
//!    there because the steady levels are not proportional to the duty: 14.4 at 170/255
//!    against 38.7 at 250/255 (right wheel), a ratio of 2.7 for a duty ratio of 1.47. `d0` is
//!    fitted by least squares over all five steady levels with the line through
//!    `(d_ref, K)`: 129.24/255 = 0.5068 right, 147.79/255 = 0.5796 left. The line is 3-4 % low
//!    at 250/255 and 12 % (right) / 18 % (left) low at 170/255: the measured curve bends
//!    and a line cannot follow it (see [`motor`] for the per-level residuals and the choice
//!    of levels). The speed approaches `omega_ss` with the time constant `tau` (right
//!    0.0685 s, left 0.055 s); without drive beyond the dead band it decays to 0 with the
//!    coast and brake time constants and never reverses by itself.
//! 3. **Wheel and encoder** ([`encoder`]): the wheel angle is the closed-form integral of the
//!    speed; the encoder's quadrature state is the angle in steps of
//!    `2 pi / (2 * 6 * 100.37)`.
//! 4. **Pose** ([`Robot::pose`]): the wheel arcs move the robot in the [`World`] frame (origin
//!    at the start, `x` along the initial heading, `y` to the left, `theta` counter-clockwise
//!    in radians).
//!
//! Speeds are [`RadPerSec`] inside; [`ThesisRpm`] converts for comparisons with the thesis.
//!
//! # A robot that behaves like the real one
//!
//! - **Effects** ([`effects`]): fifteen named departures from the nominal robot (unequal
//!   wheels, slip, coasting, floor noise, battery sag, backlash, toe, encoder flaws, ...),
//!   each switched on by an `[effects.<name>]` table with unit-suffixed keys and off in the
//!   ideal robot. `fixtures/robots/henrytwo.toml` combines them into our best estimate of the
//!   thesis robot, fitted to the thesis' floor measurements through its own firmware.
//! - **Faults** ([`fault`]): [`Robot::set_motor_fault`] (stall, disconnected, load step),
//!   [`Robot::set_slip_burst`], [`Robot::set_battery_voltage_override`], set by the bench at
//!   exact times.
//! - **Exactness**: effects on the floor act in the pose integration only; effects on the
//!   motors keep each wheel's motion closed-form between changes; the battery's voltage is
//!   piecewise constant and changes at the times [`Robot::next_internal_change`] announces;
//!   encoder flaws are functions of the shaft angle. So [`Robot::next_encoder_transition`]
//!   stays exact with every effect on.

pub mod bridge;
pub mod check;
pub mod config;
mod duty;
pub mod effects;
pub mod encoder;
mod error;
pub mod fault;
mod ground;
pub mod identify;
pub mod motor;
pub mod pose;
pub mod rng;
pub mod robot;
pub mod side;
pub mod units;

pub use bridge::{Decay, DriveState};
pub use config::RobotConfig;
pub use duty::Duty;
pub use effects::Effects;
pub use encoder::Encoder;
pub use error::Error;
pub use fault::MotorFault;
pub use motor::{FirstOrderMotor, Modifiers, MotorModel, Relaxation, Segment};
pub use pose::{Frame, Pose, World};
pub use robot::{Robot, MAX_POSE_STEP, TRANSITION_HORIZON, TRANSITION_RESOLUTION};
pub use side::{PerSide, Side};
pub use units::{Millimetres, RadPerSec, Radians, Seconds, ThesisRpm, TimeGrid, Volts};
