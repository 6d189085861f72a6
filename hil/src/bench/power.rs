//! The robot's power as the MCU sees it: the battery on A0 through its
//! divider, VCC (and with it the ADC's reference) from the battery through
//! the regulator, and the brown-out detector's hold on the reset line (the
//! models are `crate::supply`'s; this is their glue to the MCU).

use super::core::{BenchCore, NEVER};
use super::recorder::{AnalogEvent, AnalogInput};
use crate::sim::{Core, Irq};
use crate::supply::{Bod, Supply};

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
}

impl BenchCore {
    /// The brown-out detector holds the MCU in reset.
    pub fn held_in_reset(&self) -> bool {
        self.power.bod.holds_reset()
    }

    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    pub fn brownouts(&self) -> &[(u64, Option<u64>)] {
        &self.power.brownouts
    }

    /// VCC from the battery now, the ADC's reference with it, and the
    /// brown-out detector's reaction (see [`crate::supply`]).
    pub(super) fn update_supply(&mut self, core: &mut Core, cycle: u64) {
        let battery = self.robot.battery_voltage().0;
        let p = &mut self.power;
        // With the battery as it was, only a detector counting down its
        // start-up time-out can change.
        if battery == p.supply_battery_v && !matches!(p.bod, Bod::Releasing { .. }) {
            return;
        }
        p.supply_battery_v = battery;
        let vcc = p.supply.vcc(battery);
        if vcc != p.vcc_v {
            p.vcc_v = vcc;
            let mv = (vcc * 1000.0).round() as u32;
            core.set_supply_mv(mv);
            self.recorder.analog(AnalogEvent {
                cycle,
                input: AnalogInput::Supply,
                mv,
            });
        }
        let before = p.bod.holds_reset();
        p.bod = p.bod.next(&p.supply, vcc, cycle, p.startup_cycles);
        match (before, p.bod.holds_reset()) {
            (false, true) => {
                p.brownouts.push((cycle, None));
                self.requests.reset();
            }
            (true, false) => {
                if let Some(b) = p.brownouts.last_mut() {
                    b.1 = Some(cycle);
                }
                self.requests.bod_release();
            }
            _ => {}
        }
    }

    /// Drive A0 with the battery's voltage when it changed.
    pub(super) fn update_adc(&mut self, core: &mut Core, cycle: u64) {
        let p = &mut self.power;
        // A pin cannot rise above VCC (its protection diodes clamp it).
        let mv = (self.robot.battery_voltage().0 * p.battery_divider * 1000.0)
            .round()
            .clamp(0.0, (p.vcc_v * 1000.0).round()) as u32;
        if mv != p.adc_mv {
            if let Some(irq) = p.adc0 {
                core.raise(irq, mv);
            }
            p.adc_mv = mv;
            self.recorder.analog(AnalogEvent {
                cycle,
                input: AnalogInput::Adc0,
                mv,
            });
        }
    }
}
