//! What the firmware reads and writes of an emulated timer: the control
//! registers, the 16-bit registers through TEMP (datasheet 17.3), the
//! counter, and what stays refused.

use super::mode::Update;
use super::timer::{Count, PwmTimer, WriteEffect};
use super::{Config, PwmError, Top};

impl PwmTimer {
    /// The firmware read `addr` at `cycle`: the counter's bytes (the low
    /// byte of a 16-bit one latches the high into TEMP, datasheet 17.3),
    /// or an error for what the bench does not emulate.
    pub fn read(&mut self, addr: u16, cycle: u64) -> Result<u8, PwmError> {
        let l = self.layout;
        if addr == l.tcnt {
            if let Some(e) = self.unverified(cycle) {
                return Err(e.observed("read the counter"));
            }
            let v = self.tcnt(cycle);
            self.temp = (v >> 8) as u8;
            Ok(v as u8)
        } else if l.sixteen_bit && addr == l.tcnt + 1 {
            Ok(self.temp)
        } else {
            Err(PwmError::UnsupportedAccess {
                config: self.config(),
                what: format!("read the interrupt flags (TIFR{})", l.id.number()),
            })
        }
    }

    /// The firmware wrote `value` to `addr` at `cycle`.
    pub fn write(&mut self, addr: u16, value: u8, cycle: u64) -> Result<WriteEffect, PwmError> {
        let l = self.layout;
        let n = l.id.number();
        let mut effect = WriteEffect::default();
        let refuse =
            |what: String, config: Config| Err(PwmError::UnsupportedAccess { config, what });
        if addr == l.tccra || addr == l.tccrb || l.assr == Some(addr) {
            if addr == l.tccrb && !l.sixteen_bit && value & 0xC0 != 0 && self.connected() {
                return refuse(
                    format!("forced an output compare (TCCR{n}B = 0x{value:02X})"),
                    self.config(),
                );
            }
            let old = (self.tccra, self.tccrb, self.assr);
            let levels = self.levels(cycle);
            if addr == l.tccra {
                self.tccra = value;
            } else if addr == l.tccrb {
                // FOC2A/B are strobes (read as zero); ICNCn/ICESn only
                // configure the input capture, which nothing here observes.
                self.tccrb = if l.sixteen_bit { value } else { value & 0x3F };
            } else {
                self.assr = value;
            }
            if let Err(e) = self.restart(cycle, &levels) {
                (self.tccra, self.tccrb, self.assr) = old;
                return Err(e);
            }
            effect.outputs_changed = true;
        } else if Some(addr) == l.tccrc {
            if value != 0 && self.connected() {
                return refuse(
                    format!("forced an output compare (TCCR{n}C = 0x{value:02X})"),
                    self.config(),
                );
            }
        } else if addr == l.timsk {
            if value != 0 && !self.mirrored {
                return Err(PwmError::FirmwareClock {
                    config: self.config(),
                    timsk: value,
                });
            }
        } else if l.is_high_byte(addr) {
            self.temp = value;
        } else if addr == l.tcnt {
            let v = self.with_temp(value);
            match self.count {
                Count::Held { up, .. } => self.count = Count::Held { tcnt: v, up },
                Count::Running(_) => {
                    return refuse(
                        format!("wrote TCNT{n} while the timer runs (write it while stopped)"),
                        self.config(),
                    )
                }
            }
        } else if l.icr == Some(addr) {
            // ICRn is writable only in the modes that take TOP from it
            // (17.11.x); elsewhere it is the input capture register.
            let v = self.with_temp(value);
            if self.mode().is_some_and(|m| m.top == Top::Icr) {
                let levels = self.levels(cycle);
                let old = self.icr;
                self.icr = v;
                if let Err(e) = self.restart(cycle, &levels) {
                    self.icr = old;
                    return Err(e);
                }
                effect.outputs_changed = true;
            }
        } else if let Some(i) = l.ocr.iter().position(|&(_, a)| a == addr) {
            let v = self.with_temp(value);
            let immediate = self.mode().is_none_or(|m| m.update() == Update::Immediate);
            if immediate {
                let levels = self.levels(cycle);
                let old = self.channels[i].ocr;
                self.channels[i].ocr = v;
                self.channels[i].buffered = None;
                if let Err(e) = self.restart(cycle, &levels) {
                    self.channels[i].ocr = old;
                    return Err(e);
                }
                effect.outputs_changed = true;
            } else {
                // Double buffered: takes effect at the update point (a
                // stopped timer's buffer waits for it too).
                self.channels[i].buffered = Some(v);
                effect.pending_update = true;
            }
        }
        Ok(effect)
    }

    /// The 16-bit value of a low-byte write: TEMP (the high byte written
    /// before) and `low`.
    fn with_temp(&self, low: u8) -> u32 {
        if self.sixteen_bit() {
            (self.temp as u32) << 8 | low as u32
        } else {
            low as u32
        }
    }
}
