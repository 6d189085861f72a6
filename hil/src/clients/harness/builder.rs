//! [`HarnessBuilder`]: a bench from a robot, a board, an ELF and a test
//! description, each given as a file or as a value already in hand.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use plant_model::RobotConfig;

use super::{Harness, HarnessError};
use crate::bench::{Bench, BenchOptions};
use crate::board::Board;
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;

/// One input of a [`HarnessBuilder`]: a file to read when the harness is
/// built, or the value itself (a robot config edited in the test, a board
/// built in code, a description parsed from a string).
///
/// Made by `From`, so each builder method takes either: a path
/// (`&str`, `String`, `&Path`, `PathBuf`) or the value (`RobotConfig`,
/// `Board`, `Firmware`, `Description`).
#[derive(Debug, Clone)]
pub enum Source<T> {
    File(PathBuf),
    Value(T),
}

macro_rules! sources {
    ($($t:ty),*) => {$(
        impl From<$t> for Source<$t> {
            fn from(value: $t) -> Self {
                Source::Value(value)
            }
        }
        impl From<PathBuf> for Source<$t> {
            fn from(path: PathBuf) -> Self {
                Source::File(path)
            }
        }
        impl From<&PathBuf> for Source<$t> {
            fn from(path: &PathBuf) -> Self {
                Source::File(path.clone())
            }
        }
        impl From<&Path> for Source<$t> {
            fn from(path: &Path) -> Self {
                Source::File(path.to_path_buf())
            }
        }
        impl From<&str> for Source<$t> {
            fn from(path: &str) -> Self {
                Source::File(path.into())
            }
        }
        impl From<String> for Source<$t> {
            fn from(path: String) -> Self {
                Source::File(path.into())
            }
        }
    )*};
}
sources!(RobotConfig, Board, Firmware, Description);

impl<T> Source<T> {
    /// The value, read from its file with `load` when it is one.
    fn get<E>(self, load: impl FnOnce(&Path) -> Result<T, E>) -> Result<T, E> {
        match self {
            Source::File(path) => load(&path),
            Source::Value(v) => Ok(v),
        }
    }
}

/// What a [`Harness`] is built from; [`Harness::builder`] starts one.
/// Only the firmware is required, and a description that names its ELF
/// gives it.
#[derive(Debug, Clone, Default)]
pub struct HarnessBuilder {
    robot: Option<Source<RobotConfig>>,
    board: Option<Source<Board>>,
    firmware: Option<Source<Firmware>>,
    tests: Option<Source<Description>>,
    seed: u64,
}

impl HarnessBuilder {
    /// The robot: a config TOML's path, or a [`RobotConfig`] (the plant:
    /// motors, wheels, encoders, effects; the ranges are listed in
    /// `fixtures/robots/henrytwo-ideal.toml`). Default:
    /// `fixtures/robots/henrytwo.toml`, the thesis robot.
    pub fn robot(mut self, robot: impl Into<Source<RobotConfig>>) -> Self {
        self.robot = Some(robot.into());
        self
    }

    /// The board: a board TOML's path, or a [`Board`] (which MCU pin each
    /// part is on, the motor driver, the links' USARTs). Default:
    /// Henrytwo's ([`crate::board::HENRYTWO`]).
    pub fn board(mut self, board: impl Into<Source<Board>>) -> Self {
        self.board = Some(board.into());
        self
    }

    /// The firmware: an ELF's path (built for the board's MCU), or a loaded
    /// [`Firmware`]; e.g. [`crate::paths::firmware_elf`]`("robust")` for
    /// this repository's. Default: the ELF the test description names.
    pub fn firmware(mut self, elf: impl Into<Source<Firmware>>) -> Self {
        self.firmware = Some(elf.into());
        self
    }

    /// The test description of a firmware without the bench interface (an
    /// Arduino sketch, your own C): a TOML's path or a [`Description`]
    /// (`docs/reference/test-description.md`). With it,
    /// [`Harness::boot`] waits as its `[ready]` says and
    /// [`Harness::start`] starts its tests as it describes them.
    pub fn tests(mut self, description: impl Into<Source<Description>>) -> Self {
        self.tests = Some(description.into());
        self
    }

    /// The seed of the plant's random effects (default 0): the same inputs
    /// and seed give the same run, bit for bit.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Read and check the inputs, flash the ELF: the MCU at its reset
    /// vector, robot time 0, nothing run yet.
    pub fn build(self) -> Result<Harness, HarnessError> {
        let robot = match self.robot {
            Some(r) => r.get(|p| RobotConfig::load(p)),
            None => RobotConfig::load(crate::paths::robot_config(crate::paths::REFERENCE_ROBOT)),
        }
        .map_err(HarnessError::Robot)?;
        let board = match self.board {
            Some(b) => b.get(|p| Board::load(p))?,
            None => Board::default(),
        };
        let description = match self.tests {
            Some(d) => Some(d.get(|p| Description::load(p))?),
            None => None,
        };
        let firmware = match (
            self.firmware,
            description.as_ref().and_then(|d| d.elf.clone()),
        ) {
            (Some(f), _) => f.get(Firmware::load)?,
            (None, Some(elf)) => Firmware::load(&elf)?,
            (None, None) => return Err(HarnessError::NoFirmware),
        };
        if let Some(d) = &description {
            // What the run would refuse, refused before anything runs.
            d.check_usb(board.mcu).map_err(HarnessError::Start)?;
            d.resolve(&firmware)?;
        }
        let options = BenchOptions {
            seed: self.seed,
            board,
            // The cable in only for a description that talks over it, as
            // in `hil run`.
            usb_cable: description
                .as_ref()
                .is_some_and(|d| d.usb_field().is_some()),
            ..Default::default()
        };
        let bench = Bench::new(firmware, &robot, options)?;
        let mut h = Harness {
            bench,
            robot,
            description: description.map(Arc::new),
            started: None,
            ready: false,
        };
        if let Some(d) = &h.description {
            if let Some(c) = d.resolve(h.bench.firmware())?.counts {
                h.bench.set_count_variables(c);
            }
        }
        Ok(h)
    }
}
