//! The simavr MCU itself: the one owner of the `avr_t`, and the raw accesses
//! to its memories that every other part goes through.

use std::ffi::{c_void, CStr};
use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::{CpuState, SimError};

/// Owns one `avr_t`, from `avr_make_mcu_by_name` to its free: whatever path
/// leaves [`super::Avr::new`], and however the `Avr` ends, the MCU is
/// terminated and freed exactly once.
pub(super) struct Mcu(NonNull<ffi::avr_t>);

impl Mcu {
    /// A fresh, not yet initialised MCU, or None when simavr does not know
    /// the name.
    pub(super) fn by_name(name: &CStr) -> Option<Self> {
        // SAFETY: simavr returns a freshly allocated MCU (a copy of its
        // static core description) or null.
        let raw = unsafe { ffi::avr_make_mcu_by_name(name.as_ptr()) };
        NonNull::new(raw).map(Self)
    }

    /// Set up memories and peripherals; returns the step function simavr
    /// installed (what `avr_run` calls).
    pub(super) fn init(
        &mut self,
        mcu: &str,
    ) -> Result<unsafe extern "C" fn(*mut ffi::avr_t), SimError> {
        // SAFETY: `self` is a fresh MCU from `by_name`, initialised once.
        if unsafe { ffi::avr_init(self.as_ptr()) } != 0 {
            return Err(SimError::InitFailed(mcu.into()));
        }
        // SAFETY: plain field read on the initialised MCU.
        unsafe { (*self.as_ptr()).run }.ok_or_else(|| SimError::InitFailed(mcu.into()))
    }

    #[inline]
    pub(super) fn ptr(&self) -> NonNull<ffi::avr_t> {
        self.0
    }

    #[inline]
    pub(super) fn as_ptr(&self) -> *mut ffi::avr_t {
        self.0.as_ptr()
    }
}

impl Drop for Mcu {
    fn drop(&mut self) {
        extern "C" {
            fn free(p: *mut c_void);
        }
        // SAFETY: we own the MCU. avr_terminate frees its memories and IO
        // (and is a no-op on a core that was never initialised: its pointers
        // are null in simavr's static description); the avr_t itself was
        // malloc'ed by avr_make_mcu_by_name. Nothing uses the MCU after.
        unsafe {
            ffi::avr_terminate(self.as_ptr());
            free(self.as_ptr() as *mut c_void);
        }
    }
}

/// A byte of data space, without side effects.
///
/// # Safety
/// `avr` points to a live, initialised MCU.
pub(super) unsafe fn data_read(avr: NonNull<ffi::avr_t>, addr: u16) -> u8 {
    // SAFETY: the caller guarantees a live MCU; `data` is simavr's array of
    // ramend + 1 bytes and the bound is checked against ramend first.
    unsafe {
        let a = avr.as_ptr();
        assert!(
            addr <= (*a).ramend,
            "data address 0x{addr:04x} beyond RAMEND"
        );
        *(*a).data.add(addr as usize)
    }
}

/// Store a byte of data space, without side effects (no IO handler runs).
///
/// # Safety
/// `avr` points to a live, initialised MCU.
pub(super) unsafe fn data_write(avr: NonNull<ffi::avr_t>, addr: u16, value: u8) {
    // SAFETY: as in `data_read`.
    unsafe {
        let a = avr.as_ptr();
        assert!(
            addr <= (*a).ramend,
            "data address 0x{addr:04x} beyond RAMEND"
        );
        *(*a).data.add(addr as usize) = value;
    }
}

/// The slot of IO register `addr` (a data-space address) in simavr's IO
/// table.
pub(super) fn io_slot(addr: u16) -> Result<usize, SimError> {
    if addr < 32 || (addr as usize - 32) >= ffi::MAX_IOs as usize {
        return Err(SimError::IoOutOfRange(addr));
    }
    Ok(addr as usize - 32)
}

/// simavr's four-character ioctl codes.
pub(super) fn ioctl_def(a: u8, b: u8, c: u8, d: u8) -> u32 {
    (a as u32) << 24 | (b as u32) << 16 | (c as u32) << 8 | d as u32
}

#[inline]
pub(super) fn decode_state(state: i32) -> CpuState {
    // The two states of every step first, as plain compares: this runs once
    // per emulated instruction.
    let s = state as u32;
    if s == ffi::cpu_Running {
        CpuState::Running
    } else if s == ffi::cpu_Sleeping {
        CpuState::Sleeping
    } else {
        match s {
            ffi::cpu_Done | ffi::cpu_Stopped => CpuState::Done,
            ffi::cpu_Crashed => CpuState::Crashed,
            _ => CpuState::Other(state),
        }
    }
}
