//! The robust firmware on the bench, as a user's regression tests would hold
//! it: it answers a PING, drives a 300 mm line to within 1 %, and stops both
//! motors within 250 ms of losing an encoder. The last test runs the thesis
//! build, which has no encoder watchdog, to show the dropout test catches it.

use hil::clients::harness::{
    Action, Command, CommandId, Condition, EncoderFault, FrameId, Harness, HarnessError,
    Millimetres, Side, Test, VERSION,
};

/// The bench with one of this repository's firmware builds on Henrytwo,
/// its board and robot config given as a user would give their own.
fn bench(build: &str) -> Harness {
    let root = hil::paths::workspace_root();
    Harness::builder()
        .robot(root.join("fixtures/robots/henrytwo.toml"))
        .board(root.join("fixtures/boards/henrytwo.toml"))
        .firmware(hil::paths::firmware_elf(build))
        .seed(0)
        .build()
        .unwrap()
}

/// A PING over the Bluetooth UART gets its reply, carrying the protocol's
/// version, within 50 ms of robot time.
#[test]
fn a_ping_gets_its_reply() -> Result<(), HarnessError> {
    let mut h = bench("robust");
    h.boot()?;
    let sent_at = h.robot_time_s();
    let reply = h.request(&Command::Ping, 0.05)?;
    assert_eq!(
        reply.frame_id(),
        FrameId::Reply(CommandId::Ping),
        "{reply:?}"
    );
    assert!(reply.ok, "{reply:?}");
    assert_eq!(reply.data, [VERSION]);
    assert!(h.robot_time_s() - sent_at < 0.05);
    Ok(())
}

/// A 300 mm line: TEST_DONE arrives, and the robot stands within 1 % of
/// 300 mm from where it started, ahead of it.
#[test]
fn a_300_mm_line_ends_within_1_percent() -> Result<(), HarnessError> {
    let mut h = bench("robust");
    h.start(Test::Line, 300.0)?;
    h.assert_within(&Condition::frame(FrameId::TestDone), 10.0);
    h.assert_distance(300.0, 3.0);
    // Ahead, not beside: the line's drift is a few millimetres.
    let pose = h.pose();
    assert!(pose.x() > Millimetres(290.0), "{pose}");
    // The same check as a scenario file's pose expectation.
    h.run_until(&Condition::distance_within_pct(300.0, 1.0), 0.01)?;
    Ok(())
}

/// The left encoder's cable comes off mid-line: both motors off within
/// 250 ms of robot time, and the firmware's fault code set.
#[test]
fn an_encoder_dropout_stops_the_motors_within_250_ms() -> Result<(), HarnessError> {
    let mut h = bench("robust");
    let stopped = dropout_mid_line(&mut h)?;
    stopped?;
    let code = h.var::<u8>("HT_FAULT")?;
    assert_ne!(code, 0, "the firmware's fault code after the dropout");
    assert_eq!(h.motor_duty(), [0.0, 0.0]);
    Ok(())
}

/// The thesis build has no encoder watchdog: the same dropout leaves its
/// motors driven past 250 ms, and the check above says so.
#[test]
fn the_dropout_check_fails_on_a_build_without_the_watchdog() -> Result<(), HarnessError> {
    let mut h = bench("thesis");
    match dropout_mid_line(&mut h)? {
        Err(HarnessError::Timeout { what, seen, .. }) => {
            assert!(what.contains("off"), "{what}");
            assert!(seen.contains("forward"), "{seen}");
        }
        other => panic!("the thesis build stopped its motors: {other:?}"),
    }
    Ok(())
}

/// A 600 mm line, driven for half a second, then the left encoder's lines
/// frozen: what waiting 250 ms for both motors off gave (the outer error:
/// the run itself went wrong).
fn dropout_mid_line(h: &mut Harness) -> Result<Result<f64, HarnessError>, HarnessError> {
    h.start(Test::Line, 600.0)?;
    h.run_until(&Condition::driving_forward(0.05), 3.0)?;
    h.run_for(0.5)?;
    h.inject(Action::Encoder {
        side: Side::Left,
        fault: EncoderFault::Dropout,
    });
    Ok(h.run_until(&Condition::motors_off(), 0.25))
}

/// What the harness refuses, before anything runs, each with one line
/// naming the value and the range allowed.
#[test]
fn bad_input_is_refused_with_its_range() {
    let refused = |e: HarnessError, words: &str| {
        let line = e.to_string();
        assert!(line.contains(words), "{line}");
        assert!(!line.contains('\n'), "{line}");
    };
    refused(
        Harness::builder().build().err().unwrap(),
        "give its ELF with .firmware(path)",
    );
    let mut h = bench("robust");
    refused(
        h.run_for(0.0).unwrap_err(),
        "give more than 0 and at most 86400 s",
    );
    refused(
        h.run_until(&Condition::motors_off(), f64::NAN).unwrap_err(),
        "run_until within_s = NaN s",
    );
    refused(
        h.start(Test::Line, 5.0).unwrap_err(),
        "leg_mm = 5: the firmware's legs are 10 to 5000 mm",
    );
    refused(
        h.run_until(
            &Condition::pin("D99", hil::clients::harness::Level::High),
            1.0,
        )
        .unwrap_err(),
        "give an Arduino Mega pin, D0-D69 or A0-A15",
    );
    refused(
        h.run_until(&Condition::var_eq("NO_SUCH_SYMBOL", 1u8), 1.0)
            .unwrap_err(),
        "NO_SUCH_SYMBOL",
    );
    assert_eq!(h.robot_time_s(), 0.0, "nothing ran");
}
