//! How the bench takes part in the MCU's IO: IRQs it watches, IO registers
//! whose writes and reads it claims or observes (simavr's own handlers saved
//! where they must still run).

use std::ffi::c_void;

use simavr_ffi as ffi;

use super::mcu::io_slot;
use super::shared::WriteSlot;
use super::trampolines::{
    io_read_observe_trampoline, io_read_trampoline, io_write_trampoline, irq_trampoline,
};
use super::{Avr, Handler, IoClaim, Irq, SimError};

impl<H: Handler> Avr<H> {
    /// Call [`Handler::irq`] with `tag` whenever `irq` is raised.
    ///
    /// # Panics
    /// When `irq` belongs to another `Avr`.
    pub fn watch_irq(&mut self, irq: Irq, tag: u32) {
        let raw = irq.raw_for(self.owner());
        let param = self.shared.new_tag(tag).as_ptr() as *mut c_void;
        // SAFETY: `raw` is an IRQ of this live MCU (checked above); the tag
        // lives in `self.shared` until after the MCU is freed.
        unsafe { ffi::avr_irq_register_notify(raw, Some(irq_trampoline::<H>), param) }
    }

    /// Take part in writes to IO register `addr` (a data-space address).
    /// Claiming a slot again changes how it is claimed: simavr's own
    /// handler, saved at the first claim, stays the one observed writes
    /// forward to.
    pub fn claim_io_write(&mut self, addr: u16, claim: IoClaim) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        let p = self.state_ptr();
        // SAFETY: `slot` is within the IO table; outside callbacks (`&mut
        // self`), so nothing reads `writes` meanwhile. We install our
        // trampoline directly, which avoids simavr's 4-entry write
        // multiplexer, and save what simavr had there the first time only:
        // after that the slot holds our own trampoline, which must never be
        // its own forward.
        unsafe {
            let io = &mut (*self.raw()).io[slot];
            let writes = &mut (*p).writes;
            let original = writes[slot].map_or((io.w.c, io.w.param), |s| s.original);
            writes[slot] = Some(WriteSlot {
                original,
                observe: claim == IoClaim::Observe,
            });
            io.w.c = Some(io_write_trampoline::<H>);
            io.w.param = p.cast();
        }
        Ok(())
    }

    /// Emulate reads of IO register `addr`: simavr's read handler no longer runs.
    pub fn claim_io_read(&mut self, addr: u16) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        // SAFETY: `slot` is within the IO table.
        unsafe {
            let io = &mut (*self.raw()).io[slot];
            io.r.c = Some(io_read_trampoline::<H>);
            io.r.param = self.state_ptr().cast();
        }
        Ok(())
    }

    /// Be told before every read of IO register `addr` ([`Handler::before_io_read`]);
    /// simavr's read handler still produces the value.
    pub fn observe_io_read(&mut self, addr: u16) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        let p = self.state_ptr();
        // SAFETY: `slot` is within the IO table; outside callbacks, so
        // nothing reads `reads` meanwhile. We keep what simavr had there to
        // call after the bench's hook.
        unsafe {
            let io = &mut (*self.raw()).io[slot];
            let reads = &mut (*p).reads;
            // Observing a slot twice keeps the first (simavr's) handler.
            if reads[slot].is_none() {
                reads[slot] = Some((io.r.c, io.r.param));
            }
            io.r.c = Some(io_read_observe_trampoline::<H>);
            io.r.param = p.cast();
        }
        Ok(())
    }
}
