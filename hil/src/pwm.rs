//! The bench's own model of the ATmega2560's PWM timers 2, 3, 4 and 5.
//!
//! simavr emulates phase-correct PWM wrongly (it counts to 256 instead of up to
//! 255 and back down, and produces no output-pin edges), and each running
//! prescaler-1 timer costs it one callback per period and compare channel. So
//! the bench takes the timers a board's PWM pins are on over: their registers are handled here,
//! simavr never clocks them, and the waveform is computed from the registers
//! exactly as the datasheet specifies (ATmega640/1280/2560 datasheet, section
//! 17.9.4 / 20.7.4 "Phase Correct PWM Mode"):
//!
//! - the counter counts 0, 1, ..., TOP, TOP-1, ..., 1, 0, ... with TOP = 0xFF
//!   (mode 1, "PWM, Phase Correct, 8-bit"), one step per prescaled clock, so the
//!   period is 2 * TOP = 510 steps and f = f_clk / (2 * N * TOP);
//! - non-inverting output (COMnx = 2) is cleared on the compare match while up
//!   counting and set on the match while down counting; OCR = 0 keeps it low,
//!   OCR = TOP keeps it high; inverting (COMnx = 3) is the complement;
//! - OCR writes are double buffered and take effect at TOP;
//! - 16-bit registers of timers 3, 4 and 5 (laid out alike, section 17.11)
//!   are written through the shared TEMP byte:
//!   the high byte first, then the low byte commits both.
//!
//! Anything else (other modes, timer interrupts, reading the counter, force
//! output compare, external clocks, asynchronous timer 2) is refused with
//! [`PwmError`]: the bench never pretends to emulate what it has not verified.

use thiserror::Error;

/// One of the timers the bench emulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum TimerId {
    Timer2,
    Timer3,
    Timer4,
    Timer5,
}

impl TimerId {
    /// The timer's number.
    pub fn number(self) -> u8 {
        match self {
            TimerId::Timer2 => 2,
            TimerId::Timer3 => 3,
            TimerId::Timer4 => 4,
            TimerId::Timer5 => 5,
        }
    }
}

impl std::fmt::Display for TimerId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "timer {}", self.number())
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PwmError {
    #[error("{timer}: waveform mode {wgm} with clock select {cs} is not emulated by the bench (only mode 1, 8-bit phase-correct PWM, is verified); use that mode or extend hil/src/pwm.rs with a datasheet test")]
    UnsupportedMode { timer: TimerId, wgm: u8, cs: u8 },
    #[error("{timer}: clock select {cs} (external clock) is not emulated by the bench")]
    ExternalClock { timer: TimerId, cs: u8 },
    #[error("{timer}: compare output mode {com} on channel {channel} is not emulated in phase-correct PWM (use 0, 2 or 3)")]
    UnsupportedCom {
        timer: TimerId,
        channel: char,
        com: u8,
    },
    #[error("{timer}: the firmware {what}; the bench emulates this timer for PWM output only (no interrupts, no counter access)")]
    UnsupportedAccess { timer: TimerId, what: String },
}

/// Phase-correct 8-bit PWM: TOP and the period in counter steps.
pub const TOP: u32 = 0xFF;
pub const PERIOD_STEPS: u32 = 2 * TOP;

/// Compare output mode of one channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Com {
    Disconnected,
    NonInverting,
    Inverting,
}

/// What a PWM-capable pin outputs, as far as the timer decides it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum PinDrive {
    /// The timer does not drive the pin: its PORT/DDR bits do.
    Gpio,
    /// A waveform of `duty` (fraction of time high) at `hz`; constant
    /// levels (OCR at BOTTOM or TOP) are reported as duty 0 or 1.
    Pwm { duty: f64, hz: f64 },
}

/// The counter's waveform: pure functions of the start cycle and prescaler.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PhaseCorrect {
    /// Cycle at which the counter was at BOTTOM, counting up.
    pub start: u64,
    /// Prescaler N (CPU cycles per counter step).
    pub prescaler: u32,
}

impl PhaseCorrect {
    pub fn period_cycles(&self) -> u64 {
        PERIOD_STEPS as u64 * self.prescaler as u64
    }

    pub fn frequency_hz(&self, clock_hz: u32) -> f64 {
        clock_hz as f64 / (2.0 * self.prescaler as f64 * TOP as f64)
    }

    /// Counter value at `cycle` (>= start).
    pub fn tcnt(&self, cycle: u64) -> u32 {
        let phase = ((cycle - self.start) / self.prescaler as u64 % PERIOD_STEPS as u64) as u32;
        if phase <= TOP {
            phase
        } else {
            PERIOD_STEPS - phase
        }
    }

    /// The first cycle > `after` at which the counter is at TOP (where
    /// double-buffered OCR values take effect).
    pub fn next_top(&self, after: u64) -> u64 {
        let period = self.period_cycles();
        let first = self.start + TOP as u64 * self.prescaler as u64;
        if after < first {
            return first;
        }
        first + ((after - first) / period + 1) * period
    }

    /// Output level at `cycle` for compare value `ocr` and mode `com`.
    pub fn level(&self, ocr: u32, com: Com, cycle: u64) -> bool {
        let phase = ((cycle - self.start) / self.prescaler as u64 % PERIOD_STEPS as u64) as u32;
        let ocr = ocr.min(TOP);
        // High from the down-counting match (phase 510 - OCR) through BOTTOM
        // to the up-counting match (phase OCR).
        let high = phase < ocr || phase >= PERIOD_STEPS - ocr;
        match com {
            Com::NonInverting => high,
            Com::Inverting => !high,
            Com::Disconnected => false,
        }
    }

    /// Fraction of time high.
    pub fn duty(ocr: u32, com: Com) -> f64 {
        let d = ocr.min(TOP) as f64 / TOP as f64;
        match com {
            Com::NonInverting => d,
            Com::Inverting => 1.0 - d,
            Com::Disconnected => 0.0,
        }
    }

    /// Output edges in [from, to): (cycle, new level).
    pub fn edges(&self, ocr: u32, com: Com, from: u64, to: u64) -> Vec<(u64, bool)> {
        let mut out = Vec::new();
        let ocr = ocr.min(TOP);
        if ocr == 0 || ocr == TOP || com == Com::Disconnected || to <= from {
            return out;
        }
        let n = self.prescaler as u64;
        let period = self.period_cycles();
        let k0 = from.saturating_sub(self.start) / period;
        let mut k = k0;
        loop {
            let base = self.start + k * period;
            if base >= to {
                break;
            }
            // Up-counting match at step OCR: clear (non-inverting).
            let fall = base + ocr as u64 * n;
            // Down-counting match at step 510 - OCR: set.
            let rise = base + (PERIOD_STEPS - ocr) as u64 * n;
            for (c, lvl) in [(fall, false), (rise, true)] {
                if c >= from && c < to {
                    out.push((c, if com == Com::Inverting { !lvl } else { lvl }));
                }
            }
            k += 1;
        }
        out
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Channel {
    /// OCR value in use.
    ocr: u32,
    /// Value written, taking effect at the next TOP.
    buffered: Option<u32>,
    com: u8,
}

/// Register addresses and layout of one emulated timer.
#[derive(Debug, Clone, Copy)]
struct Layout {
    id: TimerId,
    tccra: u16,
    tccrb: u16,
    tccrc: Option<u16>,
    tcnt: u16,
    /// Low-byte address of each OCR (channel letter, address); 16-bit timers
    /// have the high byte at address + 1.
    ocr: &'static [(char, u16)],
    icr: Option<u16>,
    timsk: u16,
    assr: Option<u16>,
    sixteen_bit: bool,
}

const TIMER2: Layout = Layout {
    id: TimerId::Timer2,
    tccra: 0xB0,
    tccrb: 0xB1,
    tccrc: None,
    tcnt: 0xB2,
    ocr: &[('A', 0xB3), ('B', 0xB4)],
    icr: None,
    timsk: 0x70,
    assr: Some(0xB6),
    sixteen_bit: false,
};

/// Timer 3 (register summary: 0x90-0x9D, TIMSK3 0x71).
const TIMER3: Layout = Layout {
    id: TimerId::Timer3,
    tccra: 0x90,
    tccrb: 0x91,
    tccrc: Some(0x92),
    tcnt: 0x94,
    ocr: &[('A', 0x98), ('B', 0x9A), ('C', 0x9C)],
    icr: Some(0x96),
    timsk: 0x71,
    assr: None,
    sixteen_bit: true,
};

/// Timer 5 (register summary: 0x120-0x12D, TIMSK5 0x73).
const TIMER5: Layout = Layout {
    id: TimerId::Timer5,
    tccra: 0x120,
    tccrb: 0x121,
    tccrc: Some(0x122),
    tcnt: 0x124,
    ocr: &[('A', 0x128), ('B', 0x12A), ('C', 0x12C)],
    icr: Some(0x126),
    timsk: 0x73,
    assr: None,
    sixteen_bit: true,
};

const TIMER4: Layout = Layout {
    id: TimerId::Timer4,
    tccra: 0xA0,
    tccrb: 0xA1,
    tccrc: Some(0xA2),
    tcnt: 0xA4,
    ocr: &[('A', 0xA8), ('B', 0xAA), ('C', 0xAC)],
    icr: Some(0xA6),
    timsk: 0x72,
    assr: None,
    sixteen_bit: true,
};

/// One emulated PWM timer: its registers and waveform.
#[derive(Debug, Clone)]
pub struct PwmTimer {
    layout: Layout,
    tccra: u8,
    tccrb: u8,
    temp: u8,
    channels: [Channel; 3],
    /// Running waveform, when clocked.
    wave: Option<PhaseCorrect>,
}

/// The effect of a register write on the outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WriteEffect {
    /// Outputs changed now.
    pub outputs_changed: bool,
    /// A buffered OCR value waits for the next TOP.
    pub pending_update: bool,
}

impl PwmTimer {
    pub fn timer2() -> Self {
        Self::new(TIMER2)
    }

    pub fn timer3() -> Self {
        Self::new(TIMER3)
    }

    pub fn timer4() -> Self {
        Self::new(TIMER4)
    }

    pub fn timer5() -> Self {
        Self::new(TIMER5)
    }

    /// Timer `n`, if the bench emulates it (2-5).
    pub fn number(n: u8) -> Option<Self> {
        match n {
            2 => Some(Self::timer2()),
            3 => Some(Self::timer3()),
            4 => Some(Self::timer4()),
            5 => Some(Self::timer5()),
            _ => None,
        }
    }

    fn new(layout: Layout) -> Self {
        Self {
            layout,
            tccra: 0,
            tccrb: 0,
            temp: 0,
            channels: [Channel::default(); 3],
            wave: None,
        }
    }

    pub fn id(&self) -> TimerId {
        self.layout.id
    }

    /// Every data-space address whose writes this timer handles.
    pub fn write_addresses(&self) -> Vec<u16> {
        let l = &self.layout;
        let mut v = vec![l.tccra, l.tccrb, l.tcnt, l.timsk];
        v.extend(l.tccrc);
        v.extend(l.assr);
        if l.sixteen_bit {
            v.push(l.tcnt + 1);
        }
        for &(_, a) in l.ocr {
            v.push(a);
            if l.sixteen_bit {
                v.push(a + 1);
            }
        }
        if let Some(icr) = l.icr {
            v.extend([icr, icr + 1]);
        }
        v
    }

    /// Whether `addr` is one of [`PwmTimer::write_addresses`] (without
    /// building the list: this runs at each write).
    pub fn owns_write(&self, addr: u16) -> bool {
        let l = &self.layout;
        let width = if l.sixteen_bit { 2 } else { 1 };
        let in_reg = |reg: u16| addr >= reg && addr < reg + width;
        addr == l.tccra
            || addr == l.tccrb
            || addr == l.timsk
            || l.tccrc == Some(addr)
            || l.assr == Some(addr)
            || in_reg(l.tcnt)
            || l.ocr.iter().any(|&(_, a)| in_reg(a))
            || l.icr.is_some_and(|icr| addr == icr || addr == icr + 1)
    }

    /// Addresses whose reads the bench refuses (the counter).
    pub fn read_addresses(&self) -> Vec<u16> {
        let l = &self.layout;
        if l.sixteen_bit {
            vec![l.tcnt, l.tcnt + 1]
        } else {
            vec![l.tcnt]
        }
    }

    fn wgm(&self) -> u8 {
        let low = self.tccra & 0b11;
        let high = if self.layout.sixteen_bit {
            (self.tccrb >> 3) & 0b11
        } else {
            (self.tccrb >> 3) & 0b1
        };
        high << 2 | low
    }

    fn cs(&self) -> u8 {
        self.tccrb & 0b111
    }

    fn prescaler(&self) -> Result<Option<u32>, PwmError> {
        let cs = self.cs();
        let id = self.layout.id;
        let n = match (id, cs) {
            (_, 0) => return Ok(None),
            (TimerId::Timer2, _) => [0, 1, 8, 32, 64, 128, 256, 1024][cs as usize],
            // The 16-bit timers share one prescaler table (table 17-6).
            (_, 1..=5) => [0, 1, 8, 64, 256, 1024][cs as usize],
            (_, _) => return Err(PwmError::ExternalClock { timer: id, cs }),
        };
        Ok(Some(n))
    }

    /// The firmware read `addr` (a counter register): refused.
    pub fn read(&self, addr: u16) -> PwmError {
        PwmError::UnsupportedAccess {
            timer: self.layout.id,
            what: format!("read the counter register at 0x{addr:02X}"),
        }
    }

    /// The firmware wrote `value` to `addr` at `cycle`.
    pub fn write(&mut self, addr: u16, value: u8, cycle: u64) -> Result<WriteEffect, PwmError> {
        let l = self.layout;
        let id = l.id;
        let refuse = |what: String| Err(PwmError::UnsupportedAccess { timer: id, what });
        let mut effect = WriteEffect::default();
        if addr == l.tccra || addr == l.tccrb {
            if addr == l.tccra {
                self.tccra = value;
            } else {
                if value & 0xC0 != 0 && !l.sixteen_bit {
                    return refuse(format!(
                        "set force-output-compare bits (TCCR2B = 0x{value:02X})"
                    ));
                }
                if l.sixteen_bit && value & 0xC0 != 0 {
                    return refuse(format!(
                        "set input-capture bits (TCCR{}B = 0x{value:02X})",
                        id.number()
                    ));
                }
                self.tccrb = value;
            }
            self.reconfigure(cycle)?;
            effect.outputs_changed = true;
        } else if Some(addr) == l.tccrc {
            if value != 0 {
                return refuse(format!(
                    "forced an output compare (TCCR{}C = 0x{value:02X})",
                    id.number()
                ));
            }
        } else if addr == l.timsk {
            if value != 0 {
                return refuse(format!("enabled its interrupts (TIMSK = 0x{value:02X})"));
            }
        } else if Some(addr) == l.assr {
            if value & 0x60 != 0 {
                return refuse(format!(
                    "selected the asynchronous clock (ASSR = 0x{value:02X})"
                ));
            }
        } else if addr == l.tcnt || (l.sixteen_bit && addr == l.tcnt + 1) {
            return refuse(format!("wrote the counter register at 0x{addr:02X}"));
        } else if l.icr.is_some_and(|icr| addr == icr || addr == icr + 1) {
            return refuse("wrote ICR (input capture / TOP in other modes)".into());
        } else if let Some(i) = l.ocr.iter().position(|&(_, a)| a == addr) {
            let v = if l.sixteen_bit {
                // The low byte commits TEMP (the high byte written before).
                (self.temp as u32) << 8 | value as u32
            } else {
                value as u32
            };
            match self.wave {
                // Double buffered in PWM modes: takes effect at TOP.
                Some(_) => {
                    self.channels[i].buffered = Some(v);
                    effect.pending_update = true;
                }
                // Not clocked: no TOP will come; the datasheet's buffer
                // would hold it, and so do we, until the timer starts.
                None => self.channels[i].buffered = Some(v),
            }
        } else if l.sixteen_bit && l.ocr.iter().any(|&(_, a)| a + 1 == addr) {
            self.temp = value;
        }
        Ok(effect)
    }

    fn reconfigure(&mut self, cycle: u64) -> Result<(), PwmError> {
        let id = self.layout.id;
        for (i, &(name, _)) in self.layout.ocr.iter().enumerate() {
            let com = (self.tccra >> (6 - 2 * i)) & 0b11;
            if com == 1 {
                return Err(PwmError::UnsupportedCom {
                    timer: id,
                    channel: name,
                    com,
                });
            }
            self.channels[i].com = com;
        }
        let prescaler = self.prescaler()?;
        let wgm = self.wgm();
        match (wgm, prescaler) {
            (_, None) => {
                // Stopped: the counter holds; outputs hold their last level.
                // The bench models a stopped timer's compare outputs as
                // constant; only mode 1 is verified once clocked.
                self.wave = None;
            }
            (1, Some(n)) => {
                if self.wave.is_none_or(|w| w.prescaler != n) {
                    // Starting from TCNT = 0 counting up (the reset value;
                    // the bench refuses TCNT writes).
                    self.wave = Some(PhaseCorrect {
                        start: cycle,
                        prescaler: n,
                    });
                    // A timer that was stopped applies buffered values at
                    // its first TOP.
                }
            }
            (wgm, Some(_)) => {
                return Err(PwmError::UnsupportedMode {
                    timer: id,
                    wgm,
                    cs: self.cs(),
                })
            }
        }
        Ok(())
    }

    /// The cycle of the next TOP, if a buffered OCR value waits for it.
    pub fn pending_update_at(&self, after: u64) -> Option<u64> {
        let wave = self.wave?;
        self.channels
            .iter()
            .any(|c| c.buffered.is_some())
            .then(|| wave.next_top(after))
    }

    /// Apply buffered OCR values (call at the TOP cycle).
    pub fn apply_buffered(&mut self) {
        for c in &mut self.channels {
            if let Some(v) = c.buffered.take() {
                c.ocr = v;
            }
        }
    }

    /// What channel `ch` ('A', 'B', 'C') does to its pin.
    pub fn drive(&self, ch: char, clock_hz: u32) -> PinDrive {
        let Some(i) = self.layout.ocr.iter().position(|&(c, _)| c == ch) else {
            return PinDrive::Gpio;
        };
        let c = self.channels[i];
        let com = match c.com {
            2 => Com::NonInverting,
            3 => Com::Inverting,
            _ => return PinDrive::Gpio,
        };
        match self.wave {
            Some(w) => PinDrive::Pwm {
                duty: PhaseCorrect::duty(c.ocr, com),
                hz: w.frequency_hz(clock_hz),
            },
            // Connected but not clocked: the compare output holds its level,
            // which after reset is low.
            None => PinDrive::Pwm { duty: 0.0, hz: 0.0 },
        }
    }

    /// The running waveform and channel `ch`'s (ocr, com), for tracing.
    pub fn waveform(&self, ch: char) -> Option<(PhaseCorrect, u32, Com)> {
        let i = self.layout.ocr.iter().position(|&(c, _)| c == ch)?;
        let c = self.channels[i];
        let com = match c.com {
            2 => Com::NonInverting,
            3 => Com::Inverting,
            _ => Com::Disconnected,
        };
        Some((self.wave?, c.ocr, com))
    }
}

#[cfg(test)]
mod tests;
