//! PID gains for a robot the factory gains do not suit, derived from its
//! motor model and its encoder resolution the way the thesis derived
//! Henrytwo's, and a prediction of whether a set of gains chatters the duty
//! to 0 on a robot.
//!
//! The thesis tuned by Ziegler and Nichols' first method in Ogata's table
//! form, `Kp = 1.2 T/L`, `Ti = 2L`, `Td = L/2`, with `T` the motor's 63.2 %
//! time constant and `L` two control periods (0.03 s); it left out the
//! process gain `K` (`plant_model::identify`). Henrytwo's process gain in
//! the controller's units (thesis RPM per unit of `U`, which drives
//! `PWM = 127.5 + 5.3125 U`) is 1.6-1.9, so leaving it out cost little. A
//! fast motor with a small dead band has the same gain per unit of `U` but
//! holds the set-point near the bottom of the duty range, where the factory
//! PID's limit cycle reaches 0; coarse encoders add a count quantum of
//! several thesis RPM to every period's error. So the derivation uses the
//! rule with the process gain, `Kp = 1.2 T/(K L)`, and then checks the
//! gains on a model of the firmware's loop (its quantised speed, its PID,
//! its output stage, the first-order motor with its dead band, 15 ms
//! periods): while the derivative's reaction to one count's flicker
//! (`2 Kd/T` per count quantum) chatters the duty to 0 it drops `Td`, then
//! halves `Kp` (keeping `Ti`) until the duty stays off 0.
//!
//! Henrytwo's runs keep the factory gains: they are replaced only when the
//! robot config gives none and the same model predicts that they chatter.

use henrytwo_protocol::Param;
use plant_model::{FirstOrderMotor, MotorModel, RobotConfig};

/// The firmware's control period, s (`robot::SAMPLE_PERIOD_S`).
pub const PERIOD_S: f64 = 0.015;
/// The Ziegler-Nichols dead time: two control periods, the thesis' 0.03 s.
pub const ZN_DEAD_TIME_S: f64 = 2.0 * PERIOD_S;
/// PWM counts per unit of the controller output `U` (`map(U, 24, -24, 255, 0)`).
const PWM_PER_UNIT: f64 = 255.0 / 48.0;
/// Robot time of the loop model, s: the start and many times the motors' time constants.
const MODEL_S: f64 = 2.0;
/// Periods after the start during which a duty of 0 is the start's
/// transient, not chatter: the integral of the first periods' error can
/// overshoot once.
const START_PERIODS: usize = 6;

/// One wheel's gains.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WheelGains {
    pub kp: f64,
    pub ki: f64,
    pub kd: f64,
}

/// The factory gains (Henrytwo's, the thesis'), left and right.
pub fn factory() -> [WheelGains; 2] {
    let g = |kp: Param, ki: Param, kd: Param| WheelGains {
        kp: kp.factory_default() as f64,
        ki: ki.factory_default() as f64,
        kd: kd.factory_default() as f64,
    };
    [
        g(Param::KpLeft, Param::KiLeft, Param::KdLeft),
        g(Param::KpRight, Param::KiRight, Param::KdRight),
    ]
}

/// What the loop model saw of one wheel driven by a set of gains.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Predicted {
    /// Periods after the start whose duty was 0 while driving.
    pub duty_zero_periods: usize,
    /// Peak speed over the set-point, as a fraction of it.
    pub overshoot: f64,
    /// Time after the start from which the speed stays within 10 % of the set-point, s;
    /// `None` when it never does.
    pub settling_s: Option<f64>,
}

/// One wheel's derivation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WheelTuning {
    /// `K`: thesis RPM per unit of the controller output, at the set-point.
    pub process_gain: f64,
    /// `T`: the motor's time constant, s.
    pub tau_s: f64,
    /// The set-point, thesis RPM.
    pub setpoint_rpm: f64,
    /// Counts per 15 ms control period at the set-point.
    pub counts_per_period: f64,
    /// The steady duty at the set-point, of 255.
    pub steady_duty: f64,
    /// Ziegler-Nichols' `1.2 T/(K L)`, `Ti = 2L`, `Td = L/2`.
    pub ziegler_nichols: WheelGains,
    /// The gains after the chatter check.
    pub gains: WheelGains,
    /// How the gains differ from Ziegler-Nichols', and why; empty when they do not.
    pub adjusted: Vec<String>,
    pub factory_predicted: Predicted,
    pub predicted: Predicted,
}

/// The derivation for both wheels.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Tuning {
    pub left: WheelTuning,
    pub right: WheelTuning,
}

impl Tuning {
    pub fn wheels(&self) -> [&WheelTuning; 2] {
        [&self.left, &self.right]
    }

    /// Whether the factory gains are predicted to chatter the duty to 0 on either wheel.
    pub fn factory_chatters(&self) -> bool {
        self.wheels()
            .iter()
            .any(|w| w.factory_predicted.duty_zero_periods > 0)
    }

    /// The derived gains as the firmware's parameters, in the `[firmware]` table's order.
    pub fn params(&self) -> Vec<(Param, f32)> {
        let [l, r] = [self.left.gains, self.right.gains];
        vec![
            (Param::KpLeft, l.kp as f32),
            (Param::KiLeft, l.ki as f32),
            (Param::KdLeft, l.kd as f32),
            (Param::KpRight, r.kp as f32),
            (Param::KiRight, r.ki as f32),
            (Param::KdRight, r.kd as f32),
        ]
    }
}

/// Four significant digits: what a config file shows and the firmware is sent.
fn round(v: f64) -> f64 {
    if v == 0.0 {
        return 0.0;
    }
    let scale = 10f64.powi(3 - v.abs().log10().floor() as i32);
    (v * scale).round() / scale
}

/// Why a robot cannot be tuned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TuneError {
    #[error("the {side} motor cannot reach the set-point {setpoint:.2} thesis RPM (its top speed is {top:.2}): lower setpoint_{side}")]
    TooSlow {
        side: &'static str,
        setpoint: f64,
        top: f64,
    },
    #[error("no gains keep the {side} wheel's duty off 0 on the loop model ({counts:.1} counts per period at the set-point)")]
    NoGains { side: &'static str, counts: f64 },
}

/// The set-point the firmware drives wheel `i` at on `robot`: the config's
/// `[firmware]` `setpoint_*`, else the factory value.
fn setpoint(robot: &RobotConfig, p: Param) -> f64 {
    super::settings::setpoint_thesis_rpm(robot, usize::from(p == Param::SetpointRight))
}

fn first_order(m: &MotorModel) -> &FirstOrderMotor {
    match m {
        MotorModel::FirstOrder(f) => f,
    }
}

/// The firmware's loop on one wheel, as a model: each period the speed
/// measured from whole counts, the PID, `map` and the clamp, the duty held
/// for the period on a first-order motor with its dead band.
struct Loop<'a> {
    motor: &'a FirstOrderMotor,
    volts: f64,
    counts_per_rev: f64,
    setpoint: f64,
}

impl Loop<'_> {
    fn run(&self, g: WheelGains) -> Predicted {
        let q = 10.0 / (PERIOD_S * self.counts_per_rev);
        let (mut speed, mut position, mut iterm, mut prev_e) = (0.0f64, 0.0f64, 0.0, 0.0);
        let mut duty = f64::from(crate::firmware::tune::START_DUTY);
        let (mut zeros, mut peak, mut last_out) = (0, 0.0f64, None);
        let periods = (MODEL_S / PERIOD_S) as usize;
        for k in 0..periods {
            // The motor over one period at `duty`: thesis RPM, wheel turns = RPM / 10 per s.
            let target = self.steady(duty / 255.0);
            let a = (-PERIOD_S / self.motor.tau_s).exp();
            let before = position.floor();
            position += (target * PERIOD_S + (speed - target) * self.motor.tau_s * (1.0 - a))
                / 10.0
                * self.counts_per_rev;
            speed = target + (speed - target) * a;
            peak = peak.max(speed);
            if (speed - self.setpoint).abs() > 0.1 * self.setpoint {
                last_out = Some(k);
            }
            let counts = position.floor() - before;
            let e = self.setpoint - counts * q;
            iterm += g.ki * PERIOD_S * e;
            let u = (g.kp + g.kd / PERIOD_S) * e - g.kd / PERIOD_S * prev_e + iterm;
            prev_e = e;
            duty = (127.5 + PWM_PER_UNIT * u).clamp(0.0, 255.0).floor();
            if duty == 0.0 && k >= START_PERIODS {
                zeros += 1;
            }
        }
        Predicted {
            duty_zero_periods: zeros,
            overshoot: (peak - self.setpoint).max(0.0) / self.setpoint,
            settling_s: match last_out {
                Some(k) if k + 1 >= periods => None,
                Some(k) => Some((k + 1) as f64 * PERIOD_S),
                None => Some(0.0),
            },
        }
    }

    fn steady(&self, duty: f64) -> f64 {
        let m = self.motor;
        let excess = (duty - m.dead_band_duty).max(0.0);
        m.gain_thesis_rpm * excess / (m.reference_duty - m.dead_band_duty) * self.volts
            / m.fit_voltage_v
    }
}

/// The duty the firmware holds at the start of a leg until its first tick.
const START_DUTY: u8 = 50;

/// The gains for `robot`, derived and checked on the loop model.
pub fn derive(robot: &RobotConfig) -> Result<Tuning, TuneError> {
    let counts_per_rev = robot.encoder.gear_ratio * robot.encoder.a_edges_per_motor_rev as f64;
    let factory = factory();
    let wheel = |i: usize| -> Result<WheelTuning, TuneError> {
        let (side, motor, p) = if i == 0 {
            ("left", &robot.motor.left, Param::SetpointLeft)
        } else {
            ("right", &robot.motor.right, Param::SetpointRight)
        };
        let motor = first_order(motor);
        let lp = Loop {
            motor,
            volts: robot.battery.voltage_v,
            counts_per_rev,
            setpoint: setpoint(robot, p),
        };
        let top = lp.steady(1.0);
        if top < lp.setpoint * 1.05 {
            return Err(TuneError::TooSlow {
                side,
                setpoint: lp.setpoint,
                top,
            });
        }
        // Thesis RPM per unit of U: the motor's slope per duty over the PWM's per U.
        let process_gain = lp.steady(1.0) - lp.steady(0.99);
        let process_gain = process_gain / 0.01 / 48.0;
        let l = ZN_DEAD_TIME_S;
        let kp = 1.2 * motor.tau_s / (process_gain * l);
        let zn = WheelGains {
            kp,
            ki: kp / (2.0 * l),
            kd: kp * l / 2.0,
        };
        let mut g = zn;
        let mut adjusted = Vec::new();
        let mut predicted = lp.run(g);
        let q = 10.0 / (PERIOD_S * counts_per_rev);
        if predicted.duty_zero_periods > 0 && g.kd > 0.0 {
            g.kd = 0.0;
            adjusted.push(format!(
                "Td dropped: one count's flicker ({q:.2} thesis RPM) moves the derivative term by \
                 {:.0} of 255 and chatters the duty to 0",
                2.0 * zn.kd / PERIOD_S * q * PWM_PER_UNIT
            ));
            predicted = lp.run(g);
        }
        let mut halvings = 0;
        while predicted.duty_zero_periods > 0 {
            if halvings == 8 {
                return Err(TuneError::NoGains {
                    side,
                    counts: lp.setpoint / q,
                });
            }
            g.kp /= 2.0;
            g.ki /= 2.0;
            halvings += 1;
            predicted = lp.run(g);
        }
        if halvings > 0 {
            adjusted.push(format!(
                "Kp and Ki halved {halvings} time(s): the duty still chattered to 0 on the loop model"
            ));
        }
        let steady = (motor.dead_band_duty
            + lp.setpoint / lp.steady(1.0) * (1.0 - motor.dead_band_duty))
            * 255.0;
        Ok(WheelTuning {
            process_gain,
            tau_s: motor.tau_s,
            setpoint_rpm: lp.setpoint,
            counts_per_period: lp.setpoint / q,
            steady_duty: steady,
            ziegler_nichols: zn,
            gains: WheelGains {
                kp: round(g.kp),
                ki: round(g.ki),
                kd: round(g.kd),
            },
            adjusted,
            factory_predicted: lp.run(factory[i]),
            predicted,
        })
    };
    Ok(Tuning {
        left: wheel(0)?,
        right: wheel(1)?,
    })
}

/// Whether `robot`'s config gives any PID gain.
pub fn gives_gains(robot: &RobotConfig) -> bool {
    GAINS.iter().any(|p| robot.firmware.contains_key(p.name()))
}

/// The PID gains' parameters.
pub const GAINS: [Param; 6] = [
    Param::KpLeft,
    Param::KiLeft,
    Param::KdLeft,
    Param::KpRight,
    Param::KiRight,
    Param::KdRight,
];

/// The gains to send instead of the factory's on `robot`: derived ones when
/// its config gives none and the factory gains are predicted to chatter; the
/// one-line note saying so. None for Henrytwo (the factory gains are kept).
pub fn automatic(robot: &RobotConfig) -> Option<(Vec<(Param, f32)>, String)> {
    if gives_gains(robot) {
        return None;
    }
    let t = derive(robot).ok()?;
    if !t.factory_chatters() {
        return None;
    }
    let [l, r] = [t.left.gains, t.right.gains];
    Some((
        t.params(),
        format!(
            "the factory PID gains are predicted to chatter the duty to 0 on this robot ({:.1} \
             counts per period at the set-point) and its config gives none: using derived gains \
             kp/ki/kd left {}/{}/{}, right {}/{}/{} (hil tune --robot FILE --write keeps them)",
            t.left.counts_per_period.min(t.right.counts_per_period),
            l.kp,
            l.ki,
            l.kd,
            r.kp,
            r.ki,
            r.kd
        ),
    ))
}

/// Prints `note` on stderr once per process: a command of many runs on one
/// robot says it once.
pub fn note_once(note: &str) {
    static SAID: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
    if !said.iter().any(|s| s == note) {
        eprintln!("note: {note}");
        said.push(note.to_string());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn robot(path: &str) -> RobotConfig {
        let p = crate::paths::workspace_root().join(path);
        plant_model::RobotConfig::from_toml_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    }

    /// The thesis' own rule on Henrytwo's motors, with the process gain left
    /// out (K = 1), gives the factory gains: the derivation is the thesis'.
    #[test]
    fn the_thesis_rule_without_the_process_gain_gives_the_factory_gains() {
        let zn = |tau: f64| {
            let kp = 1.2 * tau / ZN_DEAD_TIME_S;
            (kp, kp / (2.0 * ZN_DEAD_TIME_S), kp * ZN_DEAD_TIME_S / 2.0)
        };
        let f = factory();
        let (kp, ki, kd) = zn(0.0685);
        assert!((kp - f[1].kp).abs() < 1e-3 && (ki - f[1].ki).abs() < 0.01);
        assert!((kd - f[1].kd).abs() < 1e-4);
        let (kp, ki, kd) = zn(0.055);
        assert!((kp - f[0].kp).abs() < 1e-3 && (ki - f[0].ki).abs() < 0.01);
        assert!((kd - f[0].kd).abs() < 1e-4);
    }

    #[test]
    fn henrytwo_keeps_the_factory_gains() {
        for path in [
            "fixtures/robots/henrytwo.toml",
            "fixtures/robots/henrytwo-ideal.toml",
            "fixtures/robots/compact48.toml",
            "fixtures/robots/rover65.toml",
        ] {
            let r = robot(path);
            let t = derive(&r).unwrap();
            assert!(!t.factory_chatters(), "{path}: {t:#?}");
            assert_eq!(automatic(&r), None, "{path}");
        }
    }

    #[test]
    fn coarse65_gets_gains_that_do_not_chatter() {
        let r = robot("fixtures/robots/coarse65.toml");
        let t = derive(&r).unwrap();
        assert!(t.factory_chatters(), "{t:#?}");
        for w in t.wheels() {
            assert_eq!(w.predicted.duty_zero_periods, 0, "{w:#?}");
            assert!((w.counts_per_period - 7.8).abs() < 0.1, "{w:#?}");
            // 1.2 * 0.04 / (K * 0.03) with K = 60 / 0.7 / 48 = 1.786.
            assert!((w.process_gain - 1.7857).abs() < 1e-3, "{w:#?}");
            assert!((w.ziegler_nichols.kp - 0.896).abs() < 1e-3, "{w:#?}");
        }
        let (params, note) = automatic(&r).unwrap();
        assert_eq!(params.len(), 6);
        assert!(note.contains("predicted to chatter"), "{note}");
        // A config with gains of its own keeps them.
        let mut own = r.clone();
        own.firmware.insert("kp_left".into(), 1.0);
        assert_eq!(automatic(&own), None);
    }
}
