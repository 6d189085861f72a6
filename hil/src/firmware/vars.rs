//! The firmware's bench interface: variables the bench reads from SRAM by
//! their ELF symbol names (documented in docs/reference/firmware.md). What their
//! bytes mean is the protocol's: `HT_STATE` is a
//! [`henrytwo_protocol::RunState`], `HT_PHASE` a [`henrytwo_protocol::Phase`]
//! (the bench decodes them in `Bench::run_state` and `Bench::phase`).

use crate::firmware::elf::{ElfError, Firmware};

/// Data-space addresses of the interface variables.
#[derive(Debug, Clone, Copy)]
pub struct FwVars {
    pub left_count: u16,
    pub right_count: u16,
    pub ticks: u16,
    pub state: u16,
    pub done_count: u16,
    pub leg_length_mm: u16,
    pub stop_left: u16,
    pub stop_right: u16,
    pub speed_left: u16,
    pub speed_right: u16,
    pub duty_left: u16,
    pub duty_right: u16,
    /// Optional variables: a build without them is judged on the others.
    pub phase: Option<u16>,
    pub segment: Option<u16>,
    pub fault: Option<u16>,
}

impl FwVars {
    pub fn resolve(fw: &Firmware) -> Result<Self, ElfError> {
        Ok(Self {
            left_count: fw.variable("HT_LEFT_COUNT", 4)?,
            right_count: fw.variable("HT_RIGHT_COUNT", 4)?,
            ticks: fw.variable("HT_TICKS", 4)?,
            state: fw.variable("HT_STATE", 1)?,
            done_count: fw.variable("HT_DONE_COUNT", 2)?,
            leg_length_mm: fw.variable("HT_LEG_LENGTH_MM", 4)?,
            stop_left: fw.variable("HT_STOP_LEFT", 4)?,
            stop_right: fw.variable("HT_STOP_RIGHT", 4)?,
            speed_left: fw.variable("HT_SPEED_LEFT", 4)?,
            speed_right: fw.variable("HT_SPEED_RIGHT", 4)?,
            duty_left: fw.variable("HT_DUTY_LEFT", 1)?,
            duty_right: fw.variable("HT_DUTY_RIGHT", 1)?,
            phase: fw.variable("HT_PHASE", 1).ok(),
            segment: fw.variable("HT_SEGMENT", 1).ok(),
            fault: fw.variable("HT_FAULT", 1).ok(),
        })
    }
}
