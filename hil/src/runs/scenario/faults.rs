//! A `[[fault]]` of a scenario file: when, what, for how long, and its checks.

use serde::Deserialize;

use super::load::check_time;
use crate::bench::inject::{EncoderFault, LinkFault};
use crate::bench::{Action, ScheduledFault, Trigger};

/// One fault of a scenario file.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultEntry {
    pub trigger: Trigger,
    pub action: Action,
    /// How long the fault lasts; without `undo`, the bench ends it with the
    /// action's healthy counterpart.
    #[serde(default)]
    pub duration_s: Option<f64>,
    #[serde(default)]
    pub undo: Option<Action>,
}

impl FaultEntry {
    pub(super) fn scheduled(&self) -> ScheduledFault {
        let undo = self.duration_s.map(|d| {
            let a = self
                .undo
                .clone()
                .or_else(|| healthy(&self.action))
                .expect("validated: a duration has an undo");
            (d, a)
        });
        ScheduledFault {
            trigger: self.trigger,
            action: self.action.clone(),
            undo,
        }
    }

    pub(super) fn validate(&self) -> Result<(), String> {
        match self.trigger {
            Trigger::Time { s } => check_time("trigger.s", s, false)?,
            Trigger::TurnStart { n: 0 }
            | Trigger::LegStart { n: 0 }
            | Trigger::HostByte { n: 0 } => {
                return Err("trigger n = 0: events are counted from 1".into())
            }
            _ => {}
        }
        check_action(&self.action)?;
        if let Some(a) = &self.undo {
            check_action(a).map_err(|e| format!("undo: {e}"))?;
            if self.duration_s.is_none() {
                return Err("`undo` without `duration_s`: say how long the fault lasts".into());
            }
        }
        if let Some(d) = self.duration_s {
            check_time("duration_s", d, true)?;
            if self.undo.is_none() && healthy(&self.action).is_none() {
                return Err(format!(
                    "`{}` has no healthy state to return to: drop duration_s, or give `undo`",
                    self.action.name()
                ));
            }
        }
        Ok(())
    }
}

/// The action that ends `a`'s fault, when it has one.
fn healthy(a: &Action) -> Option<Action> {
    Some(match a {
        Action::Encoder { side, .. } => Action::Encoder {
            side: *side,
            fault: EncoderFault::Healthy,
        },
        Action::Link { .. } => Action::Link {
            fault: LinkFault::default(),
        },
        Action::MotorDisconnected { side, .. } => Action::MotorDisconnected {
            side: *side,
            disconnected: false,
        },
        Action::Motor { side, .. } => Action::Motor {
            side: *side,
            fault: plant_model::MotorFault::None,
        },
        Action::SlipBurst { side, .. } => Action::SlipBurst {
            side: *side,
            slip: 0.0,
        },
        Action::BatteryVolts { .. } => Action::BatteryVolts { volts: None },
        Action::Reset | Action::EncoderGlitch { .. } | Action::HostSend { .. } => return None,
    })
}

fn check_action(a: &Action) -> Result<(), String> {
    let unit = |what: &str, p: f64| {
        if (0.0..=1.0).contains(&p) {
            Ok(())
        } else {
            Err(format!("{what} = {p}: give a probability from 0 to 1"))
        }
    };
    match a {
        Action::Encoder {
            fault: EncoderFault::MissPairs { every },
            ..
        } if *every < 2 => Err(format!(
            "miss_pairs every = {every}: give 2 or more (every n-th edge and the next are lost)"
        )),
        Action::Link { fault } => {
            unit("link loss", fault.loss)?;
            unit("link corrupt", fault.corrupt)?;
            unit("link garbage", fault.garbage)
        }
        Action::Motor { fault, .. } => fault.validate().map_err(|e| e.to_string()),
        Action::SlipBurst { slip, .. } if !(0.0..1.0).contains(slip) => Err(format!(
            "slip = {slip}: give a fraction from 0 up to (not including) 1"
        )),
        Action::BatteryVolts { volts: Some(v) } if !(v.is_finite() && (0.0..=20.0).contains(v)) => {
            Err(format!("battery volts = {v}: give 0 to 20 V"))
        }
        Action::EncoderGlitch {
            pulses,
            width_us,
            period_us,
            ..
        } => {
            if !(1..=100_000).contains(pulses) {
                Err(format!("glitch pulses = {pulses}: give 1 to 100000"))
            } else if !(width_us.is_finite() && *width_us > 0.0) {
                Err(format!(
                    "glitch width_us = {width_us}: give a positive width"
                ))
            } else if !(period_us.is_finite() && *period_us <= 1e6) {
                Err(format!(
                    "glitch period_us = {period_us}: give at most 1000000 (one pulse a second)"
                ))
            } else if period_us <= width_us {
                Err(format!(
                    "glitch period_us = {period_us}: give more than width_us ({width_us})"
                ))
            } else {
                Ok(())
            }
        }
        Action::HostSend { bytes } if bytes.is_empty() => {
            Err("host_send with no bytes: give at least one".into())
        }
        _ => Ok(()),
    }
}
