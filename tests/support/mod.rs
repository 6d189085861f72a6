#![allow(dead_code)] // each test file uses a part
//! Shared set-up for the end-to-end tests (included by each test file): the firmware ELF, built from
//! source on first use, and the robot configs.

use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

use hil::firmware::elf::Firmware;
use plant_model::config::RobotConfig;

/// Build the firmware (incremental: about a second when nothing changed) once
/// per test process and return the path of build `name` ("robust").
pub fn firmware_path(name: &str) -> PathBuf {
    static BUILT: OnceLock<Result<(), String>> = OnceLock::new();
    let built = BUILT.get_or_init(|| {
        let dir = hil::paths::workspace_root().join("firmware");
        let mut cmd = Command::new("cargo");
        cmd.current_dir(&dir)
            .args(["build", "--release", "--quiet"]);
        // The host build's environment must not leak into the AVR build: the
        // firmware picks its own toolchain from rust-toolchain.toml.
        for (key, _) in std::env::vars_os() {
            let k = key.to_string_lossy();
            if k.starts_with("CARGO")
                || k.starts_with("RUSTUP_TOOLCHAIN")
                || k.starts_with("RUSTC")
                || k == "RUSTFLAGS"
                || k == "RUSTDOC"
            {
                cmd.env_remove(&key);
            }
        }
        let out = cmd.output().map_err(|e| format!("cannot run cargo: {e}"))?;
        if out.status.success() {
            Ok(())
        } else {
            Err(String::from_utf8_lossy(&out.stderr).into_owned())
        }
    });
    if let Err(e) = built {
        panic!("building the firmware failed (run tools/setup.sh):\n{e}");
    }
    hil::paths::firmware_elf(name)
}

/// The firmware build `name`, loaded.
pub fn firmware(name: &str) -> Firmware {
    Firmware::load(&firmware_path(name)).expect("firmware ELF loads")
}

/// A robot config from fixtures/robots/.
pub fn robot(name: &str) -> RobotConfig {
    RobotConfig::load(hil::paths::robot_config(name)).expect("robot config loads")
}

/// Runs the `hil` binary with `args` from the workspace root (the fixtures' paths are
/// relative to it), the robust firmware built first.
pub fn hil_at_root(args: &[&str]) -> std::process::Output {
    let _ = firmware_path("robust");
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .current_dir(hil::paths::workspace_root())
        .output()
        .expect("hil runs")
}

/// The JSON report a command printed on stdout.
pub fn json_report(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).expect("the report is JSON")
}

/// Runs the `hil` binary with `args`, the robust firmware built first (the CLI looks for it
/// in `firmware/target`).
pub fn hil(args: &[&str]) -> std::process::Output {
    let _ = firmware_path("robust");
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .output()
        .expect("hil runs")
}

/// `hil run umbmark-cw` and `umbmark-ccw` of the robot config `robot` with nothing by hand:
/// each exits 0, completed, a square as [`assert_umbmark_square`] has it, and one line on
/// stderr, the note that starts `note`.
pub fn assert_umbmark_both_ways_with_one_note(robot: &str, note: &str) {
    for test in ["umbmark-cw", "umbmark-ccw"] {
        let out = hil_at_root(&["run", test, "--robot", robot, "--json"]);
        assert_eq!(out.status.code(), Some(0), "{test}: {out:?}");
        let v = json_report(&out);
        assert_eq!(v["completed"], true, "{test}");
        assert_umbmark_square(&v, test);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.starts_with(note), "{stderr}");
    }
}

/// A UMBmark run's report as issue 47's robots must drive it: 4 legs each within 1 % of
/// 2 m, 4 turns within 10 degrees of 90.
pub fn assert_umbmark_square(v: &serde_json::Value, what: &str) {
    let legs = v["legs"].as_array().unwrap();
    let turns = v["turns"].as_array().unwrap();
    assert_eq!((legs.len(), turns.len()), (4, 4), "{what}: {v:#}");
    for l in legs {
        let d = l["plant_distance_mm"].as_f64().unwrap();
        assert!((d - 2000.0).abs() <= 20.0, "{what}: leg {d} mm");
    }
    for t in turns {
        let a = t["plant_angle_deg"].as_f64().unwrap().abs();
        assert!((a - 90.0).abs() <= 10.0, "{what}: turn {a} deg");
    }
}
