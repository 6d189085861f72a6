//! IRQs: the pins and peripheral lines the bench drives or watches.
//!
//! An [`Irq`] is a pointer into one MCU's IRQ tables, which live as long as
//! that MCU. It is `Copy` and kept in handlers (which are `'static`), so a
//! lifetime cannot tie it to its `Avr`; it carries its owner's id instead,
//! and every use checks it: an `Irq` used with another `Avr`, or after its
//! own is gone (ids are never reused), panics instead of touching memory.

use std::ffi::c_void;
use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::mcu::ioctl_def;
use super::owner::Owner;
use super::{Avr, Handler, SimError};

/// A pin or peripheral line the bench drives or watches, usable with the
/// [`Avr`] (and inside its callbacks, the [`super::Core`]) it came from only.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Irq {
    raw: NonNull<ffi::avr_irq_t>,
    owner: Owner,
}

impl Irq {
    /// The raw IRQ, for use with the MCU of `owner`.
    ///
    /// # Panics
    /// When the IRQ belongs to another (or a dropped) `Avr`.
    #[inline]
    pub(super) fn raw_for(self, owner: Owner) -> *mut ffi::avr_irq_t {
        if self.owner != owner {
            foreign(self, owner);
        }
        self.raw.as_ptr()
    }
}

#[cold]
#[inline(never)]
fn foreign(irq: Irq, owner: Owner) -> ! {
    panic!(
        "an Irq of Avr #{} used with Avr #{}: an Irq works with the Avr it came from only",
        irq.owner.number(),
        owner.number()
    )
}

/// Drive `irq` to `value`.
///
/// # Safety
/// `irq` comes from the tables of a live MCU (checked by [`Irq::raw_for`]
/// against the caller's owner), and no reference to that MCU's handler is
/// alive unless the handler is marked busy (callbacks the raise causes
/// then refuse to run).
pub(super) unsafe fn raise(irq: *mut ffi::avr_irq_t, value: u32) {
    // SAFETY: as the caller guarantees; simavr's raise runs the IRQ's
    // hooks, which re-enter the bench through the guarded trampolines.
    unsafe { ffi::avr_raise_irq(irq, value) }
}

impl<H: Handler> Avr<H> {
    /// The IRQ of pin `bit` of IO port `port` ('A'..'L').
    pub fn port_pin(&mut self, port: char, bit: u8) -> Result<Irq, SimError> {
        self.port_irq(port, bit as i32)
    }

    /// Port `port`'s PORT-register IRQ (raised with the whole byte on every
    /// write, however it is written).
    pub fn port_register(&mut self, port: char) -> Result<Irq, SimError> {
        self.port_irq(port, ffi::IOPORT_IRQ_REG_PORT as i32)
    }

    /// Port `port`'s DDR IRQ (raised with the whole byte on every write).
    pub fn port_direction(&mut self, port: char) -> Result<Irq, SimError> {
        self.port_irq(port, ffi::IOPORT_IRQ_DIRECTION_ALL as i32)
    }

    fn port_irq(&mut self, port: char, index: i32) -> Result<Irq, SimError> {
        let ctl = ioctl_def(b'i', b'o', b'g', port as u8);
        // SAFETY: simavr looks the IRQ up in its port list (the index is
        // checked against the port's IRQ count), or returns null.
        let irq = unsafe { ffi::avr_io_getirq(self.raw(), ctl, index) };
        self.own(irq).ok_or(SimError::NoSuchPort(port))
    }

    /// The ADC's analog input `channel` (raise it with millivolts).
    pub fn adc_input(&mut self, channel: u8) -> Result<Irq, SimError> {
        let ctl = ioctl_def(b'a', b'd', b'c', b'0');
        // SAFETY: simavr looks the IRQ up in its peripheral list, or returns null.
        let irq = unsafe { ffi::avr_io_getirq(self.raw(), ctl, channel as i32) };
        self.own(irq).ok_or(SimError::NoSuchPort('A'))
    }

    /// USART `n`'s (input, output) IRQs, with simavr's stdio echo and its
    /// wall-clock poll sleep turned off.
    pub fn uart(&mut self, n: u8) -> Result<(Irq, Irq), SimError> {
        let name = b'0'.checked_add(n).ok_or(SimError::NoSuchUart(n))?;
        let get = ioctl_def(b'u', b'a', b'r', name);
        let a = self.raw();
        // SAFETY: IRQ lookups on the live MCU, null when there is no such UART.
        let (input, output) = unsafe {
            (
                ffi::avr_io_getirq(a, get, ffi::UART_IRQ_INPUT as i32),
                ffi::avr_io_getirq(a, get, ffi::UART_IRQ_OUTPUT as i32),
            )
        };
        let (Some(input), Some(output)) = (self.own(input), self.own(output)) else {
            return Err(SimError::NoSuchUart(n));
        };
        let mut flags: u32 = 0;
        // SAFETY: the UART exists (its IRQs do); `flags` is the u32 simavr's
        // UART flag ioctls read and write.
        unsafe {
            ffi::avr_ioctl(
                a,
                ioctl_def(b'u', b'a', b'g', name),
                &mut flags as *mut u32 as *mut c_void,
            );
            flags &= !(ffi::AVR_UART_FLAG_STDIO | ffi::AVR_UART_FLAG_POLL_SLEEP);
            ffi::avr_ioctl(
                a,
                ioctl_def(b'u', b'a', b's', name),
                &mut flags as *mut u32 as *mut c_void,
            );
        }
        Ok((input, output))
    }

    pub(super) fn own(&self, irq: *mut ffi::avr_irq_t) -> Option<Irq> {
        NonNull::new(irq).map(|raw| Irq {
            raw,
            owner: self.owner(),
        })
    }

    /// Drive an input line from outside callbacks.
    ///
    /// # Panics
    /// When `irq` belongs to another `Avr`, and with the panic of a callback
    /// the raise ran.
    pub fn raise(&mut self, irq: Irq, value: u32) {
        let raw = irq.raw_for(self.owner());
        // SAFETY: `raw` is an IRQ of this live MCU (checked above); `&mut
        // self` means no reference to the handler is alive.
        unsafe { raise(raw, value) };
        self.resume_failure();
    }
}
