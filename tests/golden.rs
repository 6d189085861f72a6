//! `hil golden record` then `hil golden check`, through the binary on the
//! robust build over a 300 mm line: the same run checks (exit 0); wheels
//! larger than the firmware knows, a changed firmware parameter and another
//! ELF are reported with what moved (exit 1); a corrupted golden file and a
//! golden run of one test checked as another are refused on one line
//! (exit 2). A described firmware's own test (square-demo's half-square) is
//! recorded and checked by its name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn hil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("hil runs")
}

fn text(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A folder of this test process's files.
fn dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("hil-golden-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    })
}

/// Record a golden run of a 300 mm line into `name` (with `extra` options).
fn record(name: &str, extra: &[&str]) -> String {
    let path = dir().join(name).display().to_string();
    let mut args = vec![
        "golden", "record", "line", "--leg-mm", "300", "--out", &path,
    ];
    args.extend_from_slice(extra);
    let out = hil(&args);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("quantities written to"), "{stdout}");
    path
}

/// The golden run of the line as the bench runs it by default.
fn line() -> &'static str {
    static G: OnceLock<String> = OnceLock::new();
    G.get_or_init(|| record("line.json", &[]))
}

/// The result column of quantity `name` in a check's table.
fn result_of<'a>(table: &'a str, name: &str) -> &'a str {
    let row = table
        .lines()
        .find(|l| l.trim_start().starts_with(name))
        .unwrap_or_else(|| panic!("no row {name:?} in\n{table}"));
    row.split_whitespace().last().unwrap()
}

/// A check of `golden` with `extra` that moved `quantities` (and exits 1
/// naming them on stderr); returns the table.
fn check_moved(golden: &str, extra: &[&str], quantities: &[&str]) -> String {
    let mut args = vec!["golden", "check", golden];
    args.extend_from_slice(extra);
    let out = hil(&args);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    for q in quantities {
        assert_eq!(result_of(&stdout, q), "MOVED", "{q} in\n{stdout}");
        assert!(stderr.contains(q), "{q} named in {stderr:?}");
    }
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    stdout
}

/// A refused check: exit 2, one error line naming the golden file, nothing run.
fn check_refused(golden: &str, extra: &[&str], says: &str) {
    let mut args = vec!["golden", "check", golden];
    args.extend_from_slice(extra);
    let out = hil(&args);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with(&format!("error: {golden}: ")),
        "{stderr}"
    );
    assert!(stderr.contains(says), "{stderr:?} should say {says:?}");
    assert!(stdout.is_empty(), "nothing ran: {stdout}");
}

#[test]
fn the_same_run_checks_within_every_tolerance() {
    let golden = line();
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(golden).unwrap()).unwrap();
    let with = &file["recorded_with"];
    assert_eq!(with["firmware"], "robust");
    assert_eq!(with["robot"], "fixtures/robots/henrytwo.toml", "{with}");
    assert_eq!(with["seed"], 0);
    assert_eq!(with["elf_hash"].as_str().unwrap().len(), 16, "{with}");
    let names: Vec<&str> = file["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["name"].as_str().unwrap())
        .collect();
    for q in [
        "leg 1 end x (mm)",
        "leg 1 heading change (deg)",
        "leg 1 duty left (mean)",
        "control function, mean (cycles)",
    ] {
        assert!(names.contains(&q), "{q} recorded: {names:?}");
    }

    let out = hil(&["golden", "check", golden]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("in force: as recorded"), "{stdout}");
    assert!(
        stdout.contains(&format!("all {} quantities within tolerance", names.len())),
        "{stdout}"
    );
    // The bench is deterministic: the same run is the same to the last digit.
    assert_eq!(result_of(&stdout, "leg 1 end x (mm)"), "ok");
    assert!(stdout.contains("+0.000"), "{stdout}");
}

/// Wheels of 33 mm where the firmware keeps its factory 32 mm: every leg
/// is 3 % long, 9 mm of 300, beyond the 5 mm tolerance; the robot file is
/// named as what differs.
#[test]
fn wheels_larger_than_the_firmware_knows_move_the_legs_end() {
    let golden = record("keep.json", &["--keep-firmware-params"]);
    let robot = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/robots/henrytwo.toml"),
    )
    .unwrap();
    let bigger = robot
        .replace(
            "wheel_diameter_left_mm = 32.0",
            "wheel_diameter_left_mm = 33.0",
        )
        .replace(
            "wheel_diameter_right_mm = 32.0",
            "wheel_diameter_right_mm = 33.0",
        );
    assert_ne!(bigger, robot, "the fixture names its wheel diameters");
    let path = dir().join("bigger-wheels.toml");
    std::fs::write(&path, bigger).unwrap();
    let table = check_moved(
        &golden,
        &["--robot", path.to_str().unwrap()],
        &["leg 1 end x (mm)", "end x (mm)"],
    );
    assert_eq!(result_of(&table, "leg 1 end y (mm)"), "ok", "{table}");
    assert!(table.contains("robot hash: golden "), "{table}");
}

/// The left wheel's set-point raised: it runs faster (a higher duty) and
/// the line bends right.
#[test]
fn a_changed_firmware_parameter_moves_the_duty_and_the_heading() {
    let table = check_moved(
        line(),
        &["--param", "setpoint_left=18"],
        &[
            "leg 1 duty left (mean)",
            "leg 1 heading change (deg)",
            "leg 1 end y (mm)",
        ],
    );
    assert!(
        table.contains("params: golden none, now setpoint_left=18"),
        "{table}"
    );
}

/// Another ELF is what a check is for: compared, its hash reported.
#[test]
fn another_elf_is_compared_and_reported() {
    let table = check_moved(
        line(),
        &["--firmware", "thesis"],
        &["leg 1 heading change (deg)"],
    );
    assert!(
        table.contains("(a different ELF: what is compared)"),
        "{table}"
    );
}

#[test]
fn a_corrupted_golden_file_is_refused_on_one_line() {
    let good = std::fs::read_to_string(line()).unwrap();
    let cases = [
        (
            "truncated.json",
            good[..good.len() / 2].to_string(),
            "not a golden file",
        ),
        (
            "text-value.json",
            good.replacen("\"value\": ", "\"value\": \"x\", \"was\": ", 1),
            "not a golden file",
        ),
        (
            "format.json",
            good.replace("hil-golden/1", "hil-golden/9"),
            "golden file format \"hil-golden/9\"",
        ),
        (
            "tolerance.json",
            good.replace("\"leg_mm\": 5.0", "\"leg_mm\": -5.0"),
            "tolerances.leg_mm = -5",
        ),
    ];
    for (name, text, says) in cases {
        assert_ne!(text, good, "{name} is corrupted");
        let path = dir().join(name);
        std::fs::write(&path, text).unwrap();
        check_refused(path.to_str().unwrap(), &[], says);
    }
    let missing = dir().join("missing.json");
    check_refused(
        missing.to_str().unwrap(),
        &[],
        "cannot read the golden file",
    );
}

#[test]
fn a_golden_run_of_one_test_checked_as_another_is_refused() {
    check_refused(
        line(),
        &["--test", "umbmark-cw"],
        "the golden run is of line with legs of 300 mm; a run of umbmark-cw",
    );
    check_refused(line(), &["--leg-mm", "600"], "with legs of 600 mm");
}

/// A described firmware's own test, by its name (square-demo's half-square,
/// `--tests`): its golden run records the legs and turns and the description
/// it ran by; the same run checks within every tolerance (exit 0); on another
/// robot the legs' ends move (exit 1), the description is still the golden's.
#[test]
fn a_described_firmwares_own_test_is_recorded_and_checked_by_name() {
    const DEMO: &str = "fixtures/arduino/square-demo/tests.toml";
    let golden = dir().join("half-square.json").display().to_string();
    let out = hil(&[
        "golden",
        "record",
        "half-square",
        "--tests",
        DEMO,
        "--out",
        &golden,
    ]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&golden).unwrap()).unwrap();
    assert_eq!(file["test"], "half-square");
    // The sketch's own leg, as hil run takes it.
    assert_eq!(file["leg_mm"], 501.0);
    let with = &file["recorded_with"];
    assert_eq!(with["tests"], DEMO, "{with}");
    assert_eq!(with["firmware"], "square-demo", "{with}");
    let names: Vec<&str> = file["quantities"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["name"].as_str().unwrap())
        .collect();
    for q in [
        "leg 2 end x (mm)",
        "leg 2 duty right (mean)",
        "turn 2 angle (deg)",
    ] {
        assert!(names.contains(&q), "{q} not in {names:?}");
    }
    assert!(
        !names
            .iter()
            .any(|n| n.starts_with("leg 3") || n.starts_with("turn 3")),
        "{names:?}"
    );

    // Checked as recorded (the description read from the golden file).
    let out = hil(&["golden", "check", &golden]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert!(!stdout.contains("MOVED"), "{stdout}");

    let table = check_moved(
        &golden,
        &["--robot", "fixtures/robots/henrytwo-ideal.toml"],
        &["leg 1 end x (mm)", "turn 1 angle (deg)"],
    );
    assert!(
        !table.contains("tests"),
        "the description is the golden's:\n{table}"
    );
}
