//! The motor drivers' truth tables: what a driver's input levels do to the
//! motor, as the plant's bridge command.
//!
//! The plant takes each motor as a DRV8833's two input duties `(in1, in2)`
//! and averages one PWM period (`plant_model::bridge`): `in1 - in2` of it
//! driven (forward when positive), `min(in1, in2)` braking (both outputs
//! low, the motor shorted), the rest coasting (outputs high impedance). Any
//! driver's period splits into the same three parts, so each is given to
//! the plant as the DRV8833 inputs with the same split:
//! `in1 = brake + forward`, `in2 = brake + reverse`.
//!
//! Inputs are duties in `[0, 1]`; a direction pin is 0 or 1. As the plant
//! does, waveforms of one timer are taken to start their high time together
//! (the same period, phase-correct PWM centred on BOTTOM), so an input of
//! duty `d` is high over `[0, d)` of the period.

use crate::board::DriverKind;

/// The part of a period driven forward, driven in reverse, and braking.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Split {
    forward: f64,
    reverse: f64,
    brake: f64,
}

/// Length of the part of `[0, 1)` where a signal high over `[0, hi)` is
/// high and one high over `[0, lo)` is low: `[lo, hi)`.
fn high_while_low(hi: f64, lo: f64) -> f64 {
    (hi - lo).max(0.0)
}

/// How one period splits for `kind` with pin duties `d` (pins 1-3 as
/// [`DriverKind`] numbers them; an absent pin 3 is 0).
fn split(kind: DriverKind, [d1, d2, d3]: [f64; 3]) -> Split {
    match kind {
        // DRV8833 table 2: IN1 alone forward, IN2 alone reverse, both brake,
        // neither coasts.
        DriverKind::Drv8833 => Split {
            forward: high_while_low(d1, d2),
            reverse: high_while_low(d2, d1),
            brake: d1.min(d2),
        },
        // L298: enable high with C > D forward, C < D reverse, C = D fast
        // motor stop (brake); enable low free-running stop (coast).
        DriverKind::L298n => {
            let (en, c, d) = (d1, d2, d3);
            Split {
                forward: high_while_low(en.min(c), d),
                reverse: high_while_low(en.min(d), c),
                // Both high while enabled, or both low while enabled.
                brake: en.min(c).min(d) + high_while_low(en, c.max(d)),
            }
        }
        // TB6612FNG: IN1 H IN2 L with PWM H forward (CW), IN1 L IN2 H with
        // PWM H reverse (CCW); either of those with PWM L short brake; IN1
        // and IN2 both H short brake; both L stop (high impedance).
        DriverKind::Tb6612 => {
            let (pwm, in1, in2) = (d1, d2, d3);
            let one_high_from = in1.min(in2);
            Split {
                forward: high_while_low(pwm.min(in1), in2),
                reverse: high_while_low(pwm.min(in2), in1),
                brake: in1.min(in2) + high_while_low(in1.max(in2), pwm.max(one_high_from)),
            }
        }
        // Phase/enable: PWM H with DIR H forward, DIR L reverse; PWM L
        // brakes (both outputs low).
        DriverKind::PwmDir => {
            let (pwm, dir) = (d1, d2);
            Split {
                forward: pwm.min(dir),
                reverse: high_while_low(pwm, dir),
                brake: 1.0 - pwm,
            }
        }
        // DRV8838 table 1 (nSLEEP high): EN H with PH L forward (OUT1 H,
        // OUT2 L), PH H reverse; EN L brakes (both outputs low).
        DriverKind::Drv8838 => {
            let (en, ph) = (d1, d2);
            Split {
                forward: high_while_low(en, ph),
                reverse: en.min(ph),
                brake: 1.0 - en,
            }
        }
    }
}

/// The DRV8833 inputs `(in1, in2)` that make the plant's motor do what
/// `kind`'s inputs at duties `d` make it do.
pub(super) fn plant_inputs(kind: DriverKind, d: [f64; 3]) -> (f64, f64) {
    if kind == DriverKind::Drv8833 {
        // The plant's own driver: its inputs, as they are.
        return (d[0], d[1]);
    }
    let s = split(kind, d);
    let clamp = |x: f64| x.clamp(0.0, 1.0);
    (clamp(s.brake + s.forward), clamp(s.brake + s.reverse))
}

/// What a motor does as [`super::recorder::Motion`] counts it, from the
/// plant inputs `(in1, in2)` [`plant_inputs`] gave: +1 forward, -1 reverse,
/// 0 off, 2 brake. A DRV8833 brakes when the firmware holds both inputs on,
/// whatever else it drives; the other drivers brake in the PWM's off-time
/// by design (TB6612, PWM/DIR), so for them a motor driven at all is
/// driven, and brakes only when not driven.
pub(super) fn motion_sign(kind: DriverKind, (in1, in2): (f64, f64)) -> i8 {
    let drive = in1 - in2;
    match kind {
        DriverKind::Drv8833 => match (in1 > 0.0, in2 > 0.0) {
            (false, false) => 0,
            (true, false) => 1,
            (false, true) => -1,
            (true, true) => 2,
        },
        _ if drive > 0.0 => 1,
        _ if drive < 0.0 => -1,
        _ if in1.min(in2) > 0.0 => 2,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use rstest::rstest;
    use DriverKind::*;

    /// Each datasheet's truth table, static levels and with PWM on the
    /// speed input, as the split the plant sees (forward, reverse, brake;
    /// coast is the rest).
    #[rstest]
    // DRV8833: IN1, IN2.
    #[case::drv_coast(Drv8833, [0.0, 0.0, 0.0], (0.0, 0.0, 0.0))]
    #[case::drv_forward(Drv8833, [0.7, 0.0, 0.0], (0.7, 0.0, 0.0))]
    #[case::drv_reverse(Drv8833, [0.0, 0.4, 0.0], (0.0, 0.4, 0.0))]
    #[case::drv_brake(Drv8833, [1.0, 1.0, 0.0], (0.0, 0.0, 1.0))]
    #[case::drv_slow_decay(Drv8833, [1.0, 0.3, 0.0], (0.7, 0.0, 0.3))]
    // L298N: EN, IN1, IN2.
    #[case::l298_enable_low_coasts(L298n, [0.0, 1.0, 0.0], (0.0, 0.0, 0.0))]
    #[case::l298_forward(L298n, [0.6, 1.0, 0.0], (0.6, 0.0, 0.0))]
    #[case::l298_reverse(L298n, [0.6, 0.0, 1.0], (0.0, 0.6, 0.0))]
    #[case::l298_both_high_brake(L298n, [1.0, 1.0, 1.0], (0.0, 0.0, 1.0))]
    #[case::l298_both_low_brake(L298n, [0.5, 0.0, 0.0], (0.0, 0.0, 0.5))]
    // TB6612: PWM, IN1, IN2.
    #[case::tb_forward_full(Tb6612, [1.0, 1.0, 0.0], (1.0, 0.0, 0.0))]
    #[case::tb_forward_pwm_brakes_off_time(Tb6612, [0.6, 1.0, 0.0], (0.6, 0.0, 0.4))]
    #[case::tb_reverse_pwm(Tb6612, [0.25, 0.0, 1.0], (0.0, 0.25, 0.75))]
    #[case::tb_pwm_low_brakes(Tb6612, [0.0, 1.0, 0.0], (0.0, 0.0, 1.0))]
    #[case::tb_both_high_brake(Tb6612, [0.6, 1.0, 1.0], (0.0, 0.0, 1.0))]
    #[case::tb_both_low_stop(Tb6612, [0.6, 0.0, 0.0], (0.0, 0.0, 0.0))]
    // PWM/DIR: PWM, DIR.
    #[case::dir_forward(PwmDir, [0.8, 1.0, 0.0], (0.8, 0.0, 0.2))]
    #[case::dir_reverse(PwmDir, [0.8, 0.0, 0.0], (0.0, 0.8, 0.2))]
    #[case::dir_pwm_low_brakes(PwmDir, [0.0, 1.0, 0.0], (0.0, 0.0, 1.0))]
    // DRV8838: EN, PH (high reverse).
    #[case::drv8838_forward(Drv8838, [0.75, 0.0, 0.0], (0.75, 0.0, 0.25))]
    #[case::drv8838_reverse(Drv8838, [0.3, 1.0, 0.0], (0.0, 0.3, 0.7))]
    #[case::drv8838_en_low_brakes(Drv8838, [0.0, 1.0, 0.0], (0.0, 0.0, 1.0))]
    fn truth_tables(
        #[case] kind: DriverKind,
        #[case] d: [f64; 3],
        #[case] (forward, reverse, brake): (f64, f64, f64),
    ) {
        let s = split(kind, d);
        assert_relative_eq!(s.forward, forward, epsilon = 1e-12);
        assert_relative_eq!(s.reverse, reverse, epsilon = 1e-12);
        assert_relative_eq!(s.brake, brake, epsilon = 1e-12);
        // The plant, given the equivalent DRV8833 inputs, splits the period
        // the same way (plant_model::bridge: drive in1 - in2, brake min).
        let (in1, in2) = plant_inputs(kind, d);
        assert_relative_eq!(in1 - in2, forward - reverse, epsilon = 1e-12);
        assert_relative_eq!(in1.min(in2), brake, epsilon = 1e-12);
    }

    /// Driving with PWM counts as driving on every driver; a DRV8833 with
    /// both inputs on counts as braking (the thesis firmware's brake), the
    /// others brake when no part of the period is driven.
    #[rstest]
    #[case::drv_forward(Drv8833, [0.7, 0.0, 0.0], 1)]
    #[case::drv_both_on_brakes(Drv8833, [1.0, 0.3, 0.0], 2)]
    #[case::drv_off(Drv8833, [0.0, 0.0, 0.0], 0)]
    #[case::tb_forward_pwm(Tb6612, [0.6, 1.0, 0.0], 1)]
    #[case::tb_reverse_pwm(Tb6612, [0.6, 0.0, 1.0], -1)]
    #[case::tb_brake(Tb6612, [0.6, 1.0, 1.0], 2)]
    #[case::tb_stop(Tb6612, [0.6, 0.0, 0.0], 0)]
    #[case::dir_reverse(PwmDir, [0.8, 0.0, 0.0], -1)]
    #[case::dir_pwm_low_brakes(PwmDir, [0.0, 1.0, 0.0], 2)]
    #[case::drv8838_forward(Drv8838, [0.75, 0.0, 0.0], 1)]
    #[case::drv8838_reverse(Drv8838, [0.75, 1.0, 0.0], -1)]
    #[case::l298_enable_low_coasts(L298n, [0.0, 1.0, 0.0], 0)]
    #[case::l298_forward(L298n, [0.6, 1.0, 0.0], 1)]
    fn motion_signs(#[case] kind: DriverKind, #[case] d: [f64; 3], #[case] sign: i8) {
        assert_eq!(motion_sign(kind, plant_inputs(kind, d)), sign);
    }
}
