//! The EEPROM (4 KiB): one byte read or written at a time, never waited for
//! in the main loop.
//!
//! Registers (I/O space; data space + 0x20): EECR 0x1F, EEDR 0x20, EEARL
//! 0x21, EEARH 0x22. A write is the datasheet's sequence: EEPE clear (the
//! caller checks [`Eeprom::busy`]), the address in EEARH:EEARL, the byte in
//! EEDR, then EEMPE set and, within four cycles, EEPE set: two back-to-back
//! `sbi` in inline assembly with interrupts off (an interrupt between them
//! would let EEMPE time out). The chip then takes about 3.4 ms, with EEPE
//! set, before the next read or write. Erase-and-write mode (EEPM = 00, the
//! reset value). The robust build never self-programs the flash, so SPMEN
//! is always clear.

use core::arch::asm;
use core::ptr::write_volatile;

use avr_device::atmega2560::EEPROM;
use avr_device::interrupt;

/// EECR's I/O address (for `sbi`).
const EECR_IO: u8 = 0x1F;
/// EECR bit EERE (read enable).
const EERE: u8 = 1 << 0;
/// EECR bit EEPE (write enable; set while a write is in progress).
const EEPE: u8 = 1 << 1;
/// EECR bit EEMPE (master write enable, for four cycles).
const EEMPE_BIT: u8 = 2;
/// EECR bit number of EEPE, for `sbi`.
const EEPE_BIT: u8 = 1;

/// The EEPROM.
pub struct Eeprom {
    ee: EEPROM,
}

impl Eeprom {
    /// Takes the EEPROM.
    pub fn new(ee: EEPROM) -> Self {
        Eeprom { ee }
    }

    /// A write is in progress (EEPE set): no read or write may start.
    #[inline(always)]
    pub fn busy(&self) -> bool {
        self.ee.eecr().read().bits() & EEPE != 0
    }

    /// EEARH, then EEARL.
    #[inline(always)]
    fn set_address(&mut self, addr: u16) {
        let eearl = self.ee.eear().as_ptr() as *mut u8;
        let [lo, hi] = addr.to_le_bytes();
        // SAFETY: EEAR is EEARL at its address and EEARH right after it;
        // plain registers, no TEMP latch, only this driver writes them.
        unsafe {
            write_volatile(eearl.add(1), hi);
            write_volatile(eearl, lo);
        }
    }

    /// The byte at `addr` (only when not [`Eeprom::busy`]; the CPU halts
    /// four cycles for it).
    pub fn read(&mut self, addr: u16) -> u8 {
        self.set_address(addr);
        // SAFETY: EERE alone starts a read; EEMPE and EEPE stay clear.
        self.ee.eecr().write(|w| unsafe { w.bits(EERE) });
        self.ee.eedr().read().bits()
    }

    /// Starts writing `byte` at `addr` (only when not [`Eeprom::busy`]).
    pub fn write(&mut self, addr: u16, byte: u8) {
        self.set_address(addr);
        // SAFETY: any byte is a valid EEDR value.
        self.ee.eedr().write(|w| unsafe { w.bits(byte) });
        interrupt::free(|_| {
            // SAFETY: EECR is I/O register 0x1F; `sbi` EEMPE then `sbi` EEPE
            // (2 cycles each) sets EEPE within EEMPE's four cycles, which
            // starts the write of EEDR at EEAR. Interrupts are off.
            unsafe {
                asm!(
                    "sbi {eecr}, {eempe}",
                    "sbi {eecr}, {eepe}",
                    eecr = const EECR_IO,
                    eempe = const EEMPE_BIT,
                    eepe = const EEPE_BIT,
                )
            };
        });
    }
}
