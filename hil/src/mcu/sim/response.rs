//! The interrupt response of the AVR, which simavr leaves out.
//!
//! Datasheet "Interrupt Response Time" (ATmega2560 §7.8.1, ATmega328P
//! §6.7.1, ATmega32U4 §4.8.1): the response takes a cycle per byte of the
//! PC it pushes and the vector fetch before the vector's first instruction,
//! normally a `jmp` of three more: five cycles with the ATmega2560's 3-byte
//! PC, four with a 2-byte one; as many more when the interrupt wakes the
//! CPU from sleep (on top of the sleep mode's start-up time, none in idle);
//! `reti` takes as many again. The MCU's description has them
//! ([`Chip::response_cycles`], [`Chip::wake_up_cycles`]).
//!
//! simavr (`sim_interrupts.c`, `avr_service_interrupts`) pushes the PC and
//! sets it to the vector between two instructions without counting a
//! cycle; its `jmp` and `reti` (`sim_core.c`) count their three and
//! `1 + address_size`. Entering a vector raises the "running" line of
//! `AVR_INT_ANY` (so does `reti`, told apart by the I bit), so one notify
//! on it adds the missing cycles to `avr->cycle`: the CPU stalls, as it
//! does during a multi-cycle instruction. Nothing else changes: the cycle
//! timers due during the stall (simavr's peripherals, the bench's events)
//! fire right after the next instruction with their own `when`, as they do
//! after any long instruction, and the timers derive their counters from
//! the cycle.
//!
//! Waking is known from the sleep: simavr calls `avr->sleep` as it jumps
//! over one, then adds `1 + how_long` to the cycle, one past the timer it
//! sleeps until. [`sleep`] takes that cycle back, so that the timer fires
//! at its own cycle (an edge that wakes the CPU is raised when it happens),
//! and notes where the jump ends: an interrupt entered at that cycle, with
//! no instruction run since, is the one that woke the CPU.

use std::cell::Cell;
use std::ffi::c_void;
use std::ptr::NonNull;

use simavr_ffi as ffi;

use crate::mcu::chip::Chip;

/// No sleep has ended since the last interrupt was entered.
const NOT_ASLEEP: u64 = u64::MAX;

/// What the response's callbacks keep between them; a field of the state
/// simavr's callbacks reach (`shared.rs`), so it lives as long as the MCU.
pub(super) struct Response {
    avr: NonNull<ffi::avr_t>,
    /// The cycle the last jump over a sleep ended at ([`NOT_ASLEEP`]: none
    /// since the last interrupt was entered).
    sleep_end: Cell<u64>,
    /// The cycle the last `sleep` instruction began at.
    sleep_start: Cell<u64>,
    /// The MCU's response, awake and waking.
    cycles: u64,
    wake_up_cycles: u64,
}

impl Response {
    pub(super) fn new(avr: NonNull<ffi::avr_t>, chip: &Chip) -> Self {
        Self {
            avr,
            cycles: chip.response_cycles(),
            wake_up_cycles: chip.wake_up_cycles(),
            sleep_end: Cell::new(NOT_ASLEEP),
            sleep_start: Cell::new(0),
        }
    }

    /// The cycle the last `sleep` instruction began at: what a run loop
    /// stepping one instruction at a time counts a sleep from, however many
    /// instructions ran before it in the same step.
    pub(super) fn sleep_start(&self) -> u64 {
        self.sleep_start.get()
    }

    /// Forget a sleep (the MCU was reset: it is awake).
    pub(super) fn forget_sleep(&self) {
        self.sleep_end.set(NOT_ASLEEP);
    }
}

/// Install the response on the MCU `response` belongs to: the sleep
/// callback, and the notify on `AVR_INT_ANY`'s running line.
///
/// # Safety
/// `response` points to a `Response` made for this live, initialised MCU,
/// which stays where it is until after the MCU is freed.
pub(super) unsafe fn install(response: NonNull<Response>) {
    // SAFETY: as the caller guarantees; plain field writes on the MCU, and
    // `avr_get_interrupt_irq(.., AVR_INT_ANY)` returns the table's array of
    // AVR_INT_IRQ_COUNT lines, of which RUNNING is one.
    unsafe {
        let avr = (*response.as_ptr()).avr.as_ptr();
        let param = response.as_ptr() as *mut c_void;
        (*avr).sleep = Some(sleep);
        (*avr).custom.data = param;
        let any = ffi::avr_get_interrupt_irq(avr, ffi::AVR_INT_ANY as u8);
        assert!(!any.is_null(), "simavr has no AVR_INT_ANY lines");
        let running = any.add(ffi::AVR_INT_IRQ_RUNNING as usize);
        ffi::avr_irq_register_notify(running, Some(running_changed), param);
    }
}

/// simavr's sleep callback, called as it jumps over a sleep of `how_long`
/// cycles (to the next cycle timer) and just before it adds `1 + how_long`
/// to the cycle. simavr's default usleeps to keep emulated time in step
/// with the wall clock, which would pin a sleeping firmware to 1x real time
/// and make runs depend on the host: this one does not wait. It takes back
/// simavr's extra cycle, so the jump ends on the timer's own cycle (which
/// is at least one cycle ahead: simavr sleeps only until a timer not yet
/// due), and notes that cycle.
///
/// # Safety
/// Called by simavr only, on an MCU [`install`] set up: `custom.data` is
/// its `Response`.
unsafe extern "C" fn sleep(avr: *mut ffi::avr_t, how_long: ffi::avr_cycle_count_t) {
    // SAFETY: as the caller guarantees; the `Response` is only ever read
    // through shared references (its field is a `Cell`).
    unsafe {
        let response = &*((*avr).custom.data as *const Response);
        // simavr jumps in the step that ran the `sleep`, right after it and
        // the due timers (which leave the cycle alone); `sleep` takes one
        // cycle.
        response.sleep_start.set((*avr).cycle.wrapping_sub(1));
        // Unsigned arithmetic: simavr adds the cycle back right after.
        (*avr).cycle = (*avr).cycle.wrapping_sub(1);
        response
            .sleep_end
            .set((*avr).cycle.wrapping_add(1).wrapping_add(how_long));
    }
}

/// `AVR_INT_ANY`'s running line changed: an interrupt was entered (simavr
/// has just pushed the PC, cleared I and set the PC to the vector) or a
/// `reti` is executing (simavr has just set I; the notify comes whether or
/// not a vector was running). I tells the two apart.
///
/// # Safety
/// Called by simavr only, with the `param` [`install`] registered.
unsafe extern "C" fn running_changed(_irq: *mut ffi::avr_irq_t, _value: u32, param: *mut c_void) {
    // SAFETY: as the caller guarantees; plain field accesses on the MCU the
    // response belongs to, which is running this callback.
    unsafe {
        let response = &*(param as *const Response);
        let avr = response.avr.as_ptr();
        let cycle = (*avr).cycle;
        let stall = if (*avr).sreg[ffi::S_I as usize] != 0 {
            // `reti`: simavr counts its five cycles itself.
            0
        } else if response.sleep_end.replace(NOT_ASLEEP) == cycle {
            response.cycles + response.wake_up_cycles
        } else {
            response.cycles
        };
        (*avr).cycle = cycle + stall;
    }
}
