//! One emulated timer: its registers, as the firmware writes and reads
//! them, and the waveform they select (see the parent module).

use super::layout::Layout;
use super::mode::{self, Action, Mode, Top, Update};
use super::waveform::{ChannelWave, Counter, Lead};
use super::{Config, PwmError, TimerId};

#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Channel {
    /// OCR value the compare unit uses.
    pub(super) ocr: u32,
    /// Value written in a buffered mode, waiting for its update point.
    pub(super) buffered: Option<u32>,
    /// The output's level at a cycle since which nothing changed it but
    /// the waveform (see [`ChannelWave::anchor`]).
    pub(super) anchor: (u64, bool),
}

/// What is running: the counter, or the value it holds while stopped.
#[derive(Debug, Clone, Copy)]
pub(super) enum Count {
    Running(Counter),
    /// Stopped at this TCNT (counting up or down when it stopped).
    Held {
        tcnt: u32,
        up: bool,
    },
}

/// One emulated timer: its registers and waveform.
#[derive(Debug, Clone)]
pub struct PwmTimer {
    pub(super) layout: Layout,
    pub(super) tccra: u8,
    pub(super) tccrb: u8,
    pub(super) assr: u8,
    /// The shared high byte of 16-bit accesses (datasheet 17.3).
    pub(super) temp: u8,
    pub(super) icr: u32,
    pub(super) channels: [Channel; 3],
    pub(super) count: Count,
    /// simavr runs the timer (its counter, interrupts and flags); this
    /// model follows the writes only to compute the outputs (see
    /// [`PwmTimer::mirror`]).
    pub(super) mirrored: bool,
}

/// The effect of a register write on the outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WriteEffect {
    /// Outputs changed now.
    pub outputs_changed: bool,
    /// A buffered OCR value waits for its update point.
    pub pending_update: bool,
}

/// What a PWM-capable pin outputs, as far as the timer decides it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum PinDrive {
    /// The timer does not drive the pin: its PORT/DDR bits do.
    Gpio,
    /// A waveform of `duty` (fraction of time high) at `hz`; constant
    /// levels are reported as duty 0 or 1 (a stopped timer's at 0 Hz).
    Pwm { duty: f64, hz: f64 },
}

impl PwmTimer {
    pub fn timer2() -> Self {
        Self::new(Layout::TIMER2)
    }

    pub fn timer4() -> Self {
        Self::new(Layout::TIMER4)
    }

    /// The ATmega2560's timer `n` (0-5), emulated: the model is the whole
    /// timer, its registers are the bench's and simavr never clocks it.
    pub fn number(n: u8) -> Option<Self> {
        Layout::of(n).map(Self::new)
    }

    /// The ATmega2560's timer `n` (0-5), mirrored: simavr runs it (its
    /// counter, interrupts, flags: what firmware that times itself with
    /// the timer needs) and the model follows the firmware's writes to its
    /// mode, clock and compare registers to compute the outputs, which
    /// simavr gets wrong. Its interrupt mask, counter reads and flags are
    /// simavr's: [`PwmTimer::write_addresses`] leaves TIMSKn out and
    /// [`PwmTimer::read_addresses`] is empty. The model's counter starts
    /// with simavr's, at the write that clocks the timer.
    pub fn mirror(n: u8) -> Option<Self> {
        Layout::of(n).map(|l| Self {
            mirrored: true,
            ..Self::new(l)
        })
    }

    pub fn is_mirrored(&self) -> bool {
        self.mirrored
    }

    fn new(layout: Layout) -> Self {
        Self {
            mirrored: false,
            layout,
            tccra: 0,
            tccrb: 0,
            assr: 0,
            temp: 0,
            icr: 0,
            channels: [Channel::default(); 3],
            count: Count::Held { tcnt: 0, up: true },
        }
    }

    pub fn id(&self) -> TimerId {
        self.layout.id
    }

    /// Every data-space address whose writes this timer handles.
    pub fn write_addresses(&self) -> Vec<u16> {
        let mut v = self.layout.write_addresses();
        if self.mirrored {
            v.retain(|&a| a != self.layout.timsk);
        }
        v
    }

    /// Whether `addr` is one of [`PwmTimer::write_addresses`] (without
    /// building the list: this runs at each write).
    pub fn owns_write(&self, addr: u16) -> bool {
        self.layout.owns_write(addr) && !(self.mirrored && addr == self.layout.timsk)
    }

    /// Addresses whose reads the timer answers: the counter, and the
    /// interrupt flags (refused: not emulated); none when mirrored.
    pub fn read_addresses(&self) -> Vec<u16> {
        if self.mirrored {
            Vec::new()
        } else {
            self.layout.read_addresses()
        }
    }

    pub(super) fn sixteen_bit(&self) -> bool {
        self.layout.sixteen_bit
    }

    fn wgm(&self) -> u8 {
        let low = self.tccra & 0b11;
        let high = if self.sixteen_bit() {
            (self.tccrb >> 3) & 0b11
        } else {
            (self.tccrb >> 3) & 0b1
        };
        high << 2 | low
    }

    fn cs(&self) -> u8 {
        self.tccrb & 0b111
    }

    /// The mode and clock select in force.
    pub fn config(&self) -> Config {
        Config {
            timer: self.layout.id,
            wgm: self.wgm(),
            cs: self.cs(),
            mode: self.mode(),
            max: if self.sixteen_bit() { 0xFFFF } else { 0xFF },
        }
    }

    pub(super) fn mode(&self) -> Option<Mode> {
        Mode::decode(self.wgm(), self.sixteen_bit())
    }

    /// Timer 2 clocked from its asynchronous oscillator (ASSR AS2/EXCLK).
    pub(super) fn asynchronous(&self) -> bool {
        self.assr & 0x60 != 0
    }

    /// What the bench does not emulate in the configuration in force: a
    /// clock that is not the CPU's (external, asynchronous) or a reserved
    /// mode, on a clocked timer. The bench then holds the counter; the
    /// caller judges whether that can matter (see `bench/timers.rs`).
    /// Also a counter above TOP counting up to MAX (see
    /// [`Lead`]) with a connected output whose OCR it would meet on the
    /// way: the model holds the outputs through a lead.
    pub fn unverified(&self, cycle: u64) -> Option<PwmError> {
        let config = self.config();
        let cs = self.cs();
        match mode::prescaler(cs, self.layout.prescalers) {
            Some(None) => None,
            None => Some(PwmError::ExternalClock { config }),
            Some(Some(_)) if self.asynchronous() => Some(PwmError::Asynchronous { config }),
            Some(Some(_)) if config.mode.is_none() => Some(PwmError::ReservedMode { config }),
            Some(Some(_)) => {
                let c = self.running()?;
                let lead = c.in_lead(cycle).filter(|l| l.up)?;
                let tcnt = c.tcnt(cycle);
                let met = (0..self.layout.ocr.len()).any(|i| {
                    let ocr = self.channels[i].ocr;
                    self.action(i) != Action::Disconnected && ocr > tcnt && ocr <= config.max
                });
                met.then_some(PwmError::MatchAboveTop {
                    config,
                    tcnt: lead.tcnt,
                    top: c.top,
                })
            }
        }
    }

    /// Channel `ch`'s ('A', 'B', 'C') compare output drives its pin.
    pub fn channel_connected(&self, ch: char) -> bool {
        let i = self.layout.ocr.iter().position(|&(c, _)| c == ch);
        i.is_some_and(|i| self.action(i) != Action::Disconnected)
    }

    /// A compare output drives its pin.
    pub fn connected(&self) -> bool {
        (0..self.layout.ocr.len()).any(|i| self.action(i) != Action::Disconnected)
    }

    fn com(&self, i: usize) -> u8 {
        (self.tccra >> (6 - 2 * i)) & 0b11
    }

    pub(super) fn action(&self, i: usize) -> Action {
        match self.mode() {
            Some(m) => m.action(i, self.com(i)),
            None if self.com(i) == 0 => Action::Disconnected,
            // A reserved mode: the datasheet says nothing of the outputs;
            // taken as toggling (connected: an unverified mode with an
            // output is refused at once).
            None => Action::Toggle,
        }
    }

    /// The counter's TOP in mode `m` with the registers in force.
    pub(super) fn top(&self, m: &Mode) -> u32 {
        match m.top {
            Top::Fixed(t) => t,
            Top::Ocra => self.channels[0].ocr,
            Top::Icr => self.icr,
        }
    }

    pub(super) fn running(&self) -> Option<Counter> {
        match self.count {
            Count::Running(c) => Some(c),
            Count::Held { .. } => None,
        }
    }

    /// TCNT at `cycle`.
    pub fn tcnt(&self, cycle: u64) -> u32 {
        match self.count {
            Count::Running(c) => c.tcnt(cycle),
            Count::Held { tcnt, .. } => tcnt,
        }
    }

    /// Channel `i`'s output as a function of the cycle (a stopped timer's
    /// holds its level: an idle counter).
    fn wave(&self, i: usize) -> ChannelWave {
        let ch = self.channels[i];
        let counter = self
            .running()
            .unwrap_or(Counter::periodic(ch.anchor.0, 0, 1, 0, false));
        let action = match (self.running(), self.action(i)) {
            (None, Action::Disconnected) => Action::Disconnected,
            // Stopped: no match comes; the output holds.
            (None, _) => Action::Clear,
            (Some(_), a) => a,
        };
        let ocr = if self.running().is_some() {
            ch.ocr
        } else {
            u32::MAX
        };
        ChannelWave {
            counter,
            ocr,
            action,
            anchor: ch.anchor,
        }
    }

    /// Channel `i`'s output level at `cycle`.
    fn level(&self, i: usize, cycle: u64) -> bool {
        self.wave(i).level(cycle)
    }

    pub(super) fn levels(&self, cycle: u64) -> [bool; 3] {
        [0, 1, 2].map(|i| i < self.layout.ocr.len() && self.level(i, cycle))
    }

    /// The registers changed at `cycle`: the counter goes on from where it
    /// is in the new mode, the outputs from the `levels` they had.
    pub(super) fn restart(&mut self, cycle: u64, levels: &[bool; 3]) -> Result<(), PwmError> {
        let (tcnt, up, into_step, old) = match self.count {
            Count::Running(c) => (
                c.tcnt(cycle),
                c.counting_up(cycle),
                (cycle - c.in_lead(cycle).map_or(c.since, |l| l.since)) % c.prescaler as u64,
                Some(c),
            ),
            Count::Held { tcnt, up } => (tcnt, up, 0, None),
        };
        let prescaler = match mode::prescaler(self.cs(), self.layout.prescalers) {
            Some(Some(n)) if !self.asynchronous() => Some(n),
            _ => None,
        };
        let next = match (self.mode(), prescaler) {
            (Some(m), Some(n)) => {
                let top = self.top(&m);
                let dual = m.dual_slope();
                match old {
                    // Same counting: the counter goes on as it was.
                    Some(c) if c.prescaler == n && c.top == top && c.dual == dual => {
                        Count::Running(c)
                    }
                    _ => {
                        // A new prescaler starts its steps now.
                        let into = if old.is_some_and(|c| c.prescaler == n) {
                            into_step
                        } else {
                            0
                        };
                        let start = cycle - into;
                        let step = n as u64;
                        Count::Running(if tcnt > top {
                            // Above TOP: on to MAX (or down to BOTTOM)
                            // first, see `Lead`.
                            let up = up || !dual;
                            let steps = if up {
                                (m.max + 1 - tcnt) as u64
                            } else {
                                tcnt as u64
                            };
                            Counter {
                                lead: Some(Lead {
                                    since: start,
                                    tcnt,
                                    up,
                                }),
                                ..Counter::periodic(start + steps * step, 0, n, top, dual)
                            }
                        } else {
                            let phase0 = if dual && !up && tcnt < top {
                                2 * top - tcnt
                            } else {
                                tcnt
                            };
                            Counter::periodic(start, phase0, n, top, dual)
                        })
                    }
                }
            }
            // Stopped, or not emulated: the counter holds.
            _ => Count::Held { tcnt, up },
        };
        self.count = next;
        for (i, ch) in self.channels.iter_mut().enumerate() {
            ch.anchor = (cycle, levels[i]);
        }
        if self.mode().is_none_or(|m| m.update() == Update::Immediate) {
            // Normal and CTC: the buffer is transparent.
            for ch in &mut self.channels {
                if let Some(v) = ch.buffered.take() {
                    ch.ocr = v;
                }
            }
        }
        Ok(())
    }

    /// The next cycle after `after` at which the outputs change other than
    /// by their waveform: a buffered OCR value's update point (TOP or
    /// BOTTOM), or the first match of a set or clear output.
    /// Also the end of a lead (when the periodic waveform starts).
    pub fn pending_update_at(&self, after: u64) -> Option<u64> {
        let counter = self.running()?;
        let mut next = counter.in_lead(after).map(|_| counter.since);
        if self.channels.iter().any(|c| c.buffered.is_some()) {
            if let Some(m) = self.mode() {
                let p = match m.update() {
                    Update::AtTop => Some(counter.top),
                    Update::AtBottom => Some(0),
                    Update::Immediate => None,
                };
                if let Some(p) = p {
                    let at = counter.next_entry(p, after + 1);
                    next = Some(next.map_or(at, |n: u64| n.min(at)));
                }
            }
        }
        for i in 0..self.layout.ocr.len() {
            let w = self.wave(i);
            if matches!(w.action, Action::Set | Action::Clear) && w.level(after) == w.anchor.1 {
                if let Some(m) = w.next_match(after) {
                    if w.level(m) != w.anchor.1 {
                        next = Some(next.map_or(m, |n: u64| n.min(m)));
                    }
                }
            }
        }
        next
    }

    /// The update point `at` came: apply buffered OCR values (TOP may
    /// change with OCRnA) and let set and clear outputs latch.
    pub fn apply_update(&mut self, at: u64) -> Result<(), PwmError> {
        let levels = self.levels(at);
        let due = self.running().is_some_and(|c| {
            self.mode().is_some_and(|m| match m.update() {
                Update::AtTop => c.phase(at) == c.top,
                Update::AtBottom => c.phase(at) == 0,
                Update::Immediate => false,
            })
        });
        let saved = self.channels;
        if due {
            for ch in &mut self.channels {
                if let Some(v) = ch.buffered.take() {
                    ch.ocr = v;
                }
            }
        }
        if let Err(e) = self.restart(at, &levels) {
            self.channels = saved;
            return Err(e);
        }
        Ok(())
    }

    /// What channel `ch` ('A', 'B', 'C') does to its pin at `cycle`.
    pub fn drive(&self, ch: char, clock_hz: u32, cycle: u64) -> PinDrive {
        let Some(i) = self.layout.ocr.iter().position(|&(c, _)| c == ch) else {
            return PinDrive::Gpio;
        };
        if self.action(i) == Action::Disconnected {
            return PinDrive::Gpio;
        }
        let w = self.wave(i);
        match self.running() {
            Some(c) if c.in_lead(cycle).is_some() => PinDrive::Pwm {
                duty: f64::from(u8::from(w.level(cycle))),
                hz: 0.0,
            },
            Some(_) => PinDrive::Pwm {
                duty: w.duty(cycle),
                hz: w.frequency_hz(clock_hz),
            },
            // Connected but not clocked: the output holds its level.
            None => PinDrive::Pwm {
                duty: f64::from(u8::from(w.level(cycle))),
                hz: 0.0,
            },
        }
    }

    /// Channel `ch`'s running waveform, for tracing.
    pub fn waveform(&self, ch: char) -> Option<ChannelWave> {
        let i = self.layout.ocr.iter().position(|&(c, _)| c == ch)?;
        self.running()?;
        Some(self.wave(i))
    }
}
