//! The robust build's framed protocol on the emulated robot, byte for byte
//! over the Bluetooth UART: every command, parameter round trips, and the
//! documented error reply for each kind of bad input, none of which changes
//! the robot's state. And the battery LEDs of both builds following A0.

#[path = "support/mod.rs"]
mod support;

use hil::bench::{Action, Trigger};
use hil::clients::harness::{Harness, Param};
use hil::firmware::link::{frame, replies, Command, ProtoTest, Received};

/// The build `build` on the ideal Henrytwo, booted, as a user's test holds it.
fn bench(build: &str) -> Harness {
    let mut h = Harness::builder()
        .firmware(support::firmware(build))
        .robot(support::robot("henrytwo-ideal"))
        .build()
        .unwrap();
    h.boot().unwrap();
    h
}

/// Send `bytes`, let them arrive and be answered, return the new replies.
fn exchange(b: &mut Harness, bytes: &[u8]) -> Vec<Received> {
    let before = b.output().len();
    b.send(bytes);
    // ~1 ms per byte at 9600 baud, the reply as long again, and margin.
    b.run_for(0.1 + bytes.len() as f64 * 0.003).unwrap();
    replies(&b.output()[before..])
}

/// The state the robot must keep through bad input: parameters, tests done,
/// and where it stands.
fn state(b: &mut Harness) -> (f32, f32, u16, f64, f64) {
    let done = b.var::<u16>("HT_DONE_COUNT").unwrap();
    let pose = b.pose();
    (
        b.param(Param::WheelbaseMm).unwrap(),
        b.param(Param::CorrLeft).unwrap(),
        done,
        pose.x().get(),
        pose.y().get(),
    )
}

#[test]
fn every_command_and_parameter_round_trips() {
    let mut b = bench("robust");
    let r = exchange(&mut b, &frame(&Command::Ping));
    assert!(r.len() == 1 && r[0].ok && r[0].id == 0x81, "{r:?}");
    for (p, v) in [
        (Param::CorrLeft, 1.01f32),
        (Param::CorrRight, 0.99),
        (Param::WheelbaseMm, 125.5),
        (Param::LegLengthMm, 750.0),
        (Param::SetpointLeft, 14.0),
        (Param::KpRight, 2.5),
    ] {
        let r = exchange(&mut b, &frame(&Command::SetParam(p, v)));
        assert!(r.len() == 1 && r[0].ok, "{p:?}: {r:?}");
        assert_eq!(b.param(p).unwrap(), v, "{p:?}");
    }
    for cmd in [Command::GetState, Command::GetTelemetry] {
        let r = exchange(&mut b, &frame(&cmd));
        assert!(
            r.len() == 1 && r[0].ok && !r[0].data.is_empty(),
            "{cmd:?}: {r:?}"
        );
    }
    // A framed start runs the test with the parameters set: a 750 mm line.
    let r = exchange(&mut b, &frame(&Command::StartTest(ProtoTest::Line)));
    assert!(r[0].ok, "{r:?}");
    b.assert_within(
        &hil::clients::harness::Condition::var_eq("HT_DONE_COUNT", 1u16),
        30.0,
    );
    let x = b.pose().x().get();
    assert!((x - 750.0).abs() < 60.0, "drove to x = {x} mm");
}

#[test]
fn bad_input_gets_its_error_reply_and_changes_nothing() {
    let mut b = bench("robust");
    let before = state(&mut b);
    let status = |r: &[Received]| r.iter().map(|r| r.status.clone()).collect::<Vec<_>>();

    let mut bad_crc = frame(&Command::SetParam(Param::WheelbaseMm, 99.0));
    *bad_crc.last_mut().unwrap() ^= 0x5A;
    assert_eq!(status(&exchange(&mut b, &bad_crc)), ["BadCrc"]);

    let out_of_range = frame(&Command::SetParam(Param::WheelbaseMm, 5.0));
    assert_eq!(status(&exchange(&mut b, &out_of_range)), ["OutOfRange"]);

    // An unknown command id in a well-formed frame.
    let mut unknown = vec![0xA5, 1, 0x3E];
    unknown.push(henrytwo_protocol::crc::crc8(&[1, 0x3E]));
    assert_eq!(status(&exchange(&mut b, &unknown)), ["UnknownCommand"]);

    // A frame that stops half way: the inter-byte timeout ends it.
    let whole = frame(&Command::SetParam(Param::CorrLeft, 1.2));
    assert_eq!(status(&exchange(&mut b, &whole[..4])), ["Truncated"]);

    // Random bytes (seeded): whatever they are, no state changes.
    let mut x: u64 = 0x1234_5678;
    let noise: Vec<u8> = (0..300)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect();
    let _ = exchange(&mut b, &noise);
    b.run_for(0.5).unwrap();
    assert_eq!(state(&mut b), before, "bad input changed the robot's state");
}

/// Battery LEDs (D10 green, D11 blue, D12 red on port B bits 4, 5, 6) follow
/// A0 across both thresholds (ADC 942 and 901), in both builds.
#[test]
fn battery_leds_follow_a0() {
    for build in ["robust", "thesis"] {
        let mut b = bench(build);
        // battery volts -> expected LED bit (A0 = 0.55 x battery).
        for (i, (volts, bit)) in [(8.6, 5u8), (8.2, 4), (7.6, 6)].into_iter().enumerate() {
            let at = b.robot_time_s() + 0.01;
            b.schedule(hil::bench::ScheduledFault {
                trigger: Trigger::Time { s: at },
                action: Action::BatteryVolts { volts: Some(volts) },
                undo: None,
            });
            b.run_for(0.3).unwrap();
            let portb = b.bench().read_u8(0x25);
            let leds = (portb >> 4) & 0b111;
            assert_eq!(
                leds,
                1 << (bit - 4),
                "{build}, step {i}: {volts} V gave PORTB {portb:#010b}"
            );
        }
    }
}

/// Seeded invalid frames at the link's real pace: the firmware answers each
/// kind with an error or nothing, never resets or hangs, and its state is the
/// same afterwards (`hil fuzz` runs 100 000 of them).
#[test]
fn fuzzed_invalid_frames_change_nothing() {
    let report = hil::runs::fuzz::fuzz(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        4000,
        7,
        &|_| {},
    )
    .unwrap();
    assert!(
        report.by_mutation.iter().all(|(_, n)| *n > 500),
        "{report:?}"
    );
    assert!(report.error_replies > 2000, "{report:?}");
    assert!(report.passed(), "{report:?}");
}
