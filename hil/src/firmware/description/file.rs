//! The test-description file (TOML; documented in docs/reference/test-description.md)
//! and its checks: each field against what the bench and the MCU allow,
//! one line per problem naming the file, the field and the allowed range.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use thiserror::Error;

use super::{
    DescribedTest, Description, End, Ready, Shape, Start, Symbols, TestName, UartText, USB_SERIAL,
};
use crate::board::{pin_named, Mcu};

#[derive(Debug, Error)]
pub enum DescriptionError {
    #[error("cannot read test description {path}: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Toml { path: String, message: String },
    #[error("{path}: {field} = {value}: {allowed}")]
    Field {
        path: String,
        field: String,
        value: String,
        allowed: String,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    #[serde(default)]
    firmware: FirmwareDoc,
    #[serde(default)]
    ready: ReadyDoc,
    leg: LegDoc,
    #[serde(default)]
    end: EndDoc,
    #[serde(default)]
    symbols: Symbols,
    tests: BTreeMap<String, StartDoc>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct FirmwareDoc {
    name: Option<String>,
    elf: Option<PathBuf>,
}

/// A serial link as a description names it: a USART's number, or "usb"
/// for the MCU's USB serial.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
enum UartDoc {
    Usart(i64),
    Name(String),
}

impl std::fmt::Display for UartDoc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UartDoc::Usart(n) => write!(f, "{n}"),
            UartDoc::Name(s) => write!(f, "{s:?}"),
        }
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ReadyDoc {
    after_s: Option<f64>,
    uart: Option<UartDoc>,
    text: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LegDoc {
    mm: Option<f64>,
    variable: Option<String>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct EndDoc {
    idle_s: Option<f64>,
    limit_s: Option<f64>,
    uart: Option<UartDoc>,
    text: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StartDoc {
    uart: Option<UartDoc>,
    bytes: Option<Vec<u8>>,
    text: Option<String>,
    pin: Option<String>,
    level: Option<String>,
    /// This test's own end, in place of the file's `[end]`.
    end: Option<EndDoc>,
    /// What the test drives; a run that drives otherwise fails.
    shape: Option<ShapeDoc>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ShapeDoc {
    legs: usize,
    #[serde(default)]
    turns: usize,
    turn_deg: Option<f64>,
    leg_mm: Option<f64>,
}

/// The bench's default wait after reset when the file gives none: the
/// Arduino core's start-up plus a sketch's `setup()` delays.
const DEFAULT_READY_S: f64 = 1.0;
/// The default quiet time that ends a test: above the thesis' 2.025 s of
/// braking and waits between two segments.
const DEFAULT_IDLE_S: f64 = 3.0;

/// A number as a person would write it: 1e300, not 300 digits.
fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

struct Checker<'a> {
    path: &'a str,
}

impl Checker<'_> {
    fn field(&self, field: &str, value: impl std::fmt::Display, allowed: &str) -> DescriptionError {
        DescriptionError::Field {
            path: self.path.to_string(),
            field: field.to_string(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }

    fn seconds(&self, field: &str, v: f64, min: f64, max: f64) -> Result<f64, DescriptionError> {
        if v.is_finite() && v >= min && v <= max {
            Ok(v)
        } else {
            Err(self.field(
                field,
                number(v),
                &format!("give {min} to {max} s of robot time"),
            ))
        }
    }

    /// The serial channel: USART 0-3 (the board's MCU may have fewer,
    /// checked at the run), or "usb", the USB serial ([`USB_SERIAL`]).
    fn usart(&self, field: &str, u: &UartDoc) -> Result<u8, DescriptionError> {
        match u {
            UartDoc::Usart(n @ 0..=3) => Ok(*n as u8),
            UartDoc::Name(s) if s == "usb" => Ok(USB_SERIAL),
            _ => Err(self.field(
                field,
                u,
                "give a USART, 0-3, or \"usb\" (the USB serial of an MCU with USB)",
            )),
        }
    }

    fn text(&self, field: &str, t: &str) -> Result<Vec<u8>, DescriptionError> {
        if t.is_empty() || t.len() > 64 {
            return Err(self.field(field, format!("{t:?}"), "give 1 to 64 bytes"));
        }
        Ok(t.as_bytes().to_vec())
    }

    fn uart_text(
        &self,
        section: &str,
        uart: &Option<UartDoc>,
        text: &Option<String>,
    ) -> Result<Option<UartText>, DescriptionError> {
        match (uart, text) {
            (None, None) => Ok(None),
            (Some(u), Some(t)) => Ok(Some(UartText {
                usart: self.usart(&format!("{section}.uart"), u)?,
                text: self.text(&format!("{section}.text"), t)?,
            })),
            (Some(u), None) => Err(self.field(
                &format!("{section}.uart"),
                u,
                "give the text to wait for too (text = \"...\")",
            )),
            (None, Some(t)) => Err(self.field(
                &format!("{section}.text"),
                format!("{t:?}"),
                "give the link it comes on too (uart = 0-3 or \"usb\")",
            )),
        }
    }

    fn end(&self, section: &str, d: &EndDoc) -> Result<End, DescriptionError> {
        Ok(End {
            idle_s: self.seconds(
                &format!("{section}.idle_s"),
                d.idle_s.unwrap_or(DEFAULT_IDLE_S),
                0.05,
                60.0,
            )?,
            limit_s: d
                .limit_s
                .map(|s| self.seconds(&format!("{section}.limit_s"), s, 1.0, 3600.0))
                .transpose()?,
            text: self.uart_text(section, &d.uart, &d.text)?,
        })
    }

    fn shape(&self, test: &TestName, d: &ShapeDoc) -> Result<Shape, DescriptionError> {
        let f = |k: &str| format!("tests.{test}.shape.{k}");
        if let TestName::Thesis(t) = test {
            let (legs, turns, deg) = t.shape();
            return Err(self.field(
                &format!("tests.{test}.shape"),
                "...",
                &format!(
                    "{test} is the thesis' test: {legs} legs, {turns} turns of {deg:+} deg; \
                     give the test another name to give it a shape of its own"
                ),
            ));
        }
        if !(1..=100).contains(&d.legs) {
            return Err(self.field(&f("legs"), d.legs, "give 1 to 100 legs"));
        }
        if d.turns > d.legs {
            return Err(self.field(
                &f("turns"),
                d.turns,
                &format!("give 0 to {} turns (one after each leg at most)", d.legs),
            ));
        }
        let turn_deg = match (d.turns, d.turn_deg) {
            (0, None) => 0.0,
            (0, Some(a)) => {
                return Err(self.field(
                    &f("turn_deg"),
                    number(a),
                    "a shape without turns has no turn angle",
                ))
            }
            (_, Some(a)) if a.is_finite() && a != 0.0 && a.abs() <= 360.0 => a,
            (_, a) => {
                return Err(self.field(
                    &f("turn_deg"),
                    a.map_or("(none)".into(), number),
                    "give each turn's angle, -360 to 360 deg but not 0 (positive: to the left)",
                ))
            }
        };
        let leg_mm = match d.leg_mm {
            None => None,
            Some(mm) => {
                let r = crate::firmware::link::Param::LegLengthMm.range();
                if !(mm.is_finite() && mm >= r.min as f64 && mm <= r.max as f64) {
                    return Err(self.field(
                        &f("leg_mm"),
                        number(mm),
                        &format!("give {} to {} mm", r.min, r.max),
                    ));
                }
                Some(mm)
            }
        };
        Ok(Shape {
            legs: d.legs,
            turns: d.turns,
            turn_deg,
            leg_mm,
        })
    }

    fn start(&self, name: &str, d: &StartDoc) -> Result<Start, DescriptionError> {
        let f = |k: &str| format!("tests.{name}.{k}");
        match (&d.uart, &d.pin) {
            (Some(u), None) => {
                let usart = self.usart(&f("uart"), u)?;
                let bytes = match (&d.bytes, &d.text) {
                    (Some(b), None) if !b.is_empty() && b.len() <= 64 => b.clone(),
                    (Some(b), None) => {
                        return Err(self.field(&f("bytes"), format!("{b:?}"), "give 1 to 64 bytes"))
                    }
                    (None, Some(t)) => self.text(&f("text"), t)?,
                    _ => {
                        return Err(self.field(
                            &f("uart"),
                            u,
                            "give what is sent: bytes = [...] or text = \"...\" (one of them)",
                        ))
                    }
                };
                if d.level.is_some() {
                    return Err(self.field(
                        &f("level"),
                        "...",
                        "a pin level goes with pin, not uart",
                    ));
                }
                Ok(Start::Uart { usart, bytes })
            }
            (None, Some(p)) => {
                // The board's MCU is known at the run; a name no MCU has is
                // refused now.
                if !Mcu::ALL.iter().any(|&m| pin_named(m, p).is_some()) {
                    return Err(self.field(
                        &f("pin"),
                        format!("{p:?}"),
                        "give a pin of the board's MCU: \"D<n>\", \"A<n>\" or \"P<port><bit>\"",
                    ));
                }
                let pin = p.clone();
                let high = match d.level.as_deref() {
                    Some("high") => true,
                    Some("low") => false,
                    other => {
                        return Err(self.field(
                            &f("level"),
                            format!("{other:?}"),
                            "give \"low\" or \"high\" (the level the bench holds the pin at)",
                        ))
                    }
                };
                if d.bytes.is_some() || d.text.is_some() {
                    return Err(self.field(
                        &f("pin"),
                        format!("{p:?}"),
                        "bytes and text go with uart, not pin",
                    ));
                }
                Ok(Start::Pin { pin, high })
            }
            _ => Err(self.field(
                &format!("tests.{name}"),
                "...",
                "say how the test starts: uart = 0-3 or \"usb\" with bytes or text, or pin with level",
            )),
        }
    }
}

/// Parse and check a description; relative paths in it are relative to
/// `dir` (the file's folder).
pub(super) fn parse(text: &str, path: &str, dir: &Path) -> Result<Description, DescriptionError> {
    let doc: FileDoc = toml::from_str(text).map_err(|e| DescriptionError::Toml {
        path: path.to_string(),
        message: e.message().to_string()
            + &e.span()
                .map(|s| format!(" (line {})", text[..s.start].lines().count().max(1)))
                .unwrap_or_default(),
    })?;
    let c = Checker { path };
    let ready = Ready {
        after_s: c.seconds(
            "ready.after_s",
            doc.ready.after_s.unwrap_or(DEFAULT_READY_S),
            0.0,
            60.0,
        )?,
        text: c.uart_text("ready", &doc.ready.uart, &doc.ready.text)?,
    };
    let leg_mm = match (doc.leg.mm, &doc.leg.variable) {
        (Some(mm), None) => {
            let r = crate::firmware::link::Param::LegLengthMm.range();
            if !(mm.is_finite() && mm >= r.min as f64 && mm <= r.max as f64) {
                return Err(c.field("leg.mm", number(mm), &format!("give {} to {} mm", r.min, r.max)));
            }
            super::Leg::Fixed(mm)
        }
        (None, Some(v)) if !v.is_empty() => super::Leg::Variable(v.clone()),
        _ => {
            return Err(c.field(
                "leg",
                "...",
                "give the firmware's own leg (mm = ...) or the float variable the bench sets (variable = \"...\"), one of them",
            ))
        }
    };
    let end = c.end("end", &doc.end)?;
    if doc.tests.is_empty() {
        return Err(c.field(
            "tests",
            "{}",
            "describe at least one test ([tests.umbmark-cw], [tests.my-test], ...)",
        ));
    }
    let mut tests = BTreeMap::new();
    for (name, d) in &doc.tests {
        let test =
            TestName::parse(name).map_err(|why| c.field(&format!("tests.{name}"), "...", &why))?;
        let described = DescribedTest {
            start: c.start(name, d)?,
            end: match &d.end {
                Some(e) => Some(c.end(&format!("tests.{name}.end"), e)?),
                None => None,
            },
            shape: match &d.shape {
                Some(s) => Some(c.shape(&test, s)?),
                None => None,
            },
        };
        tests.insert(test, described);
    }
    Ok(Description {
        path: path.to_string(),
        name: doc.firmware.name,
        elf: doc.firmware.elf.map(|p| lexically_normal(&dir.join(p))),
        ready,
        leg: leg_mm,
        end,
        symbols: doc.symbols,
        tests,
    })
}

/// `path` without `.` and `dir/..` pairs (the ELF named relative to the
/// description reads as the path a person would give).
fn lexically_normal(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out.iter().collect()
}
