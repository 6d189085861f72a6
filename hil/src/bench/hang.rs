//! Hang detection: a firmware that is in a test but makes no progress for a
//! configurable robot time is stopped by the bench and reported where it is
//! (PC and symbol), as a finding rather than a time-out of the whole run.
//!
//! Progress, as the bench defines it, is what a person watching the robot
//! and its bench interface would call progress:
//! - the plant moves: either wheel produces an encoder transition (counted by
//!   the plant, before any injected encoder fault, so a robot running away
//!   on a dead encoder is moving, not hung);
//! - the firmware's test state changes: `HT_STATE`, `HT_PHASE`, `HT_SEGMENT`,
//!   `HT_DONE_COUNT` or `HT_FAULT` (a wait ending, a segment starting, a test
//!   completing or a fault being raised).
//!
//! Only a firmware that says it is busy (`HT_STATE` not idle) is expected to
//! progress: an idle firmware waits for a command, which is not a hang (the
//! robust build stopping on a fault is idle). Main-loop or control-tick
//! activity alone is not progress: the thesis build's turn loop runs its PID
//! and prints speeds forever with a blocked wheel, and that is exactly the
//! hang to find. UART output alone is not progress either, for the same reason.
//!
//! A firmware without the bench interface (run from a test description,
//! [`crate::firmware::description`]) has no state to say it is busy: the watch is on
//! only while its test should run, and a change of what the motors are
//! driven to do counts as progress beside the wheels' motion.
//!
//! The firmware's own longest still phase is the thesis' braking and waits
//! between segments: 2.025 s of delays after a cut-off (the wheels coast for
//! part of it). A limit above that (the bench's default is 3 s) never calls a
//! healthy run a hang.

use henrytwo_protocol::RunState;

use crate::firmware::elf::{Firmware, Location};
use crate::mcu::sim::{Avr, Handler};

/// The default robot time without progress after which a busy firmware is
/// hung: above the 2.025 s of braking and waits between two segments.
pub const DEFAULT_HANG_AFTER_S: f64 = 3.0;

/// What the bench shows the watch at one check: the plant's wheels and the
/// firmware's test state (the optional interface variables read as 0 in a
/// build without them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    pub cycle: u64,
    /// A edges the plant produced, before any injected encoder fault.
    pub left_edges: i64,
    pub right_edges: i64,
    /// `HT_STATE`, `HT_PHASE`, `HT_SEGMENT`, `HT_DONE_COUNT`, `HT_FAULT`.
    pub state: u8,
    pub phase: u8,
    pub segment: u8,
    pub done: u16,
    pub fault: u8,
    /// Changes of what the motors are driven to do, for a firmware without
    /// the bench interface (0 for one with it: its state says more).
    pub outputs: usize,
    /// The brown-out detector holds the MCU in reset.
    pub held_in_reset: bool,
}

/// What the watch compares to see progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Signature {
    left_edges: i64,
    right_edges: i64,
    state: u8,
    phase: u8,
    segment: u8,
    done: u16,
    fault: u8,
    outputs: usize,
}

/// Watches a run for progress (see the module docs).
#[derive(Debug, Clone)]
pub struct HangWatch {
    after_cycles: u64,
    last: Option<Signature>,
    /// Cycle of the last progress seen.
    since: u64,
}

impl HangWatch {
    /// A watch that calls `after_cycles` without progress a hang.
    pub fn new(after_cycles: u64) -> Self {
        Self {
            after_cycles,
            last: None,
            since: 0,
        }
    }

    /// The limit, in cycles.
    pub fn after_cycles(&self) -> u64 {
        self.after_cycles
    }

    /// Cycles since the last progress, when the firmware is hung now.
    pub fn check(&mut self, p: &Progress) -> Option<u64> {
        let sig = Signature {
            left_edges: p.left_edges,
            right_edges: p.right_edges,
            state: p.state,
            phase: p.phase,
            segment: p.segment,
            done: p.done,
            fault: p.fault,
            outputs: p.outputs,
        };
        // A MCU held in reset by the brown-out detector runs nothing: it is
        // not hung.
        let busy = RunState::from_u8(sig.state) != Some(RunState::Idle) && !p.held_in_reset;
        if self.last != Some(sig) || !busy {
            self.last = Some(sig);
            self.since = p.cycle;
            return None;
        }
        let still = p.cycle - self.since;
        (still >= self.after_cycles).then_some(still)
    }
}

/// Where a hung firmware was: the PC and its function, and the calls that
/// led there.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HangReport {
    /// Robot time without progress when the bench stopped it.
    pub still_s: f64,
    pub at: Location,
    /// Return addresses on the stack, innermost first (see [`callers`]).
    pub callers: Vec<String>,
}

impl std::fmt::Display for HangReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.at)?;
        for c in &self.callers {
            write!(f, ", called from {c}")?;
        }
        Ok(())
    }
}

/// The return addresses on the stack, named, innermost first, at most `max`:
/// a heuristic backtrace without debug info. A word address on the stack
/// as wide as the MCU's PC (3 bytes on the ATmega2560, 2 on the others,
/// high byte first) counts when the instruction before it is a call
/// (`call`, `rcall`, `icall`, `eicall`); an interrupted PC, pushed by no
/// call, is skipped with the ISR's frame. The walk ends at the firmware's
/// entry (`main`).
pub fn callers<H: Handler>(mcu: &Avr<H>, firmware: &Firmware, max: usize) -> Vec<String> {
    walk(
        |addr, n| mcu.read_data(addr, n),
        |a| mcu.flash_word(a),
        mcu.sp(),
        mcu.chip().pc_bytes,
        firmware,
        max,
    )
}

/// [`callers`] over any memory: `data(addr, n)` reads `n` bytes of the data
/// space, `flash(addr)` a word of flash; return addresses are `pc_bytes`
/// wide.
fn walk(
    data: impl Fn(u32, usize) -> Option<Vec<u8>>,
    flash: impl Fn(u32) -> u16,
    sp: u16,
    pc_bytes: u8,
    firmware: &Firmware,
    max: usize,
) -> Vec<String> {
    let after_call = |ret: u32| {
        ret >= 4
            && (flash(ret - 4) & 0xfe0e == 0x940e
                || flash(ret - 2) & 0xf000 == 0xd000
                || matches!(flash(ret - 2), 0x9509 | 0x9519))
    };
    let width = usize::from(pc_bytes);
    let mut out = Vec::new();
    let mut addr = u32::from(sp) + 1;
    while out.len() < max {
        let Some(b) = data(addr, width).filter(|b| b.len() == width) else {
            break;
        };
        let ret = b.iter().fold(0u32, |r, &byte| r << 8 | u32::from(byte)) * 2;
        let named = after_call(ret).then(|| firmware.function_at(ret)).flatten();
        match named {
            Some((name, off)) => {
                out.push(format!("{name}+0x{off:x}"));
                addr += u32::from(pc_bytes);
                // The entry never returns: what lies above its frame is
                // left over from start-up, not a caller.
                if name == "main" || name.ends_with("rt_main") {
                    break;
                }
            }
            None => addr += 1,
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On the Uno's ATmega328P a call pushes a 2-byte return address: the
    /// walk reads two bytes (as the MCU's description says) and names the
    /// caller; read as the ATmega2560's three it names nothing.
    #[test]
    fn return_addresses_are_as_wide_as_the_mcus_pc() {
        let path = crate::paths::workspace_root().join("firmware/target/arduino/uno-l298n.elf");
        let fw = Firmware::load(&path).expect("built by tools/build-sketches.sh");
        let flash = |a: u32| -> u16 {
            fw.segments
                .iter()
                .find_map(|(start, bytes)| {
                    let i = a.checked_sub(*start)? as usize;
                    Some(u16::from_le_bytes([*bytes.get(i)?, *bytes.get(i + 1)?]))
                })
                .unwrap_or(0xffff)
        };
        let main = fw.symbol("main").unwrap().addr;
        // main's first `call`: the return address is the word after it.
        let call = (main..)
            .step_by(2)
            .find(|&a| flash(a) & 0xfe0e == 0x940e)
            .unwrap();
        let ret = (call + 4) / 2;
        // The stack above SP: the return address, high byte first, then
        // nothing pushed.
        let sp: u16 = 0x8f0;
        let mut stack = vec![0u8; 0x900];
        stack[usize::from(sp) + 1] = (ret >> 8) as u8;
        stack[usize::from(sp) + 2] = ret as u8;
        let data = |addr: u32, n: usize| {
            stack
                .get(addr as usize..addr as usize + n)
                .map(<[u8]>::to_vec)
        };
        let chip = &crate::mcu::chip::ATMEGA328P;
        assert_eq!(
            walk(data, flash, sp, chip.pc_bytes, &fw, 4),
            [format!("main+0x{:x}", call + 4 - main)]
        );
        assert!(walk(data, flash, sp, 3, &fw, 4).is_empty());
    }
}
