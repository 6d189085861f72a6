//! Exact fast-forward of polling loops ([`super::Avr::set_skip`]).
//!
//! A busy firmware spends most of its time in loops that wait: for a flag an
//! interrupt sets, for a conversion to end, for `millis()` to move. While no
//! interrupt is pending and no cycle timer is due, such a loop runs the same
//! iteration again and again, changing nothing. Where the bench can prove
//! that of one iteration, it advances the cycle counter by whole iterations
//! up to just before the next cycle timer, instead of running them.
//!
//! The proof, for one iteration from a loop head (the target of a backward
//! branch) back to it, run one instruction at a time with simavr's access
//! hook on (vendor/simavr-ffi/patches, 0003):
//! - it ends where it began: the general registers, SREG (the CPU's flags
//!   and simavr's interrupt state), SP and PC are as before, and every byte
//!   above the registers it wrote holds the value it had before the first
//!   write; so every further iteration starts from the same state;
//! - everything it reads is data only an event can change: it read no IO
//!   register with a read handler (a free-running counter such as TCNTn is
//!   computed in one, a FIFO such as UDR pops in one, the bench's own
//!   claimed and observed registers go through one) and wrote no IO
//!   register but SREG and SP, and those only where no handler or IRQ
//!   listens; it ran no `wdr`, `sleep`, `spm`, `break` or `reti`;
//! - no interrupt was pending and none became pending, and no cycle timer
//!   came due: every peripheral of simavr (the timers' compare and overflow,
//!   the UARTs, the ADC, the watchdog) and the bench's whole event queue
//!   (encoder edges, UART bytes, faults, the plant) act through cycle
//!   timers, and a timer's counter is computed from the cycle when read.
//!
//! So repeats of the iteration touch nothing that matters before the next
//! cycle timer fires: the skip jumps the head to the last whole iteration
//! that ends strictly before that timer and before the burst's end, and
//! the run goes on from there, every timer firing after the same
//! instruction and at the same cycle as without the skip. Anything else
//! (an access above, a loop longer than [`ITERATION_STEPS`], a step that
//! ends the burst) is run normally. `tests/skip.rs` checks the identity.

use std::ffi::c_void;
use std::ptr::NonNull;

use simavr_ffi as ffi;

/// The most instructions run looking for a backward branch.
const SEARCH_STEPS: u32 = 12;
/// The most instructions of an iteration the skip proves.
const ITERATION_STEPS: u32 = 2048;
/// The most bytes an iteration may write (each push counts, and SP twice).
const MAX_WRITES: usize = 1024;
/// Cycles without a probe after one that found no loop to skip, doubled
/// at each further such probe up to [`MAX_QUIET`], back after a skip.
const QUIET: u64 = 256;
const MAX_QUIET: u64 = 256;
/// A head whose iteration cannot be skipped is not tried again for this
/// many cycles, doubled at each further failure up to [`MAX_BACKOFF`].
const FIRST_BACKOFF: u64 = 4096;
const MAX_BACKOFF: u64 = 1 << 22;
/// While skipping, simavr's free run returns at least this often, so that
/// a loop entered between two cycle timers is probed.
pub(super) const WINDOW: u64 = 256;

const R_SREG: u16 = 0x5f;
const R_SPL: u16 = 0x5d;
const R_SPH: u16 = 0x5e;

/// What the access hook saw during one iteration.
struct Watch {
    /// An access that may act beyond the data space.
    blocked: bool,
    /// Each write above the registers: the address and the value before.
    writes: Vec<(u16, u8)>,
}

/// A loop head that failed its proof, and when to try it again.
struct Head {
    pc: u32,
    retry_at: u64,
    backoff: u64,
}

/// The skip's state, one per MCU.
pub(super) struct Skip {
    pub(super) on: bool,
    /// Owned here (`Box::into_raw`), reached by the hook through its `param`.
    watch: NonNull<Watch>,
    next_probe: u64,
    quiet: u64,
    heads: Vec<Head>,
    /// Cycles fast-forwarded so far.
    pub(super) skipped: u64,
}

impl Skip {
    pub(super) fn new() -> Self {
        let watch = Box::new(Watch {
            blocked: false,
            writes: Vec::with_capacity(MAX_WRITES),
        });
        Self {
            on: false,
            watch: NonNull::from(Box::leak(watch)),
            next_probe: 0,
            quiet: QUIET,
            heads: Vec::new(),
            skipped: 0,
        }
    }

    /// Whether a probe is due at `now`.
    #[inline]
    pub(super) fn due(&self, now: u64) -> bool {
        self.on && now >= self.next_probe
    }
}

impl Drop for Skip {
    fn drop(&mut self) {
        // SAFETY: allocated in `new` and freed once, here; the hook is
        // cleared after every probe, so simavr holds no copy of the pointer.
        drop(unsafe { Box::from_raw(self.watch.as_ptr()) });
    }
}

/// simavr's access hook while an iteration is proved.
///
/// # Safety
/// `avr` is the live MCU running the instruction; `param` is the `Watch`
/// of its `Skip`.
unsafe extern "C" fn access_hook(avr: *mut ffi::avr_t, addr: u16, write: u8, param: *mut c_void) {
    // SAFETY: as the caller guarantees; the Watch is not otherwise borrowed
    // while an instruction runs. No panic can start here.
    unsafe {
        let w = &mut *param.cast::<Watch>();
        let a = &*avr;
        let in_io = addr >= 32 && addr <= a.ioend;
        // An IO address past simavr's table of handlers: not skipped.
        let io = in_io.then(|| a.io.get(usize::from(addr - 32)));
        let quiet_io = |io: &ffi::avr_t__bindgen_ty_3| io.w.c.is_none() && io.irq.is_null();
        let ok = if matches!(io, Some(None)) {
            false
        } else if write == 0 {
            io.flatten().is_none_or(|io| io.r.c.is_none())
        } else if addr > a.ramend {
            false
        } else {
            match io.flatten() {
                Some(io) => matches!(addr, R_SREG | R_SPL | R_SPH) && quiet_io(io),
                None => true,
            }
        };
        if !ok || (write != 0 && w.writes.len() == MAX_WRITES) {
            w.blocked = true;
        } else if write != 0 {
            w.writes.push((addr, *a.data.add(usize::from(addr))));
        }
    }
}

/// What a probe leaves for the burst's loop: the last step's state, the
/// cycle after it (and after a skip), and the cycle before it.
pub(super) struct Last {
    pub(super) state: i32,
    pub(super) now: u64,
    pub(super) before: u64,
}

/// The MCU's state an iteration must leave as it found it.
#[derive(PartialEq)]
struct Snapshot {
    regs: [u8; 32],
    sreg: [u8; 8],
    sp: u16,
    pc: u32,
}

/// # Safety
/// `avr` is a live, initialised MCU.
unsafe fn snapshot(avr: *mut ffi::avr_t) -> Snapshot {
    // SAFETY: as the caller guarantees; `data` holds at least the 32
    // registers and the IO space.
    unsafe {
        let mut regs = [0; 32];
        std::ptr::copy_nonoverlapping((*avr).data, regs.as_mut_ptr(), 32);
        let d = (*avr).data;
        Snapshot {
            regs,
            sreg: (*avr).sreg,
            sp: u16::from(*d.add(R_SPL as usize)) | u16::from(*d.add(R_SPH as usize)) << 8,
            pc: (*avr).pc,
        }
    }
}

/// The cycle of simavr's next cycle timer (`u64::MAX`: none).
///
/// # Safety
/// `avr` is a live, initialised MCU.
unsafe fn next_timer(avr: *mut ffi::avr_t) -> u64 {
    // SAFETY: the head of simavr's active timer queue, null or a slot of
    // its pool.
    unsafe {
        let t = (*avr).cycle_timers.timer;
        if t.is_null() {
            u64::MAX
        } else {
            (*t).when
        }
    }
}

/// The 16-bit opcode at byte address `pc`.
///
/// # Safety
/// `avr` is a live MCU.
unsafe fn opcode(avr: *mut ffi::avr_t, pc: u32) -> u16 {
    // SAFETY: bounds checked against flashend.
    unsafe {
        if pc as u64 + 1 > (*avr).flashend as u64 {
            return 0xffff;
        }
        let f = (*avr).flash.add(pc as usize);
        u16::from_le_bytes([*f, *f.add(1)])
    }
}

/// Whether `op` at `pc` is a relative or absolute jump or a conditional
/// branch that, having gone to `to`, went backwards (not a call, a return
/// or an interrupt's entry).
fn backward_branch(op: u16, pc: u32, to: u32) -> bool {
    let target = if op & 0xf000 == 0xc000 {
        // RJMP k: 12-bit signed word offset.
        let k = ((op & 0x0fff) as i16) << 4 >> 4;
        Some(pc as i64 + 2 + 2 * k as i64)
    } else if op & 0xf800 == 0xf000 {
        // BRBS (0xf000) and BRBC (0xf400) s, k: 7-bit signed word offset.
        let k = (((op >> 3) & 0x7f) as i16) << 9 >> 9;
        Some(pc as i64 + 2 + 2 * k as i64)
    } else {
        None
    };
    target.is_some_and(|t| t == to as i64 && to <= pc)
}

/// Opcodes with an effect outside the data space: an iteration with one
/// is not skipped.
fn acts_outside(op: u16) -> bool {
    matches!(
        op,
        0x9588 /* sleep */ | 0x9598 /* break */ | 0x95a8 /* wdr */
            | 0x95e8 /* spm */ | 0x95f8 /* spm Z+ */ | 0x9518 /* reti */
    )
}

/// Bounds for simavr's run: the free run's limit and stop (see
/// `Avr::set_run_limit`).
pub(super) struct Limits {
    pub(super) limit: u64,
    pub(super) stop: u64,
}

/// # Safety
/// `avr` is live and not running.
unsafe fn set_limits(avr: *mut ffi::avr_t, limit: u64, stop: u64) {
    // SAFETY: as the caller guarantees.
    unsafe {
        (*avr).run_cycle_limit = limit;
        (*avr).run_cycle_stop = stop;
        (*avr).run_cycle_end = 0;
    }
}

/// Runs single steps that the burst's loop would have run past (running,
/// awake, before `end()`), looking for a loop head, proving an iteration
/// from it and skipping its repeats; returns the last step for the loop to
/// judge as its own, or `None` when it ran none. simavr's run bounds are
/// `limits` again on return.
///
/// # Safety
/// `avr` is a live, loaded MCU that is not running, `run` its step
/// function, and `end` reads the running burst's end.
pub(super) unsafe fn probe(
    skip: &mut Skip,
    avr: *mut ffi::avr_t,
    run: unsafe extern "C" fn(*mut ffi::avr_t),
    end: impl Fn() -> u64,
    limits: Limits,
) -> Option<Last> {
    // SAFETY: as the caller guarantees; the hook's Watch lives as long as
    // `skip`, and the hook is cleared before returning on every path.
    unsafe {
        set_limits(avr, 1, 0);
        let mut last = None;
        let end = &end;
        let step = move |last: &mut Option<Last>| -> bool {
            let before = (*avr).cycle;
            run(avr);
            let (state, now) = ((*avr).state, (*avr).cycle);
            *last = Some(Last { state, now, before });
            state == ffi::cpu_Running as i32 && now < end()
        };
        let outcome = 'probe: {
            // A backward branch: its target is the loop's head.
            let mut head = None;
            for _ in 0..SEARCH_STEPS {
                let pc = (*avr).pc;
                let op = opcode(avr, pc);
                if !step(&mut last) {
                    break 'probe Outcome::Ended;
                }
                if backward_branch(op, pc, (*avr).pc) {
                    head = Some((*avr).pc);
                    break;
                }
            }
            let Some(head) = head else {
                break 'probe Outcome::NoLoop;
            };
            let now = (*avr).cycle;
            if skip.heads.iter().any(|h| h.pc == head && h.retry_at > now) {
                break 'probe Outcome::NoLoop;
            }
            let pending = (*avr).interrupt_state != 0 || ffi::avr_has_pending_interrupts(avr) != 0;
            if pending {
                break 'probe Outcome::NoLoop;
            }
            // One iteration, watched.
            let timer = next_timer(avr);
            let start = snapshot(avr);
            let c0 = now;
            let watch = skip.watch.as_ptr();
            (*watch).blocked = false;
            (*watch).writes.clear();
            (*avr).access_hook = Some(access_hook);
            (*avr).access_hook_param = watch.cast();
            let mut back = false;
            for _ in 0..ITERATION_STEPS {
                if acts_outside(opcode(avr, (*avr).pc)) {
                    (*watch).blocked = true;
                }
                let running = step(&mut last);
                if !running {
                    (*avr).access_hook = None;
                    break 'probe Outcome::Ended;
                }
                if (*avr).cycle >= timer {
                    // A timer came due: the loop may be about to end, which
                    // says nothing against its head.
                    (*avr).access_hook = None;
                    break 'probe Outcome::NoLoop;
                }
                if (*watch).blocked {
                    break;
                }
                if (*avr).pc == head {
                    back = true;
                    break;
                }
            }
            (*avr).access_hook = None;
            (*avr).access_hook_param = std::ptr::null_mut();
            if !back || (*watch).blocked {
                break 'probe Outcome::Failed(head);
            }
            // The same state: registers, flags, SP, PC, interrupts, the
            // written bytes, and the same next timer.
            let same_bytes = {
                let w = &mut (*watch).writes;
                // The value before each address's first write.
                w.sort_by_key(|&(addr, _)| addr);
                w.dedup_by_key(|&mut (addr, _)| addr);
                w.iter()
                    .all(|&(addr, old)| *(*avr).data.add(usize::from(addr)) == old)
            };
            let same = same_bytes
                && snapshot(avr) == start
                && (*avr).interrupt_state == 0
                && ffi::avr_has_pending_interrupts(avr) == 0
                && next_timer(avr) == timer;
            if !same {
                break 'probe Outcome::Failed(head);
            }
            let now = (*avr).cycle;
            let period = now - c0;
            let bound = timer.min(end());
            let k = (bound - 1 - now) / period;
            if k == 0 {
                break 'probe Outcome::Skipped(head, bound);
            }
            (*avr).cycle += k * period;
            skip.skipped += k * period;
            if let Some(l) = &mut last {
                l.now = (*avr).cycle;
            }
            Outcome::Skipped(head, bound)
        };
        let now = (*avr).cycle;
        match outcome {
            Outcome::Ended => {}
            Outcome::NoLoop => {
                skip.next_probe = now + skip.quiet;
                skip.quiet = (skip.quiet * 2).min(MAX_QUIET);
            }
            Outcome::Failed(pc) => {
                skip.next_probe = now + skip.quiet;
                match skip.heads.iter_mut().find(|h| h.pc == pc) {
                    Some(h) => {
                        h.retry_at = now + h.backoff;
                        h.backoff = (h.backoff * 2).min(MAX_BACKOFF);
                    }
                    None => skip.heads.push(Head {
                        pc,
                        retry_at: now + FIRST_BACKOFF,
                        backoff: FIRST_BACKOFF * 2,
                    }),
                }
            }
            Outcome::Skipped(pc, bound) => {
                // Nothing changes before the timer (or the burst's end):
                // the next probe after it.
                skip.next_probe = bound;
                skip.quiet = QUIET;
                skip.heads.retain(|h| h.pc != pc);
            }
        }
        set_limits(avr, limits.limit, limits.stop);
        last
    }
}

enum Outcome {
    /// A step ended the burst (or stopped the CPU): the loop judges it.
    Ended,
    /// No loop head found, or one not to try yet.
    NoLoop,
    /// The iteration from this head failed its proof.
    Failed(u32),
    /// Repeats from this head were skipped (or none fit) before the next
    /// timer or the burst's end, the cycle given.
    Skipped(u32, u64),
}

#[cfg(test)]
#[path = "skip_tests.rs"]
mod tests;
