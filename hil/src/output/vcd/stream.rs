//! The trace written as the run makes it: every change goes into a queue
//! ordered as the trace lists changes (by cycle; at one cycle, by the
//! source's place in the trace's order, then in the order the source made
//! them), and is written out once the run has settled past its cycle. What
//! the writer holds is the changes of the last moments of robot time, not
//! of the run: a trace costs no memory per robot second.
//!
//! A trace written after the run from a run's records ([`super::render`])
//! goes through the same queue, so the two are the same bytes.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fmt::Write as _;
use std::io::Write;

use super::{frame_bits, layout, line_text, Layout};
use crate::bench::{DriveEvent, PinEvent, Sample, Tap, USB_SERIAL};
use crate::board::Board;

/// One change of one variable.
enum Change {
    Bit(bool),
    Real(f64),
    Text(String),
}

/// A change waiting to be written, ordered by (cycle, source, sequence).
struct Pending {
    cycle: u64,
    source: u32,
    seq: u64,
    var: u32,
    change: Change,
}

impl Pending {
    fn key(&self) -> (u64, u32, u64) {
        (self.cycle, self.source, self.seq)
    }
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.key() == other.key()
    }
}
impl Eq for Pending {}
impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Pending {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.key().cmp(&other.key())
    }
}

/// One direction of a UART: its line's level and when its last frame ends,
/// and the text its string variable shows.
#[derive(Default)]
struct Direction {
    free: u64,
    low: bool,
    text: String,
}

/// A VCD trace written to `W` as its changes come (see the module docs).
pub struct VcdWriter<W: Write> {
    out: W,
    clock_hz: u32,
    pwm_edges: bool,
    layout: Layout,
    /// The first encoder change's cycle, and each line's level before its
    /// first change (None: no change of the line seen yet).
    first_pin: Option<u64>,
    first_level: [Option<bool>; 4],
    first_sample: Option<[f64; 5]>,
    /// Each bridge input's last drive event: its waveform's edges run to
    /// the next one.
    last_drive: Vec<Option<DriveEvent>>,
    /// Per UART in the layout's order: sent, received.
    directions: Vec<[Direction; 2]>,
    /// The USB serial's line of text so far: sent, received.
    usb_text: [String; 2],
    queue: BinaryHeap<Reverse<Pending>>,
    seq: u64,
    header: bool,
    /// The cycle of the last `#` line (the header's `#0`).
    written: u64,
    /// Changes are written up to (not including) this cycle.
    settled: u64,
    /// Changes that came for a cycle already written (none, when the run
    /// settles as it says).
    late: u64,
    end: u64,
    error: Option<std::io::Error>,
}

impl<W: Write> VcdWriter<W> {
    pub fn new(out: W, clock_hz: u32, board: &Board, pwm_edges: bool) -> Self {
        let layout = layout(board, clock_hz, pwm_edges);
        Self {
            out,
            clock_hz,
            pwm_edges,
            last_drive: vec![None; layout.pins.len()],
            directions: layout.uarts.iter().map(|_| Default::default()).collect(),
            usb_text: Default::default(),
            layout,
            first_pin: None,
            first_level: [None; 4],
            first_sample: None,
            queue: BinaryHeap::new(),
            seq: 0,
            header: false,
            written: 0,
            settled: 0,
            late: 0,
            end: 0,
            error: None,
        }
    }

    fn push(&mut self, cycle: u64, source: u32, var: u32, change: Change) {
        if self.header && cycle < self.settled {
            self.late += 1;
        }
        self.seq += 1;
        self.queue.push(Reverse(Pending {
            cycle,
            source,
            seq: self.seq,
            var,
            change,
        }));
    }

    /// Changes held, not yet written.
    pub fn pending(&self) -> usize {
        self.queue.len()
    }

    /// Changes that came after their cycle was written: each one a trace
    /// out of order (0 when the run settles as it says).
    pub fn late(&self) -> u64 {
        self.late
    }

    /// The last cycle anything changed at so far.
    pub fn end_cycle(&self) -> u64 {
        self.end
    }

    /// An encoder line changed.
    pub fn pin(&mut self, e: PinEvent) {
        self.end = self.end.max(e.cycle);
        let first = *self.first_pin.get_or_insert(e.cycle);
        if let Some(slot) = self.first_level.get_mut(e.line as usize) {
            slot.get_or_insert(e.cycle == first && e.level);
        }
        if let Some(var) = self.layout.encoders[e.line as usize] {
            self.push(e.cycle, 0, var, Change::Bit(e.level));
        }
    }

    /// A bridge input changed; the waveform of its last change, when the
    /// trace shows it, runs up to this one.
    pub fn drive(&mut self, e: &DriveEvent) {
        self.end = self.end.max(e.cycle);
        let Some(i) = self.layout.pins.iter().position(|p| p.0 == e.pin) else {
            return;
        };
        let (_, duty, wave) = self.layout.pins[i];
        let source = 1 + i as u32;
        if let Some(prev) = self.last_drive[i].take() {
            if let (true, Some(w)) = (self.waving(&prev), prev.wave) {
                let mut edges = w.edges(prev.cycle, e.cycle);
                // The waveform lists its falls, then its rises.
                edges.sort_by_key(|x| x.0);
                for (c, level) in edges {
                    self.push(c, source, wave, Change::Bit(level));
                }
            }
        }
        self.push(e.cycle, source, duty, Change::Real(e.duty));
        let level = if e.duty <= 0.0 {
            Some(false)
        } else if e.duty >= 1.0 || !self.pwm_edges {
            Some(true)
        } else {
            e.wave.map(|w| w.level(e.cycle))
        };
        if let Some(level) = level {
            self.push(e.cycle, source, wave, Change::Bit(level));
        }
        self.last_drive[i] = Some(*e);
    }

    /// The event's waveform is written edge by edge.
    fn waving(&self, e: &DriveEvent) -> bool {
        self.pwm_edges && e.duty > 0.0 && e.duty < 1.0 && e.wave.is_some()
    }

    /// A byte on a UART: sent by the firmware (its frame starts at `cycle`)
    /// or received (the receiver had it at `cycle`, its frame done).
    pub fn uart(&mut self, received: bool, cycle: u64, usart: u8, byte: u8) {
        self.end = self.end.max(cycle);
        if usart == USB_SERIAL {
            self.usb(received, cycle, byte);
            return;
        }
        let base = 1 + self.layout.pins.len() as u32;
        for j in 0..self.layout.uarts.len() {
            let (n, cycles_per_bit, ids) = self.layout.uarts[j];
            if n != usart {
                continue;
            }
            let d = usize::from(received);
            let back = if received {
                (10.0 * cycles_per_bit).round() as u64
            } else {
                0
            };
            let source = base + 4 * j as u32 + 2 * d as u32;
            let at = cycle.saturating_sub(back);
            let dir = &mut self.directions[j][d];
            let text = line_text(&mut dir.text, byte);
            let (line, value, shown) = (ids[d], ids[2 + d], ids[4 + d]);
            self.push(at, source, value, Change::Real(f64::from(byte)));
            self.push(at, source, shown, Change::Text(text));
            let dir = &mut self.directions[j][d];
            let mut level = !dir.low;
            let (edges, free) = frame_bits(at, byte, dir.free, &mut level, cycles_per_bit);
            dir.free = free;
            dir.low = !level;
            for (c, bit) in edges {
                self.push(c, source + 1, line, Change::Bit(bit));
            }
        }
    }

    /// A byte on the USB serial at `cycle`, as the host had it (sent) or
    /// gave it to the device (received): its value and the line's text.
    fn usb(&mut self, received: bool, cycle: u64, byte: u8) {
        let Some(ids) = self.layout.usb else {
            return;
        };
        let d = usize::from(received);
        let source = 2 + self.layout.pins.len() as u32 + 4 * self.layout.uarts.len() as u32;
        let text = line_text(&mut self.usb_text[d], byte);
        self.push(
            cycle,
            source + d as u32,
            ids[d],
            Change::Real(f64::from(byte)),
        );
        self.push(cycle, source + d as u32, ids[2 + d], Change::Text(text));
    }

    /// A trace sample of the plant.
    pub fn sample(&mut self, s: &Sample) {
        let c = (s.t_s * self.clock_hz as f64).round() as u64;
        self.end = self.end.max(c);
        let vals = [
            s.x_mm,
            s.y_mm,
            s.theta_rad,
            s.left_edges as f64,
            s.right_edges as f64,
        ];
        self.first_sample.get_or_insert(vals);
        let source = 1 + self.layout.pins.len() as u32 + 4 * self.layout.uarts.len() as u32;
        for (v, var) in vals.into_iter().zip(self.layout.plant) {
            self.push(c, source, var, Change::Real(v));
        }
    }

    /// Nothing that comes from now on changes anything before `cycle`:
    /// write what changed before it. (A waveform written edge by edge
    /// holds back what follows its last drive change, whose edges run to
    /// the next change.)
    pub fn settle(&mut self, cycle: u64) {
        let open = (0..self.last_drive.len())
            .filter_map(|i| self.last_drive[i].filter(|e| self.waving(e)))
            .map(|e| e.cycle)
            .min()
            .unwrap_or(u64::MAX);
        self.write_before(cycle.min(open));
    }

    fn write_before(&mut self, cycle: u64) {
        if self.error.is_some() {
            self.queue.clear();
            return;
        }
        let r = self.try_write_before(cycle);
        if let Err(e) = r {
            self.error = Some(e);
            self.queue.clear();
        }
    }

    fn try_write_before(&mut self, cycle: u64) -> std::io::Result<()> {
        if !self.header {
            let levels = self.first_level.map(|l| l.unwrap_or(false));
            let text = self.layout.header(levels, self.first_sample);
            self.out.write_all(text.as_bytes())?;
            self.header = true;
        }
        self.settled = self.settled.max(cycle);
        let mut line = String::new();
        while self.queue.peek().is_some_and(|p| p.0.cycle < cycle) {
            let Reverse(p) = self.queue.pop().expect("peeked");
            line.clear();
            if p.cycle != self.written {
                let _ = writeln!(line, "#{}", p.cycle);
                self.written = p.cycle;
            }
            let id = &self.layout.ids[p.var as usize];
            let _ = match p.change {
                Change::Bit(b) => writeln!(line, "{}{id}", u8::from(b)),
                Change::Real(v) => writeln!(line, "r{v} {id}"),
                Change::Text(t) => writeln!(line, "s{t} {id}"),
            };
            self.out.write_all(line.as_bytes())?;
        }
        Ok(())
    }

    /// Write everything still held and flush: the writer back, or the
    /// first error writing met.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.write_before(u64::MAX);
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.out.flush()?;
        Ok(self.out)
    }
}

/// A writer that takes the run's records as the bench makes them.
impl<W: Write + Send> Tap for VcdWriter<W> {
    fn pin(&mut self, e: PinEvent) {
        VcdWriter::pin(self, e);
    }
    fn drive(&mut self, e: &DriveEvent) {
        VcdWriter::drive(self, e);
    }
    fn uart(&mut self, received: bool, cycle: u64, usart: u8, byte: u8) {
        VcdWriter::uart(self, received, cycle, usart, byte);
    }
    fn sample(&mut self, s: &Sample) {
        VcdWriter::sample(self, s);
    }
    fn settle(&mut self, cycle: u64) {
        VcdWriter::settle(self, cycle);
    }
}
