//! An `[[expect]]` of a scenario file: from which event, for how long, and
//! what must hold; its checks (the symbol of a `var` is checked against the
//! ELF when the run is set up, see [`super::eval::Watch::new`]).

use plant_model::Side;
use serde::Deserialize;

use super::load::check_time;

/// One expectation: `that` holds within `within_ms` of `after`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expectation {
    /// What the report calls it (default: `expect N`).
    #[serde(default)]
    pub name: Option<String>,
    #[serde(default)]
    pub after: Anchor,
    /// The window's length in robot milliseconds (None: to the end of the run).
    #[serde(default)]
    pub within_ms: Option<f64>,
    /// Hold at every point of the window, not only at one.
    #[serde(default)]
    pub throughout: bool,
    pub that: Condition,
}

/// The event a window opens at.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case", deny_unknown_fields)]
pub enum Anchor {
    /// The test's start command.
    #[default]
    Start,
    /// The run's last cycle.
    End,
    /// `s` of robot time since reset.
    Time {
        s: f64,
    },
    /// The file's `n`-th `[[fault]]` applied (1-based).
    Fault {
        n: usize,
    },
    LegStart {
        n: usize,
    },
    TurnStart {
        n: usize,
    },
}

impl Anchor {
    pub fn describe(&self) -> String {
        match self {
            Anchor::Start => "the start".into(),
            Anchor::End => "the end of the run".into(),
            Anchor::Time { s } => format!("{s} s"),
            Anchor::Fault { n } => format!("fault {n}"),
            Anchor::LegStart { n } => format!("the start of leg {n}"),
            Anchor::TurnStart { n } => format!("the start of turn {n}"),
        }
    }
}

/// Which way a UART pattern travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Sent by the firmware.
    #[default]
    Tx,
    /// Arrived at the firmware's receiver (the host's bytes).
    Rx,
}

/// Which motors a `motor` condition is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotorSides {
    Left,
    Right,
    Both,
}

impl MotorSides {
    pub fn sides(self) -> &'static [Side] {
        match self {
            MotorSides::Left => &[Side::Left],
            MotorSides::Right => &[Side::Right],
            MotorSides::Both => &[Side::Left, Side::Right],
        }
    }
}

/// A motor's state from its bridge inputs (as the DRV8833's `in1`, `in2`,
/// whatever the driver: see `bench/driver.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotorState {
    /// Not driven: coasting or braking.
    Off,
    /// Both inputs low: the outputs open.
    Coast,
    /// Not driven, braking part of the period.
    Brake,
    Forward,
    Reverse,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    High,
    Low,
}

/// How a firmware variable's bytes read (little-endian, as avr-gcc and
/// rustc lay them out); its size must be the symbol's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VarType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
    F32,
}

impl VarType {
    pub fn size(self) -> u64 {
        match self {
            VarType::U8 | VarType::I8 => 1,
            VarType::U16 | VarType::I16 => 2,
            VarType::U32 | VarType::I32 | VarType::F32 => 4,
        }
    }

    /// The values the type holds: (least, most, whole numbers only).
    pub fn range(self) -> (f64, f64, bool) {
        match self {
            VarType::U8 => (0.0, u8::MAX as f64, true),
            VarType::I8 => (i8::MIN as f64, i8::MAX as f64, true),
            VarType::U16 => (0.0, u16::MAX as f64, true),
            VarType::I16 => (i16::MIN as f64, i16::MAX as f64, true),
            VarType::U32 => (0.0, u32::MAX as f64, true),
            VarType::I32 => (i32::MIN as f64, i32::MAX as f64, true),
            VarType::F32 => (f32::MIN as f64, f32::MAX as f64, false),
        }
    }

    /// Its name in a scenario file.
    pub fn name(self) -> &'static str {
        match self {
            VarType::U8 => "u8",
            VarType::I8 => "i8",
            VarType::U16 => "u16",
            VarType::I16 => "i16",
            VarType::U32 => "u32",
            VarType::I32 => "i32",
            VarType::F32 => "f32",
        }
    }

    /// The value of `bytes` (the variable's, little-endian).
    pub fn value(self, b: [u8; 4]) -> f64 {
        match self {
            VarType::U8 => b[0] as f64,
            VarType::I8 => b[0] as i8 as f64,
            VarType::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            VarType::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            VarType::U32 => u32::from_le_bytes(b) as f64,
            VarType::I32 => i32::from_le_bytes(b) as f64,
            VarType::F32 => f32::from_le_bytes(b) as f64,
        }
    }
}

/// What must hold, tagged by `on` (the module docs' table).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(tag = "on", rename_all = "snake_case", deny_unknown_fields)]
pub enum Condition {
    Uart {
        #[serde(default)]
        usart: Option<u8>,
        #[serde(default)]
        text: Option<String>,
        #[serde(default)]
        bytes: Option<Vec<u8>>,
        #[serde(default)]
        dir: Direction,
    },
    Frame {
        #[serde(default)]
        usart: Option<u8>,
        id: u8,
        #[serde(default)]
        status: Option<u8>,
        #[serde(default)]
        data: Option<Vec<u8>>,
    },
    Motor {
        side: MotorSides,
        state: MotorState,
        #[serde(default)]
        duty_min: Option<f64>,
        #[serde(default)]
        duty_max: Option<f64>,
    },
    Pin {
        pin: String,
        level: Level,
    },
    Var {
        symbol: String,
        #[serde(rename = "type")]
        ty: VarType,
        #[serde(default)]
        eq: Option<f64>,
        #[serde(default)]
        ne: Option<f64>,
        #[serde(default)]
        min: Option<f64>,
        #[serde(default)]
        max: Option<f64>,
    },
    Pose {
        #[serde(default)]
        x_mm: Option<f64>,
        #[serde(default)]
        y_mm: Option<f64>,
        #[serde(default)]
        distance_mm: Option<f64>,
        #[serde(default)]
        heading_deg: Option<f64>,
        #[serde(default)]
        tol_mm: Option<f64>,
        #[serde(default)]
        tol_pct: Option<f64>,
        #[serde(default)]
        tol_deg: Option<f64>,
    },
}

/// The farthest a pose may be asked for: 100 km, the scenario's longest leg
/// a thousand times.
const MAX_MM: f64 = 1e8;

fn check_range(what: &str, v: f64, low: f64, high: f64, unit: &str) -> Result<(), String> {
    if v.is_finite() && (low..=high).contains(&v) {
        Ok(())
    } else {
        Err(format!("{what} = {v}: give {low} to {high}{unit}"))
    }
}

impl Expectation {
    /// Every value in its range; `faults` is the file's number of `[[fault]]`s.
    pub(super) fn validate(&self, faults: usize) -> Result<(), String> {
        match self.after {
            Anchor::Time { s } => check_time("after.s", s, false)?,
            Anchor::Fault { n } if n == 0 || n > faults => {
                return Err(format!(
                    "after fault n = {n}: give 1 to {faults} (the file's [[fault]]s, in order)"
                ))
            }
            Anchor::LegStart { n: 0 } | Anchor::TurnStart { n: 0 } => {
                return Err("after n = 0: legs and turns are counted from 1".into())
            }
            _ => {}
        }
        if let Some(w) = self.within_ms {
            check_time("within_ms (in s)", w / 1000.0, false)
                .map_err(|_| format!("within_ms = {w}: give 0 to 86400000 ms (one day)"))?;
        }
        if self.throughout && matches!(self.that, Condition::Uart { .. } | Condition::Frame { .. })
        {
            return Err(
                "throughout = true with bytes or a frame: they arrive once; drop throughout".into(),
            );
        }
        self.that.validate()
    }

    /// Its name in reports: its own, else `expect N` (1-based).
    pub fn label(&self, index: usize) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| format!("expect {}", index + 1))
    }
}

impl Condition {
    pub(crate) fn validate(&self) -> Result<(), String> {
        let usart = |u: &Option<u8>| match u {
            Some(n) if *n > 3 => Err(format!(
                "usart = {n}: give 0 to 3 (the ATmega2560's USARTs)"
            )),
            _ => Ok(()),
        };
        match self {
            Condition::Uart {
                usart: u,
                text,
                bytes,
                ..
            } => {
                usart(u)?;
                match (text, bytes) {
                    (Some(_), Some(_)) => Err("uart: give `text` or `bytes`, not both".into()),
                    (None, None) => Err("uart: give the pattern, as `text` or `bytes`".into()),
                    (Some(t), None) if t.is_empty() => {
                        Err("uart text = \"\": give at least one character".into())
                    }
                    (None, Some(b)) if b.is_empty() => {
                        Err("uart bytes = []: give at least one byte".into())
                    }
                    _ => Ok(()),
                }
            }
            Condition::Frame { usart: u, data, .. } => {
                usart(u)?;
                match data {
                    Some(d) if d.len() > 32 => Err(format!(
                        "frame data has {} bytes: a payload holds at most 32",
                        d.len()
                    )),
                    _ => Ok(()),
                }
            }
            Condition::Motor {
                duty_min, duty_max, ..
            } => {
                for (what, v) in [("duty_min", duty_min), ("duty_max", duty_max)] {
                    if let Some(v) = v {
                        check_range(what, *v, 0.0, 1.0, " (a fraction of the period)")?;
                    }
                }
                match (duty_min, duty_max) {
                    (Some(lo), Some(hi)) if lo > hi => Err(format!(
                        "duty_min = {lo} is above duty_max = {hi}: no duty is both"
                    )),
                    _ => Ok(()),
                }
            }
            Condition::Pin { pin, .. } => {
                // Scenarios run the robust firmware, a build for the Mega.
                let mega = crate::board::Mcu::Atmega2560;
                crate::board::pin_named(mega, pin)
                    .map(|_| ())
                    .ok_or_else(|| {
                        format!("pin = {pin:?}: give an Arduino Mega pin, D0-D69 or A0-A15")
                    })
            }
            Condition::Var {
                symbol,
                ty,
                eq,
                ne,
                min,
                max,
            } => {
                if symbol.is_empty() {
                    return Err("var symbol = \"\": give the variable's ELF symbol".into());
                }
                let given = [("eq", eq), ("ne", ne), ("min", min), ("max", max)];
                if given.iter().all(|(_, v)| v.is_none()) {
                    return Err(format!(
                        "var {symbol}: give what it must be, with eq, ne, min or max"
                    ));
                }
                for (what, v) in given {
                    if let Some(v) = v.filter(|v| !v.is_finite()) {
                        return Err(format!("var {symbol} {what} = {v}: give a finite number"));
                    }
                }
                // A value the type cannot hold makes the condition always
                // false (eq = 300 on a u8) or always true (ne = 300): either
                // way the expectation tests nothing.
                let (low, high, whole) = ty.range();
                for (what, v) in given {
                    let Some(v) = *v else { continue };
                    if !(low..=high).contains(&v) || (whole && v.fract() != 0.0) {
                        let kind = if whole { "whole numbers " } else { "" };
                        return Err(format!(
                            "var {symbol} {what} = {v}: a {} holds {kind}{low} to {high}",
                            ty.name()
                        ));
                    }
                }
                Ok(())
            }
            Condition::Pose {
                x_mm,
                y_mm,
                distance_mm,
                heading_deg,
                tol_mm,
                tol_pct,
                tol_deg,
            } => {
                for (what, v, low) in [
                    ("x_mm", x_mm, -MAX_MM),
                    ("y_mm", y_mm, -MAX_MM),
                    ("distance_mm", distance_mm, 0.0),
                    ("heading_deg", heading_deg, -3600.0),
                ] {
                    if let Some(v) = v {
                        let high = if what == "heading_deg" {
                            3600.0
                        } else {
                            MAX_MM
                        };
                        check_range(what, *v, low, high, "")?;
                    }
                }
                if let Some(v) = tol_mm {
                    check_range("tol_mm", *v, 0.0, MAX_MM, " mm")?;
                }
                if let Some(v) = tol_pct {
                    check_range("tol_pct", *v, 0.0, 100.0, " %")?;
                }
                if let Some(v) = tol_deg {
                    check_range("tol_deg", *v, 0.0, 360.0, " degrees")?;
                }
                let lengths = x_mm.is_some() || y_mm.is_some() || distance_mm.is_some();
                if lengths == (tol_mm.is_some() || tol_pct.is_some()) && lengths {
                    if tol_mm.is_some() && tol_pct.is_some() {
                        return Err("pose: give tol_mm or tol_pct, not both".into());
                    }
                } else if lengths {
                    return Err(
                        "pose: give the tolerance of x_mm, y_mm, distance_mm as tol_mm or tol_pct"
                            .into(),
                    );
                } else if tol_mm.is_some() || tol_pct.is_some() {
                    return Err("pose: tol_mm or tol_pct without x_mm, y_mm or distance_mm".into());
                }
                if heading_deg.is_some() != tol_deg.is_some() {
                    return Err("pose: give heading_deg and tol_deg together".into());
                }
                if !lengths && heading_deg.is_none() {
                    return Err("pose: give x_mm, y_mm, distance_mm or heading_deg".into());
                }
                Ok(())
            }
        }
    }
}
