//! The thesis firmware's straight-line and UMBmark routines, emulated around the plant in
//! open loop, quirks included (as `firmware/src/bin/thesis.rs` ports them): what the real
//! robot ran when the thesis recorded its end points. A quick, plant-only stand-in for the
//! bench (`hil run ... --firmware thesis` runs the ported sketch cycle by cycle and is the
//! reference): it reproduces the bench's lines, but the UMBmark's CW/CCW asymmetry hangs on
//! sub-millisecond timing details of the leg starts that it does not copy exactly.
//!
//! Emulated: the busy loop, polled every [`LOOP_S`]; `PID()` with its 15 ms window measured
//! by `micros()` and its `abs()` speeds; `map(U, 24, -24, 255, 0)`; the per-wheel count
//! targets of the turns, which cut the *other* wheel's input for one loop pass only (the
//! loop writes both inputs again until both targets are reached); the stop sequences
//! (cut, 20 ms, 5 ms full reverse, 1 s, `Stop_General` 1 s); `reinicio`, which zeroes
//! `pwm_D` twice and leaves `pwm_I`, `Flag_One` and `Tiempo_Actual`; counts zeroed where the
//! sketch zeroes them; the time the right speed's `println` takes before the left count is
//! read ([`PRINT_S`]) and the rest of a PID update ([`COMPUTE_S`]). The loop's pass time varies (uniformly by [`JITTER`] around [`LOOP_S`],
//! from a seed), as the real loop's did with its serial prints; the leg starts' PID transients
//! are sensitive to that timing, which is where most of the scatter between runs comes
//! from. Not emulated: interrupt latency.

use plant_model::{Duty, Robot, Seconds, Side};

/// One pass of the sketch's busy loop (two `analogRead`s at 104 us plus the rest).
pub const LOOP_S: f64 = 0.3e-3;

/// `Serial.println(rpm_mot_D)`: `Print::printFloat` in software f32 on the AVR, between the
/// reads of the right and the left count. The left speed is measured over a window this
/// much longer than `Tiempo_s`, so it reads 3 % high and its PID holds the left wheel that
/// much slower: the two wheels end up at nearly equal count rates although the set-points
/// are 3.6 % apart. Calibrated against the bench, which runs the ported sketch cycle by
/// cycle: on `henrytwo.toml` its line ends (-5.7, +0.6) cm, this emulation's 20 runs
/// (-5.8, +0.4) on average. (Without the delay the ideal robot's lines curve 29 deg off.)
pub const PRINT_S: f64 = 0.45e-3;

/// The rest of a pass that updates the PIDs: the left speed's `println` and both PIDs' f32
/// arithmetic. With it the PID period averages 16.6 ms while driving, as the bench measures
/// on the ported sketch (827 periods in a 13.7 s leg).
pub const COMPUTE_S: f64 = 1.0e-3;

/// The loop pass time varies by up to this fraction either way (the serial queue, the ADC):
/// enough to vary the PID transients from run to run, small enough for lines that end within
/// millimetres of each other as the thesis' did.
pub const JITTER: f64 = 0.1;

/// `Constante`: mm per count.
const CONSTANTE: f32 = 0.166_933_95;
const MUESTREO: f32 = 0.015;
/// Left (I), right (D).
const SET: [f32; 2] = [15.0, 14.47];
const KP: [f32; 2] = [2.20, 2.74];
const KI: [f32; 2] = [36.666, 45.66];
const KD: [f32; 2] = [0.033, 0.0411];
const GIRO_90: i32 = 612;

/// `map((long)U, 24, -24, 255, 0)` clamped to 0..=255, as the sketch does it.
fn output_to_duty(u: f32) -> f32 {
    if u.is_nan() {
        return 0.0;
    }
    let x = u.clamp(-1.0e6, 1.0e6) as i32;
    let m = (x - 24) * (0 - 255) / (-24 - 24) + 255;
    m.clamp(0, 255) as f32
}

/// Direction of a UMBmark run, as the sketch names its routines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Routine {
    /// `UMBmark_CW` with `Giro_CW` (pins 7 and 8: right forward, left backward).
    Cw,
    /// `UMBmark_CCW` with `Giro_CCW` (pins 6 and 9: right backward, left forward).
    Ccw,
}

/// The sketch's state around a plant.
pub struct Thesis {
    pub robot: Robot,
    /// Duties on pins 6, 7, 8, 9 (right reverse, right forward, left reverse, left forward).
    pins: [u8; 4],
    /// `a_edges` where the sketch last zeroed each count.
    zero: [i64; 2],
    flag_one: bool,
    tiempo_actual: f32,
    conteo_actual: [f32; 2],
    pwm: [f32; 2],
    error_pasado: [f32; 2],
    error_anterior: [f32; 2],
    /// Loop-time jitter generator (a 64-bit LCG).
    jitter: u64,
}

impl Thesis {
    /// The sketch after `setup()`, the robot at rest; `pwm_D = pwm_I = 50`. The loop's
    /// timing jitter is seeded with the robot's seed.
    pub fn new(robot: Robot) -> Self {
        let jitter = robot.seed().wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        Thesis {
            robot,
            pins: [0; 4],
            zero: [0; 2],
            flag_one: true,
            tiempo_actual: 0.0,
            conteo_actual: [0.0; 2],
            pwm: [50.0; 2],
            error_pasado: [0.0; 2],
            error_anterior: [0.0; 2],
            jitter,
        }
    }

    fn count(&self, side: Side) -> i32 {
        (self.robot.a_edges(side) - self.zero[side.index()]) as i32
    }

    fn zero_count(&mut self, side: Side) {
        self.zero[side.index()] = self.robot.a_edges(side);
    }

    fn micros(&self) -> f32 {
        (self.robot.now().0 * 1e6).floor() as u32 as f32
    }

    fn wait(&mut self, seconds: f64) {
        let t = self.robot.now() + Seconds(seconds);
        self.robot.advance_to(t).unwrap();
    }

    fn analog_write(&mut self, pin: u8, val: f32) {
        self.pins[usize::from(pin - 6)] = (val as i16).clamp(0, 255) as u8;
        let d = |v: u8| Duty::from_pwm8(v);
        let [r_rev, r_fwd, l_rev, l_fwd] = self.pins;
        self.robot.set_bridge(Side::Right, d(r_fwd), d(r_rev));
        self.robot.set_bridge(Side::Left, d(l_fwd), d(l_rev));
    }

    fn pid(&mut self) {
        if self.flag_one {
            self.tiempo_actual = self.micros();
            for side in Side::BOTH {
                self.conteo_actual[side.index()] = self.count(side).abs() as f32;
            }
            self.flag_one = false;
        }
        let tiempo_s = self.micros() - self.tiempo_actual;
        if tiempo_s >= 15000.0 {
            let mut rpm = [0.0f32; 2];
            for side in [Side::Right, Side::Left] {
                if side == Side::Left {
                    // Serial.println(rpm_mot_D) formats the right speed before the left
                    // count is read: the left's window is longer than tiempo_s.
                    self.wait(PRINT_S);
                }
                let i = side.index();
                let conteo = self.count(side).abs() as f32 - self.conteo_actual[i];
                let frecuencia = conteo / (tiempo_s / 1_000_000.0);
                let rpm_enc = frecuencia * 60.0 / 6.0;
                rpm[i] = rpm_enc.abs() * 0.0016605;
            }
            self.flag_one = true;
            let mut error = [0.0f32; 2];
            for i in 0..2 {
                error[i] = SET[i] - rpm[i];
                self.error_pasado[i] += error[i] * MUESTREO;
                let errord = (error[i] - self.error_anterior[i]) / MUESTREO;
                let u = KP[i] * error[i] + KI[i] * self.error_pasado[i] + KD[i] * errord;
                self.pwm[i] = output_to_duty(u);
            }
            self.error_anterior = error;
            // Serial.println(rpm_mot_I) and the two PIDs' f32 arithmetic.
            self.wait(COMPUTE_S);
        }
    }

    /// One pass of the loop's body ends: time moves on by [`LOOP_S`].
    fn pass(&mut self) {
        self.jitter = self
            .jitter
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let unit = (self.jitter >> 11) as f64 / (1u64 << 53) as f64;
        self.wait(LOOP_S * (1.0 + JITTER * (2.0 * unit - 1.0)));
    }

    fn adelante(&mut self) {
        self.analog_write(7, self.pwm[1]);
        self.analog_write(9, self.pwm[0]);
        self.pid();
    }

    fn du_i(&self) -> f32 {
        let du_r = CONSTANTE * self.count(Side::Right) as f32;
        let du_l = CONSTANTE * self.count(Side::Left) as f32;
        (du_r + du_l) / 2.0
    }

    fn inercia_stop_ad(&mut self) {
        self.analog_write(7, 0.0);
        self.analog_write(9, 0.0);
        self.wait(0.020);
        self.analog_write(6, 255.0);
        self.analog_write(8, 255.0);
        self.wait(0.005);
        self.analog_write(6, 0.0);
        self.analog_write(8, 0.0);
        self.wait(1.0);
    }

    fn stop_general(&mut self) {
        for pin in 6..=9 {
            self.analog_write(pin, 0.0);
        }
        self.wait(1.0);
    }

    /// `Giro_CW` (pins 7, 8) or `Giro_CCW` (pins 6, 9), then its `Inercia_Stop`,
    /// `Stop_General` and the variables' reset.
    fn giro(&mut self, routine: Routine) {
        let (right_pin, left_pin, right_back, left_back) = match routine {
            Routine::Cw => (7, 8, 6, 9),
            Routine::Ccw => (6, 9, 7, 8),
        };
        let mut flags = [true, true];
        while flags[0] || flags[1] {
            self.analog_write(right_pin, self.pwm[1]);
            self.analog_write(left_pin, self.pwm[0]);
            self.pid();
            // The left count's branch cuts the pin written first, the right count's the
            // other: crossed, and undone by the next pass anyway.
            if self.count(Side::Left).abs() >= GIRO_90 {
                self.analog_write(right_pin, 0.0);
                self.zero_count(Side::Left);
                flags[0] = false;
            }
            if self.count(Side::Right).abs() >= GIRO_90 {
                self.analog_write(left_pin, 0.0);
                self.zero_count(Side::Right);
                flags[1] = false;
            }
            self.pass();
        }
        // Inercia_Stop_Izq / _Der: the turn's pins off, 20 ms, the opposite pins at full
        // duty for 5 ms, off, 1 s.
        self.analog_write(right_pin, 0.0);
        self.analog_write(left_pin, 0.0);
        self.wait(0.020);
        self.analog_write(right_back, 255.0);
        self.analog_write(left_back, 255.0);
        self.wait(0.005);
        self.analog_write(right_back, 0.0);
        self.analog_write(left_back, 0.0);
        self.wait(1.0);
        self.stop_general();
        // reinicio: pwm_D = 0 (twice; pwm_I stays), U, errors and speed state to 0.
        self.pwm[1] = 0.0;
        self.error_pasado = [0.0; 2];
        self.error_anterior = [0.0; 2];
        self.conteo_actual = [0.0; 2];
    }

    /// `Linear_Path_Test` of `leg_mm`.
    pub fn line(&mut self, leg_mm: f32) {
        self.stop_general();
        loop {
            self.adelante();
            if self.du_i() >= leg_mm {
                self.inercia_stop_ad();
                self.stop_general();
                self.zero_count(Side::Right);
                self.zero_count(Side::Left);
                return;
            }
            self.pass();
        }
    }

    /// `UMBmark_CW` or `UMBmark_CCW` with legs of `leg_mm`: four legs, four turns.
    pub fn umbmark(&mut self, routine: Routine, leg_mm: f32) {
        let mut legs = 0;
        while legs <= 3 {
            self.adelante();
            if self.du_i() >= leg_mm {
                legs += 1;
                self.inercia_stop_ad();
                self.stop_general();
                self.zero_count(Side::Right);
                self.zero_count(Side::Left);
                self.giro(routine);
            } else {
                self.pass();
            }
        }
    }
}
