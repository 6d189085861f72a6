//! The state simavr's callbacks reach: the handler and the bookkeeping the
//! trampolines keep around it, allocated once and reached only through one
//! raw pointer.
//!
//! simavr holds pointers to this state (as the `param` of IO slots and of
//! the cycle timer, and inside the IRQ tags) for the MCU's whole life. So
//! that they stay valid under Rust's aliasing rules, nothing ever makes a
//! `&mut Shared<H>` (nor a `&Shared<H>`) after the allocation: the box is
//! turned into a raw pointer at once ([`SharedBox::new`]), every access is
//! a place expression on one field through that pointer, and the only long
//! borrow is the handler's own `&mut H`, taken once at a time
//! ([`Shared::busy`], see the trampolines). The other fields are `Cell`s or
//! change only outside callbacks (with the `Avr` borrowed mutably), so the
//! borrows of two fields never overlap on the same bytes.

use std::any::Any;
use std::cell::Cell;
use std::ffi::c_void;
use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::owner::Owner;
use super::pins::ExternalPins;
use super::response::Response;
use crate::mcu::chip::Chip;

/// A panic caught at the C boundary, to be resumed in Rust.
pub(super) type Payload = Box<dyn Any + Send>;

/// How an IO write slot the bench claimed forwards to simavr.
#[derive(Clone, Copy)]
pub(super) struct WriteSlot {
    /// The handler simavr had installed on the slot before the bench's first
    /// claim (a later claim does not take the bench's own trampoline for it).
    pub(super) original: (ffi::avr_io_write_t, *mut c_void),
    /// [`super::IoClaim::Observe`]: call `original` (or store the byte, as
    /// simavr does for a slot without a handler) before the bench's handler.
    pub(super) observe: bool,
}

pub(super) struct Shared<H> {
    pub(super) avr: NonNull<ffi::avr_t>,
    /// The `Avr` this state belongs to (checked on every use of an `Irq`).
    pub(super) owner: Owner,
    /// The cycle at which the running burst ends ([`super::Avr::run_burst`]
    /// sets it as it starts). A callback that leaves the handler wanting
    /// attention, or that failed, sets it to 0, so that the burst's loop has
    /// one bound to test per instruction.
    pub(super) burst_end: Cell<u64>,
    /// The handler is borrowed (a callback or `with_core` is running): a
    /// callback that arrives now is refused instead of making a second
    /// `&mut H`.
    pub(super) busy: Cell<bool>,
    /// [`super::Handler::timer`] is running (it must return its next cycle,
    /// not schedule it).
    pub(super) in_timer: Cell<bool>,
    /// A callback panicked or was refused: `failure` holds the payload until
    /// the `Avr` call that ran simavr returns and resumes it.
    pub(super) failed: Cell<bool>,
    pub(super) failure: Cell<Option<Payload>>,
    /// Per IO slot, what the bench's write claim forwards to (None: not
    /// claimed). Changed only outside callbacks.
    pub(super) writes: Vec<Option<WriteSlot>>,
    /// The read handler simavr had on each slot watched with
    /// [`super::Avr::observe_io_read`], called after the bench's. Changed
    /// only outside callbacks.
    pub(super) reads: Vec<Option<(ffi::avr_io_read_t, *mut c_void)>>,
    /// The interrupt response's bookkeeping; simavr's sleep callback and
    /// the notify on its running-interrupt line point here (`response.rs`).
    pub(super) response: Response,
    /// The pins the bench drives and their levels, as simavr was told
    /// them (`pins.rs`): `Cell`s, reached through `&` only.
    pub(super) external: ExternalPins,
    pub(super) handler: H,
}

impl<H> Shared<H> {
    pub(super) fn new(
        avr: NonNull<ffi::avr_t>,
        chip: &'static Chip,
        owner: Owner,
        handler: H,
    ) -> Self {
        Self {
            avr,
            owner,
            burst_end: Cell::new(0),
            busy: Cell::new(false),
            in_timer: Cell::new(false),
            failed: Cell::new(false),
            failure: Cell::new(None),
            writes: vec![None; ffi::MAX_IOs as usize],
            reads: vec![None; ffi::MAX_IOs as usize],
            response: Response::new(avr, chip),
            external: ExternalPins::new(chip),
            handler,
        }
    }
}

/// A watched IRQ's `param`: which handler, and the tag it is told.
pub(super) struct IrqTag<H> {
    pub(super) shared: NonNull<Shared<H>>,
    pub(super) tag: u32,
}

/// The one owner of a `Shared<H>` and of the IRQ tags that point to it.
/// It must be dropped after the MCU (no callback may run once it is gone):
/// [`super::Avr`] declares it after its `Mcu`.
pub(super) struct SharedBox<H> {
    ptr: NonNull<Shared<H>>,
    tags: Vec<NonNull<IrqTag<H>>>,
}

impl<H> SharedBox<H> {
    pub(super) fn new(shared: Shared<H>) -> Self {
        let ptr =
            NonNull::new(Box::into_raw(Box::new(shared))).expect("Box::into_raw is never null");
        Self {
            ptr,
            tags: Vec::new(),
        }
    }

    /// The pointer every access goes through (and the one simavr holds).
    #[inline]
    pub(super) fn ptr(&self) -> NonNull<Shared<H>> {
        self.ptr
    }

    /// A new IRQ tag, owned here until drop; its address is stable.
    pub(super) fn new_tag(&mut self, tag: u32) -> NonNull<IrqTag<H>> {
        let boxed = Box::new(IrqTag {
            shared: self.ptr,
            tag,
        });
        let tag = NonNull::new(Box::into_raw(boxed)).expect("Box::into_raw is never null");
        self.tags.push(tag);
        tag
    }
}

impl<H> Drop for SharedBox<H> {
    fn drop(&mut self) {
        // SAFETY: each pointer came from `Box::into_raw` here and is freed
        // once; the MCU that held copies of them is gone (see the type's
        // doc), so no callback can reach them.
        unsafe {
            for tag in self.tags.drain(..) {
                drop(Box::from_raw(tag.as_ptr()));
            }
            drop(Box::from_raw(self.ptr.as_ptr()));
        }
    }
}

/// A `Cell<bool>` set for as long as this guard lives, unwinding included.
pub(super) struct Flag<'a>(&'a Cell<bool>);

impl<'a> Flag<'a> {
    /// Sets the flag; None when it was set already.
    #[inline]
    pub(super) fn raise(flag: &'a Cell<bool>) -> Option<Self> {
        (!flag.replace(true)).then_some(Self(flag))
    }
}

impl Drop for Flag<'_> {
    #[inline]
    fn drop(&mut self) {
        self.0.set(false);
    }
}
