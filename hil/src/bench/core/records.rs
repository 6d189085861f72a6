//! What the core's parts hold, for the bench and its callers: the run's
//! records, counters and the fault schedule.

use super::*;
use crate::bench::uart::USB_SERIAL;
use crate::bench::usb::UsbState;

/// What the parts hold, for the bench and its callers.
impl BenchCore {
    /// The plant and the firmware's counters now (`cycle` is the current one).
    pub fn snapshot(&self, core: &Core, cycle: u64) -> Snapshot {
        Snapshot::take(&self.robot, self.counts, core, cycle)
    }

    /// The longest a level on the bridge inputs may last and still be a
    /// stale one, not a cut-off: one period of the slowest PWM seen on them
    /// (a firmware writing the inputs one after the other leaves a level
    /// for a few instructions; a real stop lasts at least a period), and at
    /// least 64 us for drivers switched by plain pin writes.
    pub(crate) fn stale_level_cycles(&self) -> u64 {
        let hz = self.clock.hz() as f64;
        self.bridge
            .pin_stats()
            .iter()
            .filter(|p| p.hz > 0.0)
            .map(|p| (hz / p.hz).ceil() as u64)
            .max()
            .unwrap_or(0)
            .max(self.clock.cycles_in(Seconds(64e-6)))
    }

    /// Where the firmware keeps its wheel counters, when known.
    pub(crate) fn count_variables(&self) -> Option<[u16; 2]> {
        self.counts
    }

    pub(in crate::bench) fn set_count_variables(&mut self, counts: [u16; 2]) {
        self.counts = Some(counts);
    }

    /// Trace samples, one per `BenchOptions::trace_interval_s`.
    pub fn trace(&self) -> &[Sample] {
        self.recorder.trace()
    }

    /// Every change of an H-bridge input.
    pub fn drive_log(&self) -> &[DriveEvent] {
        self.recorder.drive_log()
    }

    pub fn cutoffs(&self) -> &[Cutoff] {
        self.recorder.cutoffs()
    }

    pub fn motions(&self) -> &[MotionEvent] {
        self.recorder.motions()
    }

    /// Changes of [`crate::bench::Motion`] since the start, kept or not.
    pub fn motion_changes(&self) -> u64 {
        self.recorder.motion_changes()
    }

    /// How many items each record holds now.
    pub fn retained(&self) -> Retained {
        let (uart_bytes, uart_log) = self.uart.retained();
        Retained {
            uart_bytes,
            uart_log,
            applied: self.faults.applied().len(),
            ..self.recorder.retained()
        }
    }

    /// A notice for each record that reached its cap (see `log.rs`): what
    /// the run's results do not cover.
    pub fn record_notices(&self) -> Vec<String> {
        let interval_s = self.clock.seconds(self.step_cycles).0 * f64::from(self.trace_every);
        let mut v = self.recorder.notices(interval_s);
        v.extend(self.uart.notices());
        v
    }

    pub(in crate::bench) fn keep_latest_records(&mut self) {
        self.recorder.keep_latest();
        self.uart.keep_latest();
    }

    pub(in crate::bench) fn take_uart_out(&mut self, n: usize) -> Vec<u8> {
        self.uart.take_out(n)
    }

    /// Battery LED changes.
    pub fn leds(&self) -> &[LedEvent] {
        self.recorder.leds()
    }

    /// Encoder pin changes since `Bench::start_recording` (None before).
    pub fn recording(&self) -> Option<&[PinEvent]> {
        self.recorder.recording()
    }

    /// Every change of the analog inputs since cycle 0.
    pub fn analog_log(&self) -> &[AnalogEvent] {
        self.recorder.analog_log()
    }

    /// Mean active duty per pin, finalised.
    pub fn pin_stats(&self) -> Vec<PinStats> {
        self.bridge.pin_stats()
    }

    /// A edges raised on the pins per side, signed as the thesis' decoder
    /// counts them.
    pub fn edges_raised(&self) -> [i64; 2] {
        self.edges.edges_raised()
    }

    /// Cycle at which the last A edge of each encoder was due.
    pub(crate) fn last_a_edge(&self) -> [u64; 2] {
        self.edges.last_a_edge()
    }

    /// Callbacks that raised planned edges from the plan alone.
    pub fn lean_edge_callbacks(&self) -> u64 {
        self.edges.lean_edge_callbacks()
    }

    /// PIN reads that brought a lazy B up to date.
    pub fn lazy_b_reads(&self) -> u64 {
        self.edges.lazy_b_reads()
    }

    /// PIN reads of a lazy B answered from the last A edge.
    pub fn quiet_b_reads(&self) -> u64 {
        self.edges.quiet_b_reads()
    }

    /// PIN reads of a lazy B that evaluated the plant.
    pub(crate) fn b_reads_evaluated(&self) -> u64 {
        self.edges.b_reads_evaluated()
    }

    /// The brown-out detector holds the MCU in reset.
    pub fn held_in_reset(&self) -> bool {
        self.power.holds_reset()
    }

    /// Brown-out resets: the cycle the detector pulled the reset and the
    /// cycle it let go (None while it still holds).
    pub fn brownouts(&self) -> &[(u64, Option<u64>)] {
        self.power.brownouts()
    }

    /// Schedule `action` at `cycle` (kept sorted; equal cycles keep order).
    pub fn schedule_action(&mut self, cycle: u64, action: Action) {
        self.faults.at(cycle, action);
    }

    /// Run `action` when `trigger` fires, and `undo` `duration` cycles later.
    pub(crate) fn schedule_triggered(
        &mut self,
        trigger: Trigger,
        action: Action,
        undo: Option<(u64, Action)>,
    ) {
        self.faults.arm(self.clock, trigger, action, undo);
    }

    /// The actions applied so far: (cycle, action).
    pub fn applied(&self) -> &[(u64, Action)] {
        self.faults.applied()
    }

    /// Queue bytes from the host for USART `n` (or the USB serial).
    pub(crate) fn queue_uart(&mut self, n: usize, bytes: &[u8], now: u64) {
        match &mut self.usb {
            Some(usb) if n == USB_SERIAL as usize => usb.queue(bytes),
            _ => self.uart.queue(n, bytes, now),
        }
    }

    /// Where the USB host is; None without USB.
    pub(crate) fn usb_state(&self) -> Option<&UsbState> {
        self.usb.as_ref().map(|u| u.state())
    }

    /// The USB host's moments: (cycle, what).
    pub(crate) fn usb_events(&self) -> &[(u64, &'static str)] {
        self.usb.as_ref().map_or(&[], |u| u.events())
    }

    /// Bytes the firmware sent on USART `n` so far.
    pub(crate) fn uart_out(&self, n: usize) -> &[u8] {
        self.uart.out(n)
    }

    /// Bytes the firmware sent: (cycle, USART, byte).
    pub fn uart_log(&self) -> &[(u64, u8, u8)] {
        self.uart.log()
    }

    /// Bytes that arrived at the firmware's receivers from the host's side:
    /// (cycle, USART, byte).
    pub fn uart_rx_log(&self) -> &[(u64, u8, u8)] {
        self.uart.rx_log()
    }
}
