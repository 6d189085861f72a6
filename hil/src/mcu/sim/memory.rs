//! The MCU's memories and registers, read and written from outside
//! callbacks (a debugger, the bench's checks, tests).

use super::mcu::{data_read, data_write};
use super::{Avr, Handler, SimError};

use simavr_ffi as ffi;

impl<H: Handler> Avr<H> {
    /// Copy a firmware segment into flash at byte address `addr`.
    pub fn load_flash(&mut self, addr: u32, bytes: &[u8]) -> Result<(), SimError> {
        let a = self.raw();
        // SAFETY: plain field read.
        let flash = unsafe { (*a).flashend } + 1;
        if addr as u64 + bytes.len() as u64 > flash as u64 {
            return Err(SimError::FlashOverflow {
                addr,
                len: bytes.len(),
                flash,
            });
        }
        self.code_end = self.code_end.max(addr + bytes.len() as u32);
        // SAFETY: the bound is checked above, before simavr's memcpy (which
        // aborts on overflow); `codeend` tells simavr's crash check where
        // code ends.
        unsafe {
            ffi::avr_loadcode(a, bytes.as_ptr() as *mut u8, bytes.len() as u32, addr);
            (*a).codeend = self.code_end;
        }
        Ok(())
    }

    /// The program counter, as a byte address in flash.
    pub fn pc(&self) -> u32 {
        // SAFETY: plain field read.
        unsafe { (*self.raw()).pc }
    }

    /// The global interrupt enable flag (SREG.I).
    pub fn interrupts_enabled(&self) -> bool {
        // SAFETY: plain read of simavr's split SREG array (8 entries).
        unsafe { (*self.raw()).sreg[7] != 0 }
    }

    /// The 16-bit word of flash at byte address `addr` (an opcode); 0 past
    /// the end of flash.
    pub fn flash_word(&self, addr: u32) -> u16 {
        let a = self.raw();
        // SAFETY: `flash` holds flashend + 1 bytes; the bound is checked
        // without overflow (the last byte read is addr + 1).
        unsafe {
            if addr as u64 + 1 > (*a).flashend as u64 {
                return 0;
            }
            u16::from_le_bytes([
                *(*a).flash.add(addr as usize),
                *(*a).flash.add(addr as usize + 1),
            ])
        }
    }

    /// The status register, composed from simavr's per-flag copy (the byte
    /// at SREG's data address is not kept up to date while running).
    pub fn sreg(&self) -> u8 {
        // SAFETY: plain read of simavr's split SREG array (8 entries).
        let bits = unsafe { (*self.raw()).sreg };
        bits.iter()
            .enumerate()
            .fold(0u8, |acc, (i, b)| acc | (u8::from(*b != 0) << i))
    }

    /// Set the status register (a debugger's register write).
    pub fn set_sreg(&mut self, value: u8) {
        for i in 0..8 {
            // SAFETY: plain writes of simavr's split SREG array (8 entries).
            unsafe { (*self.raw()).sreg[i] = (value >> i) & 1 };
        }
        // simavr keeps SREG's data byte in step at each SREG write.
        self.set_data(0x5f, value);
    }

    /// Set the program counter (a byte address in flash).
    pub fn set_pc(&mut self, pc: u32) {
        // SAFETY: plain field write; simavr fetches from `pc` at the next
        // instruction and reports a crash for an address past the code.
        unsafe { (*self.raw()).pc = pc }
    }

    /// Stack pointer (SPH:SPL).
    pub fn sp(&self) -> u16 {
        u16::from_le_bytes([self.data(0x5d), self.data(0x5e)])
    }

    /// Set the stack pointer (SPH:SPL).
    pub fn set_sp(&mut self, sp: u16) {
        let [lo, hi] = sp.to_le_bytes();
        self.set_data(0x5d, lo);
        self.set_data(0x5e, hi);
    }

    /// A byte of data space (registers, IO, SRAM), without side effects.
    ///
    /// # Panics
    /// Past RAMEND.
    pub fn data(&self, addr: u16) -> u8 {
        // SAFETY: the MCU is live while `self` is.
        unsafe { data_read(self.mcu.ptr(), addr) }
    }

    /// Store a byte of data space, without side effects (no IO handler runs).
    ///
    /// # Panics
    /// Past RAMEND.
    pub fn set_data(&mut self, addr: u16, value: u8) {
        // SAFETY: the MCU is live while `self` is.
        unsafe { data_write(self.mcu.ptr(), addr, value) }
    }

    pub fn read_bytes<const N: usize>(&self, addr: u16) -> [u8; N] {
        let mut out = [0u8; N];
        for (i, b) in out.iter_mut().enumerate() {
            *b = self.data(addr + i as u16);
        }
        out
    }

    pub fn write_bytes(&mut self, addr: u16, bytes: &[u8]) {
        for (i, b) in bytes.iter().enumerate() {
            self.set_data(addr + i as u16, *b);
        }
    }

    /// RAMEND, the last data-space address.
    fn ramend(&self) -> u64 {
        // SAFETY: plain field read.
        unsafe { (*self.raw()).ramend as u64 }
    }

    /// Bytes of data space (registers, IO, SRAM): RAMEND + 1.
    pub fn data_size(&self) -> u32 {
        self.ramend() as u32 + 1
    }

    /// Bytes of flash.
    pub fn flash_size(&self) -> u32 {
        // SAFETY: plain field read.
        unsafe { (*self.raw()).flashend + 1 }
    }

    /// Bytes of data space (registers, IO, SRAM) from `addr`; None when the
    /// range passes RAMEND.
    pub fn read_data(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
        let end = addr as u64 + len as u64;
        (end <= self.ramend() + 1).then(|| {
            (addr..addr + len as u32)
                .map(|a| self.data(a as u16))
                .collect()
        })
    }

    /// Store bytes in data space; false (and nothing written) when the range
    /// passes RAMEND.
    pub fn write_data(&mut self, addr: u32, bytes: &[u8]) -> bool {
        if addr as u64 + bytes.len() as u64 > self.ramend() + 1 {
            return false;
        }
        self.write_bytes(addr as u16, bytes);
        true
    }

    /// Bytes of flash from byte address `addr`; None when the range passes
    /// the end of flash.
    pub fn read_flash(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
        // SAFETY: `flash` holds flashend + 1 bytes; the range is checked
        // against it first.
        unsafe {
            let a = self.raw();
            if addr as u64 + len as u64 > (*a).flashend as u64 + 1 {
                return None;
            }
            Some(std::slice::from_raw_parts((*a).flash.add(addr as usize), len).to_vec())
        }
    }

    /// Store bytes in flash (a debugger loading code); false (and nothing
    /// written) when the range passes the end of flash.
    pub fn write_flash(&mut self, addr: u32, bytes: &[u8]) -> bool {
        // SAFETY: as in `read_flash`; the destination range is checked.
        unsafe {
            let a = self.raw();
            if addr as u64 + bytes.len() as u64 > (*a).flashend as u64 + 1 {
                return false;
            }
            std::ptr::copy_nonoverlapping(
                bytes.as_ptr(),
                (*a).flash.add(addr as usize),
                bytes.len(),
            );
        }
        true
    }
}
