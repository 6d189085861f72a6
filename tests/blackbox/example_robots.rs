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

const ONE_CHANNEL_TESTS: &str = "fixtures/arduino/uno-one-channel/tests.toml";

/// The Uno robot with one-channel encoders (channel A alone on INT0 and
/// INT1, no B): its sketch counts the left A on both edges and the right A
/// on its rising edges only, each in the direction it last commanded. It
/// drives its leg and its spin, and the counts it prints after each are
/// the plant's: the left one its net A edges (the left wheel goes forward,
/// then back), the right one the rising edges the bench raised on D3 (the
/// right wheel only goes forward; mirrored, so the plant counts it down).
#[test]
fn one_channel_encoders_count_the_plants_a_edges() {
    let (d, fw) = described(ONE_CHANNEL_TESTS);
    let root = hil::paths::workspace_root();
    let board = hil::board::Board::load(root.join("fixtures/boards/uno-one-channel.toml")).unwrap();
    let opts = TestOptions {
        leg_mm: d.leg_mm(None, 1000.0).unwrap(),
        bench: BenchOptions {
            board,
            ..Default::default()
        },
        record: true,
        description: Some(d),
        ..Default::default()
    };
    let test = TestName::parse("leg-and-spin").unwrap();
    let r =
        run_test(fw, &support::robot("uno-l298n"), test, &opts).expect("the bench runs the sketch");
    assert!(r.completed, "{:?}", r.finding);
    let leg = r.legs[0].plant_distance_mm;
    assert!((leg - 1000.0).abs() <= 50.0, "leg {leg} mm");
    let spin = r.turns[0].plant_angle_deg;
    assert!((spin - 90.0).abs() <= 15.0, "spin {spin} deg");
    // Only A's lines are on pins: left A (line 0) and right A (line 2).
    assert!(r.edges.iter().all(|e| e.line == 0 || e.line == 2));
    // D3's rising edges up to `cycle`, the first record being its level at
    // the start.
    let first = r.edges[0].cycle;
    let rising_at = |cycle: u64| {
        let mut level = None;
        let mut n = 0;
        for e in r.edges.iter().filter(|e| e.line == 2 && e.cycle <= cycle) {
            if e.cycle > first && e.level && level == Some(false) {
                n += 1;
            }
            level = Some(e.level);
        }
        n
    };
    let expected = |cycle| [plant_edges_at(&r, cycle)[0], rising_at(cycle)];
    let (after_leg, done) = (printed_counts(&r, "leg"), printed_counts(&r, "spin"));
    // The sketch stops at 2821 of the left wheel's counts (about 1410 of the right's).
    assert!(after_leg[0] + 2 * after_leg[1] >= 2 * 2821, "{after_leg:?}");
    let at_leg_end = r.turns[0].start_cycle;
    assert_eq!(after_leg, expected(at_leg_end), "after the leg");
    assert_eq!(done, expected(u64::MAX), "at the end");
    // The spin turned the left wheel back: the plant's net A edges fell.
    assert!(done[0] < after_leg[0] - 300, "{done:?} {after_leg:?}");
    // The right wheel's A edges (both) are about twice its rising ones.
    let right = -plant_edges_at(&r, u64::MAX)[1];
    assert!((right - 2 * done[1]).abs() <= 1, "{right} {done:?}");
}
