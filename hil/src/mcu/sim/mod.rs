//! The only module that talks to simavr.
//!
//! [`Avr`] owns one simulated ATmega and one [`Handler`], the bench's side of
//! the simulation. simavr calls back into the handler through C trampolines
//! for: IO register writes the bench claims or observes, pin and UART IRQs, and
//! one cycle timer that carries the bench's whole event queue. Inside a
//! callback the handler gets a [`Core`], a narrow view of the running MCU.
//!
//! What simavr does that we change, and why:
//! - the interrupt response is the datasheet's (`response.rs`): entering a
//!   vector takes five cycles on the ATmega2560, four on the 2-byte-PC
//!   MCUs (twice that when it wakes the CPU), where simavr takes none; a jump over a sleep ends on the cycle of the timer it
//!   sleeps until, not one past it;
//! - the sleep callback does not wait: simavr's default usleeps to keep
//!   emulated time in step with the wall clock, which pins a sleeping
//!   firmware to 1x real time and makes runs depend on the host;
//! - the UARTs' "poll sleep" and stdio flags are cleared: the first usleeps on
//!   status polls, the second prints the firmware's bytes on our stdout;
//! - a pin the bench drives keeps its level when the firmware writes its
//!   port: simavr re-applies an input's pull-up on every PORT or DDR write,
//!   over the level an outside driver holds, unless the pin is declared
//!   external (`pins.rs`);
//! - the firmware image is loaded from the ELF by the bench ([`crate::firmware::elf`]),
//!   since a Rust ELF has no `.mmcu` section and simavr's loader prints to
//!   stdout;
//! - the core runs free between cycle timers ([`Avr::set_free_run`]):
//!   simavr's `run_cycle_limit` is 1 by default, so it processes its timers
//!   after every instruction; raised, the core runs instructions back to back
//!   up to the next timer's cycle, which the vendored simavr keeps as an
//!   absolute cycle (`run_cycle_end`, vendor/simavr-ffi/patches) so that the
//!   cycles the response and the sleep jump add cannot carry it past a timer.
//!   The burst's end bounds the free run too (`run_cycle_stop`, of the same
//!   patch: a cycle timer there would also cut a jump over a sleep short),
//!   and a callback that ends a burst ends the free run after its
//!   instruction (`trampolines.rs`): every timer fires, and every burst
//!   ends, after the same instruction as when stepping one at a time.
//!
//! # Soundness
//! The safe API holds whatever safe code does with it:
//! - the handler's state is allocated once and reached only through the raw
//!   pointer simavr also holds (`shared.rs`): no reborrow ever invalidates
//!   simavr's copies;
//! - the handler is borrowed by one callback at a time: a callback simavr
//!   makes while the handler runs is refused with a panic, never nested;
//! - no panic unwinds into C: each trampoline catches it, the burst stops,
//!   and the `Avr` call that ran simavr resumes the panic (`trampolines.rs`);
//! - an [`Irq`] works with its own `Avr` only, checked at each use (`irq.rs`);
//! - the `avr_t` is freed once on every path, after which no callback can
//!   run (`mcu.rs`, and the order of [`Avr`]'s fields).
//!
//! # Where the unsafe lines are
//! All of the crate's `unsafe` is in this module and in `crate::mcu::sim::sys` (the
//! OS calls; the crate denies `unsafe_code` everywhere else). Here, every unsafe block has
//! its `// SAFETY:` line and every unsafe fn its `# Safety` doc:
//! - `mod.rs`: [`Avr::new`]'s setup of the MCU's fields, the step calls and
//!   field reads of the run loops, `avr_reset`, the
//!   response's installation, and the
//!   handler borrows of [`Avr::handler`], [`Avr::handler_mut`] and
//!   [`Avr::with_core`];
//! - `claims.rs`: the IO slot installs of the claims and the notify
//!   registration of [`Avr::watch_irq`];
//! - `skip.rs`: the access hook's installation and the core's state read
//!   and moved on by a fast-forward over a polling loop;
//! - `mcu.rs`: making, initialising and freeing the `avr_t`, and the raw
//!   data-space reads and writes everything else uses;
//! - `memory.rs`: field and flash accesses of the memory accessors, each
//!   bounds-checked first;
//! - `view.rs`: [`Core`]'s field accesses and its raise and schedule calls;
//! - `irq.rs`: IRQ lookups and `avr_raise_irq`;
//! - `pins.rs`: the external-pin ioctl and its raise;
//! - `shared.rs`: the handler state's allocation and free;
//! - `response.rs`: the sleep callback and the running-interrupt notify,
//!   which add the response's cycles, and their installation;
//! - `trampolines.rs`: the `extern "C"` callbacks and the timer
//!   registration;
//! - `usb.rs`: the USB controller's ioctls, its vector's raise, the
//!   look-up of its IRQ and vector, and the side-effect-free look at an
//!   endpoint through simavr's read handlers;
//! - `owner.rs`, `tests.rs`: none.

use std::ffi::CString;
use std::ptr::NonNull;

use simavr_ffi as ffi;
use thiserror::Error;

mod claims;
mod irq;
mod mcu;
mod memory;
mod owner;
mod pins;
mod response;
mod shared;
mod skip;
pub(crate) mod sys;
#[cfg(test)]
mod tests;
mod trampolines;
mod usb;
mod view;

pub use irq::Irq;
pub use pins::DrivenPin;
pub use usb::{EndpointState, UsbAnswer, UsbPort};
pub use view::Core;

use mcu::{decode_state, Mcu};
use owner::Owner;
use shared::{Flag, Shared, SharedBox};
use trampolines::{schedule_from_core, schedule_timer};

/// simavr's `run_cycle_limit` while the core runs free: no bound of its own,
/// only the next cycle timer's and the burst's end (`run_cycle_stop`).
const FREE_RUN_LIMIT: u64 = u64::MAX;
/// simavr's default `run_cycle_limit`: back to the timers after every
/// instruction.
const STEP_LIMIT: u64 = 1;

/// Errors from creating or driving the simulated MCU.
#[derive(Debug, Error)]
pub enum SimError {
    #[error(
        "the bench has no description of the MCU simavr calls {0:?} (it describes {names})",
        names = crate::mcu::chip::Mcu::names()
    )]
    UnknownMcu(String),
    #[error("simavr failed to initialise the MCU {0:?}")]
    InitFailed(String),
    #[error("firmware segment at flash 0x{addr:05x} with {len} bytes does not fit in the {flash} bytes of flash")]
    FlashOverflow { addr: u32, len: usize, flash: u32 },
    #[error("the MCU has no IO port {0:?}")]
    NoSuchPort(char),
    #[error("the MCU has no pin P{0}{1}")]
    NoSuchPin(char, u8),
    #[error("the MCU has no USART{0}")]
    NoSuchUart(u8),
    #[error("the MCU has no USB device controller")]
    NoUsb,
    #[error("IO address 0x{0:04x} is outside simavr's IO table")]
    IoOutOfRange(u16),
}

/// simavr's CPU states, as far as the bench cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CpuState {
    Running,
    Sleeping,
    /// Stopped for good: sleeping with interrupts off, `break`, or done.
    Done,
    /// simavr detected a crash (bad PC, bad opcode, stack overflow, ...).
    Crashed,
    Other(i32),
}

/// How a burst of steps ([`Avr::run_burst`]) ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Burst {
    /// Cycles spent asleep.
    pub slept: u64,
    /// The CPU's state after the last step.
    pub state: CpuState,
}

/// How the bench takes part in writes to an IO register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IoClaim {
    /// The bench emulates the register: simavr's own handler never runs.
    Replace,
    /// simavr's handler runs first, then the bench sees the value.
    Observe,
}

/// The bench's half of the simulation. All methods run inside simavr's
/// callbacks, at the current emulated cycle, one at a time: a callback
/// that would start while another runs (a [`Core::raise`] that reaches a
/// watched IRQ) is refused with a panic. A panic in a method ends the
/// running burst and is resumed by the `Avr` call that ran it.
pub trait Handler: 'static {
    /// A write to a register claimed with [`Avr::claim_io_write`].
    fn io_write(&mut self, core: &mut Core, addr: u16, value: u8);
    /// A read of a register claimed with [`Avr::claim_io_read`]; returns the
    /// value the CPU reads.
    fn io_read(&mut self, core: &mut Core, addr: u16) -> u8;
    /// A read of a register watched with [`Avr::observe_io_read`] is about
    /// to happen (simavr's own read handler runs right after): the moment to
    /// bring input lines up to date.
    fn before_io_read(&mut self, _core: &mut Core, _addr: u16) {}
    /// Whether a callback left something for the caller of
    /// [`Avr::run_burst`] to handle: the burst ends after that step.
    fn attention(&self) -> bool {
        false
    }
    /// The bench's cycle timer fired; `when` is the cycle it was scheduled for
    /// (the current cycle may be a few cycles later: simavr checks timers
    /// between instructions, and after the instruction that follows an
    /// interrupt's response). Returns the next cycle to fire at, or 0 for none.
    fn timer(&mut self, core: &mut Core, when: u64) -> u64;
    /// An IRQ watched with [`Avr::watch_irq`] was raised.
    fn irq(&mut self, core: &mut Core, tag: u32, value: u32);
}

/// One simulated MCU and the bench's handler.
pub struct Avr<H: Handler> {
    // Fields drop in order: the MCU first, so that no callback can run once
    // the handler's state (which simavr points to) is freed.
    mcu: Mcu,
    shared: SharedBox<H>,
    code_end: u32,
    /// The step function simavr installed at init (what `avr_run` calls),
    /// called directly to save a call per instruction.
    run: unsafe extern "C" fn(*mut ffi::avr_t),
    /// Bursts and [`Avr::run_to`] let the core run free between cycle
    /// timers ([`Avr::set_free_run`]).
    free_run: bool,
    /// Exact fast-forward of polling loops in bursts ([`Avr::set_skip`]).
    skip: skip::Skip,
    chip: &'static crate::mcu::chip::Chip,
}

impl<H: Handler> Avr<H> {
    /// Create an MCU by simavr name at `frequency_hz`, with empty flash.
    /// Only an MCU the bench describes (`crate::mcu::chip`): its response
    /// and its pins are read from there.
    pub fn new(mcu: &str, frequency_hz: u32, handler: H) -> Result<Self, SimError> {
        let chip = crate::mcu::chip::Mcu::ALL
            .into_iter()
            .map(crate::mcu::chip::Mcu::chip)
            .find(|c| c.simavr_core == mcu)
            .ok_or_else(|| SimError::UnknownMcu(mcu.into()))?;
        let name = CString::new(mcu).map_err(|_| SimError::UnknownMcu(mcu.into()))?;
        // From here the MCU is freed on every error path (`Mcu`'s drop).
        let mut avr = Mcu::by_name(&name).ok_or_else(|| SimError::UnknownMcu(mcu.into()))?;
        let run = avr.init(mcu)?;
        let shared = SharedBox::new(Shared::new(avr.ptr(), chip, Owner::next(), handler));
        // SAFETY: plain field writes on the initialised MCU.
        unsafe {
            let a = avr.as_ptr();
            (*a).frequency = frequency_hz;
            // The Arduino Mega runs at 5 V; AVCC and AREF on the same rail
            // (millivolts, as simavr's ADC takes its inputs).
            (*a).vcc = 5000;
            (*a).avcc = 5000;
            (*a).aref = 5000;
            (*a).set_log(1); // LOG_ERROR: simavr's errors only
        }
        // SAFETY: the response is a field of the state, allocated once and
        // freed after the MCU (the order of `Avr`'s fields).
        unsafe {
            let p = shared.ptr().as_ptr();
            let response = NonNull::new(std::ptr::addr_of_mut!((*p).response))
                .expect("a field of a live allocation");
            response::install(response);
        }
        Ok(Self {
            mcu: avr,
            shared,
            code_end: 0,
            run,
            free_run: true,
            skip: skip::Skip::new(),
            chip,
        })
    }

    /// The description of the MCU simavr emulates.
    pub fn chip(&self) -> &'static crate::mcu::chip::Chip {
        self.chip
    }

    #[inline]
    fn raw(&self) -> *mut ffi::avr_t {
        self.mcu.as_ptr()
    }

    #[inline]
    fn state_ptr(&self) -> *mut Shared<H> {
        self.shared.ptr().as_ptr()
    }

    fn owner(&self) -> Owner {
        // SAFETY: a field that never changes, read through the state's
        // pointer; no callback runs while `self` is borrowed.
        unsafe { (*self.state_ptr()).owner }
    }

    /// After a call that ran simavr: resume the panic of a callback it ran
    /// (a panic of the handler, or a refused re-entrant callback).
    #[inline]
    fn resume_failure(&mut self) {
        // SAFETY: a `Cell` field of the live state; no callback is running.
        if unsafe { (*self.state_ptr()).failed.get() } {
            self.resume_failure_now()
        }
    }

    #[cold]
    #[inline(never)]
    fn resume_failure_now(&mut self) {
        // SAFETY: as in `resume_failure`.
        let payload = unsafe {
            let p = self.state_ptr();
            (*p).failed.set(false);
            (*p).failure.take()
        };
        if let Some(payload) = payload {
            std::panic::resume_unwind(payload);
        }
    }

    /// Whether [`Avr::run_burst`] and [`Avr::run_to`] let the core run
    /// free between cycle timers (the default) or step one instruction at a
    /// time, as simavr does by default. The results are the same to the
    /// cycle and the bit either way; free is faster. [`Avr::step`] always
    /// runs one instruction.
    pub fn set_free_run(&mut self, on: bool) {
        self.free_run = on;
    }

    pub fn free_run(&self) -> bool {
        self.free_run
    }

    /// Whether [`Avr::run_burst`] fast-forwards over the repeats of a
    /// polling loop that it proves change nothing before the next cycle
    /// timer (`skip.rs`; off by default). The results are the same to the
    /// cycle and the bit either way.
    pub fn set_skip(&mut self, on: bool) {
        self.skip.on = on;
    }

    /// Cycles fast-forwarded over polling loops so far.
    pub fn skipped_cycles(&self) -> u64 {
        self.skip.skipped
    }

    /// Set simavr's run-cycle bounds: `limit` cycles at most between two
    /// passes over the timers, never past cycle `stop` (0: no such bound),
    /// and back to the timers after the next instruction (simavr sets the
    /// next end when it passes over them).
    #[inline]
    fn set_run_limit(&mut self, limit: u64, stop: u64) {
        // SAFETY: plain field writes on the live MCU; no callback runs.
        unsafe {
            let a = self.raw();
            (*a).run_cycle_limit = limit;
            (*a).run_cycle_stop = stop;
            (*a).run_cycle_end = 0;
        }
    }

    /// Execute one instruction (or, while sleeping, jump to the next timer).
    ///
    /// # Panics
    /// With the panic of a callback the step ran.
    #[inline]
    pub fn step(&mut self) -> CpuState {
        self.set_run_limit(STEP_LIMIT, 0);
        let avr = self.raw();
        // SAFETY: the MCU is initialised and loaded; callbacks reach the
        // handler through the state's pointer, and `&mut self` means nothing
        // else borrows it during the call.
        let state = unsafe {
            (self.run)(avr);
            (*avr).state
        };
        self.resume_failure();
        decode_state(state)
    }

    /// Runs steps (an instruction, or a jump over a sleep) and ends after the
    /// first that reaches cycle `until`, leaves the CPU neither running nor
    /// sleeping, or whose callbacks leave the handler wanting
    /// [`Handler::attention`] (a burst begun with attention pending runs one
    /// step). `sleeping` says whether the CPU slept before the first step
    /// and is updated; cycles of steps that slept (or began or ended asleep)
    /// are summed in [`Burst::slept`]. The same as calling [`Avr::step`] in
    /// a loop, without leaving this module per instruction, and with one
    /// bound per instruction as [`Avr::run_to`] has; with free run
    /// ([`Avr::set_free_run`]) a step is every instruction up to the next
    /// cycle timer, the burst's end being one, with the same results.
    ///
    /// # Panics
    /// With the panic of a callback, after the step that ran it.
    // Out of line, so that the loop keeps its bounds in registers.
    #[inline(never)]
    pub fn run_burst(&mut self, until: u64, sleeping: &mut bool) -> Burst {
        let avr = self.raw();
        let run = self.run;
        let shared = self.state_ptr();
        // SAFETY: field accesses through the state's pointer; the callbacks
        // run during `run` reach the same state through the same pointer,
        // and nothing holds a reference into it across a step.
        let end = unsafe {
            let end = if (*shared).handler.attention() {
                0
            } else {
                until
            };
            (*shared).burst_end.set(end);
            end
        };
        // A burst begun with attention pending runs one instruction.
        self.bound_run(end);
        let mut slept = 0;
        let mut was_asleep = *sleeping;
        // SAFETY: plain field read.
        let mut before = unsafe { (*avr).cycle };
        let (limit, stop) = self.run_limits(end);
        let skip = &mut self.skip;
        // The last step of a probe of the skip, judged here as any step. A
        // burst that begins awake probes at once: the run loop's bursts are
        // short (its checks' grid), and a loop is most often already
        // running when one begins.
        let awake = !was_asleep && {
            // SAFETY: plain field read.
            unsafe { (*avr).state == ffi::cpu_Running as i32 }
        };
        // A probe of the skip from where the MCU stands (between steps).
        let probe = |skip: &mut skip::Skip| {
            // SAFETY: called between steps of this live MCU; the burst's end
            // is read as in the loop below.
            unsafe {
                skip::probe(
                    skip,
                    avr,
                    run,
                    || (*shared).burst_end.get(),
                    skip::Limits { limit, stop },
                )
            }
        };
        let mut probed: Option<skip::Last> = if awake && end != 0 && skip.due(before) {
            probe(skip)
        } else {
            None
        };
        let state = loop {
            // SAFETY: as in `step`; plain field reads between the steps.
            let (state, now) = match probed.take() {
                Some(last) => {
                    before = last.before;
                    (last.state, last.now)
                }
                None => unsafe {
                    run(avr);
                    ((*avr).state, (*avr).cycle)
                },
            };
            // SAFETY: as above (a failed callback sets it to 0).
            let end = unsafe { (*shared).burst_end.get() };
            // Almost every step is an instruction between two awake ones:
            // nothing to account, one bound to test.
            if state == ffi::cpu_Running as i32 && !was_asleep {
                if now >= end {
                    *sleeping = false;
                    break state;
                }
                before = now;
                if skip.due(now) {
                    probed = probe(skip);
                }
                continue;
            }
            // A step that began or ended asleep counts as slept: from the
            // `sleep` instruction on, when the step began awake (with free
            // run it may have run many instructions before that one).
            let asleep = state == ffi::cpu_Sleeping as i32;
            if asleep && !was_asleep {
                // SAFETY: a `Cell` field of the live state.
                before = unsafe { (*shared).response.sleep_start() };
            }
            slept += now - before;
            before = now;
            was_asleep = asleep;
            let stopped = !asleep && state != ffi::cpu_Running as i32;
            if stopped || now >= end {
                *sleeping = asleep;
                break state;
            }
        };
        self.resume_failure();
        Burst {
            slept,
            state: decode_state(state),
        }
    }

    /// Steps until the cycle reaches `end` or the CPU stops running and
    /// sleeping, with nothing else between the steps: simavr driven as
    /// bare as it can be (the baseline `hil bench` compares the bench with).
    ///
    /// # Panics
    /// With the panic of a callback, at `end` (the bare loop does not
    /// look for one between steps).
    pub fn run_to(&mut self, end: u64) -> CpuState {
        self.bound_run(end);
        let avr = self.raw();
        let run = self.run;
        let state = loop {
            // SAFETY: as in `step`.
            let (state, now) = unsafe {
                run(avr);
                ((*avr).state, (*avr).cycle)
            };
            let stopped = state != ffi::cpu_Running as i32 && state != ffi::cpu_Sleeping as i32;
            if stopped || now >= end {
                break state;
            }
        };
        self.resume_failure();
        decode_state(state)
    }

    /// Bound the next steps: with free run, by the cycle timers and `end`
    /// (simavr stops at the first instruction that reaches it, as the loops
    /// do); otherwise one instruction per step. `end` 0: one instruction.
    #[inline]
    fn bound_run(&mut self, end: u64) {
        let (limit, stop) = self.run_limits(end);
        self.set_run_limit(limit, stop);
    }

    /// simavr's run limit and stop for [`Avr::bound_run`]. While skipping,
    /// the free run returns every [`skip::WINDOW`] cycles at least, so
    /// that a loop entered between two cycle timers gets probed.
    #[inline]
    fn run_limits(&self, end: u64) -> (u64, u64) {
        let free = if self.skip.on {
            skip::WINDOW
        } else {
            FREE_RUN_LIMIT
        };
        if !self.free_run || end == 0 {
            (STEP_LIMIT, 0)
        } else if end == u64::MAX {
            (free, 0)
        } else {
            (free, end)
        }
    }

    /// Let time pass without executing: run the cycle timers that are due,
    /// then jump to the next one (as while the MCU is held in reset, when no
    /// instruction runs but the world goes on).
    ///
    /// # Panics
    /// With the panic of a callback the timers ran.
    pub fn hold_step(&mut self) {
        // SAFETY: as in `step`; plain field accesses around the call.
        unsafe {
            let a = self.raw();
            let until_next = ffi::avr_cycle_timer_process(a);
            (*a).cycle += until_next.max(1);
        }
        self.resume_failure();
    }

    pub fn state(&self) -> CpuState {
        // SAFETY: plain field read.
        decode_state(unsafe { (*self.raw()).state })
    }

    pub fn cycle(&self) -> u64 {
        // SAFETY: plain field read.
        unsafe { (*self.raw()).cycle }
    }

    pub fn handler(&self) -> &H {
        // SAFETY: callbacks run only inside calls that take `&mut self`, so
        // while this borrow of `self` lives no `&mut H` exists; the
        // reference covers the handler field only.
        unsafe { &(*self.state_ptr()).handler }
    }

    pub fn handler_mut(&mut self) -> &mut H {
        // SAFETY: as in `handler`: `&mut self` excludes every callback and
        // every other borrow of the handler.
        unsafe { &mut (*self.state_ptr()).handler }
    }

    /// Split borrow: the handler and a [`Core`] view, for setup code that
    /// needs both outside callbacks. The handler is busy meanwhile: a
    /// watched IRQ that a raise in `f` reaches is refused.
    ///
    /// # Panics
    /// With the panic of `f`, or of a callback refused during `f`.
    pub fn with_core<R>(&mut self, f: impl FnOnce(&mut H, &mut Core) -> R) -> R {
        let shared = self.shared.ptr();
        let p = shared.as_ptr();
        let r = {
            // SAFETY: a `Cell` field of the live state.
            let busy = unsafe { &(*p).busy };
            // `&mut self`: no callback runs and no other borrow of the
            // handler lives, so the flag is clear.
            let Some(_busy) = Flag::raise(busy) else {
                unreachable!("the handler is busy outside callbacks")
            };
            // SAFETY: the only reference to the handler while the flag is
            // set (callbacks during `f` are refused).
            let handler = unsafe { &mut *std::ptr::addr_of_mut!((*p).handler) };
            // SAFETY: live state; the `Core` is dropped before `self` is
            // given back.
            let mut core = unsafe { Core::new(shared, schedule_from_core::<H>) };
            f(handler, &mut core)
        };
        self.resume_failure();
        r
    }

    /// (Re)schedule the bench's cycle timer at absolute cycle `at` (a cycle
    /// already past fires at the next instruction boundary; `u64::MAX` cancels).
    pub fn schedule(&mut self, at: u64) {
        // SAFETY: the live state of this live MCU.
        unsafe { schedule_timer::<H>(self.shared.ptr(), at) }
    }

    /// Reset the MCU as the RESET pin would. simavr drops all cycle timers on
    /// reset, so the caller must schedule its timer again. Time goes on: simavr
    /// sets the cycle counter back to 0, the bench puts it back, since the
    /// robot's clock does not stop when its MCU resets.
    ///
    /// # Panics
    /// With the panic of a callback the reset ran.
    pub fn reset(&mut self) {
        // SAFETY: resetting a live, loaded MCU; restoring the cycle counter
        // right after is sound because the reset dropped every cycle timer
        // (none refers to the old time base) and peripherals are stopped.
        unsafe {
            let a = self.raw();
            let cycle = (*a).cycle;
            ffi::avr_reset(a);
            (*a).cycle = cycle;
            (*self.state_ptr()).response.forget_sleep();
        }
        self.resume_failure();
    }
}
