//! Gains derived for a robot unlike Henrytwo (issue 47, item 2): `coarse65`
//! (65 mm wheels, 7.8 counts per 15 ms period, fast motors at 27 % duty),
//! whose config gives no gains, runs UMBmark CW and CCW with no hand
//! tuning; `hil tune` derives, checks and writes the gains; Henrytwo keeps
//! the factory gains and no note is printed.

mod support;

use support::{
    assert_umbmark_both_ways_with_one_note, assert_umbmark_square as assert_square,
    hil_at_root as hil, json_report as json,
};

const COARSE: &str = "fixtures/robots/coarse65.toml";

#[test]
fn a_robot_whose_config_gives_no_gains_runs_umbmark_with_derived_ones() {
    // Said once, on one line.
    assert_umbmark_both_ways_with_one_note(
        COARSE,
        "note: the factory PID gains are predicted to chatter the duty to 0 on this robot (7.8 counts per period",
    );
}

#[test]
fn henrytwo_keeps_the_factory_gains_and_says_nothing() {
    let out = hil(&["run", "line", "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `hil tune` prints the derivation and passing checks; `--write` puts the
/// gains in the config keeping its comments; the written config's runs use
/// its own gains (no note) and drive the square.
#[test]
fn tune_checks_and_writes_the_gains() {
    let out = hil(&["tune", "--robot", COARSE, "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let v = json(&out);
    assert_eq!(v["factory_chatters"], true);
    let checks = v["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 6, "{v:#}");
    assert!(checks.iter().all(|c| c["pass"] == true), "{v:#}");
    assert_eq!(v["left"]["duty_zero_samples"], 0);
    // Ziegler-Nichols with the process gain: 1.2 * 0.04 / (1.786 * 0.03).
    assert_eq!(v["tuning"]["left"]["gains"]["kp"], 0.896, "{v:#}");

    let dir = std::env::temp_dir().join(format!("hil-tune-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("coarse65.toml");
    let original = std::fs::read_to_string(hil::paths::workspace_root().join(COARSE)).unwrap();
    std::fs::write(&path, &original).unwrap();
    let p = path.to_str().unwrap();
    let out = hil(&["tune", "--robot", p, "--write"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let written = std::fs::read_to_string(&path).unwrap();
    assert!(written.starts_with(&original), "{written}");
    let table: toml::Table = written.parse().unwrap();
    assert_eq!(table["firmware"]["kp_left"].as_float(), Some(0.896));
    assert_eq!(table["firmware"].as_table().unwrap().len(), 6);
    let out = hil(&["run", "umbmark-cw", "--robot", p, "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_square(&json(&out), "written config");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A check that fails is not a success: a line too short to show the
/// speed settled fails the settling checks, exits 1 and writes nothing.
#[test]
fn a_failed_check_exits_1_and_writes_nothing() {
    let dir = std::env::temp_dir().join(format!("hil-tune-fail-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("coarse65.toml");
    let original = std::fs::read_to_string(hil::paths::workspace_root().join(COARSE)).unwrap();
    std::fs::write(&path, &original).unwrap();
    // 100 mm: the line ends before the speed settles.
    let out = hil(&[
        "tune",
        "--robot",
        path.to_str().unwrap(),
        "--length-mm",
        "100",
        "--write",
    ]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("failed") && stderr.contains("nothing written"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&path).unwrap(), original);
    let _ = std::fs::remove_dir_all(&dir);
}
