//! Idle sleep and the "something happened" flag that makes it race-free.
//!
//! Every interrupt handler that may give the main loop work calls [`wake`].
//! The main loop polls all its sources, then calls [`Sleeper::idle`], which
//! sleeps only if no handler has called [`wake`] since the previous `idle`
//! returned. The check and the `sleep` happen with interrupts off, and
//! interrupts come back on with `sei` immediately followed by `sleep`: the
//! AVR executes the instruction after `sei` before any pending interrupt, so
//! an interrupt that arrives after the check still wakes the CPU from that
//! very `sleep` instead of being lost until the next one.

use core::arch::asm;
use core::cell::Cell;

use avr_device::atmega2560::CPU;
use avr_device::interrupt::{self, CriticalSection, Mutex};

/// Set by handlers, cleared when `idle` returns.
static WOKEN: Mutex<Cell<bool>> = Mutex::new(Cell::new(false));

/// SMCR: SM2:0 = 000 (idle: timers, USARTs and external interrupts keep
/// running) and SE = 1.
const SMCR_IDLE_ENABLED: u8 = 0b0000_0001;

/// Records that the main loop has something to look at. Called from handlers.
#[inline(always)]
pub fn wake() {
    interrupt::free(|cs| WOKEN.borrow(cs).set(true));
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

    /// Sleeps in idle mode until the next interrupt, unless an interrupt has
    /// already called [`wake`] since the last return from here. Returns with
    /// interrupts enabled and the flag cleared: everything handlers did before
    /// this return is for the caller's next poll to see.
    pub fn idle(&mut self) {
        interrupt::disable();
        // SAFETY: interrupts were disabled on the line above.
        let cs = unsafe { CriticalSection::new() };
        if !WOKEN.borrow(cs).get() {
            // SAFETY: idle mode with SE is a valid SMCR value; SE is set only
            // for the one `sleep` below, as the datasheet recommends.
            unsafe { self.cpu.smcr().write(|w| w.bits(SMCR_IDLE_ENABLED)) };
            // SAFETY: `sei; sleep` enables interrupts; the instruction after
            // `sei` always runs first, so the CPU is asleep before any pending
            // handler runs and that handler wakes it. No Rust state is held
            // across (the asm is a compiler barrier: no `nomem`).
            unsafe { asm!("sei", "sleep") };
            // SAFETY: back to the reset value, sleep disabled.
            unsafe { self.cpu.smcr().write(|w| w.bits(0)) };
        } else {
            // SAFETY: we are in the main loop, which always runs with
            // interrupts enabled; this only undoes the `disable` above.
            unsafe { interrupt::enable() };
        }
        // A handler that runs between the wake-up and this line is still seen:
        // the caller polls after this returns.
        interrupt::free(|cs| WOKEN.borrow(cs).set(false));
    }

    /// Gives the register back.
    pub fn release(self) -> CPU {
        self.cpu
    }
}
