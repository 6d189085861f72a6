//! The robust build's clock, all from timer 1 (see `hal::tick`):
//! - the control tick: one COMPA interrupt every 15 ms (`HT_TICKS`);
//! - a monotonic clock in timer clocks ([`crate::time`]): the time at the
//!   start of the current period plus TCNT1;
//! - one alarm: a COMPB wake-up at a given time inside the current period
//!   (later alarms are re-armed by the main loop after each tick).

use core::cell::Cell;

use avr_device::atmega2560::TC1;
use avr_device::interrupt::{self, CriticalSection, Mutex};

use crate::bench;
use crate::board::CPU_HZ;
use crate::hal::sleep;
use crate::hal::tick::{self, CtcPeriod, TickTimer};
use crate::io::TickClock;
use crate::robot;
use crate::time::{ms, reached, PRESCALER};

/// Timer 1 period: OCR1A = 3749, exactly 15 ms at 16 MHz.
pub const TICK: CtcPeriod = CtcPeriod::exact_us(CPU_HZ, PRESCALER, robot::SAMPLE_PERIOD_US);
const _: () = assert!(TICK.top == 3749);
/// Timer clocks per tick.
pub const CLOCKS_PER_TICK: u32 = TICK.clocks();
const _: () = assert!(ms(15) == CLOCKS_PER_TICK);

/// Time at the start of the current period (advanced by the COMPA handler).
static EPOCH: Mutex<Cell<u32>> = Mutex::new(Cell::new(0));

/// The clock: timer 1 and the last tick count the main loop has seen.
pub struct Clock {
    timer: TickTimer,
    seen: u32,
}

impl Clock {
    /// Starts timer 1 (time 0 now).
    pub fn start(tc1: TC1) -> Self {
        let timer = TickTimer::start(tc1, TICK);
        Clock { timer, seen: interrupt::free(bench::ticks) }
    }

    /// The start of the counter's current period and TCNT1, at one instant.
    fn snapshot(&self, cs: CriticalSection) -> (u32, u32) {
        let c = self.timer.count();
        let mut epoch = EPOCH.borrow(cs).get();
        // The period ended but its handler has not run: if the counter has
        // already wrapped (small value), the time is one period later.
        if c.period_pending && (c.tcnt as u32) < CLOCKS_PER_TICK / 2 {
            epoch = epoch.wrapping_add(CLOCKS_PER_TICK);
        }
        (epoch, c.tcnt as u32)
    }

    fn now_cs(&self, cs: CriticalSection) -> u32 {
        let (start, tcnt) = self.snapshot(cs);
        start.wrapping_add(tcnt)
    }

    /// The current time, timer clocks.
    #[inline]
    pub fn now(&self) -> u32 {
        interrupt::free(|cs| self.now_cs(cs))
    }

    /// Ticks since the previous call (0 if none; more than 1 means the main
    /// loop missed a period).
    #[inline]
    pub fn take_ticks(&mut self) -> u32 {
        let now = interrupt::free(bench::ticks);
        let n = now.wrapping_sub(self.seen);
        self.seen = now;
        n
    }

    /// Starts a fresh 15 ms period now (TCNT1 = 0, a pending tick dropped),
    /// keeping the clock continuous; disarms the alarm. The next tick comes
    /// one full period later (less up to one prescaler step, since the
    /// shared prescaler keeps running).
    pub fn restart_period(&mut self) {
        interrupt::free(|cs| {
            let now = self.now_cs(cs);
            self.timer.restart_period();
            EPOCH.borrow(cs).set(now);
        });
        self.take_ticks();
    }

    /// Wakes the CPU at `at` if that is inside the current period (COMPB);
    /// a later time needs no alarm yet (the tick wakes the CPU first, and the
    /// caller arms again). Returns false, with no alarm, if `at` has already
    /// been reached: the caller must handle it now.
    pub fn arm_alarm(&mut self, at: u32) -> bool {
        interrupt::free(|cs| {
            let (period_start, tcnt) = self.snapshot(cs);
            if reached(period_start.wrapping_add(tcnt), at) {
                self.timer.disarm_compare_b();
                return false;
            }
            let offset = at.wrapping_sub(period_start);
            if offset < CLOCKS_PER_TICK {
                self.timer.arm_compare_b(offset as u16);
            } else {
                self.timer.disarm_compare_b();
            }
            // The counter may have passed the compare value while it was
            // written.
            if reached(self.now_cs(cs), at) {
                self.timer.disarm_compare_b();
                return false;
            }
            true
        })
    }

    /// Cancels the alarm.
    pub fn disarm_alarm(&mut self) {
        interrupt::free(|_| self.timer.disarm_compare_b());
    }
}

/// Body of the TIMER1_COMPA vector: a period ended.
///
/// # Safety
/// Call only from the TIMER1_COMPA vector.
#[inline(always)]
pub unsafe fn on_tick() {
    // SAFETY: interrupts are off inside the handler.
    let cs = unsafe { CriticalSection::new() };
    let e = EPOCH.borrow(cs);
    e.set(e.get().wrapping_add(CLOCKS_PER_TICK));
    // SAFETY: inside the handler; the only writer of HT_TICKS in this build.
    unsafe { bench::isr_count_tick() };
    sleep::wake();
}

/// Body of the TIMER1_COMPB vector: the alarm time came. One-shot: the
/// handler disables itself.
///
/// # Safety
/// Call only from the TIMER1_COMPB vector.
#[inline(always)]
pub unsafe fn on_alarm() {
    // SAFETY: forwarded; we are that handler.
    unsafe { tick::isr_disarm_compare_b() };
    sleep::wake();
}

impl TickClock for Clock {
    #[inline(always)]
    fn now(&self) -> u32 {
        Clock::now(self)
    }

    #[inline(always)]
    fn take_ticks(&mut self) -> u32 {
        Clock::take_ticks(self)
    }

    #[inline(always)]
    fn restart_period(&mut self) {
        Clock::restart_period(self)
    }

    #[inline(always)]
    fn arm_alarm(&mut self, at: u32) -> bool {
        Clock::arm_alarm(self, at)
    }

    #[inline(always)]
    fn disarm_alarm(&mut self) {
        Clock::disarm_alarm(self)
    }
}
