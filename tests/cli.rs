//! The `hil` command line as a user meets it: the line summary, JSON, and one
//! clear error line for bad input.

#[path = "support/mod.rs"]
mod support;

use std::process::{Command, Output};

fn hil(args: &[&str]) -> Output {
    // Make sure the firmware is built before the CLI looks for it, and pin
    // the robot: the default one may carry random effects.
    let _ = support::firmware_path("robust");
    let ideal = hil::paths::robot_config("henrytwo-ideal");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hil"));
    cmd.args(args);
    if args.first() == Some(&"line") && !args.contains(&"--lenght-mm") {
        cmd.arg("--robot").arg(ideal);
    }
    cmd.output().expect("hil runs")
}

fn assert_one_line_error(out: &Output, needle: &str) {
    assert!(!out.status.success(), "exit status {:?}", out.status);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "not one line: {stderr}"
    );
    assert!(stderr.contains(needle), "{needle:?} not in: {stderr}");
}

/// `hil line --json` reports equal edge and count totals per wheel, and two
/// runs print byte-identical JSON when host timing is left out.
#[test]
fn line_json_is_complete_and_deterministic() {
    let args = ["line", "--length-mm", "500", "--json", "--deterministic"];
    let a = hil(&args);
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let b = hil(&args);
    assert_eq!(a.stdout, b.stdout, "two runs differ");
    let v: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    for key in [
        "robot_time_s",
        "rtf",
        "pwm_hz",
        "distance_firmware_mm",
        "distance_plant_mm",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    for k in ["x_mm", "y_mm", "theta_rad"] {
        assert!(v["pose"][k].is_number(), "pose.{k}");
    }
    for side in ["left", "right"] {
        let w = &v["wheels"][side];
        assert_eq!(w["plant_edges"], w["firmware_count"], "{side}");
    }
}

/// The text summary shows the numbers a person checks first.
#[test]
fn line_text_summary() {
    let out = hil(&["line", "--length-mm", "300"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "robot time",
        "real-time x",
        "firmware odometry",
        "final pose",
        "equal",
        "31372.55 Hz",
    ] {
        assert!(text.contains(needle), "{needle:?} not in:\n{text}");
    }
}

#[test]
fn missing_elf_is_one_clear_line() {
    let out = hil(&["line", "--elf", "no/such/firmware.elf"]);
    assert_one_line_error(&out, "cannot read firmware");
}

#[test]
fn non_avr_elf_is_one_clear_line() {
    // An x86-64 ELF header and nothing else (the test's own executable, the ELF this took
    // before, now passes the 64 MiB an input file may hold).
    let mut header = b"\x7fELF\x02\x01\x01".to_vec();
    header.resize(16, 0);
    for (value, bytes) in [(2u64, 2), (62, 2), (1, 4), (0, 8), (0, 8), (0, 8), (0, 4)] {
        header.extend_from_slice(&value.to_le_bytes()[..bytes]); // type .. flags
    }
    for value in [64u16, 56, 0, 64, 0, 0] {
        header.extend_from_slice(&value.to_le_bytes()); // header sizes and counts
    }
    assert_eq!(header.len(), 64);
    let elf = std::env::temp_dir().join(format!("hil-x86-{}.elf", std::process::id()));
    std::fs::write(&elf, header).unwrap();
    let out = hil(&["line", "--elf", elf.to_str().unwrap()]);
    std::fs::remove_file(&elf).unwrap();
    assert_one_line_error(&out, "not for the AVR");
}

#[test]
fn unknown_option_is_one_clear_line() {
    let out = hil(&["line", "--lenght-mm", "5"]);
    assert_one_line_error(&out, "--lenght-mm");
}

#[test]
fn invalid_length_is_one_clear_line() {
    for bad in ["-5", "abc", "0", "inf"] {
        let out = hil(&["line", "--length-mm", bad]);
        assert_one_line_error(&out, "length");
    }
}

/// `hil identify --json` on the thesis' right motor prints the fields a
/// script reads, with the thesis' Ziegler-Nichols times.
#[test]
fn identify_json_fields() {
    let csv = hil::paths::workspace_root().join("fixtures/thesis-data/motor_step_right.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["identify", csv.to_str().unwrap(), "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for key in [
        "k",
        "tau_s",
        "dead_time_s",
        "kp",
        "ti_s",
        "td_s",
        "ki",
        "kd",
        "pole",
    ] {
        assert!(v[key].is_number(), "{key} missing");
    }
    assert!((v["ti_s"].as_f64().unwrap() - 0.06).abs() < 1e-9);
    assert!((v["k"].as_f64().unwrap() - 25.0).abs() < 0.5);
}

/// `hil calibrate --from-csv --thesis-compat` reproduces the thesis GUI's
/// figure 43 on experiment 1 (cL 0.983934, cR 1.01607, Ba 12.2323 cm), and
/// the default mode names the formulas the GUI gets wrong.
#[test]
fn calibrate_from_csv_reproduces_the_thesis_gui() {
    let csv = hil::paths::workspace_root().join("fixtures/thesis-data/umbmark_endpoints.csv");
    let run = |extra: &[&str]| {
        let mut args = vec!["calibrate", "--from-csv", csv.to_str().unwrap(), "--json"];
        args.extend_from_slice(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_hil"))
            .args(&args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
    };
    let compat = run(&["--thesis-compat"]);
    let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k}"));
    assert!((f(&compat, "cl") - 0.983934).abs() < 5e-7);
    assert!((f(&compat, "cr") - 1.01607).abs() < 5e-6);
    assert!((f(&compat, "wheelbase_mm") - 122.323).abs() < 5e-3);
    assert_eq!(compat["runs"].as_array().unwrap().len(), 10);
    let correct = run(&[]);
    for key in [
        "r_cg_cw_cm",
        "r_cg_ccw_cm",
        "e_max_cm",
        "alpha_deg",
        "beta_deg",
        "ed",
        "eb",
        "cl",
        "cr",
        "wheelbase_mm",
    ] {
        assert!(correct[key].is_number(), "{key}");
    }
    let formulas: Vec<String> = correct["thesis_discrepancies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["formula"].as_str().unwrap().to_string())
        .collect();
    assert!(formulas.iter().any(|f| f.contains("sin()")), "{formulas:?}");
    // Another robot's table is computed with that robot's wheelbase, and
    // --wheelbase-mm still overrides it.
    let rover = hil::paths::robot_config("rover65");
    let rover = rover.to_str().unwrap();
    let other = run(&["--robot", rover]);
    assert_eq!(f(&other, "wheelbase_nominal_mm"), 180.0);
    assert_eq!(f(&correct, "wheelbase_nominal_mm"), 130.0);
    let given = run(&["--robot", rover, "--wheelbase-mm", "150"]);
    assert_eq!(f(&given, "wheelbase_nominal_mm"), 150.0);
}

/// A malformed end-point table is refused with the line it is on.
#[test]
fn calibrate_bad_csv_names_the_line() {
    let dir = std::env::temp_dir().join(format!("hil-cal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(
        &bad,
        "experiment,direction,run,x_cm,y_cm\n1,cw,1,-28.6,30.5\n1,cw,2,abc,32.2\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["calibrate", "--from-csv", bad.to_str().unwrap()])
        .output()
        .unwrap();
    assert_one_line_error(&out, "line 3");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hil gap --self-test --json` lists, per hidden effect, what the diagnosis
/// found; every effect the kinematic model has is ranked first.
#[test]
fn gap_self_test_json() {
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["gap", "--self-test", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cases = v.as_array().unwrap();
    assert!(cases.len() >= 5);
    for c in cases {
        for k in [
            "effect",
            "injected",
            "ranked_first",
            "fitted",
            "value_error_pct",
            "heldout_gap_before",
            "heldout_gap_after",
        ] {
            assert!(c.get(k).is_some(), "{k} missing in {c}");
        }
        assert_eq!(c["ranked_first"], true, "{c}");
    }
}

/// A scenario file with a bad value stops `hil run` before anything runs,
/// with one line naming the fault and what to give instead.
#[test]
fn bad_scenario_is_one_clear_error() {
    let dir = std::env::temp_dir().join(format!("hil-scenario-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "[[fault]]\ntrigger = { at = \"time\", s = 1.0 }\naction = { action = \"slip_burst\", side = \"left\", slip = 2.0 }\n",
    )
    .unwrap();
    let out = hil(&["run", "line", "--scenario", path.to_str().unwrap()]);
    assert_one_line_error(&out, "fault 1: slip = 2");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Faults from a scenario file reach the run: the left encoder frozen from
/// 2 s stops the robust build with a fault code, and the run says so.
#[test]
fn scenario_faults_reach_the_run() {
    let dir = std::env::temp_dir().join(format!("hil-scenario-ok-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("dropout.json");
    std::fs::write(
        &path,
        r#"{"fault": [{"trigger": {"at": "time", "s": 2.0},
            "action": {"action": "encoder", "side": "left", "fault": {"kind": "dropout"}}}]}"#,
    )
    .unwrap();
    let ideal = hil::paths::robot_config("henrytwo-ideal");
    let out = hil(&[
        "run",
        "line",
        "--leg-mm",
        "1000",
        "--json",
        "--deterministic",
        "--hang-after",
        "2.5",
        "--robot",
        ideal.to_str().unwrap(),
        "--scenario",
        path.to_str().unwrap(),
    ]);
    // The run is printed whole, and the exit code says it did not complete.
    assert_eq!(
        out.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("did not complete"), "{stderr}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["completed"], false);
    assert_eq!(v["fault_code"], 1, "stall of the left wheel");
    assert_eq!(v["applied"].as_array().map(|a| a.len()), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hil faults --json` prints the table as a list of rows with the issue's
/// fields, the thesis build's reaction as a finding.
#[test]
fn faults_json_rows_have_the_table_fields() {
    let ideal = hil::paths::robot_config("henrytwo-ideal");
    let out = hil(&[
        "faults",
        "--fault",
        "uart-garbage",
        "--json",
        "--robot",
        ideal.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = v.as_array().expect("a list of rows");
    assert_eq!(rows.len(), 1);
    for key in ["fault", "expected", "robust", "thesis"] {
        assert!(rows[0][key].is_string(), "{key}");
    }
    assert_eq!(rows[0]["pass"], true);
    assert_eq!(rows[0]["verdict"], "pass");
}

/// `--param NAME=VALUE` reaches the firmware before the run: a distance per
/// count 20 % larger ends the same line 20 % sooner (by the plant).
#[test]
fn param_sets_a_firmware_parameter_for_the_run() {
    let leg = |extra: &[&str]| {
        let mut args = vec![
            "run",
            "line",
            "--leg-mm",
            "500",
            "--deterministic",
            "--json",
        ];
        args.extend_from_slice(extra);
        let out = hil(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["legs"][0]["plant_distance_mm"].as_f64().unwrap()
    };
    let mm = 0.166_933_95_f64 * 1.2;
    let (l, r) = (
        format!("mm_per_count_left={mm}"),
        format!("mm_per_count_right={mm}"),
    );
    let ratio = leg(&[]) / leg(&["--param", &l, "--param", &r]);
    assert!((ratio - 1.2).abs() < 0.02, "ratio {ratio}");
}

/// A `--param` the firmware would refuse is one error line before anything
/// runs: an unknown name lists the names, a value out of range gives it.
#[test]
fn param_errors_are_one_line() {
    let out = hil(&["run", "line", "--param", "kp=1"]);
    assert_one_line_error(&out, "kp_left");
    assert_eq!(out.status.code(), Some(2));
    let out = hil(&["run", "line", "--param", "stall_duty=300"]);
    assert_one_line_error(&out, "1 to 255, whole numbers");
    let out = hil(&["run", "line", "--param", "c_left"]);
    assert_one_line_error(&out, "NAME=VALUE");
}

/// A leg the firmware would refuse is refused before anything runs, not
/// run into a table of incomplete runs and a perfect correction.
#[test]
fn a_leg_the_firmware_refuses_is_a_usage_error() {
    for cmd in ["umbmark", "triangle", "calibrate"] {
        let out = hil(&[cmd, "--leg-mm", "5001"]);
        assert_one_line_error(&out, "the firmware's legs are 10 to 5000 mm");
        assert_eq!(out.status.code(), Some(2), "{cmd}");
    }
    let out = hil(&["run", "line", "--leg-mm", "9"]);
    assert_one_line_error(&out, "10 to 5000 mm");
}
