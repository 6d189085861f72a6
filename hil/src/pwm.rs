//! The bench's own model of the ATmega2560's PWM timers 2 and 4.
//!
//! simavr emulates phase-correct PWM wrongly (it counts to 256 instead of up to
//! 255 and back down, and produces no output-pin edges), and each running
//! prescaler-1 timer costs it one callback per period and compare channel. So
//! the bench takes these two timers over: their registers are handled here,
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
//! - 16-bit registers of timer 4 are written through the shared TEMP byte:
//!   the high byte first, then the low byte commits both.
//!
//! Anything else (other modes, timer interrupts, reading the counter, force
//! output compare, external clocks, asynchronous timer 2) is refused with
//! [`PwmError`]: the bench never pretends to emulate what it has not verified.

use thiserror::Error;

/// One of the two timers the bench emulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum TimerId {
    Timer2,
    Timer4,
}

impl std::fmt::Display for TimerId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimerId::Timer2 => write!(f, "timer 2"),
            TimerId::Timer4 => write!(f, "timer 4"),
        }
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

    pub fn timer4() -> Self {
        Self::new(TIMER4)
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
            (TimerId::Timer4, 1..=5) => [0, 1, 8, 64, 256, 1024][cs as usize],
            (TimerId::Timer4, _) => return Err(PwmError::ExternalClock { timer: id, cs }),
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
                    return refuse(format!("set input-capture bits (TCCR4B = 0x{value:02X})"));
                }
                self.tccrb = value;
            }
            self.reconfigure(cycle)?;
            effect.outputs_changed = true;
        } else if Some(addr) == l.tccrc {
            if value != 0 {
                return refuse(format!("forced an output compare (TCCR4C = 0x{value:02X})"));
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
mod tests {
    use super::*;
    use rstest::rstest;

    const F_CPU: u32 = 16_000_000;

    /// The check at each write and the list the bench claims agree on every
    /// data-space address.
    #[test]
    fn owns_write_is_the_list_of_write_addresses() {
        for timer in [PwmTimer::timer2(), PwmTimer::timer4()] {
            let list = timer.write_addresses();
            for addr in 0..0x2200u16 {
                assert_eq!(
                    timer.owns_write(addr),
                    list.contains(&addr),
                    "address {addr:#x}"
                );
            }
        }
    }

    /// Measure frequency and duty from the edges over one second of waveform.
    fn measure(ocr: u32, com: Com) -> (f64, f64) {
        let w = PhaseCorrect {
            start: 1234,
            prescaler: 1,
        };
        let from = w.start;
        let to = from + F_CPU as u64;
        let edges = w.edges(ocr, com, from, to);
        let rises: Vec<u64> = edges.iter().filter(|e| e.1).map(|e| e.0).collect();
        let hz = if rises.len() >= 2 {
            (rises.len() - 1) as f64 * F_CPU as f64 / (rises[rises.len() - 1] - rises[0]) as f64
        } else {
            0.0
        };
        // Duty by integrating the level between edges.
        let mut level = w.level(ocr, com, from);
        let mut t = from;
        let mut high = 0u64;
        for &(c, l) in &edges {
            if level {
                high += c - t;
            }
            t = c;
            level = l;
        }
        if level {
            high += to - t;
        }
        (hz, high as f64 / (to - from) as f64)
    }

    /// Datasheet: f_OCnxPCPWM = f_clk / (2 * N * TOP); duty = OCR / TOP for
    /// non-inverting; OCR = 0 continuously low, OCR = TOP continuously high.
    #[rstest]
    #[case(0)]
    #[case(1)]
    #[case(64)]
    #[case(128)]
    #[case(170)]
    #[case(254)]
    #[case(255)]
    fn waveform_matches_the_datasheet(#[case] ocr: u32) {
        let (hz, duty) = measure(ocr, Com::NonInverting);
        let expected_duty = ocr as f64 / 255.0;
        assert!(
            (duty - expected_duty).abs() < 1e-4,
            "OCR {ocr}: duty {duty} vs {expected_duty}"
        );
        if ocr == 0 || ocr == 255 {
            assert_eq!(hz, 0.0, "constant output has no edges");
        } else {
            let f = 16e6 / (2.0 * 1.0 * 255.0);
            assert!((hz - 31_372.55).abs() / 31_372.55 < 1e-4, "{hz}");
            assert!((hz - f).abs() / f < 1e-9, "{hz} vs {f}");
        }
        let (_, inv) = measure(ocr, Com::Inverting);
        assert!((inv - (1.0 - expected_duty)).abs() < 1e-4);
    }

    #[test]
    fn counter_runs_up_to_top_and_back() {
        let w = PhaseCorrect {
            start: 0,
            prescaler: 1,
        };
        assert_eq!(w.tcnt(0), 0);
        assert_eq!(w.tcnt(255), 255);
        assert_eq!(w.tcnt(256), 254);
        assert_eq!(w.tcnt(509), 1);
        assert_eq!(w.tcnt(510), 0);
        assert_eq!(w.next_top(0), 255);
        assert_eq!(w.next_top(255), 765);
    }

    #[test]
    fn prescaler_scales_the_period() {
        let w = PhaseCorrect {
            start: 0,
            prescaler: 64,
        };
        assert!((w.frequency_hz(F_CPU) - 490.196).abs() < 1e-3); // Arduino's default
    }

    fn started_timer4(cycle: u64) -> PwmTimer {
        let mut t = PwmTimer::timer4();
        t.write(0xA0, 0b0000_0001, cycle).unwrap(); // WGM40
        t.write(0xA1, 0b0000_0001, cycle).unwrap(); // CS40
        t
    }

    #[test]
    fn ocr_write_takes_effect_at_top_through_temp() {
        let mut t = started_timer4(100);
        t.write(0xA0, 0b0010_0001, 100).unwrap(); // COM4B1 + WGM40
        t.write(0xAB, 0x00, 200).unwrap(); // OCR4BH -> TEMP
        let e = t.write(0xAA, 170, 201).unwrap(); // OCR4BL commits
        assert!(e.pending_update);
        assert_eq!(
            t.drive('B', F_CPU),
            PinDrive::Pwm {
                duty: 0.0,
                hz: 16e6 / 510.0
            }
        );
        assert_eq!(t.pending_update_at(201), Some(100 + 255));
        t.apply_buffered();
        match t.drive('B', F_CPU) {
            PinDrive::Pwm { duty, .. } => assert!((duty - 170.0 / 255.0).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        assert_eq!(t.drive('A', F_CPU), PinDrive::Gpio);
    }

    #[rstest]
    #[case::fast_pwm(0b11, 0b001, "waveform mode 3")]
    #[case::ctc(0b00, 0b01_001, "waveform mode 4")]
    fn unverified_modes_are_refused(#[case] a: u8, #[case] b: u8, #[case] msg: &str) {
        let mut t = PwmTimer::timer4();
        t.write(0xA0, a, 0).unwrap();
        let err = t.write(0xA1, b, 0).unwrap_err();
        assert!(err.to_string().contains(msg), "{err}");
    }

    #[test]
    fn interrupts_and_counter_access_are_refused() {
        let mut t = PwmTimer::timer2();
        assert!(t.write(0x70, 1, 0).is_err());
        assert!(t.write(0xB2, 0, 0).is_err());
        assert!(t.read(0xB2).to_string().contains("counter"));
    }
}
