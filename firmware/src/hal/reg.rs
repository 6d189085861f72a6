//! Raw register helpers shared by the drivers.

use core::ptr::write_volatile;

/// Writes a 16-bit timer register of the ATmega2560 in the order the chip
/// requires: high byte first (it goes to the shared TEMP latch), then the low
/// byte, whose write transfers both bytes at once.
///
/// The compiler's own volatile `u16` store does not promise a byte order, so
/// the two bytes are written separately.
///
/// # Safety
/// `reg` must be the address of the low byte of a 16-bit register of this
/// chip (for example `TC1.ocr1a().as_ptr()`), and the caller must prevent an
/// interrupt handler from using the TEMP latch of the same timer between the
/// two writes (or know that no handler touches that timer's 16-bit registers).
#[inline(always)]
pub unsafe fn write_u16(reg: *mut u16, value: u16) {
    let low = reg as *mut u8;
    let [lo, hi] = value.to_le_bytes();
    // SAFETY: the caller guarantees `reg` is a 16-bit register, so `low + 1`
    // is its high byte; both are plain memory-mapped I/O bytes.
    unsafe {
        write_volatile(low.add(1), hi);
        write_volatile(low, lo);
    }
}

/// Reads a 16-bit timer register of the ATmega2560 in the order the chip
/// requires: the low byte first (this latches the high byte in TEMP), then
/// the high byte.
///
/// # Safety
/// As [`write_u16`]: `reg` must be a 16-bit register of this chip, and no
/// interrupt handler may use the same timer's TEMP latch between the reads.
#[inline(always)]
pub unsafe fn read_u16(reg: *const u16) -> u16 {
    let low = reg as *const u8;
    // SAFETY: the caller guarantees `reg` is a 16-bit register.
    unsafe {
        let lo = core::ptr::read_volatile(low);
        let hi = core::ptr::read_volatile(low.add(1));
        u16::from_le_bytes([lo, hi])
    }
}
