//! [`HarnessBuilder`]: a bench from a robot config, a board file and an ELF.

use std::path::PathBuf;

use plant_model::RobotConfig;

use super::{Harness, HarnessError};
use crate::bench::{Bench, BenchOptions};
use crate::board::Board;
use crate::firmware::elf::Firmware;

/// What a [`Harness`] is built from; [`Harness::builder`] starts one.
/// Only the firmware is required.
#[derive(Debug, Clone, Default)]
pub struct HarnessBuilder {
    robot: Option<PathBuf>,
    board: Option<PathBuf>,
    firmware: Option<PathBuf>,
    seed: u64,
}

impl HarnessBuilder {
    /// The robot config TOML (the plant: motors, wheels, encoders, effects;
    /// the ranges are listed in `fixtures/robots/henrytwo-ideal.toml`).
    /// Default: `fixtures/robots/henrytwo.toml`, the thesis robot.
    pub fn robot(mut self, path: impl Into<PathBuf>) -> Self {
        self.robot = Some(path.into());
        self
    }

    /// The board TOML: which MCU pin each part is on, the motor driver, the
    /// links' USARTs. Default: Henrytwo's (`fixtures/boards/henrytwo.toml`,
    /// built in).
    pub fn board(mut self, path: impl Into<PathBuf>) -> Self {
        self.board = Some(path.into());
        self
    }

    /// The firmware ELF (built for the atmega2560), e.g.
    /// [`crate::paths::firmware_elf`]`("robust")` for this repository's.
    pub fn firmware(mut self, elf: impl Into<PathBuf>) -> Self {
        self.firmware = Some(elf.into());
        self
    }

    /// The seed of the plant's random effects (default 0): the same files
    /// and seed give the same run, bit for bit.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Read and check the files, flash the ELF: the MCU at its reset
    /// vector, robot time 0, nothing run yet.
    pub fn build(self) -> Result<Harness, HarnessError> {
        let robot_path = self
            .robot
            .unwrap_or_else(|| crate::paths::robot_config(crate::paths::REFERENCE_ROBOT));
        let robot = RobotConfig::load(&robot_path).map_err(HarnessError::Robot)?;
        let board = match &self.board {
            Some(path) => Board::load(path)?,
            None => Board::default(),
        };
        let elf = self.firmware.ok_or(HarnessError::NoFirmware)?;
        let firmware = Firmware::load(&elf)?;
        let options = BenchOptions {
            seed: self.seed,
            board,
            ..Default::default()
        };
        let bench = Bench::new(firmware, &robot, options)?;
        Ok(Harness { bench, robot })
    }
}
