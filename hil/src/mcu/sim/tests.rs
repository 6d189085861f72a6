//! The burst loop's bounds, the guards that keep the safe API sound, and
//! driven pins: each test runs a hand-assembled program on a real simavr
//! MCU.

use std::panic::{catch_unwind, AssertUnwindSafe};

use super::*;

/// GPIOR0 in data space: a plain register the test program writes.
const GPIOR0: u16 = 0x3E;

/// What the handler does on each write to GPIOR0, besides recording it.
#[derive(Clone, Copy, PartialEq, Eq)]
enum OnWrite {
    Nothing,
    /// Panic on writing this value.
    PanicAt(u8),
    /// Raise `Writes::pin` (which the test watches) from inside the callback.
    RaisePin,
}

/// Counts writes to GPIOR0 and wants attention once it sees `at`.
struct Writes {
    seen: Vec<u8>,
    at: u8,
    attention: bool,
    on_write: OnWrite,
    pin: Option<Irq>,
    irqs: Vec<(u32, u32)>,
}

impl Handler for Writes {
    fn io_write(&mut self, core: &mut Core, _addr: u16, value: u8) {
        self.seen.push(value);
        self.attention |= value == self.at;
        match self.on_write {
            OnWrite::Nothing => {}
            OnWrite::PanicAt(v) => assert_ne!(value, v, "the handler panics"),
            OnWrite::RaisePin => core.raise(self.pin.unwrap(), u32::from(value & 1)),
        }
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
    fn irq(&mut self, _core: &mut Core, tag: u32, value: u32) {
        self.irqs.push((tag, value));
    }
}

/// An MCU running `ldi r16, 1` then, forever, `out GPIOR0, r16; inc r16;
/// rjmp` back: three steps and four cycles per write of 1, 2, 3, ...
/// GPIOR0 not claimed yet.
fn counting_program(at: u8, on_write: OnWrite) -> Avr<Writes> {
    let handler = Writes {
        seen: Vec::new(),
        at,
        attention: false,
        on_write,
        pin: None,
        irqs: Vec::new(),
    };
    let mut avr = Avr::new("atmega2560", 16_000_000, handler).unwrap();
    let words: [u16; 4] = [0xE001, 0xBB0E, 0x9503, 0xCFFD];
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    avr.load_flash(0, &bytes).unwrap();
    avr
}

fn counting_mcu(at: u8) -> Avr<Writes> {
    let mut avr = counting_program(at, OnWrite::Nothing);
    avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
    avr
}

/// The text of a caught panic.
fn message(payload: Box<dyn std::any::Any + Send>) -> String {
    match payload.downcast::<String>() {
        Ok(s) => *s,
        Err(p) => p
            .downcast::<&str>()
            .map_or_else(|_| String::new(), |s| s.to_string()),
    }
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

#[test]
fn claiming_a_write_slot_again_keeps_simavrs_handler_as_the_one_forwarded_to() {
    let mut avr = counting_program(0, OnWrite::Nothing);
    // Observed twice: each write reaches the handler once, and simavr's
    // behaviour (GPIOR0 has no handler: the byte is stored) once. Had the
    // second claim saved the bench's own trampoline as the original, the
    // first write would recurse until the stack overflowed.
    avr.claim_io_write(GPIOR0, IoClaim::Observe).unwrap();
    avr.claim_io_write(GPIOR0, IoClaim::Observe).unwrap();
    let mut sleeping = false;
    avr.run_burst(1 + 3 * 4 + 1, &mut sleeping);
    assert_eq!(avr.handler().seen, [1, 2, 3, 4]);
    assert_eq!(avr.data(GPIOR0), 4);
    // Replaced: the byte is no longer stored; observed again: it is.
    avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
    avr.run_burst(avr.cycle() + 4, &mut sleeping);
    assert_eq!(avr.handler().seen, [1, 2, 3, 4, 5]);
    assert_eq!(avr.data(GPIOR0), 4);
    avr.claim_io_write(GPIOR0, IoClaim::Observe).unwrap();
    avr.run_burst(avr.cycle() + 4, &mut sleeping);
    assert_eq!(avr.handler().seen, [1, 2, 3, 4, 5, 6]);
    assert_eq!(avr.data(GPIOR0), 6);
}

#[test]
fn an_irq_works_with_its_own_avr_only() {
    let mut first = counting_mcu(0);
    let mut other = counting_mcu(0);
    let pin = first.port_pin('B', 0).unwrap();
    // Its own: fine, and the watched IRQ reaches the handler.
    first.watch_irq(pin, 7);
    first.raise(pin, 1);
    assert_eq!(first.handler().irqs, [(7, 1)]);
    let raised = catch_unwind(AssertUnwindSafe(|| other.raise(pin, 1)));
    assert!(message(raised.unwrap_err()).contains("used with Avr"));
    let watched = catch_unwind(AssertUnwindSafe(|| other.watch_irq(pin, 7)));
    assert!(message(watched.unwrap_err()).contains("used with Avr"));
    // Its Avr gone (its IRQ tables freed), a new Avr refuses it too.
    drop(first);
    let mut later = counting_mcu(0);
    let raised = catch_unwind(AssertUnwindSafe(|| later.raise(pin, 0)));
    assert!(message(raised.unwrap_err()).contains("used with Avr"));
    // Inside a callback, through the Core: the burst stops and the panic
    // comes out of it.
    later.handler_mut().pin = Some(pin);
    later.handler_mut().on_write = OnWrite::RaisePin;
    let burst = catch_unwind(AssertUnwindSafe(|| {
        let mut sleeping = false;
        later.run_burst(u64::MAX, &mut sleeping)
    }));
    assert!(message(burst.unwrap_err()).contains("used with Avr"));
    assert_eq!(later.handler().seen, [1]);
}

#[test]
fn a_panic_in_a_callback_stops_the_burst_and_comes_out_of_it() {
    let mut avr = counting_program(0, OnWrite::PanicAt(3));
    avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
    let mut sleeping = false;
    let burst = catch_unwind(AssertUnwindSafe(|| avr.run_burst(u64::MAX, &mut sleeping)));
    assert!(message(burst.unwrap_err()).contains("the handler panics"));
    // Stopped right after the step that panicked: the ldi, two rounds, the
    // out that wrote 3.
    assert_eq!(avr.cycle(), 1 + 2 * 4 + 1);
    assert_eq!(avr.handler().seen, [1, 2, 3]);
    // The handler is free again and the MCU runs on.
    let until = avr.cycle() + 8;
    let burst = avr.run_burst(until, &mut sleeping);
    assert_eq!(burst.state, CpuState::Running);
    assert_eq!(avr.handler().seen, [1, 2, 3, 4, 5]);
}

#[test]
fn a_callback_that_arrives_while_the_handler_runs_is_refused() {
    let mut avr = counting_program(0, OnWrite::RaisePin);
    avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
    let pin = avr.port_pin('B', 0).unwrap();
    avr.watch_irq(pin, 7);
    avr.handler_mut().pin = Some(pin);
    // The write callback raises a watched IRQ: simavr would call the
    // handler again while it runs.
    let mut sleeping = false;
    let burst = catch_unwind(AssertUnwindSafe(|| avr.run_burst(u64::MAX, &mut sleeping)));
    assert!(message(burst.unwrap_err()).contains("while it was running"));
    // The nested call never reached the handler, and the burst stopped
    // after that step.
    assert_eq!(avr.handler().irqs, []);
    assert_eq!(avr.handler().seen, [1]);
    assert_eq!(avr.cycle(), 1 + 1);
    // Likewise inside `with_core`, which lends the handler too.
    let refused = catch_unwind(AssertUnwindSafe(|| {
        avr.with_core(|h, core| core.raise(h.pin.unwrap(), 0))
    }));
    assert!(message(refused.unwrap_err()).contains("while it was running"));
    assert_eq!(avr.handler().irqs, []);
    // From outside callbacks the same raise is delivered.
    avr.raise(pin, 1);
    assert_eq!(avr.handler().irqs, [(7, 1)]);
}

/// PINE, DDRE and PORTE in data space.
const PINE: u16 = 0x2C;

/// An input pin the bench drives keeps its level whatever the firmware
/// writes to its port, pull-up on; a pin nobody drives reads its pull-up.
/// The program switches on the pull-ups of PE4 and PE5, makes PE3 an
/// output, then writes PORTE and DDRE forever.
#[test]
fn a_driven_pin_keeps_its_level_through_port_writes() {
    let words: [u16; 7] = [
        0xE300, // ldi r16, 0x30: pull-ups on PE4 and PE5
        0xB90E, // out PORTE, r16
        0xE018, // ldi r17, 0x08: PE3 an output
        0xB91D, // out DDRE, r17
        0xB90E, // out PORTE, r16
        0xB91D, // out DDRE, r17
        0xCFFD, // rjmp back to the out PORTE
    ];
    let mut avr = counting_program(0, OnWrite::Nothing);
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    avr.load_flash(0, &bytes).unwrap();
    let pe4 = avr.driven_pin('E', 4, false).unwrap();
    let mut sleeping = false;
    let mut run = |avr: &mut Avr<Writes>| {
        let until = avr.cycle() + 40;
        avr.run_burst(until, &mut sleeping);
        avr.data(PINE) & 0x30
    };
    // PE4 driven low, PE5 pulled up.
    assert_eq!(run(&mut avr), 0x20);
    avr.drive(pe4, true);
    assert_eq!(run(&mut avr), 0x30);
    avr.drive(pe4, false);
    assert_eq!(run(&mut avr), 0x20);
    // Driven from inside a callback too.
    avr.with_core(|_, core| core.drive(pe4, true));
    assert_eq!(run(&mut avr), 0x30);
    avr.with_core(|_, core| core.drive(pe4, false));
    assert_eq!(run(&mut avr), 0x20);
}

/// The pins the bench may drive are the MCU's description's: the Uno's
/// ATmega328P has PC0-PC6 and no PC7 (simavr's port C has eight bits), and
/// no port E, which the ATmega2560 has; the Mega has both.
#[test]
fn a_driven_pin_is_one_the_mcu_has() {
    let make = |name: &str| {
        let handler = Writes {
            seen: Vec::new(),
            at: 0,
            attention: false,
            on_write: OnWrite::Nothing,
            pin: None,
            irqs: Vec::new(),
        };
        Avr::new(name, 16_000_000, handler).unwrap()
    };
    let mut uno = make("atmega328p");
    assert!(uno.driven_pin('C', 6, false).is_ok());
    assert!(matches!(
        uno.driven_pin('C', 7, false),
        Err(SimError::NoSuchPin('C', 7))
    ));
    assert!(matches!(
        uno.driven_pin('E', 4, false),
        Err(SimError::NoSuchPin('E', 4))
    ));
    let mut mega = make("atmega2560");
    assert!(mega.driven_pin('C', 7, false).is_ok());
    assert!(mega.driven_pin('E', 4, false).is_ok());
}

/// The vendored simavr keeps the cores of the boards the bench has wiring
/// for or is asked about (vendor/simavr-ffi/VENDORED.md); the others were
/// left out of it, and simavr does not know them.
#[test]
fn the_vendored_simavr_has_the_kept_cores_only() {
    let make = |name: &str| {
        let handler = Writes {
            seen: Vec::new(),
            at: 0,
            attention: false,
            on_write: OnWrite::Nothing,
            pin: None,
            irqs: Vec::new(),
        };
        Avr::new(name, 16_000_000, handler)
    };
    for name in ["atmega2560", "atmega328p", "atmega32u4"] {
        assert!(
            make(name).is_ok(),
            "{name} missing from the vendored simavr"
        );
    }
    for name in ["atmega1280", "attiny85"] {
        assert!(
            matches!(make(name), Err(SimError::UnknownMcu(_))),
            "{name} was left out of the vendored simavr"
        );
    }
}
