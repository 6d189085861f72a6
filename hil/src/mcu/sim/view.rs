//! [`Core`]: what a handler sees of the running MCU inside a callback.

use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::irq::{self, Irq};
use super::mcu::{data_read, data_write};
use super::owner::Owner;
use super::pins::{self, DrivenPin, ExternalPins};
use super::shared::Shared;
use super::Handler;

/// A view of the running MCU for use inside callbacks.
///
/// A `Core` exists only while a callback (or [`super::Avr::with_core`])
/// runs, and is lent as `&mut Core`: it cannot outlive the MCU it views.
pub struct Core {
    avr: NonNull<ffi::avr_t>,
    owner: Owner,
    /// The handler's state, type-erased: `Core` does not know `H`.
    shared: NonNull<()>,
    /// The state's driven pins (a field of `shared`, reached through `&`
    /// only).
    external: NonNull<ExternalPins>,
    /// The trampolines' scheduler for that `H`, given by the caller of
    /// [`Core::new`] (the view does not know the trampolines).
    schedule: unsafe fn(NonNull<()>, u64),
}

impl Core {
    /// The view of the MCU whose handler state is `shared`; `schedule`
    /// (re)schedules the bench's timer for it.
    ///
    /// # Safety
    /// `shared` is the live state of a live `Avr`, and the `Core` is dropped
    /// before the `Avr` (it is only ever lent for one callback); `schedule`
    /// expects the type-erased state of that same `H` (the trampolines'
    /// `schedule_from_core::<H>`).
    pub(super) unsafe fn new<H: Handler>(
        shared: NonNull<Shared<H>>,
        schedule: unsafe fn(NonNull<()>, u64),
    ) -> Self {
        let p = shared.as_ptr();
        Self {
            // SAFETY: plain copies of two fields that never change, read
            // through the pointer every access goes through.
            avr: unsafe { (*p).avr },
            // SAFETY: as above.
            owner: unsafe { (*p).owner },
            // SAFETY: the address of a field of the live state, no reference made.
            external: unsafe { NonNull::new_unchecked(std::ptr::addr_of_mut!((*p).external)) },
            shared: shared.cast(),
            schedule,
        }
    }

    /// The MCU, for the other views of this module (`usb.rs`).
    pub(super) fn avr_ptr(&self) -> NonNull<ffi::avr_t> {
        self.avr
    }

    /// Whose MCU this is, to check what a caller brings belongs to it.
    pub(super) fn owner(&self) -> Owner {
        self.owner
    }

    /// The current emulated cycle.
    pub fn cycle(&self) -> u64 {
        // SAFETY: `avr` is live for as long as `self` (see `new`); reading a
        // plain field is sound.
        unsafe { (*self.avr.as_ptr()).cycle }
    }

    /// The program counter, as a byte address in flash.
    pub fn pc(&self) -> u32 {
        // SAFETY: as in `cycle`.
        unsafe { (*self.avr.as_ptr()).pc }
    }

    /// Read a byte of data space (registers, IO, SRAM) without side effects.
    pub fn data(&self, addr: u16) -> u8 {
        // SAFETY: the MCU is live (see `cycle`).
        unsafe { data_read(self.avr, addr) }
    }

    /// Store a byte in data space without side effects (no IO handler runs).
    pub fn set_data(&mut self, addr: u16, value: u8) {
        // SAFETY: the MCU is live (see `cycle`).
        unsafe { data_write(self.avr, addr, value) }
    }

    /// Drive an input line (a pin, a UART's input) to `value`. A watched IRQ
    /// it reaches is not delivered to the handler (which is running): that
    /// callback is refused, and the panic saying so is resumed when the
    /// `Avr` call that ran this callback returns.
    ///
    /// # Panics
    /// When `irq` belongs to another `Avr`.
    pub fn raise(&mut self, irq: Irq, value: u32) {
        let raw = irq.raw_for(self.owner);
        // SAFETY: `raw` is an IRQ of this live MCU (checked above); the
        // handler that holds `&mut self` is marked busy, so the hooks the
        // raise runs do not borrow it again.
        unsafe { irq::raise(raw, value) }
    }

    /// Drive `pin` at `high` (see [`DrivenPin`]); a watched IRQ it reaches
    /// is refused as in [`Core::raise`].
    ///
    /// # Panics
    /// When `pin` belongs to another `Avr`.
    pub fn drive(&mut self, pin: DrivenPin, high: bool) {
        let raw = pin.irq().raw_for(self.owner);
        // SAFETY: `raw` is an IRQ of this live MCU (checked above) and
        // `external` its state's driven pins, live as long as `self`; the
        // handler is marked busy, as in `raise`.
        unsafe { pins::drive(self.avr.as_ptr(), self.external.as_ref(), raw, pin, high) }
    }

    /// Set the supply the analog parts see (VCC, AVCC and AREF are one rail
    /// on the Mega), in millivolts: the ADC converts against it.
    pub fn set_supply_mv(&mut self, mv: u32) {
        // SAFETY: plain field writes on the live MCU; simavr's ADC reads them
        // at each conversion.
        unsafe {
            let a = self.avr.as_ptr();
            (*a).vcc = mv;
            (*a).avcc = mv;
            (*a).aref = mv;
        }
    }

    /// (Re)schedule the bench's cycle timer at absolute cycle `at` (a cycle
    /// already past fires at the next instruction boundary; `u64::MAX`
    /// cancels). Must not be called from [`Handler::timer`] (return the cycle
    /// instead).
    pub fn schedule(&mut self, at: u64) {
        // SAFETY: `shared` and `schedule` were built together for one `H` by
        // `new`, from live state.
        unsafe { (self.schedule)(self.shared, at) }
    }
}
