//! Stop timing and watchdog thresholds for a robot, derived from its motor
//! model and encoders when its config gives none, as the gains are
//! ([`super::tune::automatic`]).
//!
//! - **Stop timing.** After a cut the firmware lets the wheel coast
//!   `brake_coast_ms`, then drives it backwards at full duty for
//!   `brake_pulse_ms`. On the motor model (first order: the coast time
//!   constant while coasting, `tau_s` towards the reverse top speed while
//!   pulsed) a wheel cut at its set-point covers some distance more: the
//!   *stop time*, that distance over the set-point speed. Henrytwo's motors
//!   stop within a few control periods (36 ms), which the thesis' targets
//!   absorb; a robot whose predicted stop time with the factory timing
//!   exceeds [`STOP_GATE_S`] gets a counter-pulse long enough to bring the
//!   wheel to rest (the reverse drive's time to cancel the speed left after
//!   the coast), at most [`PULSE_MAX_MS`], and a stop lead of the stop time
//!   that remains, so its legs and turns end where they are meant to.
//! - **Thresholds.** The stall watchdog's net progress (3 counts) and the
//!   wrong-way limit (64 counts) are Henrytwo's at 13 counts per control
//!   period at the set-point: scaled by the robot's counts per period at its
//!   set-point, at least 1.
//!
//! Henrytwo (its fixture and the default config) derives exactly the
//! factory values, so nothing is sent for it.

use henrytwo_protocol::Param;
use plant_model::{FirstOrderMotor, MotorModel, RobotConfig};

use super::settings::{full_duty_thesis_rpm, setpoint_thesis_rpm};
use super::tune::PERIOD_S;

/// The parameters this module derives.
pub const STOP: [Param; 5] = [
    Param::BrakeCoastMs,
    Param::BrakePulseMs,
    Param::StopLeadMs,
    Param::StallProgressCounts,
    Param::WrongWayCounts,
];

/// A predicted stop time with the factory stop timing up to this is left
/// alone (Henrytwo's 36 ms; a leg's end a few millimetres on).
pub const STOP_GATE_S: f64 = 0.1;

/// The longest derived counter-pulse: a spin the other way any longer is a
/// turn of its own to whoever watches the motors (the bench's analysis takes
/// driven phases under 30 ms for braking), and a longer brake would be the
/// lead's work anyway.
pub const PULSE_MAX_MS: f32 = 25.0;

/// Henrytwo's counts per wheel turn and factory set-point: the thresholds'
/// reference.
const HENRYTWO_COUNTS_PER_PERIOD: f64 = {
    let rev = Param::CountsPerWheelRev.factory_default() as f64;
    let sp = Param::SetpointLeft.factory_default() as f64;
    sp * 6.0 / 60.0 * rev * PERIOD_S
};

fn first_order(m: &MotorModel) -> &FirstOrderMotor {
    match m {
        MotorModel::FirstOrder(f) => f,
    }
}

/// A wheel's stop on its motor model from the set-point, in seconds of
/// driving at the set-point, with `coast_s` then `pulse_s`; and the speed
/// left after the pulse, over the set-point (negative: it reversed).
pub fn stop_time(
    motor: &FirstOrderMotor,
    volts: f64,
    setpoint: f64,
    coast_s: f64,
    pulse_s: f64,
) -> (f64, f64) {
    let tc = motor.coast_tau().0;
    let tau = motor.tau_s;
    // Speeds over the set-point.
    let reverse = -full_duty_thesis_rpm(motor, volts) / setpoint;
    let mut distance = tc * (1.0 - (-coast_s / tc).exp());
    let v1 = (-coast_s / tc).exp();
    let decay = (-pulse_s / tau).exp();
    distance += reverse * pulse_s + (v1 - reverse) * tau * (1.0 - decay);
    let v2 = reverse + (v1 - reverse) * decay;
    if v2 > 0.0 {
        distance += v2 * tc;
    }
    (distance, v2)
}

/// The derived values of every parameter in [`STOP`], in its order.
pub fn derive(robot: &RobotConfig) -> [(Param, f32); 5] {
    let f = |p: Param| p.factory_default();
    let coast_s = f(Param::BrakeCoastMs) as f64 / 1000.0;
    let mut pulse_ms = f(Param::BrakePulseMs);
    let mut lead_ms = f(Param::StopLeadMs);
    let wheels = [
        (
            first_order(&robot.motor.left),
            setpoint_thesis_rpm(robot, 0),
        ),
        (
            first_order(&robot.motor.right),
            setpoint_thesis_rpm(robot, 1),
        ),
    ];
    let volts = robot.battery.voltage_v;
    let slowest = wheels
        .iter()
        .map(|&(m, sp)| stop_time(m, volts, sp, coast_s, pulse_s(pulse_ms)).0)
        .fold(0.0, f64::max);
    if slowest > STOP_GATE_S {
        // The pulse that cancels the speed left after the coast, the longer
        // of the two wheels' (whole ms, within the firmware's range).
        let pulse = wheels
            .iter()
            .map(|&(m, sp)| {
                let v1 = (-coast_s / m.coast_tau().0).exp();
                let reverse = full_duty_thesis_rpm(m, volts) / sp;
                m.tau_s * (1.0 + v1 / reverse).ln()
            })
            .fold(0.0, f64::max);
        let r = Param::BrakePulseMs.range();
        pulse_ms = ((pulse * 1000.0).round() as f32).clamp(r.min, PULSE_MAX_MS.min(r.max));
        let stop = wheels
            .iter()
            .map(|&(m, sp)| stop_time(m, volts, sp, coast_s, pulse_s(pulse_ms)).0)
            .sum::<f64>()
            / 2.0;
        let r = Param::StopLeadMs.range();
        lead_ms = ((stop * 1000.0).round() as f32).clamp(r.min, r.max);
    }
    let counts_per_rev = robot.encoder.gear_ratio * robot.encoder.a_edges_per_motor_rev as f64;
    let per_period = |sp: f64| sp * 6.0 / 60.0 * counts_per_rev * PERIOD_S;
    let slow = per_period(wheels[0].1.min(wheels[1].1));
    let scaled = |p: Param| {
        let r = p.range();
        ((f(p) as f64 * slow / HENRYTWO_COUNTS_PER_PERIOD).round() as f32).clamp(r.min, r.max)
    };
    [
        (Param::BrakeCoastMs, f(Param::BrakeCoastMs)),
        (Param::BrakePulseMs, pulse_ms),
        (Param::StopLeadMs, lead_ms),
        (
            Param::StallProgressCounts,
            scaled(Param::StallProgressCounts),
        ),
        (Param::WrongWayCounts, scaled(Param::WrongWayCounts)),
    ]
}

fn pulse_s(ms: f32) -> f64 {
    ms as f64 / 1000.0
}

/// Parameters to send, and the note that says so (if any).
pub type Derived = (Vec<(Param, f32)>, Option<String>);

/// What to send for `robot`: each derived value its config does not give
/// and that differs from the factory one (none for Henrytwo), and a note
/// naming the stop timing among them (the thresholds change no motion, only
/// when the watchdog speaks: they go without a word); None when nothing is
/// to be sent.
pub fn automatic(robot: &RobotConfig) -> Option<Derived> {
    let send: Vec<(Param, f32)> = derive(robot)
        .into_iter()
        .filter(|(p, v)| !robot.firmware.contains_key(p.name()) && *v != p.factory_default())
        .collect();
    if send.is_empty() {
        return None;
    }
    let timing = [Param::BrakeCoastMs, Param::BrakePulseMs, Param::StopLeadMs];
    let list = send
        .iter()
        .filter(|(p, _)| timing.contains(p))
        .map(|(p, v)| format!("{} {v}", p.name()))
        .collect::<Vec<_>>();
    let note = (!list.is_empty()).then(|| {
        format!(
            "the factory stop timing is predicted to coast this robot's wheels far past their targets and \
             its config gives none: using {} ([firmware] in the robot config keeps them)",
            list.join(", ")
        )
    });
    Some((send, note))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load(name: &str) -> RobotConfig {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fixtures/robots")
            .join(name);
        RobotConfig::load(&path).unwrap()
    }

    /// `r`'s left motor stopped from the thesis set-point after the factory
    /// 20 ms coast and a pulse of `pulse_s`, as [`stop_time`] gives it.
    fn left_stop(r: &RobotConfig, pulse_s: f64) -> (f64, f64) {
        stop_time(
            first_order(&r.motor.left),
            r.battery.voltage_v,
            14.47,
            0.020,
            pulse_s,
        )
    }

    /// Henrytwo derives the factory values: nothing is sent, the firmware
    /// runs as it always has.
    #[test]
    fn henrytwo_derives_the_factory_values() {
        for robot in [load("henrytwo.toml"), RobotConfig::default()] {
            for (p, v) in derive(&robot) {
                assert_eq!(v, p.factory_default(), "{p:?}");
            }
            assert_eq!(automatic(&robot), None);
        }
    }

    /// Henrytwo's motors stop within the gate with the factory timing.
    #[test]
    fn henrytwo_stops_within_a_few_periods() {
        let (t, _) = left_stop(&RobotConfig::default(), 0.005);
        assert!(t > 0.02 && t < STOP_GATE_S, "{t}");
    }

    /// Slow, heavy motors coast for about their coast time constant: the
    /// longest pulse brakes them, the lead takes off the coast left.
    #[test]
    fn a_heavy_robot_gets_a_lead_and_a_longer_pulse() {
        let r = load("heavy100.toml");
        let d = derive(&r);
        let get = |p| d.iter().find(|(q, _)| *q == p).unwrap().1;
        let (pulse, lead) = (get(Param::BrakePulseMs), get(Param::StopLeadMs));
        assert_eq!(pulse, PULSE_MAX_MS, "{d:?}");
        let (t, left) = left_stop(&r, pulse as f64 / 1000.0);
        assert!(left > 0.0 && left < 1.0, "{left}");
        assert!(
            ((t * 1000.0).round() as f32 - lead).abs() <= 1.0,
            "{t} {lead}"
        );
        // The factory timing would coast most of the coast time constant.
        let (factory, _) = left_stop(&r, 0.005);
        assert!(factory > 0.25, "{factory}");
    }

    /// Coarse encoders make fewer counts per period: the thresholds shrink.
    #[test]
    fn coarse_encoders_scale_the_thresholds_down() {
        let d = derive(&load("coarse65.toml"));
        let get = |p| d.iter().find(|(q, _)| *q == p).unwrap().1;
        assert!(get(Param::WrongWayCounts) < 64.0, "{d:?}");
        assert!(get(Param::StallProgressCounts) >= 1.0, "{d:?}");
    }

    /// A value the config gives is not derived over.
    #[test]
    fn a_given_value_is_kept() {
        let mut r = load("heavy100.toml");
        r.firmware.insert("stop_lead_ms".into(), 100.0);
        let (send, _) = automatic(&r).unwrap();
        assert!(
            send.iter().all(|(p, _)| *p != Param::StopLeadMs),
            "{send:?}"
        );
    }
}
