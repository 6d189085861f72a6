//! The host's side of the MCU's USARTs: bytes from the host go out one per
//! byte time (those on the Bluetooth link through the link's faults, at the
//! time they are on the air), bytes from the firmware are collected.

use std::collections::VecDeque;

use super::core::{BenchCore, NEVER};
use crate::sim::{Core, Irq};
use crate::time::Clock;

pub(super) struct HostUart {
    /// The USART carrying the Bluetooth link.
    bluetooth: usize,
    /// Bytes the firmware sent, per USART.
    out: [Vec<u8>; 4],
    /// Bytes the firmware sent: (cycle, USART, byte).
    log: Vec<(u64, u8, u8)>,
    /// Bytes from the host waiting to go out on each USART, one per byte time.
    tx: [VecDeque<u8>; 4],
    next: [u64; 4],
    irq: [Option<Irq>; 4],
    byte_cycles: u64,
}

impl HostUart {
    pub(super) fn new(bluetooth: u8, clock: Clock) -> Self {
        Self {
            bluetooth: bluetooth as usize,
            out: Default::default(),
            log: Vec::new(),
            tx: Default::default(),
            next: [NEVER; 4],
            irq: [None; 4],
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
}

impl BenchCore {
    /// Queue bytes from the host for USART `n`.
    pub fn queue_uart(&mut self, n: usize, bytes: &[u8], now: u64) {
        let u = &mut self.uart;
        // Link faults apply when a byte goes over the air (see
        // `send_due_host_bytes`).
        u.tx[n].extend(bytes.iter().copied());
        if u.next[n] == NEVER && !u.tx[n].is_empty() {
            u.next[n] = now + 1;
        }
    }

    /// Put on the wire each byte from the host due at `when`.
    pub(super) fn send_due_host_bytes(&mut self, core: &mut Core, when: u64) {
        for n in 0..4 {
            if self.uart.next[n] > when {
                continue;
            }
            let byte = self.uart.tx[n].pop_front();
            if let (Some(b), Some(irq)) = (byte, self.uart.irq[n]) {
                // The Bluetooth link's faults hit the byte now, at the
                // time it is on the air.
                let arrived = if n == self.uart.bluetooth {
                    self.host_byte_on_air(core, when);
                    self.inject.link_bytes(b)
                } else {
                    vec![b]
                };
                for b in arrived {
                    core.raise(irq, b as u32);
                }
            }
            let u = &mut self.uart;
            u.next[n] = if u.tx[n].is_empty() {
                NEVER
            } else {
                when + u.byte_cycles
            };
        }
    }

    /// Bytes the firmware sent on USART `n` so far.
    pub fn uart_out(&self, n: usize) -> &[u8] {
        &self.uart.out[n]
    }

    /// Bytes the firmware sent: (cycle, USART, byte).
    pub fn uart_log(&self) -> &[(u64, u8, u8)] {
        &self.uart.log
    }
}
