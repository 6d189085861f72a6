//! The counter and the compare outputs as pure functions of the cycle.
//!
//! The counter is described by its *phase*: the step within one period,
//! 0..TOP+1 for the single slope modes (the count itself) and 0..2*TOP for
//! the dual slope ones (0..=TOP counting up, then TOP-1 down to 1). One
//! step lasts N cycles (the prescaler); the steps are counted from the
//! cycle the clock was selected (the bench does not model the phase of the
//! shared prescaler, datasheet 18.1, which simavr does not either).
//!
//! Compare events, by the datasheet's waveforms (17.9, 20.7):
//! - single slope (normal, CTC, fast PWM): a match with OCR acts at the
//!   timer clock after TCNT = OCR, the step that enters phase OCR + 1 (or
//!   BOTTOM when OCR = TOP). Fast PWM non-inverting is high from BOTTOM
//!   through OCR: duty (OCR + 1) / (TOP + 1), a one-step spike at OCR = 0,
//!   constantly high at OCR >= TOP;
//! - dual slope (phase correct, phase and frequency correct): the up
//!   counting match at phase OCR, the down counting one at 2 * TOP - OCR;
//!   non-inverting is high between the down and the up match: duty
//!   OCR / TOP, constantly low at OCR = 0 and high at OCR >= TOP.

use super::mode::Action;

/// The counter above TOP when the mode or TOP changed (a TOP written below
/// it): single slope, or counting up, it runs on to MAX and wraps to BOTTOM
/// (datasheet 17.9.3: "the counter will then have to count to the MAX value
/// ... and wrap around"); a dual slope counter counting down goes on down
/// to BOTTOM. Then the periodic counting starts, at [`Counter::since`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Lead {
    /// The cycle its first step began, and TCNT then.
    pub since: u64,
    pub tcnt: u32,
    pub up: bool,
}

/// The counter of a running timer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counter {
    /// A cycle at which a step of the periodic counting began.
    pub since: u64,
    /// The phase of that step.
    pub phase0: u32,
    /// Prescaler N (CPU cycles per counter step).
    pub prescaler: u32,
    pub top: u32,
    /// Dual slope (counts up to TOP and back down).
    pub dual: bool,
    /// Counting from above TOP to BOTTOM before `since`.
    pub lead: Option<Lead>,
}

impl Counter {
    /// The periodic counting from BOTTOM (phase 0) at `since`.
    pub fn periodic(since: u64, phase0: u32, prescaler: u32, top: u32, dual: bool) -> Self {
        Counter {
            since,
            phase0,
            prescaler,
            top,
            dual,
            lead: None,
        }
    }

    /// The lead in force at `cycle`, if any.
    pub fn in_lead(&self, cycle: u64) -> Option<Lead> {
        self.lead.filter(|_| cycle < self.since)
    }

    /// Steps per period: TOP + 1, or 2 * TOP counting up and down.
    pub fn period_steps(&self) -> u64 {
        if self.dual {
            (2 * self.top as u64).max(1)
        } else {
            self.top as u64 + 1
        }
    }

    pub fn period_cycles(&self) -> u64 {
        self.period_steps() * self.prescaler as u64
    }

    /// One period a second: f_clk / (N (1 + TOP)) single slope, f_clk /
    /// (2 N TOP) dual slope.
    pub fn frequency_hz(&self, clock_hz: u32) -> f64 {
        clock_hz as f64 / (self.prescaler as f64 * self.period_steps() as f64)
    }

    /// The step (counted from phase 0 of the period `since` is in) at `cycle`.
    fn step(&self, cycle: u64) -> u64 {
        self.phase0 as u64 + cycle.saturating_sub(self.since) / self.prescaler as u64
    }

    /// The cycle step `s` begins at (`s` >= phase0).
    fn cycle_of(&self, s: u64) -> u64 {
        self.since + (s - self.phase0 as u64) * self.prescaler as u64
    }

    pub fn phase(&self, cycle: u64) -> u32 {
        (self.step(cycle) % self.period_steps()) as u32
    }

    /// TCNT at `cycle`.
    pub fn tcnt(&self, cycle: u64) -> u32 {
        if let Some(l) = self.in_lead(cycle) {
            let steps = ((cycle - l.since) / self.prescaler as u64) as u32;
            return if l.up { l.tcnt + steps } else { l.tcnt - steps };
        }
        let p = self.phase(cycle);
        if self.dual && p > self.top {
            2 * self.top - p
        } else {
            p
        }
    }

    /// Counting up at `cycle` (always, single slope).
    pub fn counting_up(&self, cycle: u64) -> bool {
        if let Some(l) = self.in_lead(cycle) {
            return l.up;
        }
        !self.dual || self.phase(cycle) < self.top
    }

    /// The first cycle >= `at` at which a step of phase `p` begins.
    pub fn next_entry(&self, p: u32, at: u64) -> u64 {
        let period = self.period_steps();
        let s_min = if at <= self.since {
            self.phase0 as u64
        } else {
            // The first step beginning at or after `at`.
            let n = self.prescaler as u64;
            self.phase0 as u64 + (at - self.since).div_ceil(n)
        };
        let s = s_min + (p as u64 % period + period - s_min % period) % period;
        self.cycle_of(s)
    }

    /// Cycles in [from, to) at which a step of phase `p` begins.
    pub fn entries(&self, p: u32, from: u64, to: u64) -> impl Iterator<Item = u64> {
        let first = self.next_entry(p, from);
        let period = self.period_cycles();
        (0..)
            .map(move |k| first + k * period)
            .take_while(move |&c| c < to)
    }

    /// Steps of phase `p` beginning in (after, until].
    pub fn count_entries(&self, p: u32, after: u64, until: u64) -> u64 {
        if until <= after {
            return 0;
        }
        let first = self.next_entry(p, after + 1);
        if first > until {
            0
        } else {
            (until - first) / self.period_cycles() + 1
        }
    }

    /// The phases at which channel compare value `ocr` matches (see the
    /// module docs); none when OCR is above TOP.
    pub fn match_phases(&self, ocr: u32) -> Vec<u32> {
        if ocr > self.top {
            return Vec::new();
        }
        let period = self.period_steps() as u32;
        if self.dual {
            let down = (2 * self.top - ocr) % period;
            if down == ocr % period {
                vec![ocr % period]
            } else {
                vec![ocr, down]
            }
        } else {
            vec![(ocr + 1) % period]
        }
    }
}

/// One channel's compare output: the counter, the compare value in use,
/// the output's action, and its level at an anchor cycle (what the toggle,
/// set and clear actions start from).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelWave {
    pub counter: Counter,
    pub ocr: u32,
    pub action: Action,
    /// (cycle, level): the output's level at that cycle, since which the
    /// counter, OCR and action have not changed.
    pub anchor: (u64, bool),
}

impl ChannelWave {
    /// Non-inverting PWM level at `cycle`.
    fn pwm_high(&self, cycle: u64) -> bool {
        let c = &self.counter;
        let p = c.phase(cycle);
        let ocr = self.ocr.min(c.top);
        if c.dual {
            p < ocr || p >= 2 * c.top - ocr
        } else {
            self.ocr >= c.top || p <= ocr
        }
    }

    /// Compare matches in (anchor, cycle].
    fn matches_since_anchor(&self, cycle: u64) -> u64 {
        self.counter
            .match_phases(self.ocr)
            .into_iter()
            .map(|p| self.counter.count_entries(p, self.anchor.0, cycle))
            .sum()
    }

    /// Output level at `cycle` (>= the anchor).
    pub fn level(&self, cycle: u64) -> bool {
        if let Some(l) = self.counter.in_lead(cycle) {
            // Counting down, a dual slope output follows the count as in
            // its down slope; counting up past TOP, no match is modelled
            // (the timer judges a lead that would meet one: see
            // `PwmTimer::unverified`).
            let pwm = matches!(self.action, Action::NonInverting | Action::Inverting);
            if pwm && !l.up {
                let high = self.counter.tcnt(cycle) <= self.ocr;
                return high != (self.action == Action::Inverting);
            }
            return self.anchor.1;
        }
        match self.action {
            Action::NonInverting => self.pwm_high(cycle),
            Action::Inverting => !self.pwm_high(cycle),
            Action::Toggle => self.anchor.1 ^ (self.matches_since_anchor(cycle) % 2 == 1),
            Action::Set if self.matches_since_anchor(cycle) > 0 => true,
            Action::Clear if self.matches_since_anchor(cycle) > 0 => false,
            Action::Set | Action::Clear | Action::Disconnected => self.anchor.1,
        }
    }

    /// The first compare match after `after`, if any.
    pub fn next_match(&self, after: u64) -> Option<u64> {
        self.counter
            .match_phases(self.ocr)
            .into_iter()
            .map(|p| self.counter.next_entry(p, after + 1))
            .min()
    }

    /// Fraction of time high, from `cycle` on (a set or clear output: the
    /// level it has then).
    pub fn duty(&self, cycle: u64) -> f64 {
        let c = &self.counter;
        let pwm = || {
            if c.dual {
                self.ocr.min(c.top) as f64 / c.top.max(1) as f64
            } else if self.ocr >= c.top {
                1.0
            } else {
                (self.ocr + 1) as f64 / (c.top + 1) as f64
            }
        };
        match self.action {
            Action::NonInverting => pwm(),
            Action::Inverting => 1.0 - pwm(),
            Action::Toggle => match c.match_phases(self.ocr).len() {
                0 => f64::from(u8::from(self.level(cycle))),
                1 => 0.5,
                _ => {
                    // Dual slope: high either between the up and the down
                    // match (2 (TOP - OCR) steps) or the other 2 OCR.
                    let up = c.next_entry(self.ocr, cycle + 1);
                    let between = 2.0 * (c.top - self.ocr) as f64 / c.period_steps() as f64;
                    if self.level(up) {
                        between
                    } else {
                        1.0 - between
                    }
                }
            },
            Action::Set | Action::Clear | Action::Disconnected => {
                f64::from(u8::from(self.level(cycle)))
            }
        }
    }

    /// The output's frequency: the counter's, half of it for a toggle
    /// matching once per period.
    pub fn frequency_hz(&self, clock_hz: u32) -> f64 {
        let f = self.counter.frequency_hz(clock_hz);
        match self.action {
            Action::Toggle if self.counter.match_phases(self.ocr).len() == 1 => f / 2.0,
            _ => f,
        }
    }

    /// Output edges in [from, to): (cycle, new level), in cycle order.
    pub fn edges(&self, from: u64, to: u64) -> Vec<(u64, bool)> {
        let c = &self.counter;
        let mut out = Vec::new();
        if to <= from {
            return out;
        }
        let flip = self.action == Action::Inverting;
        match self.action {
            Action::NonInverting | Action::Inverting => {
                let ocr = self.ocr.min(c.top);
                let (fall, rise) = if c.dual {
                    if ocr == 0 || ocr == c.top {
                        return out;
                    }
                    (ocr, 2 * c.top - ocr)
                } else {
                    if self.ocr >= c.top {
                        return out;
                    }
                    (ocr + 1, 0)
                };
                for (p, level) in [(fall, false), (rise, true)] {
                    out.extend(c.entries(p, from, to).map(|e| (e, level != flip)));
                }
            }
            Action::Toggle => {
                let mut level = self.level(from);
                let mut all: Vec<u64> = c
                    .match_phases(self.ocr)
                    .into_iter()
                    .flat_map(|p| c.entries(p, from + 1, to))
                    .collect();
                all.sort_unstable();
                for e in all {
                    level = !level;
                    out.push((e, level));
                }
            }
            Action::Set | Action::Clear => {
                let target = self.action == Action::Set;
                if let Some(m) = self.next_match(self.anchor.0) {
                    if m >= from && m < to && self.anchor.1 != target {
                        out.push((m, target));
                    }
                }
            }
            Action::Disconnected => {}
        }
        out.sort_by_key(|e| e.0);
        out
    }
}
