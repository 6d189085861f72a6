//! The `extern "C"` callbacks simavr calls, and the guard they all go
//! through on their way to the handler.
//!
//! Every trampoline runs its body inside [`boundary`]: a panic (the
//! handler's, or one of the checks here) is caught before it can unwind into
//! C, stored in the handler's state, and ends the running burst; the `Avr`
//! call that ran simavr resumes it once back in Rust
//! ([`super::Avr::resume_failure`]). The handler is borrowed through
//! [`with_handler`] only, which marks it busy for the call: a callback that
//! arrives while it is busy (a raise inside the handler that reaches a
//! watched IRQ, or inside [`super::Avr::with_core`]) is refused with a
//! panic instead of making a second `&mut` to it.

use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr::NonNull;

use simavr_ffi as ffi;

use super::mcu::{data_read, data_write};
use super::shared::{Flag, IrqTag, Payload, Shared};
use super::{Core, Handler};

/// Run a trampoline's `body`, catching any panic: the payload is kept for
/// Rust and `fallback` returned to simavr.
///
/// # Safety
/// `shared` is the live state of a live `Avr`.
#[inline]
unsafe fn boundary<H, R>(shared: NonNull<Shared<H>>, fallback: R, body: impl FnOnce() -> R) -> R {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(r) => r,
        Err(payload) => {
            // SAFETY: as the caller guarantees.
            unsafe { fail(shared, payload) };
            fallback
        }
    }
}

/// Keep a callback's panic for Rust and end the running burst.
///
/// # Safety
/// `shared` is the live state of a live `Avr`.
#[cold]
unsafe fn fail<H>(shared: NonNull<Shared<H>>, payload: Payload) {
    let p = shared.as_ptr();
    // SAFETY: `Cell` fields of the live state, borrowed for these lines only
    // (never the handler's bytes).
    let (failed, failure, burst_end) = unsafe { (&(*p).failed, &(*p).failure, &(*p).burst_end) };
    match failure.take() {
        // The first failure is the cause; a later payload is leaked rather
        // than dropped here, where a panicking destructor would unwind into C.
        Some(first) => {
            std::mem::forget(payload);
            failure.set(Some(first));
        }
        None => failure.set(Some(payload)),
    }
    failed.set(true);
    burst_end.set(0);
    // SAFETY: as the caller guarantees.
    unsafe { end_free_run(shared) };
}

/// End simavr's free run after the running instruction, as the burst ends
/// after it: the core returns to the run loop at once, and a timer simavr
/// registers later in the same instruction cannot set a further end (its
/// stop, 1, is behind every cycle the core runs at).
///
/// # Safety
/// `shared` is the live state of a live `Avr`.
#[inline]
unsafe fn end_free_run<H>(shared: NonNull<Shared<H>>) {
    // SAFETY: plain field writes on the live MCU, which is running the
    // instruction this callback is part of; `Avr::run_burst` sets the
    // limit again as the next burst starts.
    unsafe {
        let avr = (*shared.as_ptr()).avr.as_ptr();
        (*avr).run_cycle_stop = 1;
        (*avr).run_cycle_end = 0;
    }
}

/// Call the handler once: `call` gets the only `&mut H` there is, for its
/// duration. A handler left wanting attention ends the burst.
///
/// # Panics
/// When the handler is already borrowed (`what` names the callback refused).
///
/// # Safety
/// `shared` is the live state of a live `Avr`, and no reference to its
/// handler is alive unless `busy` says so.
#[inline]
unsafe fn with_handler<H: Handler, R>(
    shared: NonNull<Shared<H>>,
    what: &'static str,
    call: impl FnOnce(&mut H, &mut Core) -> R,
) -> R {
    let p = shared.as_ptr();
    // SAFETY: a `Cell` field of the live state; no `&mut` covers it.
    let busy = unsafe { &(*p).busy };
    let Some(_busy) = Flag::raise(busy) else {
        refused(what)
    };
    // SAFETY: the flag was clear, so no other reference to the handler is
    // alive (the caller's guarantee), and none is made until it clears: this
    // is the only `&mut H` while it lives. It covers the handler field only.
    let handler = unsafe { &mut *std::ptr::addr_of_mut!((*p).handler) };
    // SAFETY: live state; the `Core` is dropped at the end of this call.
    let mut core = unsafe { Core::new(shared, schedule_from_core::<H>) };
    let r = call(handler, &mut core);
    if handler.attention() {
        // SAFETY: a `Cell` field, disjoint from the handler; the MCU's
        // fields, as in `end_free_run`.
        unsafe {
            (*p).burst_end.set(0);
            end_free_run(shared);
        }
    }
    r
}

#[cold]
#[inline(never)]
fn refused(what: &str) -> ! {
    panic!(
        "simavr called the handler ({what}) while it was running: a raise \
         inside a callback (or inside with_core) reached a watched IRQ; \
         the callback is refused, not nested"
    )
}

/// The bench's cycle timer fired.
///
/// # Safety
/// Called by simavr only: `param` is the `Shared<H>` the timer was
/// registered with ([`schedule_timer`]), live while the MCU is.
pub(super) unsafe extern "C" fn timer_trampoline<H: Handler>(
    _avr: *mut ffi::avr_t,
    when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    let shared = param_to_shared::<H>(param);
    // SAFETY: `shared` is live (the caller's guarantee); a timer never fires
    // while the handler is borrowed except through a nested raise, which
    // `with_handler` refuses.
    unsafe {
        boundary(shared, 0, || {
            let _in_timer = Flag::raise(&(*shared.as_ptr()).in_timer);
            with_handler(shared, "timer", |h, core| h.timer(core, when))
        })
    }
}

/// A write to an IO register the bench claimed.
///
/// # Safety
/// Called by simavr only, for a slot `Avr::claim_io_write` installed it on:
/// `param` is that `Avr`'s `Shared<H>`, `addr` the slot's data address.
pub(super) unsafe extern "C" fn io_write_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    value: u8,
    param: *mut c_void,
) {
    let shared = param_to_shared::<H>(param);
    // SAFETY: as the caller guarantees; `writes` changes only outside
    // callbacks, and simavr's original handler runs before the bench's
    // handler is borrowed (its own callbacks may reach the bench).
    unsafe {
        boundary(shared, (), || {
            let p = shared.as_ptr();
            let writes = &(*p).writes;
            let slot = writes
                .get(usize::from(addr).wrapping_sub(32))
                .copied()
                .flatten();
            if let Some(slot) = slot.filter(|s| s.observe) {
                match slot.original {
                    (Some(original), original_param) => original(avr, addr, value, original_param),
                    // Observed slot that had no handler: simavr would have stored it.
                    (None, _) => data_write((*p).avr, addr, value),
                }
            }
            with_handler(shared, "io_write", |h, core| h.io_write(core, addr, value));
        })
    }
}

/// A read of an IO register the bench emulates.
///
/// # Safety
/// Called by simavr only, for a slot `Avr::claim_io_read` installed it on:
/// `param` is that `Avr`'s `Shared<H>`.
pub(super) unsafe extern "C" fn io_read_trampoline<H: Handler>(
    _avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    param: *mut c_void,
) -> u8 {
    let shared = param_to_shared::<H>(param);
    // SAFETY: as the caller guarantees.
    unsafe {
        boundary(shared, 0, || {
            with_handler(shared, "io_read", |h, core| h.io_read(core, addr))
        })
    }
}

/// A read of an IO register the bench observes: the handler first, then
/// simavr's own read handler.
///
/// # Safety
/// Called by simavr only, for a slot `Avr::observe_io_read` installed it
/// on: `param` is that `Avr`'s `Shared<H>`, `addr` the slot's data address.
pub(super) unsafe extern "C" fn io_read_observe_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    param: *mut c_void,
) -> u8 {
    let shared = param_to_shared::<H>(param);
    // SAFETY: as the caller guarantees; `reads` changes only outside
    // callbacks; the original handler runs after the bench's handler is
    // given back.
    unsafe {
        boundary(shared, 0, || {
            with_handler(shared, "before_io_read", |h, core| {
                h.before_io_read(core, addr)
            });
            let p = shared.as_ptr();
            let reads = &(*p).reads;
            match reads
                .get(usize::from(addr).wrapping_sub(32))
                .copied()
                .flatten()
            {
                Some((Some(original), original_param)) => original(avr, addr, original_param),
                _ => data_read((*p).avr, addr),
            }
        })
    }
}

/// An IRQ the bench watches was raised.
///
/// # Safety
/// Called by simavr only, with the `param` `Avr::watch_irq` registered: an
/// `IrqTag<H>` owned by that `Avr`, live while the MCU is.
pub(super) unsafe extern "C" fn irq_trampoline<H: Handler>(
    _irq: *mut ffi::avr_irq_t,
    value: u32,
    param: *mut c_void,
) {
    // SAFETY: as the caller guarantees; tags are never changed after
    // `watch_irq` made them.
    let tag = unsafe { &*(param as *const IrqTag<H>) };
    let (shared, tag) = (tag.shared, tag.tag);
    // SAFETY: the tag's `shared` is its `Avr`'s live state.
    unsafe {
        boundary(shared, (), || {
            with_handler(shared, "irq", |h, core| h.irq(core, tag, value))
        })
    }
}

#[inline]
fn param_to_shared<H>(param: *mut c_void) -> NonNull<Shared<H>> {
    // Never null: every `param` the bench registers is the state's pointer.
    // A null would be simavr's bug, and aborting is all a callback can do
    // about it without unwinding into C.
    NonNull::new(param as *mut Shared<H>).unwrap_or_else(|| std::process::abort())
}

/// (Re)schedule the bench's cycle timer at absolute cycle `at`
/// (`u64::MAX` cancels). The timer is identified by (callback, param):
/// registering again replaces it, which is how the bench reschedules.
///
/// # Safety
/// `shared` is the live state of a live `Avr`.
pub(super) unsafe fn schedule_timer<H: Handler>(shared: NonNull<Shared<H>>, at: u64) {
    // SAFETY: the MCU is alive (the caller's guarantee); simavr takes a cycle
    // count relative to now and replaces any timer registered with the same
    // (callback, param).
    unsafe {
        let avr = (*shared.as_ptr()).avr.as_ptr();
        let now = (*avr).cycle;
        let param = shared.as_ptr() as *mut c_void;
        if at == u64::MAX {
            ffi::avr_cycle_timer_cancel(avr, Some(timer_trampoline::<H>), param);
        } else {
            ffi::avr_cycle_timer_register(
                avr,
                at.saturating_sub(now),
                Some(timer_trampoline::<H>),
                param,
            );
        }
    }
}

/// [`super::Core::schedule`], for the `H` the `Core` was made for.
///
/// # Safety
/// `shared` is the type-erased live state of a live `Avr<H>`.
pub(super) unsafe fn schedule_from_core<H: Handler>(shared: NonNull<()>, at: u64) {
    let shared = shared.cast::<Shared<H>>();
    // SAFETY: as the caller guarantees; `in_timer` is a `Cell`, disjoint
    // from the handler a callback may be borrowing.
    let in_timer = unsafe { (*shared.as_ptr()).in_timer.get() };
    debug_assert!(
        !in_timer,
        "schedule() called from inside the timer callback"
    );
    // SAFETY: as the caller guarantees.
    unsafe { schedule_timer(shared, at) }
}
