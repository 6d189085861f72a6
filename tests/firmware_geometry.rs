//! One robust ELF for any differential-drive robot: the geometry told over
//! the protocol (SET_PARAM `mm_per_count_left/right`, `counts_per_wheel_rev`)
//! sets where the firmware ends a leg and how fast it drives it, and the
//! EEPROM keeps it across a reset.

#[path = "support/mod.rs"]
mod support;

use hil::bench::{Bench, BenchOptions};
use hil::firmware::link::{frame, replies, Command, Param, ProtoTest, Received};
use hil::runs::start::wait_ready;

/// Another robot's geometry: 0.567 mm and 1/360 turn per count.
const MM_PER_COUNT: f32 = 0.567;
const COUNTS_PER_WHEEL_REV: f32 = 360.0;
const GEOMETRY: [(Param, f32); 3] = [
    (Param::MmPerCountLeft, MM_PER_COUNT),
    (Param::MmPerCountRight, MM_PER_COUNT),
    (Param::CountsPerWheelRev, COUNTS_PER_WHEEL_REV),
];
const LEG_MM: f32 = 1000.0;

fn bench() -> Bench {
    let mut b = Bench::new(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    wait_ready(&mut b, None).unwrap();
    b
}

/// Send `bytes`, let them arrive and be answered, return the new replies.
fn exchange(b: &mut Bench, bytes: &[u8]) -> Vec<Received> {
    let before = b.uart_output(1).len();
    b.send(1, bytes);
    b.run_for(0.1 + bytes.len() as f64 * 0.003).unwrap();
    replies(&b.uart_output(1)[before..])
}

fn set(b: &mut Bench, p: Param, v: f32) {
    let r = exchange(b, &frame(&Command::SetParam(p, v)));
    assert!(r.len() == 1 && r[0].ok, "SET_PARAM {p:?} = {v}: {r:?}");
}

fn get(b: &mut Bench, p: Param) -> f32 {
    let r = exchange(b, &frame(&Command::GetParam(p)));
    assert!(r.len() == 1 && r[0].ok, "GET_PARAM {p:?}: {r:?}");
    f32::from_le_bytes(r[0].data[1..5].try_into().unwrap())
}

/// Both firmware counts.
fn counts(b: &Bench) -> (i32, i32) {
    let v = *b.vars().expect("the robust build has the bench interface");
    (b.read_i32(v.left_count), b.read_i32(v.right_count))
}

/// The line, on Henrytwo's plant, with the firmware told it drives another
/// robot: it ends the leg when the sum of both counts reaches
/// `ceil(2 * 1000 / 0.567)` = 3528 (Henrytwo's own 0.16693 mm would make it
/// 11981), and the PID holds each wheel at the set-point's 14.47 thesis RPM
/// of a 360-count wheel turn: 14.47 * 6 * 360 / 60 = 520.9 counts/s
/// (Henrytwo's 602.22 would make it 871.4).
#[test]
fn a_line_ends_at_the_counts_and_runs_at_the_speed_of_the_geometry_it_is_told() {
    let mut b = bench();
    for (p, v) in GEOMETRY {
        set(&mut b, p, v);
    }
    let v = *b.vars().expect("the robust build has the bench interface");
    b.write_f32(v.leg_length_mm, LEG_MM);
    let done = b.read_u16(v.done_count);
    let start = counts(&b);
    let r = exchange(&mut b, &frame(&Command::StartTest(ProtoTest::Line)));
    assert!(r.len() == 1 && r[0].ok, "START_TEST: {r:?}");

    // The speed, over 1.5 s of steady driving.
    b.run_for(1.0).unwrap();
    let (l0, r0) = counts(&b);
    b.run_for(1.5).unwrap();
    let (l1, r1) = counts(&b);
    let set_point = 14.47 * 6.0 * COUNTS_PER_WHEEL_REV as f64 / 60.0;
    for (name, c) in [("left", l1 - l0), ("right", r1 - r0)] {
        let rate = c as f64 / 1.5;
        assert!(
            (rate / set_point - 1.0).abs() < 0.02,
            "{name}: {rate:.1} counts/s, the set-point is {set_point:.1}"
        );
    }

    b.run_expect("the line test to end", 30.0, |b| {
        b.read_u16(v.done_count) != done
    })
    .unwrap();
    let (left, right) = (b.read_i32(v.stop_left), b.read_i32(v.stop_right));
    let sum = (left - start.0) as i64 + (right - start.1) as i64;
    let target = (2.0 * LEG_MM / MM_PER_COUNT).ceil() as i64;
    assert_eq!(target, 3528);
    // At most two edges past the rule, as on Henrytwo (tests/line.rs).
    assert!(
        (0..=2).contains(&(sum - target)),
        "stopped at {sum} counts together, the rule's target is {target}"
    );
}

/// What SET_PARAM accepted is in the EEPROM: after a reset of the MCU
/// GET_PARAM returns it (the leg length, the bench's RAM variable, is back
/// at its default), and a line still ends at that geometry's counts.
#[test]
fn the_geometry_is_kept_across_a_reset() {
    let mut b = bench();
    assert_eq!(get(&mut b, Param::MmPerCountLeft), 0.166_933_95);
    for (p, v) in GEOMETRY {
        set(&mut b, p, v);
    }
    set(&mut b, Param::LegLengthMm, 750.0);
    // One EEPROM byte per wake-up (a control tick at least every 15 ms):
    // three slots of five bytes and the magic byte.
    b.run_for(0.5).unwrap();
    b.reset_mcu();
    // The SRAM keeps HT_STATE = 1 until the start-up code clears it: boot
    // first (well under 0.1 s), then wait for idle.
    b.run_for(0.1).unwrap();
    wait_ready(&mut b, None).unwrap();
    for (p, v) in GEOMETRY {
        assert_eq!(get(&mut b, p), v, "{p:?} after the reset");
    }
    assert_eq!(get(&mut b, Param::LegLengthMm), 2000.0);
    assert_eq!(
        get(&mut b, Param::CorrLeft),
        1.0,
        "not set, so the factory value"
    );
}
