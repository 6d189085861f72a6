//! The harness of a user's own tests (`hil::clients::harness`) on firmware
//! it knows nothing of and on the bench's own builds: built from values as
//! well as files, a described sketch booted and started through its
//! description alone, typed reads and ids, and asserts that say what they
//! saw. (examples/firmware-test is a crate of tests written with it.)

#[path = "support/mod.rs"]
mod support;

use hil::board::Board;
use hil::clients::harness::{
    CommandId, Condition, FrameId, Harness, HarnessError, Param, Test, TestName,
};

const UNO_TESTS: &str = "fixtures/arduino/uno-l298n/tests.toml";
const UNO_BOARD: &str = "fixtures/boards/uno-l298n.toml";

/// The Uno sketch's harness: its description and board as files, its
/// robot as a value.
fn uno() -> Harness {
    let root = hil::paths::workspace_root();
    Harness::builder()
        .tests(root.join(UNO_TESTS))
        .board(root.join(UNO_BOARD))
        .robot(support::robot("uno-l298n"))
        .build()
        .unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"))
}

/// The robust build on the ideal Henrytwo, booted.
fn robust() -> Harness {
    let mut h = Harness::builder()
        .firmware(support::firmware("robust"))
        .robot(support::robot("henrytwo-ideal"))
        .build()
        .unwrap();
    h.boot().unwrap();
    h
}

/// The panic message of `f`.
fn panic_message(f: impl FnOnce()) -> String {
    let e = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).expect_err("it panics");
    e.downcast_ref::<String>()
        .cloned()
        .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default()
}

thread_local! {
    /// Where this thread's last panic was raised.
    static PANICKED_AT: std::cell::RefCell<Option<(String, u32)>> = const { std::cell::RefCell::new(None) };
}

/// Where `f` panics: file and line, as the panic reports them (a hook
/// records them for the thread that panicked, then hands the panic on to
/// the hook before it, so other tests' panics are as they were).
fn panic_at<R>(f: impl FnOnce() -> R) -> (String, u32) {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let before = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if let Some(l) = info.location() {
                PANICKED_AT.with(|p| *p.borrow_mut() = Some((l.file().to_string(), l.line())));
            }
            before(info);
        }));
    });
    PANICKED_AT.with(|p| *p.borrow_mut() = None);
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    assert!(r.is_err(), "it panics");
    PANICKED_AT
        .with(|p| p.borrow_mut().take())
        .expect("the panic hook saw where")
}

/// Each assert's panic names the test's own line (`#[track_caller]`), not
/// the harness' source: a failing test points at itself.
#[test]
fn asserts_panic_at_the_callers_line() {
    let mut h = robust();
    let done = Condition::frame(FrameId::TestDone);
    let forward = Condition::driving_forward(0.05);
    let at = panic_at(|| h.assert_var("HT_STATE", 2u8));
    assert_eq!(at, (file!().to_string(), line!() - 1));
    let at = panic_at(|| h.assert_holds(&forward));
    assert_eq!(at, (file!().to_string(), line!() - 1));
    let at = panic_at(|| h.assert_distance(300.0, 3.0));
    assert_eq!(at, (file!().to_string(), line!() - 1));
    let at = panic_at(|| h.assert_within(&done, 0.1));
    assert_eq!(at, (file!().to_string(), line!() - 1));
}

/// An Arduino sketch with no bench variables starts through its
/// description: ready on its text, `leg-and-spin` started by its byte on
/// Serial, ended by its text; its 1 m leg and quarter spin are on the
/// plant, and its own counters, read as the `long`s they are, hold what
/// it printed.
#[test]
fn a_described_sketch_starts_and_ends_through_its_description() {
    let mut h = uno();
    assert!(
        hil::firmware::elf::Firmware::load(
            &hil::paths::workspace_root().join("firmware/target/arduino/uno-l298n.elf")
        )
        .unwrap()
        .symbol("HT_LEG_LENGTH_MM")
        .is_err(),
        "the sketch has no bench interface"
    );
    h.start("leg-and-spin", None).unwrap();
    let t = h.run_until_done(60.0).unwrap();
    assert!(h.text(0).contains("uno-l298n ready"), "{}", h.text(0));
    assert!(h.text(0).ends_with("done\r\n") || h.text(0).contains("done"));
    let pose = h.pose();
    let d = pose.distance_from_origin().get();
    assert!((d - 1000.0).abs() <= 50.0, "{pose} after {t} s");
    let heading = pose.theta().to_degrees();
    assert!((heading - 90.0).abs() <= 15.0, "{pose}");
    let [l, r] = [
        h.var::<i32>("leftCount").unwrap(),
        h.var::<i32>("rightCount").unwrap(),
    ];
    // The spin to the left ran the left wheel back, the right on.
    assert!(l < 2821 && r > 2821, "{l} {r}");
    // The sketch printed the same counts at the end.
    let text = h.text(0);
    let line = text
        .lines()
        .find(|l| l.starts_with("spin"))
        .expect("its spin line");
    assert_eq!(line.trim(), format!("spin L={l} R={r}"), "{text}");
    h.assert_var("leftCount", l);
}

/// `run_test` runs a described test whole, as `hil run` does, and its
/// report has the shape the description gives; on a harness that has
/// already run, it is refused in one line.
#[test]
fn run_test_reports_a_described_run_and_needs_a_fresh_harness() {
    let mut h = uno();
    let r = h
        .run_test(TestName::parse("leg-and-spin").unwrap(), None)
        .unwrap();
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!((r.legs.len(), r.turns.len()), (1, 1));
    let e = h.run_test("leg-and-spin", None).unwrap_err().to_string();
    assert!(
        e.contains("runs from reset, on a harness fresh from build()"),
        "{e}"
    );
}

/// Inputs given as values are the ones the bench runs: an edited robot, a
/// board built from text, a description parsed from text with a leg of its
/// own.
#[test]
fn the_builder_takes_values_as_well_as_files() {
    let root = hil::paths::workspace_root();
    let mut robot = support::robot("uno-l298n");
    robot.geometry.wheelbase_mm += 1.0;
    let text = std::fs::read_to_string(root.join(UNO_BOARD)).unwrap();
    let board = Board::from_toml_str(&text, "in the test").unwrap();
    let tests = hil::firmware::description::Description::from_toml_str(
        &std::fs::read_to_string(root.join(UNO_TESTS))
            .unwrap()
            .replace("mm = 1000", "mm = 700"),
        "in the test",
    )
    .unwrap();
    let h = Harness::builder()
        .firmware(root.join("firmware/target/arduino/uno-l298n.elf"))
        .robot(robot.clone())
        .board(board)
        .tests(tests)
        .build()
        .unwrap();
    assert_eq!(h.robot(), &robot);
    assert_eq!(h.bench().board(), &board);
    let d = h.description().expect("the description given");
    assert_eq!(d.path, "in the test");
    // Its fixed leg is the one a start must agree with.
    let mut h = h;
    let e = h.start("leg-and-spin", 1000.0).unwrap_err().to_string();
    assert!(e.contains("the firmware's legs are 700 mm"), "{e}");
}

/// What the harness refuses before anything runs, each in one line that
/// says what to give instead.
#[test]
fn starts_it_cannot_make_are_refused_in_one_line() {
    let root = hil::paths::workspace_root();
    let refused = |e: HarnessError, words: &str| {
        let line = e.to_string();
        assert!(line.contains(words), "{line}");
        assert!(!line.contains('\n'), "{line}");
    };
    // A sketch with no description: no HT_ interface to start it by.
    let mut bare = Harness::builder()
        .firmware(root.join("firmware/target/arduino/uno-l298n.elf"))
        .board(root.join(UNO_BOARD))
        .robot(support::robot("uno-l298n"))
        .build()
        .unwrap();
    refused(
        bare.start(Test::Line, 300.0).unwrap_err(),
        "has no bench interface (no HT_STATE): give its test description with .tests(path)",
    );
    refused(bare.run_until_done(1.0).unwrap_err(), "no test was started");
    let mut h = uno();
    refused(
        h.start("no-such-test", None).unwrap_err(),
        "describes no no-such-test test",
    );
    refused(h.start("Bad Name", None).unwrap_err(), "Bad Name");
    let mut own = Harness::builder()
        .firmware(support::firmware("robust"))
        .build()
        .unwrap();
    refused(
        own.start("leg-and-spin", None).unwrap_err(),
        "a test of the firmware's own needs its description",
    );
    assert_eq!((h.robot_time_s(), own.robot_time_s()), (0.0, 0.0));
}

/// Frame ids by name: a PING's reply is the reply to Ping, whether waited
/// for by the command's id, by the frame id or by its byte; a parameter
/// read and set by name, an out-of-range one refused with the reply.
#[test]
fn protocol_ids_and_parameters_by_name() {
    let mut h = robust();
    let reply = h
        .request(&hil::clients::harness::Command::Ping, 0.05)
        .unwrap();
    assert_eq!(reply.frame_id(), FrameId::Reply(CommandId::Ping));
    assert_eq!(reply.frame_id().to_string(), "reply to Ping (0x81)");
    h.command(&hil::clients::harness::Command::Ping);
    h.assert_within(&Condition::reply_to(CommandId::Ping), 0.05);
    h.assert_holds(&Condition::frame(0x81));
    assert_eq!(h.set_param(Param::WheelbaseMm, 125.5).unwrap(), 125.5);
    assert_eq!(h.param(Param::WheelbaseMm).unwrap(), 125.5);
    let e = h
        .set_param(Param::WheelbaseMm, 5.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("SET_PARAM WheelbaseMm = 5: the firmware replied"),
        "{e}"
    );
    assert!(e.contains("OutOfRange"), "{e}");
    assert_eq!(h.param(Param::WheelbaseMm).unwrap(), 125.5);
}

/// The asserts say what they expected and what they saw: a variable's
/// value, the motors' states, a wait that ran out.
#[test]
fn asserts_name_what_was_seen() {
    let mut h = robust();
    let m = panic_message(|| h.assert_var("HT_STATE", 2u8));
    assert!(m.contains("HT_STATE = 2; seen: HT_STATE = 1"), "{m}");
    let m = panic_message(|| h.assert_holds(&Condition::driving_forward(0.05)));
    assert!(m.contains("both motor(s) forward"), "{m}");
    assert!(
        m.contains("seen: left coast duty 0.000, right coast duty 0.000"),
        "{m}"
    );
    let m = panic_message(|| h.assert_distance(300.0, 3.0));
    assert!(m.contains("seen: 0.0 mm"), "{m}");
    let m = panic_message(|| {
        h.assert_within(&Condition::frame(FrameId::TestDone), 0.1);
    });
    assert!(
        m.contains("a frame TEST_DONE (0xc0) did not hold within 0.1 s"),
        "{m}"
    );
    h.assert_var("HT_STATE", 1u8);
    h.assert_holds(&Condition::motors_off());
}
