//! The bench's timers judged when a configuration can matter (see
//! `timers.rs`): Arduino's intermediate states pass, what the bench does
//! not emulate is refused once it shows or outlives its grace.

use super::*;
use crate::bench::timers::GRACE_CYCLES;
use crate::mcu::clock::Clock;

/// Timer 4 (Henrytwo's D6/D7): TCCR4A, TCCR4B, TIMSK4.
const TCCR4A: u16 = 0xA0;
const TCCR4B: u16 = 0xA1;
const TIMSK4: u16 = 0x72;
const PC: u32 = 0x1234;

fn bridge() -> Bridge {
    Bridge::new(Board::default(), Clock::MEGA_16MHZ)
}

/// Arduino's `init()` for timer 4: CS41, CS40 (clock/64, mode 0 for two
/// instructions), then WGM40 (mode 1): every state accepted.
#[test]
fn arduino_init_passes_through_mode_0() {
    let mut b = bridge();
    for (cycle, addr, value) in [(10, TCCR4B, 0x02), (12, TCCR4B, 0x03), (14, TCCR4A, 0x01)] {
        b.write_register(addr, value, cycle, PC).unwrap();
    }
    assert_eq!(b.next_top(), NEVER);
    assert!(b.expired_grace(1_000_000).is_none());
}

/// An external clock (CS 6) held past the grace is refused, named by the
/// write that set it; one left within the grace is not.
#[test]
fn an_external_clock_is_refused_past_its_grace() {
    let mut b = bridge();
    b.write_register(TCCR4B, 0x06, 100, PC).unwrap();
    assert_eq!(b.next_top(), 100 + GRACE_CYCLES);
    assert!(b.expired_grace(100 + GRACE_CYCLES - 1).is_none());
    let (e, cycle, pc) = b.expired_grace(100 + GRACE_CYCLES).unwrap();
    assert_eq!((cycle, pc), (100, PC));
    let text = e.to_string();
    assert!(
        text.contains("timer 4") && text.contains("clock select 6"),
        "{text}"
    );
    assert!(text.contains("external clock"), "{text}");

    let mut b = bridge();
    b.write_register(TCCR4B, 0x06, 100, PC).unwrap();
    b.write_register(TCCR4B, 0x03, 104, PC).unwrap();
    assert_eq!(b.next_top(), NEVER);
    assert!(b.expired_grace(1_000).is_none());
}

/// Observed at once: an external clock with a compare output connected,
/// an interrupt enabled.
#[test]
fn observed_states_are_refused_at_once() {
    let mut b = bridge();
    b.write_register(TCCR4B, 0x06, 100, PC).unwrap();
    let e = b.write_register(TCCR4A, 0x81, 102, PC).unwrap_err();
    assert!(e.to_string().contains("connected a compare output"), "{e}");

    let mut b = bridge();
    let e = b.write_register(TIMSK4, 0x01, 10, PC).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("TIMSK4 = 0x01") && text.contains("interrupts"),
        "{text}"
    );
}

/// Fast PWM with TOP = ICR4 as sketches set it (the mode before ICR4):
/// emulated, the output follows OCR4A from the BOTTOM after its write.
#[test]
fn a_sketchs_fast_pwm_on_icr_runs() {
    let mut b = bridge();
    let w = |b: &mut Bridge, addr: u16, v: u8, cycle: u64| b.write_register(addr, v, cycle, PC);
    w(&mut b, TCCR4A, 0b1000_0010, 0).unwrap(); // COM4A1, WGM41
    w(&mut b, TCCR4B, 0b0001_1001, 2).unwrap(); // WGM43:2, clock/1: mode 14
    w(&mut b, 0xA7, 0x02, 4).unwrap(); // ICR4 = 639
    w(&mut b, 0xA6, 0x7F, 6).unwrap();
    w(&mut b, 0xA9, 0x01, 8).unwrap(); // OCR4A = 320
    w(&mut b, 0xA8, 0x40, 10).unwrap();
    let top = b.next_top();
    // With ICR4 = 0 the counter stays at BOTTOM; from the ICR4 write (its
    // low byte at cycle 6) it counts 0..639: OCR4A waits for that BOTTOM.
    assert_eq!(top, 6 + 640, "OCR4A waits for BOTTOM");
    assert!(b.apply_top_if_due(0, top).unwrap() || b.apply_top_if_due(1, top).unwrap());
    let t = b.timers().iter().find(|t| t.id().number() == 4).unwrap();
    match t.drive('A', 16_000_000, top) {
        PinDrive::Pwm { duty, hz } => {
            assert!((duty - 321.0 / 640.0).abs() < 1e-12, "{duty}");
            assert!((hz - 25_000.0).abs() < 1e-9, "{hz}");
        }
        other => panic!("{other:?}"),
    }
    assert!(b.expired_grace(NEVER - 1).is_none());
}

/// A compare output connected to a pin the board uses for something else
/// is refused, naming the pin: on Henrytwo, OC4A, OC4B, OC4C are motor
/// inputs, OC2A (D10) the green LED; with D13 driven from OC0A and D11
/// from OC1A, timer 1's OC1C shares D13. The channels the board drives
/// pass.
#[test]
fn an_output_on_a_pin_the_board_uses_otherwise_is_refused() {
    const TCCR2A: u16 = 0xB0;
    let mut b = bridge();
    b.write_register(TCCR2A, 0x21, 10, PC).unwrap(); // COM2B1: D9, a motor input
    let e = b.write_register(TCCR2A, 0xA1, 12, PC).unwrap_err(); // COM2A1: D10
    assert!(
        matches!(
            e,
            PwmError::ForeignOutput {
                channel: 'A',
                ref pin,
                ..
            } if pin == "D10"
        ),
        "{e}"
    );
    let mut board = Board::default();
    let pin = |n| crate::board::Pin::arduino(crate::board::Mcu::Atmega2560, n).unwrap();
    let oc = |timer, channel| Some(PwmSource { timer, channel });
    board.battery_leds.as_mut().unwrap().blue = pin(30);
    board.right_motor.pin1 = BridgeInput {
        pin: pin(13),
        pwm: oc(0, 'A'),
    };
    board.right_motor.pin2 = BridgeInput {
        pin: pin(11),
        pwm: oc(1, 'A'),
    };
    let mut b = Bridge::new(board, Clock::MEGA_16MHZ);
    const TCCR1A: u16 = 0x80;
    b.write_register(TCCR1A, 0x81, 10, PC).unwrap(); // COM1A1: D11
    let e = b.write_register(TCCR1A, 0x89, 12, PC).unwrap_err(); // COM1C1: D13
    assert!(
        matches!(
            e,
            PwmError::ForeignOutput {
                channel: 'C',
                ref pin,
                ..
            } if pin == "D13"
        ),
        "{e}"
    );
    assert!(e.to_string().contains("OC1C to D13"), "{e}");
}
