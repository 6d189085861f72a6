//! Firmware that knows nothing of the bench, run black-box from a test
//! description: the thesis' Annex A sketch and a sketch of our own, built
//! by tools/setup.sh with Debian's Arduino core, unmodified.

mod support;

use std::process::Command;
use std::sync::Arc;

use hil::bench::BenchOptions;
use hil::firmware::description::Description;
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{run_test, Test, TestName, TestOptions, TestRun};

const THESIS_TESTS: &str = "firmware/arduino/henrytwo-thesis/tests.toml";
const DEMO_TESTS: &str = "fixtures/arduino/square-demo/tests.toml";
const PULLUP_TESTS: &str = "fixtures/arduino/pullup-encoders/tests.toml";

/// A description of the repository, and the ELF it names (built by set-up).
fn described(file: &str) -> (Arc<Description>, Firmware) {
    let d = Description::load(hil::paths::workspace_root().join(file)).expect("description loads");
    let elf = d.elf.clone().expect("the description names its ELF");
    let fw = Firmware::load(&elf).unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"));
    (Arc::new(d), fw)
}

fn run_described(file: &str, test: impl Into<TestName>, seed: u64, record: bool) -> TestRun {
    let (d, fw) = described(file);
    let opts = TestOptions {
        leg_mm: d.leg_mm(None, 2000.0).unwrap(),
        bench: BenchOptions {
            seed,
            ..Default::default()
        },
        record,
        description: Some(d),
        ..Default::default()
    };
    run_test(fw, &support::robot("henrytwo"), test, &opts).expect("the bench runs the sketch")
}

/// A described sketch's run on a board of the fixtures (`board`, from the
/// workspace root), the robot given: as its owner's test would run it,
/// through the harness.
fn run_on_board(
    file: &str,
    board: &str,
    robot: &plant_model::RobotConfig,
    test: impl Into<TestName>,
) -> TestRun {
    let root = hil::paths::workspace_root();
    hil::clients::harness::Harness::builder()
        .tests(root.join(file))
        .board(root.join(board))
        .robot(robot.clone())
        .build()
        .unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"))
        .run_test(test.into(), None)
        .expect("the bench runs the sketch")
}

/// The Rust port of the same listing, on the same robot, legs of the
/// sketch's printed 400 mm.
fn run_port(test: Test, seed: u64, record: bool) -> TestRun {
    let opts = TestOptions {
        leg_mm: 400.0,
        bench: BenchOptions {
            seed,
            ..Default::default()
        },
        record,
        ..Default::default()
    };
    run_test(
        support::firmware("thesis"),
        &support::robot("henrytwo"),
        test,
        &opts,
    )
    .expect("the bench runs the port")
}

/// The thesis' turns are mirrored (its CW spins left, see docs/design/thesis-build.md).
fn thesis_turn_sign(test: Test) -> f64 {
    match test {
        Test::UmbmarkCw => 1.0,
        _ => -1.0,
    }
}

/// Each selector byte runs its test to the end, black-box: the test's legs
/// (each its printed 400 mm) and turns (each its angle, in the thesis'
/// mirrored direction), each leg in one piece although `analogWrite`
/// leaves stale levels between a bridge's two pins.
#[test]
fn the_thesis_sketch_completes_every_test_in_its_shape() {
    for test in Test::ALL {
        let r = run_described(THESIS_TESTS, test, 0, false);
        let name = test.name();
        assert!(r.completed, "{name}: {:?}", r.finding);
        let (legs, turns, angle) = test.shape();
        assert_eq!(r.legs.len(), legs, "{name}: legs {:?}", r.legs);
        assert_eq!(r.turns.len(), turns, "{name}: turns {:?}", r.turns);
        for l in &r.legs {
            assert!((l.plant_distance_mm - 400.0).abs() < 15.0, "{name}: {l:?}");
            assert!(l.firmware_count_left.is_some(), "{name}: counts mapped");
        }
        for t in &r.turns {
            let a = t.plant_angle_deg;
            assert_eq!(a.signum(), thesis_turn_sign(test), "{name}: {a} deg");
            assert!((a.abs() - angle.abs()).abs() < 10.0, "{name}: {a} deg");
        }
    }
}

fn drive_s(r: &TestRun) -> Vec<f64> {
    r.legs
        .iter()
        .map(|l| (l.cutoff_cycle - l.start_cycle) as f64 / 16e6)
        .collect()
}

fn turn_s(r: &TestRun) -> Vec<f64> {
    r.turns
        .iter()
        .map(|t| {
            let end = t.cutoff_left_cycle.max(t.cutoff_right_cycle).unwrap();
            (end - t.start_cycle) as f64 / 16e6
        })
        .collect()
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, var.sqrt())
}

/// The sketch against the Rust port of the same listing, both UMBmark
/// directions over three seeds: leg and turn durations, counts at each
/// leg's cut-off, each turn's angle, and the end points: the centroids
/// within 6 cm and each seed's ends within 8 cm of each other. With the
/// interrupt response executed the two builds drift a little further apart
/// (a turn 2.3° off the other's, CW seed 0's ends 6.2 cm apart, against 2°
/// and 6 cm before): turns within 3° (a wrong turn count is 5° or more),
/// which move the end of a 40 cm square by up to ~8 cm.
#[test]
fn the_thesis_sketch_drives_as_the_rust_port() {
    for test in [Test::UmbmarkCw, Test::UmbmarkCcw] {
        let name = test.name();
        let (mut sk_end, mut rs_end) = (Vec::new(), Vec::new());
        for seed in 0..3 {
            let sk = run_described(THESIS_TESTS, test, seed, false);
            let rs = run_port(test, seed, false);
            assert!(sk.completed && rs.completed, "{name} seed {seed}");
            for (a, b) in drive_s(&sk).iter().zip(drive_s(&rs)) {
                // 2 %: with the interrupt response executed a CCW leg of the
                // sketch ends 1.6 % (43 ms) before the port's (cause not
                // found; under 1 % before).
                assert!((a / b - 1.0).abs() < 0.02, "{name}: legs {a} s vs {b} s");
            }
            for (a, b) in turn_s(&sk).iter().zip(turn_s(&rs)) {
                assert!((a / b - 1.0).abs() < 0.05, "{name}: turns {a} s vs {b} s");
            }
            for (a, b) in sk.legs.iter().zip(&rs.legs) {
                for (x, y) in [
                    (a.firmware_count_left, b.firmware_count_left),
                    (a.firmware_count_right, b.firmware_count_right),
                ] {
                    // The leg ends at a PID period (15 ms, about 13 counts at
                    // 145 mm/s): within three of them.
                    let (x, y) = (x.unwrap(), y.unwrap());
                    assert!((x - y).abs() <= 40, "{name}: leg counts {x} vs {y}");
                }
            }
            // A turn's counts at its cut-offs are not compared: the listing
            // resets a counter right after cutting a motor, and the sketch's
            // analogWrite(pin, 0) cuts at once (digitalWrite LOW) while the
            // port's OCR = 0 takes effect at the next TOP, after the reset.
            // What the turns did is compared instead.
            for (a, b) in sk.turns.iter().zip(&rs.turns) {
                let (x, y) = (a.plant_angle_deg, b.plant_angle_deg);
                assert!((x - y).abs() < 3.0, "{name}: turns of {x} vs {y} deg");
            }
            assert!(
                (sk.x_cm - rs.x_cm).hypot(sk.y_cm - rs.y_cm) < 8.0,
                "{name} seed {seed}: ends ({}, {}) vs ({}, {}) cm",
                sk.x_cm,
                sk.y_cm,
                rs.x_cm,
                rs.y_cm
            );
            sk_end.push([sk.x_cm, sk.y_cm]);
            rs_end.push([rs.x_cm, rs.y_cm]);
        }
        // The centroids (UMBmark's statistic) over the seeds: within 6 cm
        // of each other on a 40 cm square, in each axis. A systematic
        // difference beyond the seeds' spread remains: the two
        // implementations steer their legs apart by about 1 degree each.
        // Before the interrupt response was executed it showed CCW (3.2 and
        // 3.2 cm; CW 0.6 and 0.2 cm); with it, CW's y is 5.1 cm apart (sd
        // about 1 cm). Its cause is not found yet (docs/results/blackbox.md says so).
        for axis in 0..2 {
            let (ms, ss) = mean_sd(&sk_end.iter().map(|e| e[axis]).collect::<Vec<_>>());
            let (mr, sr) = mean_sd(&rs_end.iter().map(|e| e[axis]).collect::<Vec<_>>());
            assert!(
                (ms - mr).abs() < 6.0,
                "{name} axis {axis}: centroid {ms:.2} (sd {ss:.2}) vs {mr:.2} (sd {sr:.2}) cm"
            );
        }
    }
}

/// The period of the sketch's PID, from outside: the left wheel's duty
/// changes once per control period (`Muestreo`, 15 ms, and the loop's
/// prints), as the port's do.
#[test]
fn the_thesis_sketch_controls_every_15_ms() {
    let period = |r: &TestRun| {
        let start = r.legs[0].start_cycle;
        let end = r.legs[0].cutoff_cycle;
        // A control step may change a duty in more than one write (OCR,
        // then the buffered value at TOP): changes within 1 ms are one step.
        let mut changes: Vec<u64> = Vec::new();
        for d in r
            .drive
            .iter()
            .filter(|d| d.pin == 9 && d.cycle > start + 16_000_000 && d.cycle < end)
        {
            if changes.last().is_none_or(|&c| d.cycle - c > 16_000) {
                changes.push(d.cycle);
            }
        }
        let mut gaps: Vec<u64> = changes.windows(2).map(|w| w[1] - w[0]).collect();
        gaps.sort_unstable();
        assert!(gaps.len() > 20, "{} duty changes", changes.len());
        gaps[gaps.len() / 2] as f64 / 16e3
    };
    let sk = period(&run_described(THESIS_TESTS, Test::Line, 0, true));
    let rs = period(&run_port(Test::Line, 0, true));
    // At least Muestreo apart (the PID runs once 15 ms have passed, so its
    // period is 15 ms plus part of the loop's printing: about 16.5 ms).
    for (who, ms) in [("sketch", sk), ("port", rs)] {
        assert!(
            (15.0..17.0).contains(&ms),
            "{who}: median control period {ms} ms"
        );
    }
    assert!(
        (sk - rs).abs() < 0.2,
        "median control period {sk} vs {rs} ms"
    );
}

/// A plain sketch of our own (millis, analogWrite, attachInterrupt,
/// Serial): its 4 legs of 3000 counts and 4 spins of 612 counts per wheel,
/// as it drives them, ended by its "done" line.
#[test]
fn a_generic_sketch_is_reported_as_it_drives() {
    let r = run_described(DEMO_TESTS, Test::UmbmarkCcw, 0, false);
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!(r.legs.len(), 4, "{:?}", r.legs);
    assert_eq!(r.turns.len(), 4, "{:?}", r.turns);
    for l in &r.legs {
        let mean = (l.firmware_count_left.unwrap() + l.firmware_count_right.unwrap()) / 2;
        assert!((3000..3010).contains(&mean), "leg counts {l:?}");
    }
    for t in &r.turns {
        assert!(t.count_left_at_cutoff.unwrap() <= -612, "{t:?}");
        assert!(t.count_right_at_cutoff.unwrap() >= 612, "{t:?}");
        assert!((t.plant_angle_deg - 90.0).abs() < 8.0, "{t:?}");
    }
}

/// The counts a sketch printed in its line starting `what`: "what L=<l> R=<r>".
/// The plant's A edges, left and right, in the last trace sample at or
/// before `cycle`.
fn plant_edges_at(r: &TestRun, cycle: u64) -> [i64; 2] {
    let t = cycle as f64 / 16e6;
    let s = r.trace.iter().rev().find(|s| s.t_s <= t).unwrap();
    [s.left_edges, s.right_edges]
}

fn printed_counts(r: &TestRun, what: &str) -> [i64; 2] {
    printed_counts_on(r, 0, what)
}

/// The counts a sketch printed on USART `usart` in its line starting with
/// `what`.
fn printed_counts_on(r: &TestRun, usart: u8, what: &str) -> [i64; 2] {
    let text: Vec<u8> = r
        .uart
        .iter()
        .filter(|(_, n, _)| *n == usart)
        .map(|(_, _, b)| *b)
        .collect();
    let text = String::from_utf8_lossy(&text);
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix(what)?.strip_prefix(" L="))
        .unwrap_or_else(|| panic!("no {what:?} line in {text:?}"));
    let (l, r) = line.trim_end().split_once(" R=").expect("L= and R=");
    [l.parse().unwrap(), r.parse().unwrap()]
}

/// Encoders on `INPUT_PULLUP`, on ports the sketch writes every control
/// period (A on PE4/PE5 beside the left enable on PE3; right B on PH4
/// beside the right enable on PH3): the pull-up leaves the levels the
/// encoders drive alone, as on silicon, so the counts the sketch prints
/// after a leg and after a spin are the plant's edges, exactly. (simavr
/// alone raises a pulled-up input to 1 at each write to its port: the
/// sketch then miscounts.)
#[test]
fn pulled_up_encoders_on_written_ports_count_every_edge() {
    let r = run_on_board(
        PULLUP_TESTS,
        "fixtures/boards/mega-l298n.toml",
        &support::robot("henrytwo"),
        Test::Line,
    );
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!(
        (r.legs.len(), r.turns.len()),
        (1, 1),
        "{:?} {:?}",
        r.legs,
        r.turns
    );
    // At rest after the leg (the spin's start) and at the end.
    let at = |cycle| plant_edges_at(&r, cycle);
    let (leg, done) = (printed_counts(&r, "leg"), printed_counts(&r, "spin"));
    assert!(
        leg[0] >= 3000 && done[0] <= leg[0] - 600,
        "{leg:?} {done:?}"
    );
    assert_eq!(leg, at(r.turns[0].start_cycle), "after the leg");
    assert_eq!(done, at(u64::MAX), "at the end");
}

/// A hang found without any firmware variable: both wheels blocked in the
/// first turn, the sketch waits for counts that never come (its own time-out
/// is 15 s); no wheel motion and no change of the drive for the hang time
/// is a hang, reported in the sketch's loop.
#[test]
fn a_black_box_hang_is_found_without_firmware_variables() {
    use hil::bench::{Action, ScheduledFault, Trigger};
    let (d, fw) = described(DEMO_TESTS);
    let stall = |side| {
        ScheduledFault::new(
            Trigger::TurnStart { n: 1 },
            Action::Motor {
                side,
                fault: plant_model::MotorFault::Stall,
            },
        )
    };
    let opts = TestOptions {
        leg_mm: 501.0,
        faults: vec![
            stall(plant_model::Side::Left),
            stall(plant_model::Side::Right),
        ],
        hang_after_s: Some(3.0),
        description: Some(d),
        ..Default::default()
    };
    let r = run_test(fw, &support::robot("henrytwo"), Test::UmbmarkCcw, &opts).unwrap();
    assert!(!r.completed);
    let hang = r.hang.as_ref().expect("the run is reported hung");
    assert!((3.0..3.1).contains(&hang.still_s), "{hang:?}");
    assert!(
        r.finding.as_deref().unwrap().starts_with("hung"),
        "{:?}",
        r.finding
    );
    assert_eq!(r.legs.len(), 1);
    // Found 3 s after the turn began, well before the sketch's 15 s time-out.
    assert!(r.robot_time_s < 30.0, "{}", r.robot_time_s);
}

/// Without its interface or a description the bench says what to give; a
/// fixed leg refuses another length; a bad description is one line; all
/// before anything runs, with exit code 2 or 1 as docs/reference/exit-codes.md says.
#[test]
fn the_cli_says_what_a_black_box_run_needs() {
    let root = hil::paths::workspace_root();
    let (_, fw) = described(THESIS_TESTS);
    let hil = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_hil"))
            .current_dir(&root)
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let elf = fw.path.display().to_string();
    let (code, err) = hil(&["run", "line", "--elf", &elf]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("no symbol \"HT_") && err.contains("--tests FILE"),
        "{err}"
    );
    let (code, err) = hil(&["run", "line", "--tests", THESIS_TESTS, "--leg-mm", "300"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("legs are 400 mm"), "{err}");
    let (code, err) = hil(&["calibrate", "--rounds", "1", "--tests", THESIS_TESTS]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("calibration rounds send each round's correction"),
        "{err}"
    );
    let bad = std::env::temp_dir().join(format!("hil-bad-tests-{}.toml", std::process::id()));
    let text = std::fs::read_to_string(root.join(THESIS_TESTS))
        .unwrap()
        .replace("uart = 1\nbytes = [4]", "uart = 9\nbytes = [4]");
    std::fs::write(&bad, text).unwrap();
    let (code, err) = hil(&["run", "line", "--tests", bad.to_str().unwrap()]);
    let _ = std::fs::remove_file(&bad);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("tests.line.uart = 9: give a USART, 0-3, or \"usb\""),
        "{err}"
    );
}

#[path = "blackbox/commands.rs"]
mod commands;
#[path = "blackbox/example_robots.rs"]
mod example_robots;
#[path = "blackbox/own_tests.rs"]
mod own_tests;
#[path = "blackbox/usb_serial.rs"]
mod usb_serial;
