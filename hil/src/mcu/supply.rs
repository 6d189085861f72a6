//! The MCU's supply and its brown-out detector, which simavr does not model.
//!
//! The battery feeds the Arduino Mega's VIN; its linear 5 V regulator
//! (NCP1117) needs about 1 V of headroom at the board's light load, so VCC
//! follows the battery minus the dropout once the battery is below 6 V.
//!
//! The Mega's extended fuse (0xFD) sets BODLEVEL to 2.7 V (ATmega2560
//! datasheet, "System Control and Reset": V_BOT 2.5/2.7/2.9 V min/typ/max,
//! hysteresis 50 mV). While VCC is below V_BOT- the MCU is held in reset;
//! once VCC rises above V_BOT+ the reset is released after the start-up
//! time-out the fuses select (low fuse 0xFF: full-swing crystal, SUT 11:
//! 14 CK + 65 ms), and the reset flag BORF is set in MCUSR.
//!
//! Between V_BOT and 4.5 V an ATmega2560 at 16 MHz runs outside its speed
//! grade; the bench cannot model how it misbehaves there and runs it as if
//! it were in spec.

/// The supply chain from the battery to VCC, and the brown-out detector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Supply {
    /// Regulated output, V.
    pub regulator_v: f64,
    /// Regulator dropout at the board's load, V.
    pub dropout_v: f64,
    /// BODLEVEL, V.
    pub bod_level_v: f64,
    /// Brown-out hysteresis (V_BOT+ - V_BOT-), V.
    pub bod_hysteresis_v: f64,
    /// Reset time-out after VCC recovers, s.
    pub startup_s: f64,
}

impl Default for Supply {
    fn default() -> Self {
        Self {
            regulator_v: 5.0,
            dropout_v: 1.0,
            bod_level_v: 2.7,
            bod_hysteresis_v: 0.05,
            startup_s: 0.065,
        }
    }
}

impl Supply {
    /// VCC for a battery voltage.
    pub fn vcc(&self, battery_v: f64) -> f64 {
        (battery_v - self.dropout_v).clamp(0.0, self.regulator_v)
    }

    /// Below this VCC the detector pulls the reset (V_BOT-).
    pub fn falling_v(&self) -> f64 {
        self.bod_level_v - self.bod_hysteresis_v / 2.0
    }

    /// Above this VCC the detector lets go (V_BOT+).
    pub fn rising_v(&self) -> f64 {
        self.bod_level_v + self.bod_hysteresis_v / 2.0
    }
}

/// What the brown-out detector does with the reset line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bod {
    /// VCC is fine: the MCU runs.
    #[default]
    Released,
    /// VCC below V_BOT-: reset held.
    Held,
    /// VCC back above V_BOT+: reset released at this cycle.
    Releasing { at: u64 },
}

impl Bod {
    /// The detector's next state at `cycle` with `vcc`; `startup` is the
    /// time-out in cycles.
    pub fn next(self, supply: &Supply, vcc: f64, cycle: u64, startup: u64) -> Bod {
        match self {
            Bod::Released if vcc < supply.falling_v() => Bod::Held,
            Bod::Held if vcc > supply.rising_v() => Bod::Releasing {
                at: cycle + startup,
            },
            // A new dip restarts the time-out.
            Bod::Releasing { .. } if vcc < supply.falling_v() => Bod::Held,
            Bod::Releasing { at } if cycle >= at => Bod::Released,
            s => s,
        }
    }

    /// The reset line is held low.
    pub fn holds_reset(self) -> bool {
        !matches!(self, Bod::Released)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vcc_follows_the_battery_below_the_regulators_headroom() {
        let s = Supply::default();
        assert_eq!(s.vcc(7.4), 5.0);
        assert_eq!(s.vcc(6.0), 5.0);
        assert!((s.vcc(3.2) - 2.2).abs() < 1e-12);
        assert_eq!(s.vcc(0.5), 0.0);
    }

    #[test]
    fn detector_holds_below_the_level_and_releases_after_the_timeout() {
        let s = Supply::default();
        let mut b = Bod::default();
        b = b.next(&s, 2.69, 0, 100);
        assert_eq!(b, Bod::Released, "within the hysteresis");
        b = b.next(&s, 2.6, 10, 100);
        assert_eq!(b, Bod::Held);
        b = b.next(&s, 2.71, 20, 100);
        assert_eq!(b, Bod::Held, "within the hysteresis");
        b = b.next(&s, 4.0, 30, 100);
        assert_eq!(b, Bod::Releasing { at: 130 });
        assert!(b.holds_reset());
        assert_eq!(b.next(&s, 2.0, 40, 100), Bod::Held, "a new dip");
        assert_eq!(b.next(&s, 4.0, 129, 100), b);
        assert_eq!(b.next(&s, 4.0, 130, 100), Bod::Released);
    }
}
