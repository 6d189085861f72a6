//! The `hil` command line as a user meets it: the line summary, JSON, and one
//! clear error line for bad input.

#[path = "support/mod.rs"]
mod support;

use std::process::{Command, Output};

fn hil(args: &[&str]) -> Output {
    // Make sure the firmware is built before the CLI looks for it.
    let _ = support::firmware_path("robust");
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .output()
        .expect("hil runs")
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
    let exe = std::env::current_exe().unwrap();
    let out = hil(&["line", "--elf", exe.to_str().unwrap()]);
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
