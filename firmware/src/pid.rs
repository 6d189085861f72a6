//! The thesis' wheel speed control law, in `f32` (the thesis' `double` is
//! 32-bit on AVR), as pure `const fn`s so the arithmetic is checked at compile
//! time (see the `const _` checks at the end) and can be reused by every
//! firmware build.
//!
//! Per wheel and per control period T (thesis `PID()`):
//! - speed: `|counts in the period| / T * 60 / 6 * 0.0016605` (thesis "RPM":
//!   the wheel's true RPM / 6);
//! - `E = Set - RPM`, `I += E * T`, `D = (E - E_prev) / T`,
//!   `U = Kp E + Ki I + Kd D`;
//! - duty = Arduino `map((long)U, 24, -24, 255, 0)` clamped to 0..=255.

/// PID gains.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Gains {
    /// Proportional gain.
    pub kp: f32,
    /// Integral gain.
    pub ki: f32,
    /// Derivative gain.
    pub kd: f32,
}

/// The thesis' factor from encoder RPM to its wheel "RPM" (`0.0016605`,
/// its rounding of 1 / 602.22, Henrytwo's counts per wheel turn).
pub const RPM_FACTOR: f32 = 0.0016605;

/// Thesis wheel speed from the encoder counts seen during `period_s` seconds,
/// computed in the thesis' order: `Frecuencia = Conteo / T`,
/// `Pulsos_Min = Frecuencia * 60`, `RPM_Enc = Pulsos_Min / 6`,
/// `RPM_Mot = |RPM_Enc| * 0.0016605`. The count is taken as an absolute value,
/// so the speed is never negative.
pub const fn thesis_rpm(count_delta: i32, period_s: f32) -> f32 {
    let counts = count_delta.unsigned_abs() as f32;
    let frequency = counts / period_s;
    let per_minute = frequency * 60.0;
    let encoder_rpm = per_minute / 6.0;
    encoder_rpm * RPM_FACTOR
}

/// Arduino's `map()` in `long` (32-bit) arithmetic, truncating toward zero:
/// `(x - in_min) * (out_max - out_min) / (in_max - in_min) + out_min`.
/// Wraps on overflow as the AVR does; callers keep `x` small (see
/// [`output_to_duty`]). `in_min == in_max` gives `out_min` instead of a
/// division by zero.
pub const fn arduino_map(x: i32, in_min: i32, in_max: i32, out_min: i32, out_max: i32) -> i32 {
    let den = in_max.wrapping_sub(in_min);
    if den == 0 {
        return out_min;
    }
    x.wrapping_sub(in_min).wrapping_mul(out_max.wrapping_sub(out_min)).wrapping_div(den).wrapping_add(out_min)
}

/// Largest |U| passed to `map` unchanged. Beyond it the thesis' 32-bit map
/// would overflow; every |U| >= 48 already ends at 0 or 255 after the clamp,
/// so limiting U first changes no result the thesis defines.
const U_LIMIT: f32 = 1.0e6;

/// Thesis output stage: `pwm = map((long)U, 24, -24, 255, 0)` clamped to
/// 0..=255. `(long)U` truncates toward zero. A NaN gives 0 (motor off).
pub const fn output_to_duty(u: f32) -> u8 {
    if u.is_nan() {
        return 0;
    }
    let x = if u > U_LIMIT {
        U_LIMIT as i32
    } else if u < -U_LIMIT {
        -(U_LIMIT as i32)
    } else {
        u as i32
    };
    let m = arduino_map(x, 24, -24, 255, 0);
    if m >= 255 {
        255
    } else if m <= 0 {
        0
    } else {
        m as u8
    }
}

/// The thesis PID: no anti-windup, no derivative filter, derivative on the
/// error (so the first period after a reset sees the full step).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Pid {
    gains: Gains,
    setpoint: f32,
    /// Integral of the error (`Error_Pasado`).
    integral: f32,
    /// Error of the previous period (`Error_Anterior`).
    prev_error: f32,
}

impl Pid {
    /// A PID at rest.
    pub const fn new(gains: Gains, setpoint: f32) -> Self {
        Pid { gains, setpoint, integral: 0.0, prev_error: 0.0 }
    }

    /// Clears the integral and the previous error.
    pub const fn reset(&mut self) {
        self.integral = 0.0;
        self.prev_error = 0.0;
    }

    /// The set-point.
    pub const fn setpoint(&self) -> f32 {
        self.setpoint
    }

    /// One period: returns the control value U for the measured speed.
    pub const fn update(&mut self, measured: f32, period_s: f32) -> f32 {
        let error = self.setpoint - measured;
        self.integral = error * period_s + self.integral;
        let derivative = (error - self.prev_error) / period_s;
        self.prev_error = error;
        let p = self.gains.kp * error;
        let i = self.gains.ki * self.integral;
        let d = self.gains.kd * derivative;
        p + i + d
    }
}

/// One wheel's speed loop: the count at the last period boundary, the PID and
/// the output stage.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct WheelSpeedControl {
    pid: Pid,
    last_count: i32,
}

/// What one period of [`WheelSpeedControl`] measured and decided.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct WheelSample {
    /// Measured speed, thesis "RPM".
    pub rpm: f32,
    /// New duty for the wheel's forward input.
    pub duty: u8,
}

impl WheelSpeedControl {
    /// A controller at rest.
    pub const fn new(gains: Gains, setpoint: f32) -> Self {
        WheelSpeedControl { pid: Pid::new(gains, setpoint), last_count: 0 }
    }

    /// Starts a run: PID reset and `count_now` as the first period's origin.
    pub const fn start(&mut self, count_now: i32) {
        self.pid.reset();
        self.last_count = count_now;
    }

    /// One period that ends with the wheel at `count_now`.
    pub const fn update(&mut self, count_now: i32, period_s: f32) -> WheelSample {
        let delta = count_now.wrapping_sub(self.last_count);
        self.last_count = count_now;
        let rpm = thesis_rpm(delta, period_s);
        let u = self.pid.update(rpm, period_s);
        WheelSample { rpm, duty: output_to_duty(u) }
    }
}

// ---- compile-time checks of the control law ----

const fn close(a: f32, b: f32, tol: f32) -> bool {
    let d = a - b;
    d < tol && d > -tol
}

// Arduino map: U = 24 -> 255, U = -24 -> 0, U = 0 -> 255 - 127 (truncation).
const _: () = assert!(arduino_map(24, 24, -24, 255, 0) == 255);
const _: () = assert!(arduino_map(-24, 24, -24, 255, 0) == 0);
const _: () = assert!(arduino_map(0, 24, -24, 255, 0) == 128);
const _: () = assert!(output_to_duty(0.0) == 128);
// (long)23.9 = 23: (23 - 24) * -255 / -48 = -5 (not -5.3 -> -6), + 255.
const _: () = assert!(output_to_duty(23.9) == 250);
// (long)-1.5 = -1 (toward zero): -25 * -255 / -48 = -132, + 255.
const _: () = assert!(output_to_duty(-1.5) == 123);
const _: () = assert!(output_to_duty(89.2) == 255);
const _: () = assert!(output_to_duty(-30.0) == 0);
const _: () = assert!(output_to_duty(1.0e30) == 255);
const _: () = assert!(output_to_duty(-1.0e30) == 0);
const _: () = assert!(output_to_duty(f32::NAN) == 0);

// 13 counts in 15 ms: 13 / 0.015 * 60 / 6 * 0.0016605 = 14.3910.
const _: () = assert!(close(thesis_rpm(13, 0.015), 14.391, 1.0e-3));
const _: () = assert!(close(thesis_rpm(-13, 0.015), 14.391, 1.0e-3));
const _: () = assert!(thesis_rpm(0, 0.015) == 0.0);

// First period after a reset, wheel still: E = 14.47, I = E T, D = E / T;
// U = 2.74 E + 45.66 E T + 0.0411 E / T = 89.206.
const _: () = {
    let mut pid = Pid::new(Gains { kp: 2.74, ki: 45.66, kd: 0.0411 }, 14.47);
    let u = pid.update(0.0, 0.015);
    assert!(close(u, 89.206, 1.0e-2));
    // Second period at the set-point: E = 0, D = -14.47 / T, I unchanged.
    let u2 = pid.update(14.47, 0.015);
    assert!(close(u2, 45.66 * 14.47 * 0.015 - 0.0411 * 14.47 / 0.015, 1.0e-2));
    pid.reset();
    assert!(close(pid.update(0.0, 0.015), 89.206, 1.0e-2));
};

// ---- the robust build's form of the same law ----

/// The thesis PID with its constant factors folded once (when the gains or
/// the period change) so that a period costs three multiplications and four
/// additions in `f32`, no division:
/// `E = Set - RPM`, `U = (Kp + Kd/T) E - (Kd/T) E_prev + Iterm`, then
/// `Iterm += (Ki T) E`.
/// Mathematically the thesis' `Kp E + Ki I + Kd D` with `I += E T`,
/// `D = (E - E_prev) / T`; the `f32` results differ from the thesis' operation
/// order only by rounding.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct FastPid {
    /// `Kp + Kd / T`.
    a: f32,
    /// `Kd / T`.
    b: f32,
    /// `Ki T`.
    ki_t: f32,
    setpoint: f32,
    /// `Ki` times the integral of E up to the previous period.
    iterm: f32,
    prev_error: f32,
}

impl FastPid {
    /// A PID at rest for the period `period_s`.
    pub const fn new(gains: Gains, setpoint: f32, period_s: f32) -> Self {
        let b = gains.kd / period_s;
        FastPid { a: gains.kp + b, b, ki_t: gains.ki * period_s, setpoint, iterm: 0.0, prev_error: 0.0 }
    }

    /// New gains (keeps the state).
    pub fn set_gains(&mut self, gains: Gains, period_s: f32) {
        self.b = gains.kd / period_s;
        self.a = gains.kp + self.b;
        self.ki_t = gains.ki * period_s;
    }

    /// New set-point.
    pub fn set_setpoint(&mut self, setpoint: f32) {
        self.setpoint = setpoint;
    }

    /// Clears the integral and the previous error.
    pub fn reset(&mut self) {
        self.iterm = 0.0;
        self.prev_error = 0.0;
    }

    /// One period: the control value U for the measured speed.
    #[inline]
    pub fn update(&mut self, measured: f32) -> f32 {
        let error = self.setpoint - measured;
        self.iterm += self.ki_t * error;
        let u = self.a * error - self.b * self.prev_error + self.iterm;
        self.prev_error = error;
        u
    }
}

/// [`FastPid`] with its products looked up: at a segment start, for every
/// count `c` a wheel can make in one period (`0..N`), the error
/// `E(c) = Set - rpm(c)` and the three products `(Kp + Kd/T) E(c)`,
/// `(Kd/T) E(c)` and `(Ki T) E(c)` are tabulated, so a period costs three
/// `f32` additions and no multiplication. The tables hold exactly the values
/// `FastPid::update` would compute, so the results are the same bit for bit.
/// A count outside the tables (or a period that spans several ticks) takes
/// the multiplying path.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct TablePid<const N: usize> {
    pid: FastPid,
    a_e: [f32; N],
    b_e: [f32; N],
    ki_e: [f32; N],
    /// `(Kd/T) E` of the previous period.
    b_prev: f32,
}

impl<const N: usize> TablePid<N> {
    /// A controller at rest with empty tables (call [`TablePid::prepare`]).
    pub const fn new(gains: Gains, setpoint: f32, period_s: f32) -> Self {
        TablePid {
            pid: FastPid::new(gains, setpoint, period_s),
            a_e: [0.0; N],
            b_e: [0.0; N],
            ki_e: [0.0; N],
            b_prev: 0.0,
        }
    }

    /// New gains and set-point, the tables for the speeds `rpm[c]`, and the
    /// state reset.
    pub fn prepare(&mut self, gains: Gains, setpoint: f32, period_s: f32, rpm: &[f32; N]) {
        self.pid.set_gains(gains, period_s);
        self.pid.set_setpoint(setpoint);
        self.pid.reset();
        self.b_prev = 0.0;
        for (i, &r) in rpm.iter().enumerate() {
            let e = self.pid.setpoint - r;
            if let (Some(a), Some(b), Some(k)) = (self.a_e.get_mut(i), self.b_e.get_mut(i), self.ki_e.get_mut(i)) {
                *a = self.pid.a * e;
                *b = self.pid.b * e;
                *k = self.pid.ki_t * e;
            }
        }
    }

    /// One period in which the wheel made `counts` counts (speed `rpm`):
    /// the control value U.
    #[inline]
    pub fn update(&mut self, counts: u32, rpm: f32, one_period: bool) -> f32 {
        let idx = counts as usize;
        match (self.a_e.get(idx), self.b_e.get(idx), self.ki_e.get(idx)) {
            (Some(&a_e), Some(&b_e), Some(&ki_e)) if one_period => {
                self.pid.iterm += ki_e;
                let u = a_e - self.b_prev + self.pid.iterm;
                self.b_prev = b_e;
                u
            }
            _ => self.update_slow(rpm),
        }
    }

    #[cold]
    #[inline(never)]
    fn update_slow(&mut self, rpm: f32) -> f32 {
        let e = self.pid.setpoint - rpm;
        self.pid.iterm += self.pid.ki_t * e;
        let u = self.pid.a * e - self.b_prev + self.pid.iterm;
        self.b_prev = self.pid.b * e;
        u
    }
}

/// [`output_to_duty`] without floating-point compares or the 32-bit `map`,
/// from the bits of U: NaN or U <= -24 gives 0, U >= 24 gives 255; in
/// between `(long)U` is -23..=23 (the magnitude's integer part, taken from
/// the exponent and the top mantissa bits) and
/// `255 - (24 - x) * 255 / 48` (all positive, truncating) is exactly
/// Arduino's `map(x, 24, -24, 255, 0)`. Checked against [`output_to_duty`]
/// at compile time.
#[inline(always)]
pub const fn duty_from_output(u: f32) -> u8 {
    let bits = u.to_bits();
    let magnitude = bits & 0x7FFF_FFFF;
    let negative = bits >> 31 != 0;
    if magnitude > 0x7F80_0000 {
        return 0; // NaN
    }
    if magnitude >= 0x41C0_0000 {
        // |U| >= 24.0
        return if negative { 0 } else { 255 };
    }
    // |U| < 24 < 2^5: biased exponent <= 131; below 127 the integer part is 0.
    let exponent = (magnitude >> 23) as u8;
    let int_part = if exponent < 127 {
        0
    } else {
        // 1.xxxxxxx (implicit one and the 7 top mantissa bits) * 2^(e - 127)
        let significand = ((magnitude >> 16) as u8 & 0x7F) | 0x80;
        significand >> (7 - (exponent - 127))
    };
    let x = if negative { -(int_part as i8) } else { int_part as i8 };
    let k = (24 - x) as u16;
    255 - (k * 255 / 48) as u8
}

/// Thesis speed of `counts` counts in one period of `period_s`, for the
/// counts a wheel can make in one period (table below; the control tick
/// looks values up instead of converting and multiplying).
pub const fn rpm_table<const N: usize>(period_s: f32) -> [f32; N] {
    let mut t = [0.0; N];
    let mut i = 0;
    while i < N {
        t[i] = i as f32 * thesis_rpm(1, period_s);
        i += 1;
    }
    t
}

const _: () = {
    let mut i: i32 = -6000;
    while i <= 6000 {
        let u = i as f32 / 100.0;
        assert!(duty_from_output(u) == output_to_duty(u));
        assert!(duty_from_output(u + 0.004) == output_to_duty(u + 0.004));
        i += 1;
    }
    assert!(duty_from_output(f32::NAN) == output_to_duty(f32::NAN));
    assert!(duty_from_output(f32::INFINITY) == 255 && duty_from_output(f32::NEG_INFINITY) == 0);
    assert!(duty_from_output(-23.999) == output_to_duty(-23.999));
    assert!(duty_from_output(23.999) == output_to_duty(23.999));
};

// The folded PID gives the thesis PID's first two outputs (to rounding).
const _: () = {
    let g = Gains { kp: 2.74, ki: 45.66, kd: 0.0411 };
    let mut a = Pid::new(g, 14.47);
    let b = FastPid::new(g, 14.47, 0.015);
    let ua = a.update(0.0, 0.015);
    let e = b.setpoint - 0.0;
    let ub = b.a * e - b.b * 0.0 + b.ki_t * e;
    assert!(close(ua, ub, 1.0e-3));
    let ua2 = a.update(14.47, 0.015);
    let ub2 = b.a * 0.0 - b.b * e + b.ki_t * e;
    assert!(close(ua2, ub2, 1.0e-3));
};
