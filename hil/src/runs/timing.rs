//! Timing budgets of the firmware, measured cycle-exactly from ELF symbols.
//!
//! A [`TimingProbe`] watches every executed instruction of a run and measures:
//! - the control tick, when the firmware has a control function
//!   (`ht_control_tick`, or the one its test description names): the period
//!   and jitter of its entries, and its execution time (min/mean/max
//!   cycles) with the time spent in interrupts that preempted it taken out;
//! - each interrupt vector used: duration from the vector to the end of its
//!   RETI, and for the vectors of the board's encoder A pins (INT0-7 or a
//!   pin-change group, [`crate::board::Pin::interrupt_vector`]) the latency
//!   from the pin's edge to the vector's first instruction;
//! - the longest stretch with interrupts disabled (ISR bodies included, since
//!   the AVR clears I on entry), and where it started;
//! - CPU load (awake fraction) and the stack's high-water mark against the end
//!   of static data (`__bss_end`).
//!
//! Interrupted time is attributed to the interrupt: cycles spent in an ISR
//! that ran while the control function was active are subtracted from the
//! function's execution time.
//!
//! Everything that differs between MCUs comes from the board's MCU's
//! description ([`crate::mcu::chip`]): where the vectors are and their
//! names, how wide a return address an interrupt pushes, and the
//! datasheet's response time.

use std::collections::BTreeMap;

use serde::Serialize;
use thiserror::Error;

use plant_model::Side;

use crate::bench::{Observer, Step};
use crate::board::Board;
use crate::firmware::elf::Firmware;
use crate::mcu::chip::Chip;

const RETI: u16 = 0x9518;
const RET: u16 = 0x9508;

mod budgets;
#[cfg(test)]
mod tests;

pub use budgets::Budgets;

#[derive(Debug, Error)]
pub enum TimingError {
    #[error("cannot read the budgets file {path}: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("budgets file {path}: {source} (see fixtures/timing-budgets.toml for the keys)")]
    Parse {
        path: String,
        source: toml::de::Error,
    },
    #[error("the firmware has no function {0:?} to time")]
    NoFunction(String),
    #[error(
        "budgets file {path} sets {field}, but the firmware names no control function to time \
         (name it with the test description's symbols.control or --function, or leave \
         control_max_us, tick_period_us and tick_jitter_max_us out)"
    )]
    NoControlFunction { path: String, field: &'static str },
    #[error("budgets file {path}: {field} = {value}: {allowed}")]
    Invalid {
        path: String,
        field: &'static str,
        value: String,
        allowed: &'static str,
    },
}

/// Min, mean, max and count of a series of cycle counts.
#[derive(Debug, Clone, Copy, Default, Serialize, PartialEq)]
pub struct Stats {
    pub count: u64,
    pub min: u64,
    pub max: u64,
    pub mean: f64,
    #[serde(skip)]
    sum: u128,
}

impl Stats {
    fn add(&mut self, v: u64) {
        if self.count == 0 || v < self.min {
            self.min = v;
        }
        self.max = self.max.max(v);
        self.count += 1;
        self.sum += v as u128;
        self.mean = self.sum as f64 / self.count as f64;
    }
}

#[derive(Debug, Clone)]
struct IsrFrame {
    vector: u8,
    entry: u64,
    /// The response's cycles the CPU spent awake before `entry`.
    response: u64,
}

#[derive(Debug, Clone)]
struct FnFrame {
    entry: u64,
    sp: u16,
    interrupted: u64,
}

/// Per-vector measurements.
#[derive(Debug, Clone, Default, Serialize, PartialEq)]
pub struct IsrTiming {
    pub vector: u8,
    pub name: String,
    /// Cycles from the vector's first instruction to the end of RETI.
    pub duration: Stats,
    /// Cycles from an encoder's A edge to the vector (the vectors of the
    /// encoders' A pins only): the instruction in progress, handlers before
    /// it, and the response (see [`RESPONSE_CYCLES`]).
    pub latency: Stats,
}

/// An encoder's A pin and the vector whose latency is measured for it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EncoderVector {
    /// "left" or "right".
    pub side: &'static str,
    /// The pin's Arduino name ("D2").
    pub pin: String,
    /// The vector its edges request (None: the pin cannot interrupt).
    pub vector: Option<u8>,
    pub name: Option<String>,
}

/// Watches a run; see the module docs.
pub struct TimingProbe {
    chip: &'static Chip,
    /// The control function's name and address (None: not timed).
    control_fn: Option<(String, u32)>,
    vectors: BTreeMap<u32, u8>,
    encoders: Vec<EncoderVector>,
    /// Per encoder vector, the last edge a latency was measured from: an
    /// entry with no newer edge (a B edge on the same pin-change group, a
    /// flag set by the firmware) measures nothing.
    served: BTreeMap<u8, u64>,
    isr_stack: Vec<IsrFrame>,
    fn_frame: Option<FnFrame>,
    /// Cycle of every entry of the control function, in order (one per
    /// 15 ms: about 240 000 in an hour of robot time).
    entries: Vec<u64>,
    period_nominal: u64,
    control: Stats,
    isrs: BTreeMap<u8, IsrTiming>,
    interrupts_off_since: Option<(u64, u32)>,
    longest_off: (u64, u32),
    min_sp: u16,
    awake: u64,
    total: u64,
}

impl TimingProbe {
    /// Probe the control function `control_fn` (a symbol; None: none),
    /// whose nominal period is `period_cycles`, and the latency of the
    /// interrupts of `board`'s encoder A pins, on the board's MCU.
    pub fn new(
        fw: &Firmware,
        control_fn: Option<&str>,
        period_cycles: u64,
        board: &Board,
    ) -> Result<Self, TimingError> {
        let control = match control_fn {
            Some(name) => Some((
                name.to_string(),
                fw.symbol(name)
                    .map_err(|_| TimingError::NoFunction(name.into()))?
                    .addr,
            )),
            None => None,
        };
        let chip = board.mcu.chip();
        let vectors = (1..chip.vectors.len() as u8)
            .map(|n| (chip.vector_address(n), n))
            .collect();
        let encoders = Side::BOTH
            .map(|side| {
                let a = board.encoder(side).a;
                let vector = a.interrupt_vector();
                EncoderVector {
                    side: match side {
                        Side::Left => "left",
                        Side::Right => "right",
                    },
                    pin: a.name(),
                    vector,
                    name: vector.map(|v| vector_name(chip, v)),
                }
            })
            .to_vec();
        Ok(Self {
            chip,
            control_fn: control,
            vectors,
            encoders,
            served: BTreeMap::new(),
            isr_stack: Vec::new(),
            fn_frame: None,
            entries: Vec::new(),
            period_nominal: period_cycles,
            control: Stats::default(),
            isrs: BTreeMap::new(),
            interrupts_off_since: None,
            longest_off: (0, 0),
            min_sp: u16::MAX,
            awake: 0,
            total: 0,
        })
    }
}

/// Vector `n`'s name on `chip` (its number, when the chip has none).
fn vector_name(chip: &Chip, n: u8) -> String {
    chip.vector_name(n)
        .map(str::to_string)
        .unwrap_or_else(|| format!("vector {n}"))
}

impl Observer for TimingProbe {
    fn step(&mut self, s: &Step) {
        let dt = s.cycle_after - s.cycle_before;
        self.total += dt;
        if !s.slept {
            self.awake += dt;
        }
        self.min_sp = self.min_sp.min(s.sp_after);

        // Leaving an interrupt: RETI executed.
        if !s.slept && s.opcode == RETI {
            if let Some(frame) = self.isr_stack.pop() {
                let d = s.cycle_after - frame.entry;
                self.isrs.entry(frame.vector).or_default().duration.add(d);
                if let Some(f) = &mut self.fn_frame {
                    if self.isr_stack.is_empty() {
                        // The response (before the vector) is the
                        // interrupt's time too.
                        f.interrupted += frame.response + d;
                    }
                }
            }
        }
        // Leaving the control function: RET at the depth it was entered.
        if let Some(f) = &self.fn_frame {
            if !s.slept && s.opcode == RET && s.sp_before == f.sp && self.isr_stack.is_empty() {
                let f = self.fn_frame.take().expect("frame");
                self.control.add(s.cycle_after - f.entry - f.interrupted);
            }
        }
        // Entering an interrupt: the PC landed on a vector slot it was not
        // already at.
        if s.pc_after != s.pc_before {
            if let Some(&v) = self.vectors.get(&s.pc_after) {
                // A jump to the slot is an interrupt only if the response
                // cleared I or the stack grew by (at least) a return address.
                // The response ends the step of the instruction before it,
                // which may have popped (a `pop`, a `ret`): then the stack
                // is no lower, but I went from set to clear, which no
                // instruction that lands on a vector does.
                let responded = s.interrupts_before && !s.interrupts_after;
                let pushed = u16::from(self.chip.pc_bytes);
                if responded || s.sp_after + pushed <= s.sp_before {
                    // The response ends the step; waking, the CPU starts up
                    // first (asleep), then responds (awake).
                    let response = self.chip.response_cycles();
                    if s.slept {
                        self.awake += response;
                    }
                    self.isr_stack.push(IsrFrame {
                        vector: v,
                        entry: s.cycle_after,
                        response,
                    });
                    let t = self.isrs.entry(v).or_default();
                    t.vector = v;
                    t.name = vector_name(self.chip, v);
                    // The newest A edge of the encoders on this vector
                    // (two may share a pin-change group), if not served.
                    let served = self.served.get(&v).copied().unwrap_or(0);
                    let edge = self
                        .encoders
                        .iter()
                        .zip(s.last_a_edge)
                        .filter(|(e, _)| e.vector == Some(v))
                        .map(|(_, edge)| edge)
                        .filter(|&e| e > served && e <= s.cycle_after)
                        .max();
                    if let Some(e) = edge {
                        t.latency.add(s.cycle_after - e);
                        self.served.insert(v, e);
                    }
                }
            }
            let control = self.control_fn.as_ref().map(|c| c.1);
            if Some(s.pc_after) == control && self.fn_frame.is_none() {
                self.entries.push(s.cycle_after);
                self.fn_frame = Some(FnFrame {
                    entry: s.cycle_after,
                    sp: s.sp_after,
                    interrupted: 0,
                });
            }
        }
        // Interrupts-disabled stretches (awake only: `sei; sleep` sleeps with
        // I set).
        match (s.interrupts_after, self.interrupts_off_since) {
            (false, None) => self.interrupts_off_since = Some((s.cycle_after, s.pc_after)),
            (true, Some((since, pc))) => {
                let d = s.cycle_after.saturating_sub(since);
                if d > self.longest_off.0 {
                    self.longest_off = (d, pc);
                }
                self.interrupts_off_since = None;
            }
            _ => {}
        }
    }

    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any> {
        self
    }
}

/// What a probe measured, in cycles and microseconds.
#[derive(Debug, Clone, Serialize)]
pub struct TimingReport {
    pub clock_hz: u32,
    /// The board's MCU, whose vectors, return addresses and response these
    /// are.
    pub mcu: crate::mcu::chip::Mcu,
    /// None: the firmware named none, and it was not timed.
    pub control_function: Option<String>,
    pub control_cycles: Stats,
    /// Periods between consecutive entries of the control function, except
    /// those across a segment start (see [`TimingProbe::report`]).
    pub tick_period_cycles: Stats,
    pub tick_jitter_max_cycles: u64,
    /// Periods left out because a segment (leg or turn) started inside
    /// them: the firmware restarts its tick there, after a pause.
    pub tick_restarts: usize,
    pub isrs: Vec<IsrTiming>,
    /// The encoders' A pins and their vectors: the latencies are theirs.
    pub encoder_vectors: Vec<EncoderVector>,
    pub interrupts_off_max_cycles: u64,
    pub interrupts_off_max_at: Option<String>,
    pub stack_min_sp: u16,
    pub static_data_end: u16,
    pub stack_margin_bytes: i64,
    pub cpu_load: f64,
}

impl TimingProbe {
    /// What was measured. `segment_starts`: the cycles at which the run's
    /// legs and turns started. A firmware stops its control tick between
    /// segments and restarts it at the next one, so the period across a
    /// segment start is a pause, not jitter, and is left out (counted in
    /// [`TimingReport::tick_restarts`]); a tick missed while a segment
    /// runs still counts.
    pub fn report(&self, fw: &Firmware, clock_hz: u32, segment_starts: &[u64]) -> TimingReport {
        let bss_end = fw.symbol("__bss_end").map(|s| s.addr as u16).unwrap_or(0);
        let mut periods = Stats::default();
        let mut jitter = 0;
        let mut restarts = 0;
        for w in self.entries.windows(2) {
            let (from, to) = (w[0], w[1]);
            if segment_starts.iter().any(|&c| from < c && c <= to) {
                restarts += 1;
                continue;
            }
            let p = to - from;
            periods.add(p);
            jitter = jitter.max(p.abs_diff(self.period_nominal));
        }
        TimingReport {
            clock_hz,
            mcu: self.chip.mcu,
            control_function: self.control_fn.as_ref().map(|c| c.0.clone()),
            control_cycles: self.control,
            tick_period_cycles: periods,
            tick_jitter_max_cycles: jitter,
            tick_restarts: restarts,
            isrs: self.isrs.values().cloned().collect(),
            encoder_vectors: self.encoders.clone(),
            interrupts_off_max_cycles: self.longest_off.0,
            interrupts_off_max_at: fw
                .function_at(self.longest_off.1)
                .map(|(n, o)| format!("{n}+0x{o:x}")),
            stack_min_sp: self.min_sp,
            static_data_end: bss_end,
            stack_margin_bytes: self.min_sp as i64 - bss_end as i64,
            cpu_load: if self.total > 0 {
                self.awake as f64 / self.total as f64
            } else {
                0.0
            },
        }
    }
}

/// One row of the budget table.
#[derive(Debug, Clone, Serialize)]
pub struct BudgetRow {
    pub what: String,
    /// None: nothing was measured (a latency with no sample), which is no
    /// pass.
    pub measured: Option<f64>,
    pub budget: f64,
    pub unit: &'static str,
    pub pass: bool,
}

impl TimingReport {
    fn us(&self, cycles: f64) -> f64 {
        cycles * 1e6 / self.clock_hz as f64
    }

    /// The encoder latency's row name and its longest latency in cycles:
    /// None unless every encoder's vector measured at least one (an
    /// encoder pin that cannot interrupt, or a vector the firmware never
    /// took on an edge, is not measured).
    fn encoder_latency(&self) -> (String, Option<u64>) {
        let mut names: Vec<String> = Vec::new();
        let mut longest = Some(0);
        for e in &self.encoder_vectors {
            let name = e.name.clone().unwrap_or_else(|| format!("{} none", e.pin));
            let lat = e
                .vector
                .and_then(|v| self.isrs.iter().find(|i| i.vector == v))
                .map(|i| i.latency)
                .filter(|l| l.count > 0);
            longest = longest.zip(lat).map(|(m, l)| m.max(l.max));
            if !names.contains(&name) {
                names.push(name);
            }
        }
        (
            format!("encoder edge to handler ({}), longest", names.join(", ")),
            longest,
        )
    }

    /// Compare against `b`.
    pub fn check(&self, b: &Budgets) -> Vec<BudgetRow> {
        let mut rows = Vec::new();
        let mut row = |what: &str, measured: Option<f64>, budget: f64, unit, upper: bool| {
            rows.push(BudgetRow {
                what: what.into(),
                measured,
                budget,
                unit,
                pass: measured.is_some_and(|m| if upper { m <= budget } else { m >= budget }),
            })
        };
        // A control function that never ran, or whose tick never made a
        // period, measured nothing.
        let name = self
            .control_function
            .as_deref()
            .unwrap_or("control function");
        if let Some(budget) = b.control_max_us {
            row(
                &format!("{name} execution, max"),
                (self.control_cycles.count > 0).then(|| self.us(self.control_cycles.max as f64)),
                budget,
                "us",
                true,
            );
        }
        if let Some(budget) = b.tick_jitter_max_us {
            row(
                "control tick jitter, max |period - nominal|",
                (self.tick_period_cycles.count > 0)
                    .then(|| self.us(self.tick_jitter_max_cycles as f64)),
                budget,
                "us",
                true,
            );
        }
        let isr_max = self.isrs.iter().map(|i| i.duration.max).max().unwrap_or(0);
        row(
            "interrupt handler, longest",
            Some(self.us(isr_max as f64)),
            b.isr_max_us,
            "us",
            true,
        );
        let (what, lat) = self.encoder_latency();
        row(
            &what,
            lat.map(|c| self.us(c as f64)),
            b.isr_latency_max_us,
            "us",
            true,
        );
        row(
            "interrupts disabled, longest",
            Some(self.us(self.interrupts_off_max_cycles as f64)),
            b.interrupts_off_max_us,
            "us",
            true,
        );
        row(
            "stack margin",
            Some(self.stack_margin_bytes as f64),
            b.stack_margin_min_bytes as f64,
            "bytes",
            false,
        );
        row("CPU load", Some(self.cpu_load), b.cpu_load_max, "", true);
        rows
    }

    pub fn render(&self, rows: &[BudgetRow]) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let c = |v: u64| self.us(v as f64);
        match &self.control_function {
            Some(name) => {
                let _ = writeln!(
                    s,
                    "control function {}: {} calls, {:.1} / {:.1} / {:.1} us (min / mean / max, interrupts excluded)",
                    name,
                    self.control_cycles.count,
                    c(self.control_cycles.min),
                    self.us(self.control_cycles.mean),
                    c(self.control_cycles.max)
                );
                let _ = writeln!(
                    s,
                    "control tick: period {:.3} / {:.3} / {:.3} ms, jitter max {:.2} us{}",
                    c(self.tick_period_cycles.min) / 1e3,
                    self.us(self.tick_period_cycles.mean) / 1e3,
                    c(self.tick_period_cycles.max) / 1e3,
                    c(self.tick_jitter_max_cycles),
                    match self.tick_restarts {
                        0 => String::new(),
                        n => format!(" ({n} restarts at segment starts left out)"),
                    }
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "control function: none named (symbols.control, --function), not timed"
                );
            }
        }
        let _ = writeln!(
            s,
            "interrupts on the {}: response {} cycles ({} waking), {}-byte return addresses",
            self.mcu,
            self.mcu.chip().response_cycles(),
            self.mcu.chip().response_cycles() + self.mcu.chip().wake_up_cycles(),
            self.mcu.chip().pc_bytes
        );
        for i in &self.isrs {
            let _ = write!(
                s,
                "  {:<13} {:>7} runs, {:6.2} / {:6.2} / {:6.2} us",
                i.name,
                i.duration.count,
                c(i.duration.min),
                self.us(i.duration.mean),
                c(i.duration.max)
            );
            if i.latency.count > 0 {
                let _ = write!(
                    s,
                    ", latency from edge {:.2} / {:.2} / {:.2} us",
                    c(i.latency.min),
                    self.us(i.latency.mean),
                    c(i.latency.max)
                );
            }
            let _ = writeln!(s);
        }
        for e in &self.encoder_vectors {
            let seen = e
                .vector
                .and_then(|v| self.isrs.iter().find(|i| i.vector == v))
                .is_some_and(|i| i.latency.count > 0);
            match &e.name {
                None => {
                    let _ = writeln!(
                        s,
                        "  {} encoder A {}: cannot interrupt, latency not measured",
                        e.side, e.pin
                    );
                }
                Some(name) if !seen => {
                    let _ = writeln!(
                        s,
                        "  {} encoder A {}: {name} never ran after an edge, latency not measured",
                        e.side, e.pin
                    );
                }
                Some(_) => {}
            }
        }
        let _ = writeln!(
            s,
            "interrupts disabled at most {:.2} us (at {}), lowest SP 0x{:04x}, static data ends 0x{:04x}, CPU load {:.2} %",
            c(self.interrupts_off_max_cycles),
            self.interrupts_off_max_at.as_deref().unwrap_or("?"),
            self.stack_min_sp,
            self.static_data_end,
            self.cpu_load * 100.0
        );
        let _ = writeln!(
            s,
            "\n  {:<50} {:>12} {:>12}  result",
            "budget", "measured", "limit"
        );
        for r in rows {
            let (measured, result) = match r.measured {
                Some(m) => (
                    format!("{m:>9.2} {:<2}", r.unit),
                    if r.pass { "ok" } else { "EXCEEDED" },
                ),
                None => (format!("{:>12}", "-"), "NOT MEASURED"),
            };
            let _ = writeln!(
                s,
                "  {:<50} {measured} {:>9.2} {:<2}  {result}",
                r.what, r.budget, r.unit,
            );
        }
        s
    }
}
