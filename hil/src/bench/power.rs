//! The robot's power as the MCU sees it: the battery on A0 through its
//! divider, VCC (and with it the ADC's reference) from the battery through
//! the regulator, and the brown-out detector's hold on the reset line (the
//! models are `crate::mcu::supply`'s; this is their glue to the MCU).

use super::recorder::{AnalogEvent, AnalogInput, Recorder};
use super::NEVER;
use crate::mcu::sim::{Core, Irq};
use crate::mcu::supply::{Bod, Supply};

/// What the brown-out detector did to the reset line.
pub(super) enum Brownout {
    /// It pulled the reset: the MCU restarts when it lets go.
    Pulled,
    /// It let go: the MCU restarts with BORF set.
    Released,
}

pub(super) struct Power {
    /// A0, driven with the battery's voltage through the divider.
    adc0: Option<Irq>,
    adc_mv: u32,
    battery_divider: f64,
    supply: Supply,
    startup_cycles: u64,
    /// The brown-out detector's state; while it holds the reset, the run
    /// loop executes nothing.
    bod: Bod,
    vcc_v: f64,
    /// The battery voltage `update_supply` last saw.
    supply_battery_v: f64,
    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    brownouts: Vec<(u64, Option<u64>)>,
}

impl Power {
    pub(super) fn new(supply: Supply, battery_divider: f64, startup_cycles: u64) -> Self {
        Self {
            adc0: None,
            adc_mv: u32::MAX,
            battery_divider,
            supply,
            startup_cycles,
            bod: Bod::Released,
            vcc_v: f64::NAN,
            supply_battery_v: f64::NAN,
            brownouts: Vec::new(),
        }
    }

    pub(super) fn connect(&mut self, adc0: Irq) {
        self.adc0 = Some(adc0);
    }

    /// The detector counts down its start-up time-out before it lets go.
    pub(super) fn releasing(&self) -> bool {
        matches!(self.bod, Bod::Releasing { .. })
    }

    /// The cycle the detector lets go, while it counts down.
    pub(super) fn release_at(&self) -> u64 {
        match self.bod {
            Bod::Releasing { at } => at,
            _ => NEVER,
        }
    }

    /// The brown-out detector holds the MCU in reset.
    pub(super) fn holds_reset(&self) -> bool {
        self.bod.holds_reset()
    }

    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    pub(super) fn brownouts(&self) -> &[(u64, Option<u64>)] {
        &self.brownouts
    }

    /// VCC from the battery at `battery_v` now, the ADC's reference with it,
    /// and the brown-out detector's reaction (see [`crate::mcu::supply`]), which
    /// the caller passes on to the run loop.
    pub(super) fn update_supply(
        &mut self,
        core: &mut Core,
        cycle: u64,
        battery_v: f64,
        recorder: &mut Recorder,
    ) -> Option<Brownout> {
        // With the battery as it was, only a detector counting down its
        // start-up time-out can change.
        if battery_v == self.supply_battery_v && !matches!(self.bod, Bod::Releasing { .. }) {
            return None;
        }
        self.supply_battery_v = battery_v;
        let vcc = self.supply.vcc(battery_v);
        if vcc != self.vcc_v {
            self.vcc_v = vcc;
            let mv = (vcc * 1000.0).round() as u32;
            core.set_supply_mv(mv);
            recorder.analog(AnalogEvent {
                cycle,
                input: AnalogInput::Supply,
                mv,
            });
        }
        let before = self.bod.holds_reset();
        self.bod = self.bod.next(&self.supply, vcc, cycle, self.startup_cycles);
        match (before, self.bod.holds_reset()) {
            (false, true) => {
                self.brownouts.push((cycle, None));
                Some(Brownout::Pulled)
            }
            (true, false) => {
                if let Some(b) = self.brownouts.last_mut() {
                    b.1 = Some(cycle);
                }
                Some(Brownout::Released)
            }
            _ => None,
        }
    }

    /// Drive A0 with the battery's voltage `battery_v` when it changed.
    pub(super) fn update_adc(
        &mut self,
        core: &mut Core,
        cycle: u64,
        battery_v: f64,
        recorder: &mut Recorder,
    ) {
        // A pin cannot rise above VCC (its protection diodes clamp it).
        let mv = (battery_v * self.battery_divider * 1000.0)
            .round()
            .clamp(0.0, (self.vcc_v * 1000.0).round()) as u32;
        if mv != self.adc_mv {
            if let Some(irq) = self.adc0 {
                core.raise(irq, mv);
            }
            self.adc_mv = mv;
            recorder.analog(AnalogEvent {
                cycle,
                input: AnalogInput::Adc0,
                mv,
            });
        }
    }
}
