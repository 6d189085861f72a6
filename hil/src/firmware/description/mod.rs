//! Firmware that knows nothing of the bench, run black-box: a test
//! description (a TOML file, docs/reference/test-description.md) says how the
//! firmware is ready after reset, how each test starts (bytes on a USART, or
//! a pin held at a level) and how it ends (the motors idle for a time, a
//! text on a USART, a time limit), and, where the user has them, which of
//! the firmware's variables hold the wheel counts and the leg length and
//! which function is the control loop (for `hil timing`).
//!
//! Everything else comes from outside the firmware, as on a real floor:
//! legs and turns from the H-bridge inputs (debounced: a level shorter than
//! a PWM period is no cut-off), distances and angles from the plant. The
//! bench's own builds carry their interface in `HT_` variables
//! ([`crate::firmware::vars`]); a description is the same knowledge for a firmware
//! that has none.
//!
//! | file | part |
//! |---|---|
//! | `file.rs` | the TOML schema and its checks ([`DescriptionError`]) |
//! | `name.rs` | [`TestName`] (a thesis test or the firmware's own) and [`Shape`] |
//!
//! A run from a description is the experiment's (`crate::runs::experiment`,
//! `described.rs`): this module knows the file, not the bench.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::firmware::elf::{ElfError, Firmware};

mod file;
mod name;

pub use file::DescriptionError;
pub use name::{Shape, TestName, MAX_NAME_LEN};

/// A checked test description (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Description {
    /// The file it was read from, for messages.
    pub path: String,
    /// The firmware's name in reports (default: the ELF's file name).
    pub name: Option<String>,
    /// The ELF it describes, when the file names one (relative to the file).
    pub elf: Option<PathBuf>,
    pub ready: Ready,
    pub leg: Leg,
    /// What ends a test that has no end of its own.
    pub end: End,
    pub symbols: Symbols,
    pub tests: BTreeMap<TestName, DescribedTest>,
}

/// One test of the firmware's: how it starts, and optionally its own end
/// and the shape it drives.
#[derive(Debug, Clone, PartialEq)]
pub struct DescribedTest {
    pub start: Start,
    /// In place of the description's [`Description::end`].
    pub end: Option<End>,
    /// What it drives; a run that drives otherwise does not pass. None: a
    /// thesis test's name lends its shape (its fragments only warned), a
    /// test of the firmware's own is not judged by its shape.
    pub shape: Option<Shape>,
}

/// When the firmware is ready for a test after reset.
#[derive(Debug, Clone, PartialEq)]
pub struct Ready {
    /// Robot time after reset (or, with `text`, the most to wait for it).
    pub after_s: f64,
    /// A text the firmware sends when it is ready.
    pub text: Option<UartText>,
}

/// The leg length of the firmware's tests.
#[derive(Debug, Clone, PartialEq)]
pub enum Leg {
    /// Fixed in the firmware (the thesis sketch's printed 400 mm).
    Fixed(f64),
    /// A `float` variable the bench writes before each start.
    Variable(String),
}

/// What ends a test.
#[derive(Debug, Clone, PartialEq)]
pub struct End {
    /// The motors undriven this long, after they were driven.
    pub idle_s: f64,
    /// Robot time allowed from the start (default: from the test's shape).
    pub limit_s: Option<f64>,
    /// A text the firmware sends at the end (then the test ends there).
    pub text: Option<UartText>,
}

/// The serial channel number of the MCU's USB serial (`uart = "usb"`), after
/// USART 0-3.
pub const USB_SERIAL: u8 = 4;

/// Bytes on a serial link.
#[derive(Debug, Clone, PartialEq)]
pub struct UartText {
    /// USART 0-3, or [`USB_SERIAL`].
    pub usart: u8,
    pub text: Vec<u8>,
}

/// How a test starts.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// The host sends `bytes` to USART `usart` (or the USB serial, [`USB_SERIAL`]).
    Uart { usart: u8, bytes: Vec<u8> },
    /// The bench holds `pin` at a level (a button, a jumper) from the start
    /// to the end of the test: its name (`"D30"`, `"PE2"`), a pin of the
    /// board's MCU (resolved when the board is known).
    Pin { pin: String, high: bool },
}

/// The firmware's own names for what the bench may read, all optional.
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Symbols {
    /// 32-bit signed wheel counters.
    pub left_count: Option<String>,
    pub right_count: Option<String>,
    /// The control function, for `hil timing` (its ELF name; a C++
    /// function's plain name finds its mangled one).
    pub control: Option<String>,
}

/// The description's names as data-space addresses in one ELF.
#[derive(Debug, Clone, Copy, Default)]
pub struct Resolved {
    pub counts: Option<[u16; 2]>,
    pub leg: Option<u16>,
}

impl Description {
    /// Read and check `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, DescriptionError> {
        let path = path.as_ref();
        let text = input_file::read_text(path).map_err(|source| DescriptionError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        file::parse(&text, &path.display().to_string(), dir)
    }

    /// Parse `text` as if read from `path` (for tests and embedded files).
    pub fn from_toml_str(text: &str, path: &str) -> Result<Self, DescriptionError> {
        file::parse(text, path, Path::new("."))
    }

    /// `test` as described, or why it cannot run.
    pub fn test(&self, test: impl Into<TestName>) -> Result<&DescribedTest, DescriptionError> {
        let test = test.into();
        self.tests.get(&test).ok_or_else(|| {
            let names: Vec<&str> = self.tests.keys().map(|t| t.name()).collect();
            DescriptionError::Field {
                path: self.path.clone(),
                field: "tests".into(),
                value: format!("[{}]", names.join(", ")),
                allowed: format!("describes no {} test", test.name()),
            }
        })
    }

    /// The first field that names the USB serial (`"ready.uart"`), if any:
    /// a run on an MCU without USB refuses the description naming it.
    pub fn usb_field(&self) -> Option<String> {
        let on_usb = |t: &Option<UartText>| t.as_ref().is_some_and(|t| t.usart == USB_SERIAL);
        if on_usb(&self.ready.text) {
            return Some("ready.uart".into());
        }
        if on_usb(&self.end.text) {
            return Some("end.uart".into());
        }
        self.tests
            .iter()
            .find_map(|(name, t)| match (&t.start, &t.end) {
                (Start::Uart { usart, .. }, _) if *usart == USB_SERIAL => {
                    Some(format!("tests.{name}.uart"))
                }
                (_, Some(e)) if on_usb(&e.text) => Some(format!("tests.{name}.end.uart")),
                _ => None,
            })
    }

    /// Refuses a description that names the USB serial for an MCU without
    /// USB, in one line naming the field and the MCU's USARTs.
    pub fn check_usb(&self, mcu: crate::board::Mcu) -> Result<(), String> {
        match self.usb_field() {
            Some(field) if mcu.chip().usb.is_none() => Err(format!(
                "{}: {field} = \"usb\": the board's {mcu} has no USB; give one of its USARTs ({})",
                self.path,
                mcu.chip()
                    .usarts
                    .iter()
                    .map(|u| u.n.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
            _ => Ok(()),
        }
    }

    /// How `test` starts, or why it cannot run.
    pub fn start(&self, test: impl Into<TestName>) -> Result<&Start, DescriptionError> {
        self.test(test).map(|t| &t.start)
    }

    /// What ends `test`: its own end, else the description's.
    pub fn end_of(&self, test: &TestName) -> &End {
        self.tests
            .get(test)
            .and_then(|t| t.end.as_ref())
            .unwrap_or(&self.end)
    }

    /// The leg length a run uses: the firmware's own when fixed (a
    /// different `asked` is an error: the firmware cannot be told), else
    /// `asked`, else `default_mm`.
    pub fn leg_mm(&self, asked: Option<f64>, default_mm: f64) -> Result<f64, DescriptionError> {
        match (&self.leg, asked) {
            (Leg::Fixed(mm), Some(a)) if (a - mm).abs() > 1e-9 => Err(DescriptionError::Field {
                path: self.path.clone(),
                field: "leg.mm".into(),
                value: format!("{mm}"),
                allowed: format!(
                    "the firmware's legs are {mm} mm and it cannot be told {a} mm (name its leg variable, leg.variable, to set it)"
                ),
            }),
            (Leg::Fixed(mm), _) => Ok(*mm),
            (Leg::Variable(_), a) => Ok(a.unwrap_or(default_mm)),
        }
    }

    /// The firmware's name in reports: the file's `firmware.name`, else the
    /// ELF's.
    pub fn firmware_name(&self, firmware: &Firmware) -> String {
        self.name.clone().unwrap_or_else(|| firmware.name())
    }

    /// The named variables in `firmware` (each must exist, with its size).
    pub fn resolve(&self, firmware: &Firmware) -> Result<Resolved, DescriptionError> {
        let var = |field: &str, name: &str, size: u64| {
            firmware
                .variable(name, size)
                .map_err(|e| self.symbol_error(field, name, e))
        };
        let s = &self.symbols;
        let counts = match (&s.left_count, &s.right_count) {
            (Some(l), Some(r)) => Some([
                var("symbols.left_count", l, 4)?,
                var("symbols.right_count", r, 4)?,
            ]),
            (None, None) => None,
            (Some(l), None) | (None, Some(l)) => {
                return Err(DescriptionError::Field {
                    path: self.path.clone(),
                    field: "symbols".into(),
                    value: format!("{l:?}"),
                    allowed: "name both wheel counters (left_count and right_count) or neither"
                        .into(),
                })
            }
        };
        let leg = match &self.leg {
            Leg::Variable(name) => Some(var("leg.variable", name, 4)?),
            Leg::Fixed(_) => None,
        };
        Ok(Resolved { counts, leg })
    }

    /// The control function's ELF name in `firmware`, when the description
    /// names one.
    pub fn control_function(
        &self,
        firmware: &Firmware,
    ) -> Option<Result<String, DescriptionError>> {
        let name = self.symbols.control.as_ref()?;
        Some(
            firmware
                .function_named(name)
                .map(str::to_owned)
                .ok_or_else(|| DescriptionError::Field {
                    path: self.path.clone(),
                    field: "symbols.control".into(),
                    value: format!("{name:?}"),
                    allowed: "the firmware has no such function".into(),
                }),
        )
    }

    fn symbol_error(&self, field: &str, name: &str, e: ElfError) -> DescriptionError {
        DescriptionError::Field {
            path: self.path.clone(),
            field: field.into(),
            value: format!("{name:?}"),
            allowed: e.to_string(),
        }
    }
}

#[cfg(test)]
mod tests;
