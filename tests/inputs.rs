//! Inputs are checked before anything runs, and options are never silently
//! ignored (issue 21): a robot config, scenario, ELF or CSV outside what is
//! physical or possible is refused with one line naming the file, the field
//! and the allowed range, exit code 2; an option a command does not honour is
//! refused, not dropped. Each test here fails when its check is taken out.

#[path = "support/mod.rs"]
mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// `hil ARGS`, killed after `limit` (a check that is missing may hang:
/// that is a failure, not a stuck test run).
fn hil_within(args: &[&str], limit: Duration) -> Output {
    let _ = support::firmware_path("robust");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("hil starts");
    let start = Instant::now();
    while child.try_wait().expect("hil runs").is_none() {
        if start.elapsed() > limit {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("hil {args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn hil(args: &[&str]) -> Output {
    hil_within(args, Duration::from_secs(120))
}

fn fixture(relative: &str) -> String {
    hil::paths::workspace_root()
        .join("fixtures")
        .join(relative)
        .display()
        .to_string()
}

fn ideal() -> String {
    fixture("robots/henrytwo-ideal.toml")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Refused before anything ran: exit code 2 and one line holding `needle`.
#[track_caller]
fn assert_refused(out: &Output, needle: &str) {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(out.status.code(), Some(2), "exit code; stderr: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(err.contains(needle), "{needle:?} not in: {err}");
}

/// A fresh temporary folder for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hil-inputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---- 1. robot configs -------------------------------------------------------

/// A motor time constant of a picosecond is refused when the robot config is
/// loaded, naming the file, the key and the range; exit code 2.
#[test]
fn an_unphysical_robot_config_is_refused_at_load() {
    let file = fixture("bad/robot-tau-picosecond.toml");
    let out = hil(&["run", "line", "--robot", &file]);
    assert_refused(
        &out,
        &format!("{file}: motor.left.tau_s = 1e-12: give 1e-5 to 10 s"),
    );
}

// ---- 2. scenario files ------------------------------------------------------

/// A trigger past the 64-bit cycle counter (the bench waited for it forever)
/// and a duration that wrapped it are refused at load, in `hil run` and
/// `hil faults`, with the file, the fault and the field.
#[test]
fn scenario_times_beyond_a_day_are_refused() {
    for (file, needle) in [
        (
            "bad/scenario-trigger-past-counter.toml",
            "fault 1: trigger.s = 1.2e12: give 0 to 86400 s",
        ),
        (
            "bad/scenario-duration-1e300.toml",
            "fault 1: duration_s = 1e300: give more than 0 and at most 86400 s",
        ),
    ] {
        let path = fixture(file);
        for cmd in [
            vec!["run", "line", "--scenario", &path],
            vec!["faults", "--scenario", &path],
        ] {
            let out = hil_within(&cmd, Duration::from_secs(60));
            assert_refused(&out, needle);
            assert!(stderr(&out).contains(&path), "{}", stderr(&out));
        }
    }
}

/// A fault whose trigger the run never reaches is named in the run's
/// warnings (JSON and text), and in `hil faults --scenario`, where it fails
/// the case (verdict, text and exit code: nothing was tested); the fault that
/// fired is not named. A scenario whose faults all fire is run and reported
/// as not judged, never as a pass.
#[test]
fn a_scenario_fault_that_never_fires_is_a_warning() {
    let scenario = fixture("scenarios/never-fires.toml");
    let robot = ideal();
    let base = [
        "run",
        "line",
        "--leg-mm",
        "300",
        "--robot",
        &robot,
        "--scenario",
        &scenario,
        "--deterministic",
    ];
    let out = hil(&[&base[..], &["--json"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        v["warnings"],
        serde_json::json!(["scenario fault 1 (reset at 3000 s) never fired"]),
    );
    let text = hil(&base);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("scenario fault 1 (reset at 3000 s) never fired"),
        "{text}"
    );

    let faults = |scenario: &str, json: bool| {
        let args = ["faults", "--scenario", scenario, "--robot", &robot];
        hil(&[&args[..], if json { &["--json"][..] } else { &[][..] }].concat())
    };
    let out = faults(&scenario, true);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("never fired"), "{}", stderr(&out));
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        rows[0]["robust_observed"]["warnings"],
        serde_json::json!(["scenario fault 1 (reset at 3000 s) never fired"]),
    );
    assert_eq!(rows[0]["verdict"], "not_fired");
    assert_eq!(rows[0]["pass"], false);
    assert_eq!(
        rows[0]["robust_observed"]["faults_never_fired"],
        serde_json::json!([1])
    );
    let out = faults(&scenario, false);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("[FAIL: a fault never fired]"), "{text}");
    assert!(!text.contains("[pass]"), "{text}");
    assert_eq!(out.status.code(), Some(1));

    // Only the fault that fires: run, reported, not judged, exit 0.
    let dir = std::env::temp_dir().join(format!("hil-fires-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fires = dir.join("fires.toml");
    std::fs::write(
        &fires,
        "test = \"line\"\nleg_mm = 300.0\nlimit_s = 30.0\n\n[[fault]]\n\
         trigger = { at = \"leg_start\", n = 1 }\n\
         action = { action = \"slip_burst\", side = \"left\", slip = 0.0 }\n",
    )
    .unwrap();
    let fires = fires.display().to_string();
    let out = faults(&fires, true);
    assert!(out.status.success(), "{}", stderr(&out));
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(rows[0]["verdict"], "not_judged");
    assert_eq!(rows[0]["pass"], false);
    let out = faults(&fires, false);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("[ran, not judged]") && !text.contains("[pass]"),
        "{text}"
    );
    assert!(
        text.contains("0 passed, 0 failed, 1 ran, not judged"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- 3. the ELF's MCU -------------------------------------------------------

/// `int main` built by avr-gcc for `mcu` into `dir`, then `strip` sections
/// removed (avr-objcopy).
fn avr_gcc(dir: &Path, mcu: &str, source: &str, strip: &[&str]) -> String {
    let c = dir.join(format!("{mcu}.c"));
    std::fs::write(&c, source).unwrap();
    let elf = dir.join(format!("{mcu}.elf"));
    let status = Command::new("avr-gcc")
        .arg(format!("-mmcu={mcu}"))
        .arg("-Os")
        .arg(&c)
        .arg("-o")
        .arg(&elf)
        .status()
        .expect("avr-gcc is installed (tools/setup.sh)");
    assert!(status.success(), "avr-gcc -mmcu={mcu}");
    for section in strip {
        let status = Command::new("avr-objcopy")
            .args(["--remove-section", section])
            .arg(&elf)
            .status()
            .expect("avr-objcopy is installed");
        assert!(status.success(), "avr-objcopy");
    }
    elf.display().to_string()
}

const MAIN: &str = "int main(void) { return 0; }\n";

/// The ELF's MCU is read from its device-info note, simavr's `.mmcu`
/// section or its architecture, and must be the board's (`--mcu`
/// overrides the ELF's); an MCU the bench has no description of is refused
/// naming those it has; an ELF for the atmega2560 is accepted on the
/// default board (and then fails for want of the bench interface, a later
/// check).
#[test]
fn an_elf_for_another_mcu_is_refused() {
    let dir = temp_dir("elf");
    let robot = ideal();
    let run = |elf: &str, more: &[&str]| {
        let mut args = vec!["run", "line", "--robot", &robot, "--elf", elf];
        args.extend_from_slice(more);
        hil(&args)
    };
    let note = ".note.gnu.avr.deviceinfo";
    let described = "the bench describes atmega2560, atmega328p, atmega32u4";

    let elf = avr_gcc(&dir, "atmega328p", MAIN, &[]);
    assert_refused(
        &run(&elf, &[]),
        &format!("{elf}: built for the atmega328p (the ELF says), the board is an atmega2560's"),
    );
    assert_refused(
        &run(&elf, &["--mcu", "atmega32u4"]),
        "built for the atmega32u4 (--mcu says)",
    );
    assert_refused(
        &run(&elf, &["--mcu", "attiny85"]),
        "no MCU \"attiny85\" is described",
    );
    let elf = avr_gcc(&dir, "atmega32u4", MAIN, &[]);
    assert_refused(&run(&elf, &[]), "built for the atmega32u4 (the ELF says)");
    // Not described: another chip of the 2560's family (avr6), a tiny.
    let elf = avr_gcc(&dir, "atmega2561", MAIN, &[]);
    assert_refused(
        &run(&elf, &[]),
        &format!("is built for atmega2561; {described}"),
    );
    let elf = avr_gcc(&dir, "attiny85", MAIN, &[]);
    assert_refused(
        &run(&elf, &[]),
        &format!("is built for attiny85; {described}"),
    );
    // No device named: the architecture in e_flags says avr5, two MCUs
    // have it, so the board's is taken, which is an avr6.
    let dir5 = temp_dir("elf-avr5");
    let elf = avr_gcc(&dir5, "atmega328p", MAIN, &[note]);
    assert_refused(&run(&elf, &[]), "is not the atmega2560's avr6");
    // simavr's own tag names the device.
    let dir_mmcu = temp_dir("elf-mmcu");
    let mmcu = "__attribute__((section(\".mmcu\"), used)) const unsigned char mmcu[] = \
                {1, 11, 'a','t','m','e','g','a','3','2','8','p', 0};\n";
    let elf = avr_gcc(&dir_mmcu, "atmega2560", &format!("{mmcu}{MAIN}"), &[note]);
    assert_refused(
        &run(&elf, &[]),
        "names the atmega328p, an avr5, but is built for the AVR architecture avr6",
    );

    for strip in [&[][..], &[note][..]] {
        let dir_ok = temp_dir("elf-2560");
        let elf = avr_gcc(&dir_ok, "atmega2560", MAIN, strip);
        let out = run(&elf, &[]);
        let err = stderr(&out);
        assert!(!err.contains("built for"), "{err}");
        assert!(err.contains("HT_"), "the next check speaks: {err}");
        std::fs::remove_dir_all(dir_ok).unwrap();
    }
    for d in [dir, dir5, dir_mmcu] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

// ---- 4. calibration and CSV inputs ------------------------------------------

/// The thesis' UMBmark table with `line` (1-based) replaced by `with`
/// (None: deleted), written into `dir`.
fn umbmark_table(dir: &Path, edits: &[(usize, Option<&str>)]) -> String {
    let text = std::fs::read_to_string(fixture("thesis-data/umbmark_endpoints.csv")).unwrap();
    let lines: Vec<String> = text
        .lines()
        .enumerate()
        .filter_map(|(i, l)| match edits.iter().find(|(n, _)| *n == i + 1) {
            Some((_, with)) => with.map(str::to_owned),
            None => Some(l.to_owned()),
        })
        .collect();
    let path = dir.join("umbmark.csv");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path.display().to_string()
}

/// Line 6 of the thesis table is `1,cw,1,-28.6,30.5`.
const CW1: usize = 6;

/// End points that are not finite, or farther off than the square's side
/// (25 m on a 2 m square, 1e308), are refused naming the file, line and
/// column.
#[test]
fn csv_end_points_beyond_the_path_are_refused() {
    let dir = temp_dir("csv");
    for (row, needle) in [
        (
            "1,cw,1,1e308,30.5",
            "line 6: `x_cm` is 1e308 cm, more than the leg of the test (200 cm)",
        ),
        (
            "1,cw,1,-28.6,2500",
            "line 6: `y_cm` is 2500 cm, more than the leg of the test (200 cm)",
        ),
        (
            "1,cw,1,NaN,30.5",
            "line 6: `x_cm` is `NaN`, which is not a finite number",
        ),
        (
            "1,cw,1,-28.6,inf",
            "line 6: `y_cm` is `inf`, which is not a finite number",
        ),
    ] {
        let file = umbmark_table(&dir, &[(CW1, Some(row))]);
        let out = hil(&["calibrate", "--from-csv", &file, "--experiment", "1"]);
        assert_refused(&out, needle);
        assert!(stderr(&out).contains(&file), "{}", stderr(&out));
    }
    // The leg is the one asked for.
    let file = umbmark_table(&dir, &[(CW1, Some("1,cw,1,-28.6,250"))]);
    let out = hil(&[
        "calibrate",
        "--from-csv",
        &file,
        "--side-cm",
        "300",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A table with another number of runs per group is refused naming the
/// command line's option, which then reads it.
#[test]
fn a_wrong_run_count_names_the_option_that_reads_it() {
    let dir = temp_dir("runs");
    let file = umbmark_table(&dir, &[(CW1 + 4, None), (CW1 + 9, None)]);
    let out = hil(&["calibrate", "--from-csv", &file, "--experiment", "1"]);
    assert_refused(&out, "has 4 runs, expected 5");
    assert!(
        stderr(&out).contains("--runs-per-group 4"),
        "{}",
        stderr(&out)
    );
    assert!(!stderr(&out).contains("CsvOptions"), "{}", stderr(&out));
    let args = [
        "calibrate",
        "--from-csv",
        &file,
        "--experiment",
        "1",
        "--json",
    ];
    let out = hil(&[&args[..], &["--runs-per-group", "4"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::remove_dir_all(dir).unwrap();
}

/// A wheelbase of 0, nan or below zero is refused when the command line is
/// parsed, not printed as a correction of 0 mm or NaN.
#[test]
fn a_wheelbase_outside_20_to_2000_mm_is_a_usage_error() {
    let table = fixture("thesis-data/umbmark_endpoints.csv");
    for v in ["0", "nan", "-5", "1e9"] {
        let out = hil(&[
            "calibrate",
            "--from-csv",
            &table,
            &format!("--wheelbase-mm={v}"),
        ]);
        assert_refused(&out, "a wheelbase is 20 to 2000 mm");
        for cmd in ["umbmark", "triangle"] {
            let out = hil(&[cmd, &format!("--firmware-wheelbase-mm={v}")]);
            assert_refused(&out, "a wheelbase is 20 to 2000 mm");
        }
    }
}

/// `hil identify` reads a step response saved with a byte-order mark, as
/// `hil calibrate` reads its tables.
#[test]
fn identify_accepts_a_byte_order_mark() {
    let dir = temp_dir("bom");
    let text = std::fs::read_to_string(fixture("thesis-data/motor_step_right.csv")).unwrap();
    let file = dir.join("step.csv");
    std::fs::write(&file, format!("\u{feff}{text}")).unwrap();
    let file = file.display().to_string();
    let out = hil(&["identify", &file, "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let plain = hil(&[
        "identify",
        &fixture("thesis-data/motor_step_right.csv"),
        "--json",
    ]);
    assert_eq!(out.stdout, plain.stdout);
    std::fs::remove_dir_all(dir).unwrap();
}

// ---- 5. options accepted and ignored ----------------------------------------

/// `--vcd` on a command that writes no trace is refused with the command
/// that does, and no file appears; before, it was dropped without a word.
#[test]
fn vcd_is_refused_where_no_trace_is_written() {
    let dir = temp_dir("vcd");
    let vcd = dir.join("t.vcd").display().to_string();
    for cmd in [
        &["umbmark"][..],
        &["triangle"],
        &["line"],
        &["fuzz", "--frames", "10"],
        &["faults", "--all"],
        &["calibrate"],
        &["bench"],
        &["serve", "--pty"],
        &["ui"],
    ] {
        let out = hil(&[cmd, &["--vcd", &vcd]].concat());
        assert_refused(
            &out,
            "--vcd traces one run: use hil run TEST ... --vcd FILE",
        );
        assert!(
            stderr(&out).contains(&format!("hil {}", cmd[0])),
            "{}",
            stderr(&out)
        );
        assert!(!Path::new(&vcd).exists(), "{cmd:?} wrote {vcd}");
    }
    // --vcd-pwm alone shapes nothing either.
    let out = hil(&["run", "line", "--vcd-pwm"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--vcd"), "{}", stderr(&out));
    std::fs::remove_dir_all(dir).unwrap();
}

/// `hil serve` and `hil ui` start no run themselves: `--param` and
/// `--keep-firmware-params` (what the bench tells the firmware before a run)
/// are refused, not ignored.
#[test]
fn run_parameters_are_refused_where_no_run_is_started() {
    for cmd in [&["serve", "--pty"][..], &["ui"]] {
        for (option, args) in [
            ("--param", &["--param", "kp_left=1.5"][..]),
            ("--keep-firmware-params", &["--keep-firmware-params"]),
        ] {
            let out = hil_within(&[cmd, args].concat(), Duration::from_secs(20));
            assert_refused(
                &out,
                &format!("{option}: hil {} starts no run of its own", cmd[0]),
            );
        }
    }
}

/// With `--tests`, `hil serve` and `hil ui` take the description but refuse
/// `--param` and `--keep-firmware-params`: the firmware has no protocol for
/// parameters, so they would be dropped without a word.
#[test]
fn a_described_firmware_served_refuses_run_parameters() {
    let tests = hil::paths::workspace_root().join("fixtures/arduino/square-demo/tests.toml");
    let tests = tests.to_str().unwrap();
    for cmd in [&["serve", "--pty"][..], &["ui"]] {
        for args in [&["--param", "kp_left=1.5"][..], &["--keep-firmware-params"]] {
            let out = hil_within(
                &[cmd, &["--tests", tests], args].concat(),
                Duration::from_secs(20),
            );
            assert_refused(&out, "has no protocol for parameters");
        }
    }
}

/// `hil serve` and `hil ui` print no result: `--json` (and
/// `--deterministic`) are refused, not ignored.
#[test]
fn json_is_refused_where_no_result_is_printed() {
    for cmd in [&["serve", "--pty"][..], &["ui"]] {
        for option in ["--json", "--deterministic"] {
            let out = hil_within(&[cmd, &[option]].concat(), Duration::from_secs(20));
            assert_refused(
                &out,
                &format!("{option}: hil {} prints no result to format", cmd[0]),
            );
        }
    }
}

/// The triangle calibration from a table assumes Henrytwo's 130 mm wheelbase unless told
/// otherwise, as `--help` says and every other command does (`calib` took 125 mm, the
/// thesis' inner-face value, and printed `b = 125 mm` against its own help).
#[test]
fn a_calibration_from_a_table_assumes_the_130_mm_wheelbase_its_help_names() {
    let help = String::from_utf8_lossy(&hil(&["calibrate", "--help"]).stdout).into_owned();
    assert!(help.contains("else 130"), "{help}");
    for table in ["triangular_endpoints.csv", "umbmark_endpoints.csv"] {
        let out = hil(&[
            "calibrate",
            "--from-csv",
            &fixture(&format!("thesis-data/{table}")),
            "--experiment",
            "1",
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = String::from_utf8_lossy(&out.stdout);
        let first = text.lines().next().unwrap_or_default();
        assert!(first.ends_with("b = 130 mm"), "{table}: {first}");
    }
}

/// A robot whose wheelbase the plant takes (20-2000 mm) but the robust firmware refuses
/// (50-500 mm) is refused before anything runs, naming the file, the parameter and the
/// firmware's range; it used to run with a vague warning and 'complete' a square whose
/// turns summed to 80°.
#[test]
fn a_robot_the_firmware_would_refuse_is_refused_before_the_run() {
    let dir = temp_dir("wide-robot");
    let text = std::fs::read_to_string(ideal()).unwrap();
    let wide = text.replace("wheelbase_mm = 130.0", "wheelbase_mm = 600.0");
    assert_ne!(wide, text, "the ideal robot names its wheelbase as 130.0");
    let path = dir.join("wide.toml");
    std::fs::write(&path, wide).unwrap();
    let p = path.display().to_string();
    let out = hil(&["run", "line", "--robot", &p]);
    assert_refused(&out, "wide.toml: the robust firmware would refuse this robot's wheelbase_mm = 600 (it takes 50-500 mm)");
}

/// A missing input file's cause is said once: the error names it in its own message, and
/// the printed chain used to repeat it (`...: No such file ... : No such file ...`).
#[test]
fn a_missing_file_is_named_with_its_cause_once() {
    for args in [
        &["run", "line", "--scenario", "/nonexistent/s.toml"][..],
        &["run", "line", "--elf", "/nonexistent/f.elf"][..],
        &["board", "check", "/nonexistent/b.toml"][..],
    ] {
        let out = hil(args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.matches("No such file").count(), 1, "{args:?}: {err}");
    }
}
