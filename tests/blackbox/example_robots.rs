//! The example robots of other MCUs, each from its own sketch, as its owner
//! would run it: an Uno (ATmega328P) with an L298N
//! (`fixtures/boards/uno-l298n.toml`, `fixtures/robots/uno-l298n.toml`) and
//! a Pololu Romi 32U4 (ATmega32U4) with DRV8838s and xor-wired encoders
//! (`fixtures/boards/romi-32u4.toml`, `fixtures/robots/romi-32u4.toml`).

use super::*;

const UNO_TESTS: &str = "fixtures/arduino/uno-l298n/tests.toml";

/// `leg-and-spin` of the example robot `name` (its sketch's tests, its board and robot
/// files), checked for its shape: completed, one leg within 5 % of 1 m, one spin within
/// 15 degrees of 90.
fn leg_and_spin(tests: &str, name: &str) -> TestRun {
    let r = run_on_board(
        tests,
        &format!("fixtures/boards/{name}.toml"),
        &support::robot(name),
        TestName::parse("leg-and-spin").unwrap(),
    );
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!(
        (r.legs.len(), r.turns.len()),
        (1, 1),
        "{:?} {:?}",
        r.legs,
        r.turns
    );
    let leg = r.legs[0].plant_distance_mm;
    assert!((leg - 1000.0).abs() <= 50.0, "leg {leg} mm");
    let spin = r.turns[0].plant_angle_deg;
    assert!((spin - 90.0).abs() <= 15.0, "spin {spin} deg");
    r
}

/// The Uno robot drives its 1 m leg and its quarter spin to the left from
/// its own sketch: the ATmega328P's timer 0 fast PWM on the L298N's enables
/// (D5/D6), INPUT_PULLUP encoders on INT0/INT1 on the port the sketch writes
/// every period, its one USART carrying both the start byte and the counts.
/// The leg is within 5 % of 1 m, the spin within 15 degrees of 90, and the
/// counts the sketch prints once at rest are the plant's edges then.
#[test]
fn the_uno_robot_drives_its_leg_and_spin_counting_every_edge() {
    let r = leg_and_spin(UNO_TESTS, "uno-l298n");
    // The right encoder is mirrored (its B leads A driving forward): the
    // plant counts its edges down, the sketch's decoding up.
    let at = |cycle| {
        let [l, r] = plant_edges_at(&r, cycle);
        [l, -r]
    };
    let (after_leg, done) = (printed_counts(&r, "leg"), printed_counts(&r, "spin"));
    assert!(
        after_leg[0] >= 2821 && after_leg[1] >= 2821,
        "{after_leg:?}"
    );
    assert_eq!(after_leg, at(r.turns[0].start_cycle), "after the leg");
    assert_eq!(done, at(u64::MAX), "at the end");
}

const ROMI_TESTS: &str = "fixtures/arduino/romi-32u4/tests.toml";

/// The Romi drives its 1 m leg and its quarter spin to the left from its
/// own sketch: the Leonardo core on the ATmega32U4, timer 1 in mode 8 (20
/// kHz, TOP ICR1 = 400) on the DRV8838s' enables, direction high =
/// reverse, each encoder's A xor B on INT6 and PCINT4 with B on PF0 and on
/// PE2 (a pin with no Arduino number), every edge of both channels
/// counted, Serial1 at 115200. The leg is within 5 % of 1 m, the spin
/// within 15 degrees of 90, and the counts the sketch prints once at rest
/// are the plant's edges of both channels then.
#[test]
fn the_romi_drives_its_leg_and_spin_counting_every_edge() {
    let r = leg_and_spin(ROMI_TESTS, "romi-32u4");
    let (after_leg, done) = (
        printed_counts_on(&r, 1, "leg"),
        printed_counts_on(&r, 1, "spin"),
    );
    // The sketch stops at 6535 counts of its four-edge decoding.
    assert!(
        after_leg[0] >= 6535 && after_leg[1] >= 6535,
        "{after_leg:?}"
    );
    assert_eq!(
        after_leg,
        plant_edges_at(&r, r.turns[0].start_cycle),
        "after the leg"
    );
    assert_eq!(done, plant_edges_at(&r, u64::MAX), "at the end");
}
