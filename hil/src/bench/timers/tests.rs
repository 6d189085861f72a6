//! simavr's timers judged when something observes them, on a real simavr
//! MCU running hand-assembled writes (see `tests/timer_modes.rs` for the
//! periods that verify the accepted modes).

use super::*;
use crate::board::Board;
use crate::mcu::sim::{Avr, Handler, IoClaim};

/// Judges every watched write and read, as the bench's core does.
struct Judge {
    timers: SimavrTimers,
    refusals: Vec<String>,
}

impl Handler for Judge {
    fn io_write(&mut self, core: &mut Core, addr: u16, _value: u8) {
        if let Some(PendingError::Timer {
            timer,
            wgm,
            observed,
            ..
        }) = self.timers.judge(core, Look::Write(addr))
        {
            self.refusals
                .push(format!("timer {timer} mode {wgm}: {observed}"));
        }
    }
    fn before_io_read(&mut self, core: &mut Core, addr: u16) {
        if let Some(PendingError::Timer {
            timer,
            wgm,
            observed,
            ..
        }) = self.timers.judge(core, Look::Read(addr))
        {
            self.refusals
                .push(format!("timer {timer} mode {wgm}: {observed}"));
        }
    }
    fn io_read(&mut self, _core: &mut Core, _addr: u16) -> u8 {
        0
    }
    fn timer(&mut self, _core: &mut Core, _when: u64) -> u64 {
        0
    }
    fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
}

/// `ldi r16, value; sts addr, r16` for each write, `lds r17, addr` for
/// each read (value None), then `rjmp .`.
fn program(steps: &[(u16, Option<u8>)]) -> Vec<u8> {
    let mut words = Vec::new();
    for &(addr, value) in steps {
        match value {
            Some(v) => {
                let k = v as u16;
                words.push(0xE000 | (k & 0xF0) << 4 | (k & 0x0F)); // ldi r16
                words.extend([0x9300, addr]); // sts addr, r16
            }
            None => words.extend([0x9110, addr]), // lds r17, addr
        }
    }
    words.push(0xCFFF);
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// The refusals the program makes on Henrytwo (timers 2 and 4 emulated,
/// D11 and D12 the battery LEDs: OC1A and OC1B on board pins).
fn refusals(steps: &[(u16, Option<u8>)]) -> Vec<String> {
    let board = Board::default();
    let timers = SimavrTimers::new(&board);
    let (writes, reads) = (timers.write_addresses(), timers.read_addresses());
    let judge = Judge {
        timers,
        refusals: Vec::new(),
    };
    let mut avr = Avr::new("atmega2560", 16_000_000, judge).unwrap();
    avr.load_flash(0, &program(steps)).unwrap();
    for a in writes {
        avr.claim_io_write(a, IoClaim::Observe).unwrap();
    }
    for a in reads {
        avr.observe_io_read(a).unwrap();
    }
    avr.run_to(3 * steps.len() as u64 + 100);
    avr.handler().refusals.clone()
}

const TCCR0A: u16 = 0x44;
const TCCR0B: u16 = 0x45;
const TIMSK0: u16 = 0x6E;
const TCCR1A: u16 = 0x80;
const TCCR1B: u16 = 0x81;
const TCNT1: u16 = 0x84;
const TIMSK1: u16 = 0x6F;
const TIFR1: u16 = 0x36;
const TCCR5A: u16 = 0x120;
const TCCR5B: u16 = 0x121;

/// Arduino's `init()` on simavr's timers: timer 0 through mode 3 at
/// clock/8 to clock/64 with its overflow interrupt; timers 1, 3, 5 through
/// mode 0 to mode 1 (phase correct, unobserved, so accepted).
#[test]
fn arduino_init_is_accepted() {
    let w = |a, v| (a, Some(v));
    let steps = [
        w(TCCR0A, 0x02),
        w(TCCR0A, 0x03),
        w(TCCR0B, 0x02),
        w(TCCR0B, 0x03),
        w(TIMSK0, 0x01),
        w(TCCR1B, 0x02),
        w(TCCR1B, 0x03),
        w(TCCR1A, 0x01),
        w(0x91, 0x02),
        w(0x91, 0x03),
        w(0x90, 0x01),
        w(TCCR5B, 0x02),
        w(TCCR5B, 0x03),
        w(TCCR5A, 0x01),
    ];
    assert_eq!(refusals(&steps), Vec::<String>::new());
}

/// Phase correct is refused once observed: its interrupt enabled, its
/// counter or flags read; the same mode unobserved is not.
#[test]
fn phase_correct_is_refused_once_observed() {
    let w = |a, v| (a, Some(v));
    let start = [w(TCCR1A, 0x01), w(TCCR1B, 0x01)];
    assert!(refusals(&start).is_empty());
    let with = |last: (u16, Option<u8>)| {
        let mut s = start.to_vec();
        s.push(last);
        refusals(&s)
    };
    assert_eq!(
        with(w(TIMSK1, 0x01)),
        ["timer 1 mode 1: enabled its interrupts (TIMSK1 = 0x01)"]
    );
    assert_eq!(with((TCNT1, None)), ["timer 1 mode 1: read TCNT1"]);
    assert_eq!(with((TIFR1, None)), ["timer 1 mode 1: read TIFR1"]);
    // The interrupt enabled first: refused when the mode is set.
    let early = [w(TIMSK1, 0x01), w(TCCR1A, 0x01), w(TCCR1B, 0x01)];
    assert_eq!(
        refusals(&early),
        ["timer 1 mode 1: enabled its interrupts (TIMSK1 = 0x01)"]
    );
}

/// Verified modes may be observed: CTC with its interrupt and counter
/// reads (the robust firmware's tick).
#[test]
fn ctc_observed_is_accepted() {
    let w = |a, v| (a, Some(v));
    let steps = [
        w(TIMSK1, 0x02),
        w(TCCR1A, 0x00),
        w(TCCR1B, 0x0A),
        (TCNT1, None),
        (TIFR1, None),
    ];
    assert!(refusals(&steps).is_empty());
}

/// A compare output on a pin the board uses (OC1A: D11, Henrytwo's blue
/// LED) is refused in any clocked mode; on a pin it does not (OC5A: D46),
/// it cannot matter.
#[test]
fn compare_outputs_matter_on_board_pins_only() {
    let w = |a, v| (a, Some(v));
    assert_eq!(
        refusals(&[w(TCCR1B, 0x0A), w(TCCR1A, 0x40)]),
        ["timer 1 mode 4: connected OC1A to a pin the board uses"]
    );
    assert!(refusals(&[w(TCCR5B, 0x0A), w(TCCR5A, 0x40)]).is_empty());
}
