//! The driver's register writes for each kind, on a fake register file, and
//! every rule of the wiring check.

extern crate std;

use std::collections::BTreeMap;
use std::string::String;
use std::vec;
use std::vec::Vec;

use henrytwo_protocol::NO_PIN;

use super::{Driver, Registers, WiringError, WiringFault};
use crate::hal::mega_pins::{self as mp, PINH, PINL};
use crate::io::{Bridges, Side};
use crate::settings::{DriverWiring, Settings};

/// A data space that remembers every write in order.
#[derive(Default)]
struct Fake {
    mem: BTreeMap<u16, u8>,
    log: Vec<(u16, u8)>,
}

impl Registers for Fake {
    fn read(&mut self, addr: u16) -> u8 {
        self.mem.get(&addr).copied().unwrap_or(0)
    }
    fn write(&mut self, addr: u16, v: u8) {
        self.mem.insert(addr, v);
        self.log.push((addr, v));
    }
}

const PORTH: u16 = PINH + 2;
const DDRH: u16 = PINH + 1;
const PORTL: u16 = PINL + 2;
const DDRL: u16 = PINL + 1;

fn henrytwo() -> DriverWiring {
    Settings::DEFAULT.driver
}

fn take(d: &mut Driver<Fake>) -> Vec<(u16, u8)> {
    core::mem::take(&mut d.registers().log)
}

/// The compiled Henrytwo driver's writes (`board::drive_motors`, then
/// `HBridge::new` for the right, then the left motor): D6-D9 outputs low, the
/// two timers started, every input at 0.
#[test]
fn henrytwo_boots_like_the_compiled_driver() {
    let mut d = Driver::new(Fake::default(), &henrytwo());
    let log = take(&mut d);
    let mut want = Vec::new();
    let mut porth = 0u8;
    let mut ddrh = 0u8;
    for bit in [3, 4, 5, 6] {
        porth &= !(1 << bit);
        want.push((PORTH, porth));
        ddrh |= 1 << bit;
        want.push((DDRH, ddrh));
    }
    // Timer 4 (D6 is its first pin), then timer 2.
    want.extend([(mp::TCCR4A, 1), (mp::TCCR4B, 1), (mp::TCCR2A, 1), (mp::TCCR2B, 1)]);
    // right forward D7 (OC4B), right reverse D6 (OC4A), left forward D9
    // (OC2B), left reverse D8 (OC4C): PORTH bit low, then TCCRnA.
    for t in [mp::TCCR4A, mp::TCCR4A, mp::TCCR2A, mp::TCCR4A] {
        want.push((PORTH, 0));
        want.push((t, 1));
    }
    assert_eq!(log, want);
}

#[test]
fn a_wiring_that_fails_the_check_boots_as_the_factory_one() {
    let bad = DriverWiring { kind: 0, left: [13, 8, NO_PIN], right: [7, 6, NO_PIN] };
    let mut d = Driver::new(Fake::default(), &bad);
    assert_eq!(d.wiring(), &henrytwo());
    let mut f = Driver::new(Fake::default(), &henrytwo());
    assert_eq!(take(&mut d), take(&mut f));
}

#[test]
fn two_pwm_writes_one_channel_per_request_as_analog_write() {
    let mut d = Driver::new(Fake::default(), &henrytwo());
    take(&mut d);
    // Right forward D7 = OC4B (COM4B1 = bit 5): OCR high byte 0, low byte,
    // then TCCR4A.
    d.set_forward(Side::Right, 100);
    assert_eq!(take(&mut d), vec![(mp::OCR4B + 1, 0), (mp::OCR4B, 100), (mp::TCCR4A, 0x21)]);
    // Left forward D9 = OC2B on the 8-bit timer 2: one OCR byte.
    d.set_forward(Side::Left, 7);
    assert_eq!(take(&mut d), vec![(mp::OCR2B, 7), (mp::TCCR2A, 0x21)]);
    // 255: PORTH bit 4 high, then the channel released.
    d.set_forward(Side::Right, 255);
    assert_eq!(take(&mut d), vec![(PORTH, 0x10), (mp::TCCR4A, 0x01)]);
    // Full duty again: the pin already high stays high.
    d.set_forward(Side::Right, 255);
    assert_eq!(d.registers().mem[&PORTH] & 0x10, 0x10, "D7 (PH4) still high");
    take(&mut d);
    // Left reverse D8 = OC4C (COM4C1 = bit 3); the right's pin stays high.
    d.set_reverse(Side::Left, 200);
    assert_eq!(take(&mut d), vec![(mp::OCR4C + 1, 0), (mp::OCR4C, 200), (mp::TCCR4A, 0x09)]);
    d.set_reverse(Side::Right, 0);
    assert_eq!(take(&mut d), vec![(PORTH, 0x10), (mp::TCCR4A, 0x09)]);
    // Off: forward inputs (right, left), then reverse (right, left).
    d.all_off();
    assert_eq!(
        take(&mut d),
        vec![
            (PORTH, 0x00),
            (mp::TCCR4A, 0x09),
            (PORTH, 0),
            (mp::TCCR2A, 0x01),
            (PORTH, 0),
            (mp::TCCR4A, 0x09),
            (PORTH, 0),
            (mp::TCCR4A, 0x01)
        ]
    );
}

/// L298N style on timer 5: enable D46 (OC5A), IN1 D47, IN2 D48 (left);
/// enable D45 (OC5B), IN1 D49, IN2 D22 (right).
fn enable_two_dir() -> DriverWiring {
    DriverWiring { kind: 1, left: [46, 47, 48], right: [45, 49, 22] }
}

#[test]
fn enable_two_dir_sets_in1_in2_then_the_enable() {
    let mut d = Driver::new(Fake::default(), &enable_two_dir());
    let boot = take(&mut d);
    // Only timer 5 starts, as timer 4 would.
    assert!(boot.contains(&(mp::TCCR5B, 1)));
    assert!(!boot.iter().any(|(a, _)| [mp::TCCR2B, mp::TCCR3B, mp::TCCR4B].contains(a)));
    // Forward: IN1 (PL2) high, IN2 (PL1) low, then OC5A's duty.
    d.set_forward(Side::Left, 90);
    assert_eq!(
        take(&mut d),
        vec![(PORTL, 0x04), (PORTL, 0x04), (mp::OCR5A + 1, 0), (mp::OCR5A, 90), (mp::TCCR5A, 0x81)]
    );
    // Same direction: only the duty.
    d.set_forward(Side::Left, 91);
    assert_eq!(take(&mut d), vec![(mp::OCR5A + 1, 0), (mp::OCR5A, 91), (mp::TCCR5A, 0x81)]);
    // 0 with reverse 0: enable low (coast), IN pins as they were.
    d.set_forward(Side::Left, 0);
    assert_eq!(take(&mut d), vec![(PORTL, 0x04), (mp::TCCR5A, 0x01)]);
    // Reverse at full: IN1 low, IN2 high, enable high (PL3).
    d.set_reverse(Side::Left, 255);
    assert_eq!(take(&mut d), vec![(PORTL, 0x00), (PORTL, 0x02), (PORTL, 0x0A), (mp::TCCR5A, 0x01)]);
    // Both asked at once: coast.
    d.set_forward(Side::Left, 50);
    assert_eq!(take(&mut d), vec![(PORTL, 0x02), (mp::TCCR5A, 0x01)]);
    // The right motor: IN1 PL0, IN2 PA0, enable OC5B (COM5B1 bit 5).
    d.set_forward(Side::Right, 10);
    let porta = mp::PINA + 2;
    assert_eq!(
        take(&mut d),
        vec![(PORTL, 0x03), (porta, 0x00), (mp::OCR5B + 1, 0), (mp::OCR5B, 10), (mp::TCCR5A, 0x21)]
    );
}

/// Pin 1 PWM, pin 2 direction: left D2... no, D44 (OC5C) and D42; right D5
/// is reserved, so D7 (OC4B) and D43.
fn pwm_dir() -> DriverWiring {
    DriverWiring { kind: 2, left: [44, 42, NO_PIN], right: [7, 43, NO_PIN] }
}

#[test]
fn pwm_dir_sets_the_direction_then_the_pwm() {
    let mut d = Driver::new(Fake::default(), &pwm_dir());
    let boot = take(&mut d);
    // Timers 4 (D7) and 5 (D44), no other.
    let started: Vec<u16> = boot
        .iter()
        .filter(|(a, _)| [mp::TCCR2B, mp::TCCR3B, mp::TCCR4B, mp::TCCR5B].contains(a))
        .map(|w| w.0)
        .collect();
    assert_eq!(started, vec![mp::TCCR4B, mp::TCCR5B]);
    // Forward: direction PL7 high, then OC5C.
    d.set_forward(Side::Left, 60);
    assert_eq!(take(&mut d), vec![(PORTL, 0x80), (mp::OCR5C + 1, 0), (mp::OCR5C, 60), (mp::TCCR5A, 0x09)]);
    // Coast: PWM pin low, direction kept.
    d.set_forward(Side::Left, 0);
    assert_eq!(take(&mut d), vec![(PORTL, 0x80), (mp::TCCR5A, 0x01)]);
    // Reverse: direction low, then the PWM.
    d.set_reverse(Side::Left, 30);
    assert_eq!(take(&mut d), vec![(PORTL, 0x00), (mp::OCR5C + 1, 0), (mp::OCR5C, 30), (mp::TCCR5A, 0x09)]);
    // Right: direction D43 (PL6), PWM OC4B.
    d.set_reverse(Side::Right, 255);
    assert_eq!(take(&mut d), vec![(PORTL, 0x00), (PORTH, 0x10), (mp::TCCR4A, 0x01)]);
}

#[test]
fn rewiring_releases_the_old_inputs_first_then_sets_up_the_new() {
    let mut d = Driver::new(Fake::default(), &henrytwo());
    d.set_forward(Side::Right, 100);
    d.set_forward(Side::Left, 255);
    take(&mut d);
    d.rewire(&enable_two_dir());
    let log = take(&mut d);
    // First the four old inputs low and released, pin 1 then 2, left first.
    let release = [
        (PORTH, 0x40 & !0x40),
        (mp::TCCR2A, 0x01),
        (PORTH, 0),
        (mp::TCCR4A, 0x21),
        (PORTH, 0),
        (mp::TCCR4A, 0x01),
        (PORTH, 0),
        (mp::TCCR4A, 0x01),
    ];
    assert_eq!(log[..release.len()], release[..]);
    // Then the new pins outputs, timer 5 started, the enables low.
    let rest = &log[release.len()..];
    assert_eq!(d.registers().mem[&DDRL], 0x1F, "D45-D49 (PL4-PL0) outputs");
    assert!(rest.contains(&(mp::TCCR5B, 1)));
    assert!(!rest.iter().any(|(a, _)| *a == mp::TCCR4A || *a == mp::TCCR2A));
    assert_eq!(d.wiring(), &enable_two_dir());
    assert!(d.drives(&enable_two_dir()));
    // The wiring it no longer has is not the one it drives.
    assert!(!d.drives(&henrytwo()));
    // The same wiring again writes nothing, nor does one that fails the check.
    d.rewire(&enable_two_dir());
    assert!(take(&mut d).is_empty());
    d.rewire(&DriverWiring { kind: 1, left: [13, 47, 48], right: [45, 49, 22] });
    assert!(take(&mut d).is_empty());
    assert_eq!(d.wiring(), &enable_two_dir());
}

/// A pin the old and the new wiring share (D7, PH4) is still an output after
/// the rewiring: the release leaves the old pins outputs, and setting the new
/// ones up must not flip a DDR bit that is already set.
#[test]
fn a_pin_both_wirings_use_stays_an_output() {
    let mut d = Driver::new(Fake::default(), &henrytwo());
    assert_eq!(d.registers().mem[&DDRH], 0x78, "D6-D9 (PH3-PH6) outputs");
    d.rewire(&pwm_dir());
    assert!(d.drives(&pwm_dir()));
    assert_eq!(d.registers().mem[&DDRH] & 0x10, 0x10, "D7 (PH4) still an output");
}

#[test]
fn only_the_timers_of_pwm_inputs_start() {
    // PWM on D6 and D7 (timer 4); the direction pins D45 and D44 carry
    // OC5B and OC5C, but as plain outputs they must not start timer 5.
    let w = DriverWiring { kind: 2, left: [6, 45, NO_PIN], right: [7, 44, NO_PIN] };
    assert_eq!(w.check(), Ok(()));
    let mut d = Driver::new(Fake::default(), &w);
    let boot = take(&mut d);
    assert!(boot.contains(&(mp::TCCR4A, 1)) && boot.contains(&(mp::TCCR4B, 1)));
    assert!(!boot.iter().any(|(a, _)| [mp::TCCR2B, mp::TCCR3B, mp::TCCR5A, mp::TCCR5B].contains(a)));
}

fn err(side: Option<Side>, index: u8, value: u8, fault: WiringFault) -> Result<(), WiringError> {
    Err(WiringError { side, index, value, fault })
}

#[test]
fn the_factory_and_example_wirings_pass() {
    assert_eq!(henrytwo().check(), Ok(()));
    assert_eq!(enable_two_dir().check(), Ok(()));
    assert_eq!(pwm_dir().check(), Ok(()));
}

#[test]
fn every_wiring_rule_refuses() {
    let l = Some(Side::Left);
    let r = Some(Side::Right);
    let h = henrytwo();
    let with = |f: &dyn Fn(&mut DriverWiring)| {
        let mut w = h;
        f(&mut w);
        w.check()
    };
    assert_eq!(with(&|w| w.kind = 3), err(None, 0, 3, WiringFault::UnknownKind));
    assert_eq!(with(&|w| w.left[1] = NO_PIN), err(l, 2, NO_PIN, WiringFault::Missing));
    assert_eq!(with(&|w| w.right[2] = 30), err(r, 3, 30, WiringFault::Unused));
    assert_eq!(with(&|w| w.right[0] = 70), err(r, 1, 70, WiringFault::NotAMegaPin));
    // D13 is timer 0's, D11 timer 1's, D30 no PWM at all.
    assert_eq!(with(&|w| w.left[0] = 13), err(l, 1, 13, WiringFault::NotPwm));
    assert_eq!(with(&|w| w.left[1] = 30), err(l, 2, 30, WiringFault::NotPwm));
    for n in [0, 1, 2, 3, 4, 5, 10, 11, 12, 18, 19, 54] {
        assert_eq!(with(&|w| w.right[1] = n), err(r, 2, n, WiringFault::Reserved), "D{n}");
    }
    assert_eq!(with(&|w| w.right[0] = 9), err(r, 1, 9, WiringFault::Twice));
    // PwmDir: the direction pin needs no PWM, but pin 3 must be none.
    let pd = pwm_dir();
    assert_eq!(DriverWiring { right: [7, 43, 23], ..pd }.check(), err(r, 3, 23, WiringFault::Unused));
    // EnableTwoDir: all three needed; IN pins plain, enable PWM.
    let e = enable_two_dir();
    assert_eq!(DriverWiring { left: [46, 47, NO_PIN], ..e }.check(), err(l, 3, NO_PIN, WiringFault::Missing));
    assert_eq!(DriverWiring { left: [47, 46, 48], ..e }.check(), err(l, 1, 47, WiringFault::NotPwm));
    assert_eq!(DriverWiring { right: [45, 49, 48], ..e }.check(), err(r, 3, 48, WiringFault::Twice));
}

#[test]
fn the_refusal_names_the_pin_and_why() {
    struct Text(String);
    impl ufmt::uWrite for Text {
        type Error = ();
        fn write_str(&mut self, s: &str) -> Result<(), ()> {
            self.0.push_str(s);
            Ok(())
        }
    }
    let mut t = Text(String::new());
    let e = WiringError { side: Some(Side::Right), index: 2, value: 13, fault: WiringFault::NotPwm };
    ufmt::uwrite!(&mut t, "{}", e).unwrap();
    assert_eq!(t.0, "right pin 2 = 13: no PWM of timer 2-5");
}
