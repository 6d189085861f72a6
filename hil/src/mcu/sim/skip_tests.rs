//! The skip on hand-assembled loops: a wait on an SRAM flag that a timer
//! sets is skipped, and ends on the same cycle; a wait on TCNT0 is not.

use super::super::*;

/// GPIOR0 in data space: the programs write what they saw there at the end.
const GPIOR0: u16 = 0x3E;
/// The SRAM flag the first program waits on.
const FLAG: u16 = 0x200;

/// Notes the cycle of the write to GPIOR0 (and wants attention then); its
/// timer sets the flag.
#[derive(Default)]
struct Done {
    at: Option<(u64, u8)>,
}

impl Handler for Done {
    fn io_write(&mut self, core: &mut Core, _addr: u16, value: u8) {
        self.at = Some((core.cycle(), value));
    }
    fn io_read(&mut self, _core: &mut Core, _addr: u16) -> u8 {
        0
    }
    fn attention(&self) -> bool {
        self.at.is_some()
    }
    fn timer(&mut self, core: &mut Core, _when: u64) -> u64 {
        core.set_data(FLAG, 1);
        0
    }
    fn irq(&mut self, _core: &mut Core, _tag: u32, _value: u32) {}
}

/// Runs `words` until it writes GPIOR0, skipping or not, with the
/// handler's timer at `timer`: the cycle and value of the write, and the
/// cycles skipped.
fn run(words: &[u16], skip: bool, timer: u64) -> ((u64, u8), u64) {
    let mut avr = Avr::new("atmega2560", 16_000_000, Done::default()).unwrap();
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    avr.load_flash(0, &bytes).unwrap();
    avr.claim_io_write(GPIOR0, IoClaim::Replace).unwrap();
    avr.set_skip(skip);
    avr.schedule(timer);
    let mut sleeping = false;
    while avr.handler().at.is_none() && avr.cycle() < 10_000_000 {
        // Bursts of the run loop's length (its checks' grid).
        let until = avr.cycle() + 1024;
        avr.run_burst(until, &mut sleeping);
    }
    (
        avr.handler().at.expect("the program ends"),
        avr.skipped_cycles(),
    )
}

#[test]
fn a_wait_on_a_flag_set_by_an_event_is_skipped_to_the_same_cycle() {
    let words = [
        0x9180, FLAG,   // loop: lds r24, FLAG
        0x2388, //       tst r24
        0xF3E1, //       breq loop
        0xBB8E, //       out GPIOR0, r24
        0xCFFF, //       rjmp .
    ];
    let (stepped, none) = run(&words, false, 100_003);
    let (skipped, cycles) = run(&words, true, 100_003);
    assert_eq!(none, 0);
    assert_eq!(stepped, skipped);
    // All but the first bit of each burst of the wait.
    assert!(cycles > 90_000, "only {cycles} cycles skipped");
}

/// A loop that reads a free-running counter is a fixed point as long as
/// the counter does not move (TCNT0 at clk/64 holds for 16 of its
/// iterations): a skip would jump to the counter's overflow.
#[test]
fn a_wait_on_tcnt0_is_not_skipped() {
    let words = [
        0xE003, //       ldi r16, 3
        0xBD05, //       out TCCR0B, r16 (clk/64)
        0xB586, // loop: in r24, TCNT0
        0x3C88, //       cpi r24, 200
        0xF3E8, //       brlo loop
        0xBB8E, //       out GPIOR0, r24
        0xCFFF, //       rjmp .
    ];
    let (stepped, _) = run(&words, false, u64::MAX);
    let (skipped, cycles) = run(&words, true, u64::MAX);
    assert_eq!(stepped.1, 200);
    assert_eq!(stepped, skipped);
    assert_eq!(cycles, 0);
}
