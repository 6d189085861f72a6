//! Pins driven from outside the MCU (encoder lines, a button), kept at the
//! level their driver sets whatever the firmware writes to their port.
//!
//! On silicon an input pin's pull-up is a weak resistor: a pin that
//! something outside drives reads that level, and the pull-up only decides
//! the level of a pin nothing drives. simavr models the pull-up as a driver
//! instead: on every write to a port's PORT or DDR register
//! (`avr_ioport_update_irqs`) it raises each input pin whose PORT bit is 1
//! back to 1, over the level the bench drives, unless the pin is declared
//! external (`AVR_IOCTL_IOPORT_SET_EXTERNAL`): then it raises the level
//! declared with it. So every pin the bench drives is declared external,
//! and each level the bench drives on it is declared with it before it is
//! raised; the pins nobody drives keep simavr's pull-up.

use std::cell::Cell;
use std::ffi::c_void;

use simavr_ffi as ffi;

use super::irq::Irq;
use super::mcu::ioctl_def;
use super::{Avr, Handler, SimError};
use crate::mcu::chip::Chip;

/// A pin the bench drives from outside, from [`Avr::driven_pin`]. Drive it
/// with [`Avr::drive`] or [`super::Core::drive`] (a plain raise of its
/// IRQ would leave simavr re-applying the old level at the next port write).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrivenPin {
    irq: Irq,
    /// The port's letter, as simavr's ioctl names it.
    port: u8,
    /// The port's index in the MCU's description (`Chip::ports`).
    index: usize,
    bit: u8,
}

impl DrivenPin {
    /// The pin's IRQ, to watch it.
    pub fn irq(self) -> Irq {
        self.irq
    }
}

/// Per port of the MCU (in its description's order), the pins declared
/// external and the levels declared on them: simavr keeps one mask and one
/// value per port and takes both at once, so the bench keeps the whole of
/// them to change one bit.
pub(super) struct ExternalPins {
    chip: &'static Chip,
    ports: Box<[Cell<(u8, u8)>]>,
}

impl ExternalPins {
    pub(super) fn new(chip: &'static Chip) -> Self {
        Self {
            chip,
            ports: chip.ports.iter().map(|_| Cell::new((0, 0))).collect(),
        }
    }

    /// Declare `pin` driven at `high`: the port's (mask, value) now, and
    /// whether that changed it.
    fn set(&self, pin: DrivenPin, high: bool) -> ((u8, u8), bool) {
        let cell = &self.ports[pin.index];
        let old = cell.get();
        let bit = 1 << pin.bit;
        let new = (old.0 | bit, if high { old.1 | bit } else { old.1 & !bit });
        cell.set(new);
        (new, new != old)
    }

    /// The index of `port` in the MCU's description, when it has pin `bit`
    /// there.
    fn index(&self, port: char, bit: u8) -> Option<usize> {
        self.chip
            .has_pin((port, bit))
            .then(|| self.chip.ports.iter().position(|p| p.letter == port))
            .flatten()
    }
}

/// Tell simavr port `port`'s external pins and their levels; false when no
/// port of the MCU took the ioctl.
///
/// # Safety
/// `avr` points to a live, initialised MCU.
unsafe fn declare(avr: *mut ffi::avr_t, port: u8, (mask, value): (u8, u8)) -> bool {
    // SAFETY: a plain C struct of bit fields: all zeroes is a valid value.
    let mut ext: ffi::avr_ioport_external_t = unsafe { std::mem::zeroed() };
    ext.set_name(port.into());
    ext.set_mask(mask.into());
    ext.set_value(value.into());
    let ctl = ioctl_def(b'i', b'o', b'p', port);
    // SAFETY: as the caller guarantees; the port's ioctl reads the struct
    // during the call only, and runs no callback.
    unsafe { ffi::avr_ioctl(avr, ctl, &mut ext as *mut _ as *mut c_void) >= 0 }
}

/// Drive `pin` at `high`: declared first, then raised (the raise may make
/// simavr update the port, which then sees the new level).
///
/// # Safety
/// `avr` is the live MCU `pins` belongs to, `pin`'s IRQ is one of its own
/// (checked by the caller), and no reference to its handler is alive unless
/// the handler is marked busy (as for [`super::irq::raise`]).
pub(super) unsafe fn drive(
    avr: *mut ffi::avr_t,
    pins: &ExternalPins,
    raw: *mut ffi::avr_irq_t,
    pin: DrivenPin,
    high: bool,
) {
    let (declared, changed) = pins.set(pin, high);
    if changed {
        // SAFETY: as the caller guarantees. The port took the ioctl when
        // the pin was made ([`Avr::driven_pin`]), so it takes it again.
        unsafe { declare(avr, pin.port, declared) };
    }
    // SAFETY: as the caller guarantees.
    unsafe { super::irq::raise(raw, u32::from(high)) }
}

impl<H: Handler> Avr<H> {
    /// Pin `bit` of port `port`, driven from outside from now on at `high`:
    /// it reads what the bench drives whatever the firmware writes to the
    /// port (its pull-up only matters to pins nobody drives). The MCU's
    /// description says which pins it has: simavr's port registers have
    /// eight bits where the silicon has fewer pins (the ATmega328P's PC7).
    ///
    /// # Panics
    /// With the panic of a callback the first raise ran.
    pub fn driven_pin(&mut self, port: char, bit: u8, high: bool) -> Result<DrivenPin, SimError> {
        let index = self
            .external_pins()
            .index(port, bit)
            .ok_or(SimError::NoSuchPin(port, bit))?;
        let irq = self.port_pin(port, bit)?;
        let letter = u8::try_from(port).map_err(|_| SimError::NoSuchPort(port))?;
        let pin = DrivenPin {
            irq,
            port: letter,
            index,
            bit,
        };
        let (declared, _) = self.external_pins().set(pin, high);
        // SAFETY: the live MCU; no callback is running (`&mut self`).
        if !unsafe { declare(self.raw(), letter, declared) } {
            return Err(SimError::NoSuchPort(port));
        }
        self.raise(irq, u32::from(high));
        Ok(pin)
    }

    /// Drive `pin` at `high`, from outside callbacks.
    ///
    /// # Panics
    /// When `pin` belongs to another `Avr`, and with the panic of a callback
    /// the raise ran.
    pub fn drive(&mut self, pin: DrivenPin, high: bool) {
        let raw = pin.irq.raw_for(self.owner());
        // SAFETY: `raw` is an IRQ of this live MCU (checked above); `&mut
        // self` means no reference to the handler is alive.
        unsafe { drive(self.raw(), self.external_pins(), raw, pin, high) };
        self.resume_failure();
    }

    fn external_pins(&self) -> &ExternalPins {
        // SAFETY: a field of the live state made of `Cell`s, which callbacks
        // (none runs while `self` is borrowed) also only reach through `&`.
        unsafe { &(*self.state_ptr()).external }
    }
}
