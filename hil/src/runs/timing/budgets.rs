//! The budgets a run's timing is checked against, from a TOML file
//! (`fixtures/timing-budgets.toml`), and their own checks: those that fit
//! the firmware and the MCU before anything runs.

use serde::{Deserialize, Serialize};

use super::TimingError;
use crate::mcu::chip::Chip;

/// Budgets, from a TOML file. All times in microseconds. The control
/// function's three are for a firmware that has one: left out, it is not
/// timed.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Budgets {
    /// Longest execution of the control function (interrupts taken out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control_max_us: Option<f64>,
    /// Largest deviation of the control tick's period from `tick_period_us`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tick_jitter_max_us: Option<f64>,
    /// Nominal period of the control tick.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tick_period_us: Option<f64>,
    /// Longest execution of any interrupt handler.
    pub isr_max_us: f64,
    /// Longest latency from an encoder edge to its handler's first instruction.
    pub isr_latency_max_us: f64,
    /// Longest stretch with interrupts disabled.
    pub interrupts_off_max_us: f64,
    /// Least free stack (bytes between the lowest SP and the end of static data).
    pub stack_margin_min_bytes: u32,
    /// Highest CPU load (awake fraction) over the run.
    pub cpu_load_max: f64,
}

impl Budgets {
    pub fn load(path: &std::path::Path) -> Result<Self, TimingError> {
        let text = input_file::read_text(path).map_err(|source| TimingError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let budgets: Self = toml::from_str(&text).map_err(|source| TimingError::Parse {
            path: path.display().to_string(),
            source,
        })?;
        budgets.check(&path.display().to_string())?;
        Ok(budgets)
    }

    /// Every budget a number the measurement can exceed or meet: a NaN or a
    /// negative budget would report any firmware over it, a CPU load above 1
    /// could never be exceeded.
    pub fn check(&self, path: &str) -> Result<(), TimingError> {
        const TIME: &str = "give a time above 0 and up to 1000000 us (one second)";
        let invalid = |field, value: String, allowed| TimingError::Invalid {
            path: path.into(),
            field,
            value,
            allowed,
        };
        for (field, v) in [
            ("control_max_us", self.control_max_us),
            ("tick_period_us", self.tick_period_us),
            ("isr_max_us", Some(self.isr_max_us)),
            ("isr_latency_max_us", Some(self.isr_latency_max_us)),
            ("interrupts_off_max_us", Some(self.interrupts_off_max_us)),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0 && *v <= 1e6)) {
                return Err(invalid(field, v.to_string(), TIME));
            }
        }
        match (self.tick_jitter_max_us, self.tick_period_us) {
            (Some(jitter), _) if !(jitter.is_finite() && (0.0..=1e6).contains(&jitter)) => {
                return Err(invalid(
                    "tick_jitter_max_us",
                    jitter.to_string(),
                    "give a time from 0 to 1000000 us (one second)",
                ));
            }
            (Some(jitter), None) => {
                return Err(invalid(
                    "tick_jitter_max_us",
                    jitter.to_string(),
                    "a jitter needs the period it is from: give tick_period_us too",
                ));
            }
            _ => {}
        }
        let most = crate::mcu::chip::Mcu::ALL
            .map(|m| m.chip().sram_range().len())
            .into_iter()
            .max()
            .unwrap_or(0);
        if self.stack_margin_min_bytes as usize > most {
            return Err(invalid(
                "stack_margin_min_bytes",
                self.stack_margin_min_bytes.to_string(),
                "give 0 to 8192 bytes (the largest SRAM of the MCUs described, the ATmega2560's)",
            ));
        }
        let load = self.cpu_load_max;
        if !(load.is_finite() && load > 0.0 && load <= 1.0) {
            return Err(invalid(
                "cpu_load_max",
                load.to_string(),
                "give a fraction above 0 and up to 1 (the CPU's awake share)",
            ));
        }
        Ok(())
    }

    /// The first of the control function's budgets set, if any: a firmware
    /// must name a control function for them.
    pub fn control_budget(&self) -> Option<&'static str> {
        [
            ("control_max_us", self.control_max_us),
            ("tick_period_us", self.tick_period_us),
            ("tick_jitter_max_us", self.tick_jitter_max_us),
        ]
        .into_iter()
        .find_map(|(f, v)| v.map(|_| f))
    }

    /// Refuse control budgets for a firmware without a control function,
    /// and a stack margin larger than `chip`'s SRAM.
    pub fn check_for(
        &self,
        path: &str,
        control: Option<&str>,
        chip: &Chip,
    ) -> Result<(), TimingError> {
        if let (None, Some(field)) = (control, self.control_budget()) {
            return Err(TimingError::NoControlFunction {
                path: path.into(),
                field,
            });
        }
        let sram = chip.sram_range().len();
        if self.stack_margin_min_bytes as usize > sram {
            return Err(TimingError::Invalid {
                path: path.into(),
                field: "stack_margin_min_bytes",
                value: self.stack_margin_min_bytes.to_string(),
                allowed: match chip.mcu {
                    crate::mcu::chip::Mcu::Atmega2560 => {
                        "give at most the atmega2560's 8192 bytes of SRAM"
                    }
                    crate::mcu::chip::Mcu::Atmega328p => {
                        "give at most the atmega328p's 2048 bytes of SRAM"
                    }
                    crate::mcu::chip::Mcu::Atmega32u4 => {
                        "give at most the atmega32u4's 2560 bytes of SRAM"
                    }
                },
            });
        }
        Ok(())
    }
}
