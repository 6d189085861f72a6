//! The only module that talks to simavr: every `unsafe` line of the bench is here.
//!
//! [`Avr`] owns one simulated ATmega and one [`Handler`], the bench's side of
//! the simulation. simavr calls back into the handler through C trampolines
//! for: IO register writes the bench claims or observes, pin and UART IRQs, and
//! one cycle timer that carries the bench's whole event queue. Inside a
//! callback the handler gets a [`Core`], a narrow view of the running MCU.
//!
//! What simavr does that we change, and why:
//! - the sleep callback is a no-op: simavr's default usleeps to keep emulated
//!   time in step with the wall clock, which pins a sleeping firmware to 1x
//!   real time and makes runs depend on the host;
//! - the UARTs' "poll sleep" and stdio flags are cleared: the first usleeps on
//!   status polls, the second prints the firmware's bytes on our stdout;
//! - the firmware image is loaded from the ELF by the bench ([`crate::elf`]),
//!   since a Rust ELF has no `.mmcu` section and simavr's loader prints to
//!   stdout.

use std::ffi::{c_void, CString};
use std::ptr::NonNull;

use simavr_ffi as ffi;
use thiserror::Error;

/// Errors from creating or driving the simulated MCU.
#[derive(Debug, Error)]
pub enum SimError {
    #[error("simavr does not know the MCU {0:?}; the bench supports \"atmega2560\"")]
    UnknownMcu(String),
    #[error("simavr failed to initialise the MCU {0:?}")]
    InitFailed(String),
    #[error("firmware segment at flash 0x{addr:05x} with {len} bytes does not fit in the {flash} bytes of flash")]
    FlashOverflow { addr: u32, len: usize, flash: u32 },
    #[error("the MCU has no IO port {0:?}")]
    NoSuchPort(char),
    #[error("the MCU has no USART{0}")]
    NoSuchUart(u8),
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

/// A pin or peripheral line the bench drives or watches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Irq(NonNull<ffi::avr_irq_t>);

/// The bench's half of the simulation. All methods run inside simavr's
/// callbacks, at the current emulated cycle.
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
    /// between instructions). Returns the next cycle to fire at, or 0 for none.
    fn timer(&mut self, core: &mut Core, when: u64) -> u64;
    /// An IRQ watched with [`Avr::watch_irq`] was raised.
    fn irq(&mut self, core: &mut Core, tag: u32, value: u32);
}

/// A view of the running MCU for use inside callbacks.
pub struct Core {
    avr: NonNull<ffi::avr_t>,
}

impl Core {
    /// The current emulated cycle.
    pub fn cycle(&self) -> u64 {
        // SAFETY: `avr` points to the live avr_t owned by the `Avr` whose
        // callback is running; reading a plain field is sound.
        unsafe { (*self.avr.as_ptr()).cycle }
    }

    /// The program counter, as a byte address in flash.
    pub fn pc(&self) -> u32 {
        // SAFETY: as in `cycle`.
        unsafe { (*self.avr.as_ptr()).pc }
    }

    /// Read a byte of data space (registers, IO, SRAM) without side effects.
    pub fn data(&self, addr: u16) -> u8 {
        data_read(self.avr, addr)
    }

    /// Store a byte in data space without side effects (no IO handler runs).
    pub fn set_data(&mut self, addr: u16, value: u8) {
        data_write(self.avr, addr, value)
    }

    /// Drive an input line (a pin, a UART's input) to `value`.
    pub fn raise(&mut self, irq: Irq, value: u32) {
        // SAFETY: `irq` was obtained from this MCU's IRQ tables, which live as
        // long as the MCU; simavr's raise is re-entrant for other IRQs.
        unsafe { ffi::avr_raise_irq(irq.0.as_ptr(), value) }
    }

    /// Set the supply the analog parts see (VCC, AVCC and AREF are one rail
    /// on the Mega), in millivolts: the ADC converts against it.
    pub fn set_supply_mv(&mut self, mv: u32) {
        // SAFETY: plain field writes on the live MCU; simavr's ADC reads them
        // at each conversion.
        unsafe {
            let a = self.avr.as_ptr();
            (*a).vcc = mv;
            (*a).avcc = mv;
            (*a).aref = mv;
        }
    }

    /// (Re)schedule the bench's cycle timer at absolute cycle `at` (a cycle
    /// already past fires at the next instruction boundary; `u64::MAX`
    /// cancels). Must not be called from [`Handler::timer`] (return the cycle
    /// instead).
    pub fn schedule(&mut self, at: u64) {
        schedule_timer(self.avr, at)
    }
}

struct Shared<H> {
    handler: H,
    avr: NonNull<ffi::avr_t>,
    /// The cycle at which the running burst ends ([`Avr::run_burst`] sets
    /// it as it starts; nothing else reads it). A callback that leaves the
    /// handler wanting attention sets it to 0, so that the burst's loop has
    /// one bound to test per instruction.
    burst_end: u64,
    /// The handler simavr had installed on each IO write slot we took over
    /// with [`IoClaim::Observe`], to forward to first.
    forward: Vec<Option<(ffi::avr_io_write_t, *mut c_void)>>,
    /// The read handler simavr had on each slot watched with
    /// [`Avr::observe_io_read`], called after the bench's.
    forward_read: Vec<Option<(ffi::avr_io_read_t, *mut c_void)>>,
    in_timer: bool,
}

impl<H: Handler> Shared<H> {
    /// After a callback: a handler that wants attention ends the burst.
    #[inline]
    fn note_attention(&mut self) {
        if self.handler.attention() {
            self.burst_end = 0;
        }
    }
}

struct IrqTag<H> {
    shared: *mut Shared<H>,
    tag: u32,
}

/// One simulated MCU and the bench's handler.
pub struct Avr<H: Handler> {
    avr: NonNull<ffi::avr_t>,
    shared: Box<Shared<H>>,
    // Boxed: each tag's address is handed to simavr and must not move when
    // the Vec grows.
    #[allow(clippy::vec_box)]
    irq_tags: Vec<Box<IrqTag<H>>>,
    code_end: u32,
    /// The step function simavr installed at init (what `avr_run` calls),
    /// called directly to save a call per instruction.
    run: unsafe extern "C" fn(*mut ffi::avr_t),
}

// The bench's timer is identified by (callback, param): registering again
// replaces it, which is how the bench reschedules.
unsafe extern "C" fn timer_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    when: ffi::avr_cycle_count_t,
    param: *mut c_void,
) -> ffi::avr_cycle_count_t {
    // SAFETY: `param` is the `Shared<H>` registered with this trampoline; it
    // lives in a Box owned by `Avr<H>`, which outlives every callback.
    let shared = unsafe { &mut *(param as *mut Shared<H>) };
    let mut core = Core {
        avr: NonNull::new(avr).expect("simavr passed a null MCU"),
    };
    shared.in_timer = true;
    let next = shared.handler.timer(&mut core, when);
    shared.in_timer = false;
    shared.note_attention();
    next
}

unsafe extern "C" fn io_write_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    value: u8,
    param: *mut c_void,
) {
    // SAFETY: as in `timer_trampoline`.
    let shared = unsafe { &mut *(param as *mut Shared<H>) };
    let slot = addr as usize - 32;
    if let Some((Some(original), original_param)) = shared.forward[slot] {
        // SAFETY: the original handler and its param were installed by simavr
        // for this very slot; we call it as simavr would have.
        unsafe { original(avr, addr, value, original_param) };
    } else if shared.forward[slot].is_some() {
        // Observed slot that had no handler: simavr would have stored it.
        data_write(shared.avr, addr, value);
    }
    let mut core = Core {
        avr: NonNull::new(avr).expect("simavr passed a null MCU"),
    };
    shared.handler.io_write(&mut core, addr, value);
    shared.note_attention();
}

unsafe extern "C" fn io_read_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    param: *mut c_void,
) -> u8 {
    // SAFETY: as in `timer_trampoline`.
    let shared = unsafe { &mut *(param as *mut Shared<H>) };
    let mut core = Core {
        avr: NonNull::new(avr).expect("simavr passed a null MCU"),
    };
    let value = shared.handler.io_read(&mut core, addr);
    shared.note_attention();
    value
}

unsafe extern "C" fn io_read_observe_trampoline<H: Handler>(
    avr: *mut ffi::avr_t,
    addr: ffi::avr_io_addr_t,
    param: *mut c_void,
) -> u8 {
    // SAFETY: as in `timer_trampoline`.
    let shared = unsafe { &mut *(param as *mut Shared<H>) };
    let mut core = Core {
        avr: NonNull::new(avr).expect("simavr passed a null MCU"),
    };
    shared.handler.before_io_read(&mut core, addr);
    shared.note_attention();
    match shared.forward_read[addr as usize - 32] {
        // SAFETY: the original handler and its param were installed by simavr
        // for this very slot; we call it as simavr would have.
        Some((Some(original), original_param)) => unsafe { original(avr, addr, original_param) },
        _ => data_read(shared.avr, addr),
    }
}

unsafe extern "C" fn irq_trampoline<H: Handler>(
    _irq: *mut ffi::avr_irq_t,
    value: u32,
    param: *mut c_void,
) {
    // SAFETY: `param` is an `IrqTag<H>` boxed in `Avr::irq_tags`, alive as
    // long as the MCU; its `shared` points to the Avr's `Shared<H>`.
    let tag = unsafe { &*(param as *const IrqTag<H>) };
    // SAFETY: see above.
    let shared = unsafe { &mut *tag.shared };
    let mut core = Core { avr: shared.avr };
    shared.handler.irq(&mut core, tag.tag, value);
    shared.note_attention();
}

unsafe extern "C" fn sleep_noop(_avr: *mut ffi::avr_t, _how_long: ffi::avr_cycle_count_t) {}

fn data_read(avr: NonNull<ffi::avr_t>, addr: u16) -> u8 {
    // SAFETY: `data` is simavr's data-space array of ramend + 1 bytes; the
    // bound is checked against ramend first.
    unsafe {
        let a = avr.as_ptr();
        assert!(
            addr <= (*a).ramend,
            "data address 0x{addr:04x} beyond RAMEND"
        );
        *(*a).data.add(addr as usize)
    }
}

fn data_write(avr: NonNull<ffi::avr_t>, addr: u16, value: u8) {
    // SAFETY: as in `data_read`.
    unsafe {
        let a = avr.as_ptr();
        assert!(
            addr <= (*a).ramend,
            "data address 0x{addr:04x} beyond RAMEND"
        );
        *(*a).data.add(addr as usize) = value;
    }
}

fn schedule_timer_raw<H: Handler>(avr: NonNull<ffi::avr_t>, shared: *mut Shared<H>, at: u64) {
    // SAFETY: the MCU is alive; simavr takes a cycle count relative to now and
    // replaces any timer registered with the same (callback, param).
    unsafe {
        let now = (*avr.as_ptr()).cycle;
        if at == u64::MAX {
            ffi::avr_cycle_timer_cancel(
                avr.as_ptr(),
                Some(timer_trampoline::<H>),
                shared as *mut c_void,
            );
        } else {
            ffi::avr_cycle_timer_register(
                avr.as_ptr(),
                at.saturating_sub(now),
                Some(timer_trampoline::<H>),
                shared as *mut c_void,
            );
        }
    }
}

// `Core` does not know `H`; it finds the registration through a per-MCU
// pointer stored in simavr's `custom.data` slot.
fn schedule_timer(avr: NonNull<ffi::avr_t>, at: u64) {
    // SAFETY: `custom.data` holds the scheduler set by `Avr::new`, valid for
    // the MCU's lifetime.
    unsafe {
        let sched = (*avr.as_ptr()).custom.data as *const Scheduler;
        ((*sched).f)(avr, (*sched).shared, at);
    }
}

struct Scheduler {
    f: fn(NonNull<ffi::avr_t>, *mut c_void, u64),
    shared: *mut c_void,
}

fn schedule_erased<H: Handler>(avr: NonNull<ffi::avr_t>, shared: *mut c_void, at: u64) {
    // SAFETY: `shared` is the `Shared<H>` this scheduler was built for.
    let in_timer = unsafe { (*(shared as *mut Shared<H>)).in_timer };
    debug_assert!(
        !in_timer,
        "schedule() called from inside the timer callback"
    );
    schedule_timer_raw::<H>(avr, shared as *mut Shared<H>, at)
}

fn ioctl_def(a: u8, b: u8, c: u8, d: u8) -> u32 {
    (a as u32) << 24 | (b as u32) << 16 | (c as u32) << 8 | d as u32
}

impl<H: Handler> Avr<H> {
    /// Create an MCU by simavr name at `frequency_hz`, with empty flash.
    pub fn new(mcu: &str, frequency_hz: u32, handler: H) -> Result<Self, SimError> {
        let name = CString::new(mcu).map_err(|_| SimError::UnknownMcu(mcu.into()))?;
        // SAFETY: simavr returns a freshly allocated MCU or null.
        let raw = unsafe { ffi::avr_make_mcu_by_name(name.as_ptr()) };
        let avr = NonNull::new(raw).ok_or_else(|| SimError::UnknownMcu(mcu.into()))?;
        // SAFETY: `avr` is a fresh MCU; avr_init sets up its memories and IO.
        if unsafe { ffi::avr_init(avr.as_ptr()) } != 0 {
            return Err(SimError::InitFailed(mcu.into()));
        }
        // SAFETY: plain field read on the initialised MCU.
        let Some(run) = (unsafe { (*avr.as_ptr()).run }) else {
            return Err(SimError::InitFailed(mcu.into()));
        };
        let mut shared = Box::new(Shared {
            handler,
            avr,
            forward: vec![None; ffi::MAX_IOs as usize],
            forward_read: vec![None; ffi::MAX_IOs as usize],
            in_timer: false,
            burst_end: 0,
        });
        let scheduler = Box::new(Scheduler {
            f: schedule_erased::<H>,
            shared: &mut *shared as *mut Shared<H> as *mut c_void,
        });
        // SAFETY: plain field writes on the initialised MCU. The scheduler box
        // is leaked into `custom.data` and reclaimed in Drop.
        unsafe {
            let a = avr.as_ptr();
            (*a).frequency = frequency_hz;
            // The Arduino Mega runs at 5 V; AVCC and AREF on the same rail
            // (millivolts, as simavr's ADC takes its inputs).
            (*a).vcc = 5000;
            (*a).avcc = 5000;
            (*a).aref = 5000;
            (*a).sleep = Some(sleep_noop);
            (*a).set_log(1); // LOG_ERROR: simavr's errors only
            (*a).custom.data = Box::into_raw(scheduler) as *mut c_void;
        }
        Ok(Self {
            avr,
            shared,
            irq_tags: Vec::new(),
            code_end: 0,
            run,
        })
    }

    /// Copy a firmware segment into flash at byte address `addr`.
    pub fn load_flash(&mut self, addr: u32, bytes: &[u8]) -> Result<(), SimError> {
        // SAFETY: the bound is checked before simavr's memcpy (which aborts on
        // overflow); `codeend` tells simavr's crash check where code ends.
        unsafe {
            let a = self.avr.as_ptr();
            let flash = (*a).flashend + 1;
            if addr as u64 + bytes.len() as u64 > flash as u64 {
                return Err(SimError::FlashOverflow {
                    addr,
                    len: bytes.len(),
                    flash,
                });
            }
            ffi::avr_loadcode(a, bytes.as_ptr() as *mut u8, bytes.len() as u32, addr);
            self.code_end = self.code_end.max(addr + bytes.len() as u32);
            (*a).codeend = self.code_end;
        }
        Ok(())
    }

    /// Execute one instruction (or, while sleeping, jump to the next timer).
    #[inline]
    pub fn step(&mut self) -> CpuState {
        let avr = self.avr.as_ptr();
        // SAFETY: the MCU is initialised and loaded; callbacks re-enter the
        // handler through `shared`, which nothing else borrows during the
        // call.
        let state = unsafe {
            (self.run)(avr);
            (*avr).state
        };
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
    /// bound per instruction as [`Avr::run_to`] has.
    // Out of line, so that the loop keeps its bounds in registers.
    #[inline(never)]
    pub fn run_burst(&mut self, until: u64, sleeping: &mut bool) -> Burst {
        let avr = self.avr.as_ptr();
        let run = self.run;
        let shared: *mut Shared<H> = &mut *self.shared;
        // SAFETY: plain field accesses; the callbacks run during `run` reach
        // the same `Shared` through the pointer registered with simavr, and
        // nothing holds a reference to it across a step.
        unsafe {
            (*shared).burst_end = if (*shared).handler.attention() {
                0
            } else {
                until
            }
        };
        let mut slept = 0;
        let mut was_asleep = *sleeping;
        // SAFETY: plain field read.
        let mut before = unsafe { (*avr).cycle };
        let state = loop {
            // SAFETY: as in `step`; plain field reads between the steps.
            let (state, now) = unsafe {
                run(avr);
                ((*avr).state, (*avr).cycle)
            };
            // SAFETY: as above.
            let end = unsafe { (*shared).burst_end };
            // Almost every step is an instruction between two awake ones:
            // nothing to account, one bound to test.
            if state == ffi::cpu_Running as i32 && !was_asleep {
                if now >= end {
                    *sleeping = false;
                    break state;
                }
                before = now;
                continue;
            }
            // A step that began or ended asleep counts as slept.
            let asleep = state == ffi::cpu_Sleeping as i32;
            slept += now - before;
            before = now;
            was_asleep = asleep;
            let stopped = !asleep && state != ffi::cpu_Running as i32;
            if stopped || now >= end {
                *sleeping = asleep;
                break state;
            }
        };
        Burst {
            slept,
            state: decode_state(state),
        }
    }

    /// Steps until the cycle reaches `end` or the CPU stops running and
    /// sleeping, with nothing else between the steps: simavr driven as
    /// bare as it can be (the baseline `hil bench` compares the bench with).
    pub fn run_to(&mut self, end: u64) -> CpuState {
        let avr = self.avr.as_ptr();
        let run = self.run;
        loop {
            // SAFETY: as in `step`.
            let (state, now) = unsafe {
                run(avr);
                ((*avr).state, (*avr).cycle)
            };
            let stopped = state != ffi::cpu_Running as i32 && state != ffi::cpu_Sleeping as i32;
            if stopped || now >= end {
                return decode_state(state);
            }
        }
    }

    /// Let time pass without executing: run the cycle timers that are due,
    /// then jump to the next one (as while the MCU is held in reset, when no
    /// instruction runs but the world goes on).
    pub fn hold_step(&mut self) {
        // SAFETY: as in `step`; the timers re-enter the handler through
        // `shared`, which nothing else borrows during the call.
        unsafe {
            let a = self.avr.as_ptr();
            let until_next = ffi::avr_cycle_timer_process(a);
            (*a).cycle += until_next.max(1);
        }
    }

    pub fn state(&self) -> CpuState {
        // SAFETY: plain field read.
        decode_state(unsafe { (*self.avr.as_ptr()).state })
    }

    pub fn cycle(&self) -> u64 {
        // SAFETY: plain field read.
        unsafe { (*self.avr.as_ptr()).cycle }
    }

    /// The program counter, as a byte address in flash.
    pub fn pc(&self) -> u32 {
        // SAFETY: plain field read.
        unsafe { (*self.avr.as_ptr()).pc }
    }

    /// The global interrupt enable flag (SREG.I).
    pub fn interrupts_enabled(&self) -> bool {
        // SAFETY: plain read of simavr's split SREG array (8 entries).
        unsafe { (*self.avr.as_ptr()).sreg[7] != 0 }
    }

    /// The 16-bit word of flash at byte address `addr` (an opcode).
    pub fn flash_word(&self, addr: u32) -> u16 {
        // SAFETY: `flash` holds flashend + 1 bytes; the bound is checked.
        unsafe {
            let a = self.avr.as_ptr();
            if addr + 1 > (*a).flashend {
                return 0;
            }
            u16::from_le_bytes([
                *(*a).flash.add(addr as usize),
                *(*a).flash.add(addr as usize + 1),
            ])
        }
    }

    /// The status register, composed from simavr's per-flag copy (the byte
    /// at SREG's data address is not kept up to date while running).
    pub fn sreg(&self) -> u8 {
        // SAFETY: plain read of simavr's split SREG array (8 entries).
        let bits = unsafe { (*self.avr.as_ptr()).sreg };
        bits.iter()
            .enumerate()
            .fold(0u8, |acc, (i, b)| acc | (u8::from(*b != 0) << i))
    }

    /// Set the status register (a debugger's register write).
    pub fn set_sreg(&mut self, value: u8) {
        // SAFETY: plain writes of simavr's split SREG array and its data
        // byte (0x5F), which simavr keeps in step at each SREG write.
        unsafe {
            let a = self.avr.as_ptr();
            for i in 0..8 {
                (*a).sreg[i] = (value >> i) & 1;
            }
            *(*a).data.add(0x5f) = value;
        }
    }

    /// Set the program counter (a byte address in flash).
    pub fn set_pc(&mut self, pc: u32) {
        // SAFETY: plain field write; simavr fetches from `pc` at the next
        // instruction and reports a crash for an address past the code.
        unsafe { (*self.avr.as_ptr()).pc = pc }
    }

    /// Set the stack pointer (SPH:SPL).
    pub fn set_sp(&mut self, sp: u16) {
        let [lo, hi] = sp.to_le_bytes();
        self.set_data(0x5d, lo);
        self.set_data(0x5e, hi);
    }

    /// Bytes of data space (registers, IO, SRAM) from `addr`; None when the
    /// range passes RAMEND.
    pub fn read_data(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
        let end = addr as u64 + len as u64;
        // SAFETY: plain field read.
        let ramend = unsafe { (*self.avr.as_ptr()).ramend } as u64;
        (end <= ramend + 1).then(|| {
            (addr..addr + len as u32)
                .map(|a| self.data(a as u16))
                .collect()
        })
    }

    /// Store bytes in data space; false (and nothing written) when the range
    /// passes RAMEND.
    pub fn write_data(&mut self, addr: u32, bytes: &[u8]) -> bool {
        // SAFETY: plain field read.
        let ramend = unsafe { (*self.avr.as_ptr()).ramend } as u64;
        if addr as u64 + bytes.len() as u64 > ramend + 1 {
            return false;
        }
        self.write_bytes(addr as u16, bytes);
        true
    }

    /// Bytes of flash from byte address `addr`; None when the range passes
    /// the end of flash.
    pub fn read_flash(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
        // SAFETY: `flash` holds flashend + 1 bytes; the range is checked
        // against it first.
        unsafe {
            let a = self.avr.as_ptr();
            if addr as u64 + len as u64 > (*a).flashend as u64 + 1 {
                return None;
            }
            Some(std::slice::from_raw_parts((*a).flash.add(addr as usize), len).to_vec())
        }
    }

    /// Store bytes in flash (a debugger loading code); false (and nothing
    /// written) when the range passes the end of flash.
    pub fn write_flash(&mut self, addr: u32, bytes: &[u8]) -> bool {
        // SAFETY: as in `read_flash`; the destination range is checked.
        unsafe {
            let a = self.avr.as_ptr();
            if addr as u64 + bytes.len() as u64 > (*a).flashend as u64 + 1 {
                return false;
            }
            std::ptr::copy_nonoverlapping(
                bytes.as_ptr(),
                (*a).flash.add(addr as usize),
                bytes.len(),
            );
        }
        true
    }

    /// Stack pointer (SPH:SPL).
    pub fn sp(&self) -> u16 {
        u16::from_le_bytes([self.data(0x5d), self.data(0x5e)])
    }

    pub fn data(&self, addr: u16) -> u8 {
        data_read(self.avr, addr)
    }

    pub fn set_data(&mut self, addr: u16, value: u8) {
        data_write(self.avr, addr, value)
    }

    pub fn read_bytes<const N: usize>(&self, addr: u16) -> [u8; N] {
        let mut out = [0u8; N];
        for (i, b) in out.iter_mut().enumerate() {
            *b = self.data(addr + i as u16);
        }
        out
    }

    pub fn write_bytes(&mut self, addr: u16, bytes: &[u8]) {
        for (i, b) in bytes.iter().enumerate() {
            self.set_data(addr + i as u16, *b);
        }
    }

    pub fn handler(&self) -> &H {
        &self.shared.handler
    }

    pub fn handler_mut(&mut self) -> &mut H {
        &mut self.shared.handler
    }

    /// Split borrow: the handler and a [`Core`] view, for setup code that
    /// needs both outside callbacks.
    pub fn with_core<R>(&mut self, f: impl FnOnce(&mut H, &mut Core) -> R) -> R {
        let mut core = Core { avr: self.avr };
        f(&mut self.shared.handler, &mut core)
    }

    /// Take part in writes to IO register `addr` (a data-space address).
    pub fn claim_io_write(&mut self, addr: u16, claim: IoClaim) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        let shared_ptr = &mut *self.shared as *mut Shared<H> as *mut c_void;
        // SAFETY: `slot` is within the IO table; we save what simavr had there
        // (to forward to, for Observe) and install our trampoline directly,
        // which avoids simavr's 4-entry write multiplexer.
        unsafe {
            let io = &mut (*self.avr.as_ptr()).io[slot];
            if claim == IoClaim::Observe {
                self.shared.forward[slot] = Some((io.w.c, io.w.param));
            } else {
                self.shared.forward[slot] = None;
            }
            io.w.c = Some(io_write_trampoline::<H>);
            io.w.param = shared_ptr;
        }
        Ok(())
    }

    /// Emulate reads of IO register `addr`: simavr's read handler no longer runs.
    pub fn claim_io_read(&mut self, addr: u16) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        let shared_ptr = &mut *self.shared as *mut Shared<H> as *mut c_void;
        // SAFETY: `slot` is within the IO table.
        unsafe {
            let io = &mut (*self.avr.as_ptr()).io[slot];
            io.r.c = Some(io_read_trampoline::<H>);
            io.r.param = shared_ptr;
        }
        Ok(())
    }

    /// Be told before every read of IO register `addr` ([`Handler::before_io_read`]);
    /// simavr's read handler still produces the value.
    pub fn observe_io_read(&mut self, addr: u16) -> Result<(), SimError> {
        let slot = io_slot(addr)?;
        let shared_ptr = &mut *self.shared as *mut Shared<H> as *mut c_void;
        // SAFETY: `slot` is within the IO table; we keep what simavr had there
        // to call after the bench's hook.
        unsafe {
            let io = &mut (*self.avr.as_ptr()).io[slot];
            // Observing a slot twice keeps the first (simavr's) handler.
            if self.shared.forward_read[slot].is_none() {
                self.shared.forward_read[slot] = Some((io.r.c, io.r.param));
            }
            io.r.c = Some(io_read_observe_trampoline::<H>);
            io.r.param = shared_ptr;
        }
        Ok(())
    }

    /// The IRQ of pin `bit` of IO port `port` ('A'..'L').
    pub fn port_pin(&mut self, port: char, bit: u8) -> Result<Irq, SimError> {
        self.port_irq(port, bit as i32)
    }

    /// Port `port`'s PORT-register IRQ (raised with the whole byte on every
    /// write, however it is written).
    pub fn port_register(&mut self, port: char) -> Result<Irq, SimError> {
        self.port_irq(port, ffi::IOPORT_IRQ_REG_PORT as i32)
    }

    /// Port `port`'s DDR IRQ (raised with the whole byte on every write).
    pub fn port_direction(&mut self, port: char) -> Result<Irq, SimError> {
        self.port_irq(port, ffi::IOPORT_IRQ_DIRECTION_ALL as i32)
    }

    fn port_irq(&mut self, port: char, index: i32) -> Result<Irq, SimError> {
        let ctl = ioctl_def(b'i', b'o', b'g', port as u8);
        // SAFETY: simavr looks the IRQ up in its port list, or returns null.
        let irq = unsafe { ffi::avr_io_getirq(self.avr.as_ptr(), ctl, index) };
        NonNull::new(irq).map(Irq).ok_or(SimError::NoSuchPort(port))
    }

    /// The ADC's analog input `channel` (raise it with millivolts).
    pub fn adc_input(&mut self, channel: u8) -> Result<Irq, SimError> {
        let ctl = ioctl_def(b'a', b'd', b'c', b'0');
        // SAFETY: simavr looks the IRQ up in its peripheral list, or returns null.
        let irq = unsafe { ffi::avr_io_getirq(self.avr.as_ptr(), ctl, channel as i32) };
        NonNull::new(irq).map(Irq).ok_or(SimError::NoSuchPort('A'))
    }

    /// USART `n`'s (input, output) IRQs, with simavr's stdio echo and its
    /// wall-clock poll sleep turned off.
    pub fn uart(&mut self, n: u8) -> Result<(Irq, Irq), SimError> {
        let name = b'0' + n;
        let get = ioctl_def(b'u', b'a', b'r', name);
        // SAFETY: ioctl lookups on the live MCU; `flags` is the u32 simavr's
        // UART ioctls read and write.
        unsafe {
            let a = self.avr.as_ptr();
            let input = ffi::avr_io_getirq(a, get, ffi::UART_IRQ_INPUT as i32);
            let output = ffi::avr_io_getirq(a, get, ffi::UART_IRQ_OUTPUT as i32);
            let (Some(input), Some(output)) = (NonNull::new(input), NonNull::new(output)) else {
                return Err(SimError::NoSuchUart(n));
            };
            let mut flags: u32 = 0;
            ffi::avr_ioctl(
                a,
                ioctl_def(b'u', b'a', b'g', name),
                &mut flags as *mut u32 as *mut c_void,
            );
            flags &= !(ffi::AVR_UART_FLAG_STDIO | ffi::AVR_UART_FLAG_POLL_SLEEP);
            ffi::avr_ioctl(
                a,
                ioctl_def(b'u', b'a', b's', name),
                &mut flags as *mut u32 as *mut c_void,
            );
            Ok((Irq(input), Irq(output)))
        }
    }

    /// Call [`Handler::irq`] with `tag` whenever `irq` is raised.
    pub fn watch_irq(&mut self, irq: Irq, tag: u32) {
        let boxed = Box::new(IrqTag {
            shared: &mut *self.shared as *mut Shared<H>,
            tag,
        });
        let param = &*boxed as *const IrqTag<H> as *mut c_void;
        self.irq_tags.push(boxed);
        // SAFETY: the tag box lives in `irq_tags` as long as the MCU.
        unsafe { ffi::avr_irq_register_notify(irq.0.as_ptr(), Some(irq_trampoline::<H>), param) }
    }

    /// Drive an input line from outside callbacks.
    pub fn raise(&mut self, irq: Irq, value: u32) {
        // SAFETY: see `Core::raise`.
        unsafe { ffi::avr_raise_irq(irq.0.as_ptr(), value) }
    }

    /// (Re)schedule the bench's cycle timer at absolute cycle `at` (a cycle
    /// already past fires at the next instruction boundary; `u64::MAX` cancels).
    pub fn schedule(&mut self, at: u64) {
        let shared = &mut *self.shared as *mut Shared<H>;
        schedule_timer_raw::<H>(self.avr, shared, at)
    }

    /// Reset the MCU as the RESET pin would. simavr drops all cycle timers on
    /// reset, so the caller must schedule its timer again. Time goes on: simavr
    /// sets the cycle counter back to 0, the bench puts it back, since the
    /// robot's clock does not stop when its MCU resets.
    pub fn reset(&mut self) {
        // SAFETY: resetting a live, loaded MCU; restoring the cycle counter
        // right after is sound because the reset dropped every cycle timer
        // (none refers to the old time base) and peripherals are stopped.
        unsafe {
            let a = self.avr.as_ptr();
            let cycle = (*a).cycle;
            ffi::avr_reset(a);
            (*a).cycle = cycle;
        }
    }
}

impl<H: Handler> Drop for Avr<H> {
    fn drop(&mut self) {
        extern "C" {
            fn free(p: *mut c_void);
        }
        // SAFETY: we own the MCU; avr_terminate frees its memories and IO,
        // then the avr_t itself (malloc'ed by avr_make_mcu_by_name) is freed.
        // The scheduler box is reclaimed from `custom.data`.
        unsafe {
            let a = self.avr.as_ptr();
            let sched = (*a).custom.data as *mut Scheduler;
            (*a).custom.data = std::ptr::null_mut();
            ffi::avr_terminate(a);
            free(a as *mut c_void);
            if !sched.is_null() {
                drop(Box::from_raw(sched));
            }
        }
    }
}

fn io_slot(addr: u16) -> Result<usize, SimError> {
    if addr < 32 || (addr as usize - 32) >= ffi::MAX_IOs as usize {
        return Err(SimError::IoOutOfRange(addr));
    }
    Ok(addr as usize - 32)
}

#[inline]
fn decode_state(state: i32) -> CpuState {
    // The two states of every step first, as plain compares: this runs once
    // per emulated instruction.
    let s = state as u32;
    if s == ffi::cpu_Running {
        CpuState::Running
    } else if s == ffi::cpu_Sleeping {
        CpuState::Sleeping
    } else {
        match s {
            ffi::cpu_Done | ffi::cpu_Stopped => CpuState::Done,
            ffi::cpu_Crashed => CpuState::Crashed,
            _ => CpuState::Other(state),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// GPIOR0 in data space: a plain register the test program writes.
    const GPIOR0: u16 = 0x3E;

    /// Counts writes to GPIOR0 and wants attention once it sees `at`.
    struct Writes {
        seen: Vec<u8>,
        at: u8,
        attention: bool,
    }

    impl Handler for Writes {
        fn io_write(&mut self, _core: &mut Core, _addr: u16, value: u8) {
            self.seen.push(value);
            self.attention |= value == self.at;
        }
        fn io_read(&mut self, _core: &mut Core, _addr: u16) -> u8 {
            0
        }
        fn attention(&self) -> bool {
            self.attention
        }
        fn timer(&mut self, _core: &mut Core, _when: u64) -> u64 {
            0
        }
        fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
    }

    /// `ldi r16, 1` then, forever, `out GPIOR0, r16; inc r16; rjmp` back:
    /// three steps and four cycles per write of 1, 2, 3, ...
    fn counting_mcu(at: u8) -> Avr<Writes> {
        let handler = Writes {
            seen: Vec::new(),
            at,
            attention: false,
        };
        let mut avr = Avr::new("atmega2560", 16_000_000, handler).unwrap();
        let words: [u16; 4] = [0xE001, 0xBB0E, 0x9503, 0xCFFD];
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        avr.load_flash(0, &bytes).unwrap();
        avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
        avr
    }

    #[test]
    fn a_burst_ends_after_the_step_whose_callback_wants_attention() {
        let mut avr = counting_mcu(5);
        let mut sleeping = false;
        let start = avr.cycle();
        let burst = avr.run_burst(u64::MAX, &mut sleeping);
        // The ldi, four whole rounds, and the out that wrote 5.
        assert_eq!(avr.cycle() - start, 1 + 4 * 4 + 1);
        assert_eq!(burst.state, CpuState::Running);
        assert_eq!(avr.handler().seen, [1, 2, 3, 4, 5]);
        // Attention still pending: the next burst runs one step only (the
        // inc, one cycle).
        let at = avr.cycle();
        avr.run_burst(u64::MAX, &mut sleeping);
        assert_eq!(avr.cycle(), at + 1);
        avr.handler_mut().attention = false;
        let until = avr.cycle() + 400;
        avr.run_burst(until, &mut sleeping);
        assert_eq!(avr.cycle(), until);
        assert_eq!(avr.handler().seen.len(), 5 + 100);
        assert!(!sleeping);
    }

    #[test]
    fn a_burst_ends_at_the_first_step_that_reaches_its_cycle() {
        let mut avr = counting_mcu(0);
        let mut sleeping = false;
        // A bound already reached: one step.
        let burst = avr.run_burst(0, &mut sleeping);
        assert_eq!(avr.cycle(), 1);
        assert_eq!(burst.state, CpuState::Running);
        // Every round from here is out (1 cycle), inc (1), rjmp (2): a bound
        // inside the rjmp ends the burst one cycle past it.
        let burst = avr.run_burst(avr.cycle() + 3, &mut sleeping);
        assert_eq!(avr.cycle(), 1 + 4);
        assert_eq!(avr.handler().seen, [1]);
        avr.run_burst(avr.cycle() + 39, &mut sleeping);
        assert_eq!(avr.cycle(), 1 + 4 + 40);
        assert_eq!(avr.handler().seen.len(), 11);
        assert_eq!(burst.slept, 0);
    }
}
