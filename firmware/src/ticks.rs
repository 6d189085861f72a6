//! The control tick count: the timer 1 compare handler adds one to the
//! bench's `HT_TICKS` every period and wakes the main loop, which notices new
//! ticks through a [`TickWatch`].

use avr_device::interrupt;

use crate::bench;
use crate::hal::sleep;

/// Remembers the last tick count the main loop has handled.
pub struct TickWatch {
    seen: u32,
}

impl TickWatch {
    /// Starts watching from the current count.
    pub fn new() -> Self {
        TickWatch { seen: interrupt::free(bench::ticks) }
    }

    /// Number of ticks since the previous call (0 if none; more than 1 means
    /// the main loop missed a period).
    pub fn take(&mut self) -> u32 {
        let now = interrupt::free(bench::ticks);
        let n = now.wrapping_sub(self.seen);
        self.seen = now;
        n
    }
}

impl Default for TickWatch {
    fn default() -> Self {
        Self::new()
    }
}

// One control period elapsed.
#[avr_device::interrupt(atmega2560)]
fn TIMER1_COMPA() {
    // SAFETY: inside the handler interrupts are off; this is the only writer.
    unsafe { bench::isr_count_tick() };
    sleep::wake();
}
