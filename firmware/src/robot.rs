//! Parameters of the thesis robot (values from the thesis and its firmware,
//! mirrored in the shared `robot.toml`). The robust build takes the geometry
//! (distance per count, counts per wheel turn, wheelbase), set-points, gains
//! and limits from its settings (`settings::Settings`), whose factory values
//! these are; the thesis build uses them as they are.

use crate::pid::Gains;

/// CPU clock: the Arduino Mega 2560's 16 MHz crystal (see `board.rs`).
pub const CPU_HZ: u32 = 16_000_000;

/// Encoder counts per wheel revolution used by the thesis' speed formula
/// (100.37:1 gear, 6 counts per motor revolution on channel A, any edge).
pub const COUNTS_PER_WHEEL_REV: f32 = 602.22;
/// Millimetres travelled per encoder count: pi * 32 mm / 602.22, the thesis'
/// `Constante`, kept as the thesis writes it (f32 rounds it to 0.16693395).
#[allow(clippy::excessive_precision)]
pub const MM_PER_COUNT: f32 = 0.1669339526;
/// Control period in seconds (thesis `Muestreo`), exact with the timer tick.
pub const SAMPLE_PERIOD_S: f32 = 0.015;
/// Control period in microseconds, for the tick timer.
pub const SAMPLE_PERIOD_US: u32 = 15_000;

/// Right wheel speed set-point, thesis "RPM" (`Set_D`).
pub const SETPOINT_RIGHT: f32 = 14.47;
/// Left wheel speed set-point, thesis "RPM" (`Set_I`).
pub const SETPOINT_LEFT: f32 = 15.0;
/// The robust build's default set-point of both wheels, thesis "RPM" (the
/// sketch's right-wheel 14.47: ~145 mm/s). The sketch's 15 : 14.47 split is a
/// per-robot trim that its timing partly cancels (it reads the two counts a
/// print apart); held exactly, it curves every leg by tens of degrees. The
/// robust build starts from equal ground speeds and leaves the wheels'
/// differences to the calibration's c_L, c_R, which scale the set-points.
pub const ROBUST_SETPOINT: f32 = SETPOINT_RIGHT;
/// Right wheel PID gains (Ziegler-Nichols, `Kp_D`, `Ki_D`, `Kd_D`).
pub const GAINS_RIGHT: Gains = Gains { kp: 2.74, ki: 45.66, kd: 0.0411 };
/// Left wheel PID gains (`Kp_I`, `Ki_I`, `Kd_I`).
pub const GAINS_LEFT: Gains = Gains { kp: 2.20, ki: 36.666, kd: 0.033 };
/// Duty both wheels get from the start of a leg until the first control
/// tick: the thesis' initial `pwm_D = pwm_I = 50`.
pub const START_DUTY: u8 = 50;

/// Default leg length for the straight-line test, millimetres.
pub const DEFAULT_LEG_MM: f32 = 2000.0;

/// Default wheelbase for the spin-turn targets, millimetres (thesis `b`).
pub const DEFAULT_WHEELBASE_MM: f32 = 130.0;
/// Default UMBmark turn, degrees.
pub const DEFAULT_TURN_UMBMARK_DEG: f32 = 90.0;
/// Default triangle turn, degrees.
pub const DEFAULT_TURN_TRIANGLE_DEG: f32 = 120.0;
/// Default wheel correction factors (Borenstein's c_L, c_R).
pub const DEFAULT_CORRECTION: f32 = 1.0;
/// Default stall time-out, milliseconds.
pub const DEFAULT_STALL_TIMEOUT_MS: u16 = 200;
/// Default duty at or above which a wheel without counts is stalling.
pub const DEFAULT_STALL_DUTY: u8 = 200;
