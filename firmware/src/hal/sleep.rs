//! Idle sleep and the "something happened" flag that makes it race-free.
//!
//! Every interrupt handler that may give the main loop work calls [`wake`].
//! The main loop polls all its sources, then calls [`Sleeper::idle`], which
//! sleeps until a handler has called [`wake`] since the previous `idle`
//! returned (other interrupts only interrupt the sleep). The check and the `sleep` happen with interrupts off, and
//! interrupts come back on with `sei` immediately followed by `sleep`: the
//! AVR executes the instruction after `sei` before any pending interrupt, so
//! an interrupt that arrives after the check still wakes the CPU from that
//! very `sleep` instead of being lost until the next one.

use core::arch::asm;
use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use avr_device::atmega2560::CPU;
use avr_device::interrupt;

/// Interrupts without [`wake`] that [`Sleeper::idle`] sleeps through before
/// returning anyway.
pub const MAX_NAPS: u8 = 255;

/// Set (to 1) by handlers, cleared when `idle` returns. A plain byte so that
/// the assembly encoder handlers can set it too; Rust code accesses it only
/// through [`wake`] and [`Sleeper::idle`], with interrupts off.
#[doc(hidden)]
pub static mut WOKEN: u8 = 0;

/// SMCR: SM2:0 = 000 (idle: timers, USARTs, the ADC and external
/// interrupts keep running) and SE = 1.
const SMCR_IDLE_ENABLED: u8 = 0b0000_0001;

/// Records that the main loop has something to look at. Called from handlers.
#[inline(always)]
pub fn wake() {
    // SAFETY: a single byte store, atomic on the AVR; the only other writer
    // (`idle`) clears it with interrupts off.
    unsafe { write_volatile(addr_of_mut!(WOKEN), 1) };
}

/// Owner of the sleep mode control register.
pub struct Sleeper {
    cpu: CPU,
}

impl Sleeper {
    /// Takes SMCR; sleep stays disabled (SE = 0) except around `sleep`.
    pub fn new(cpu: CPU) -> Self {
        // SAFETY: 0 is SMCR's reset value (idle mode, sleep disabled).
        unsafe { cpu.smcr().write(|w| w.bits(0)) };
        Sleeper { cpu }
    }

    /// Sleeps in idle mode until a handler calls [`wake`], unless one has
    /// already done so since the last return from here. Interrupts whose
    /// handler does not call [`wake`] (an encoder edge that ends nothing, a
    /// byte still being sent) put the CPU back to sleep at once. Returns with
    /// interrupts enabled and the flag cleared: everything handlers did
    /// before this return is for the caller's next poll to see.
    ///
    /// Bounded: after [`MAX_NAPS`] interrupts without a [`wake`] it returns
    /// anyway (the caller then polls once for nothing). With the 15 ms tick
    /// calling [`wake`], the wait never lasts longer than one tick.
    pub fn idle(&mut self) {
        // SE stays set for the whole wait: the `sleep` below is the only one
        // in the program, and re-writing SMCR around every nap would cost
        // cycles on every encoder edge.
        // SAFETY: idle mode with SE is a valid SMCR value.
        unsafe { self.cpu.smcr().write(|w| w.bits(SMCR_IDLE_ENABLED)) };
        for _ in 0..MAX_NAPS {
            interrupt::disable();
            // SAFETY: interrupts are off; a byte load.
            if unsafe { read_volatile(addr_of!(WOKEN)) } != 0 {
                break;
            }
            // SAFETY: `sei; sleep` enables interrupts; the instruction after
            // `sei` always runs first, so the CPU is asleep before any pending
            // handler runs and that handler wakes it. No Rust state is held
            // across (the asm is a compiler barrier: no `nomem`).
            unsafe { asm!("sei", "sleep") };
        }
        // SAFETY: back to the reset value, sleep disabled.
        unsafe { self.cpu.smcr().write(|w| w.bits(0)) };
        // SAFETY: the main loop always runs with interrupts enabled; this
        // undoes the `disable` of the last round.
        unsafe { interrupt::enable() };
        // A handler that runs between the wake-up and this line is still seen:
        // the caller polls after this returns.
        // SAFETY: a byte store with interrupts off.
        interrupt::free(|_| unsafe { write_volatile(addr_of_mut!(WOKEN), 0) });
    }

    /// Gives the register back.
    pub fn release(self) -> CPU {
        self.cpu
    }
}
