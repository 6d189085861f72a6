//! The host's side of the MCU's USARTs: bytes from the host go out one per
//! byte time (those on the Bluetooth link through the link's faults, at the
//! time they are on the air), bytes from the firmware are collected. The
//! USB serial of an MCU with USB (`usb.rs` is its host) is one more
//! channel here, [`USB_SERIAL`], beside USART 0-3: its bytes are recorded
//! as theirs are.

use std::collections::VecDeque;

use super::log::Log;
use super::NEVER;
use crate::mcu::clock::Clock;
use crate::mcu::sim::Irq;

pub use crate::firmware::description::USB_SERIAL;
/// USART 0-3 and the USB serial.
pub const SERIALS: usize = 5;

/// The name of serial channel `n` for people: "USART 1", "the USB serial".
pub fn serial_name(n: u8) -> String {
    if n == USB_SERIAL {
        "the USB serial".into()
    } else {
        format!("USART {n}")
    }
}

/// Bytes kept of each USART's output and in the log: over 18 minutes of a
/// USART sending without a pause at 9600 baud.
const UART_CAP: usize = 1 << 20;

pub(super) struct HostUart {
    /// The USART carrying the Bluetooth link.
    bluetooth: usize,
    /// Bytes the firmware sent, per USART (up to a cap, unless taken).
    out: [Log<u8>; SERIALS],
    /// Bytes the firmware sent: (cycle, USART, byte).
    log: Log<(u64, u8, u8)>,
    /// Bytes the host's side put on the firmware's RX pins, as they
    /// arrived (after the link's faults): (cycle, USART, byte).
    rx_log: Log<(u64, u8, u8)>,
    /// Bytes from the host waiting to go out on each USART, one per byte time.
    tx: [VecDeque<u8>; SERIALS],
    next: [u64; SERIALS],
    irq: [Option<Irq>; SERIALS],
    byte_cycles: u64,
}

impl HostUart {
    pub(super) fn new(bluetooth: u8, clock: Clock) -> Self {
        Self {
            bluetooth: bluetooth as usize,
            out: std::array::from_fn(|_| Log::new(UART_CAP)),
            log: Log::new(UART_CAP),
            rx_log: Log::new(UART_CAP),
            tx: Default::default(),
            next: [NEVER; SERIALS],
            irq: [None; SERIALS],
            // 10 bits per byte (8N1) at 9600 baud, as the HC-05 sends them.
            byte_cycles: (clock.hz() as u64 * 10).div_ceil(9600),
        }
    }

    /// USART `n`'s receiver input.
    pub(super) fn connect(&mut self, n: u8, input: Irq) {
        self.irq[n as usize] = Some(input);
    }

    /// When the next byte from the host is due on any USART.
    pub(super) fn next_due(&self) -> u64 {
        self.next.iter().copied().min().unwrap_or(NEVER)
    }

    /// The firmware sent `byte` on USART `n` at `cycle`.
    pub(super) fn received(&mut self, cycle: u64, n: usize, byte: u8) {
        self.out[n].push(byte);
        self.log.push((cycle, n as u8, byte));
    }

    pub(super) fn bluetooth(&self) -> usize {
        self.bluetooth
    }

    /// Queue bytes from the host for USART `n`.
    pub(super) fn queue(&mut self, n: usize, bytes: &[u8], now: u64) {
        // Link faults apply when a byte goes over the air (see
        // the core's `send_due_host_bytes`).
        self.tx[n].extend(bytes.iter().copied());
        if self.next[n] == NEVER && !self.tx[n].is_empty() {
            self.next[n] = now + 1;
        }
    }

    /// USART `n`'s next byte from the host, if one is due at `when`: taken
    /// from its queue, with the receiver to raise it on (None when the
    /// queue or the receiver is missing). Then [`HostUart::reschedule`].
    pub(super) fn take_due(&mut self, n: usize, when: u64) -> Option<Option<(u8, Irq)>> {
        if self.next[n] > when {
            return None;
        }
        let byte = self.tx[n].pop_front();
        Some(byte.zip(self.irq[n]))
    }

    /// USART `n` sent its byte due at `when`: the next one byte time later.
    pub(super) fn reschedule(&mut self, n: usize, when: u64) {
        self.next[n] = if self.tx[n].is_empty() {
            NEVER
        } else {
            when + self.byte_cycles
        };
    }

    /// Bytes the firmware sent on USART `n` so far (since the last
    /// [`HostUart::take_out`]).
    pub(super) fn out(&self, n: usize) -> &[u8] {
        self.out[n].as_slice()
    }

    /// The bytes the firmware sent on USART `n` since the last call, taken.
    pub(super) fn take_out(&mut self, n: usize) -> Vec<u8> {
        self.out[n].take()
    }

    /// Bytes the firmware sent: (cycle, USART, byte).
    pub(super) fn log(&self) -> &[(u64, u8, u8)] {
        self.log.as_slice()
    }

    /// Keep only the latest entry of the log from now on (the bytes stay
    /// until taken).
    pub(super) fn keep_latest(&mut self) {
        self.log.keep_latest();
        self.rx_log.keep_latest();
    }

    /// (bytes held, log entries held).
    pub(super) fn retained(&self) -> (usize, usize) {
        let bytes = self.out.iter().map(|o| o.as_slice().len()).sum();
        (
            bytes,
            self.log.as_slice().len() + self.rx_log.as_slice().len(),
        )
    }

    /// A notice for each record that reached its cap.
    pub(super) fn notices(&self) -> Vec<String> {
        let mut v: Vec<String> = (0..SERIALS as u8)
            .filter_map(|n| {
                self.out[n as usize].notice(&format!("record of the bytes from {}", serial_name(n)))
            })
            .collect();
        v.extend(self.log.notice("UART log (VCD)"));
        v.extend(self.rx_log.notice("UART receive log (VCD)"));
        v
    }

    /// `byte` arrived at USART `n`'s receiver at `cycle` (its stop bit done).
    pub(super) fn delivered(&mut self, cycle: u64, n: usize, byte: u8) {
        self.rx_log.push((cycle, n as u8, byte));
    }

    /// Bytes that arrived at the firmware's receivers: (cycle, USART, byte).
    pub(super) fn rx_log(&self) -> &[(u64, u8, u8)] {
        self.rx_log.as_slice()
    }
}
