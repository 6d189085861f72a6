//! A run that fragments says so: more legs or turns than its test's shape is
//! a finding (text, JSON, JUnit) and exit 3, with the likely cause. The
//! fragmenting robot is `coarse65` (about 8 counts per 15 ms control period
//! with the factory PID, which chatters the duty to 0 mid-leg); Henrytwo
//! runs its shape and exits 0.

mod support;

use support::{hil_at_root as hil, json_report as json};

const COARSE: &str = "fixtures/robots/coarse65.toml";
/// Coarse65 with the factory gains as its config's own: none are derived.
const FACTORY_PID: &str = "fixtures/robots/coarse65-factory-pid.toml";

#[test]
fn a_fragmented_square_exits_3_with_the_finding_and_its_cause() {
    let out = hil(&["run", "umbmark-cw", "--robot", FACTORY_PID, "--json"]);
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    let v = json(&out);
    assert_eq!(v["completed"], false, "{v:#}");
    let f = &v["fragments"];
    assert_eq!(
        (f["shape_legs"].as_u64(), f["shape_turns"].as_u64()),
        (Some(4), Some(4))
    );
    let (legs, turns) = (f["legs"].as_u64().unwrap(), f["turns"].as_u64().unwrap());
    assert!(legs > 4 || turns > 4, "{f:#}");
    assert_eq!(v["legs"].as_array().unwrap().len() as u64, legs);
    assert_eq!(v["turns"].as_array().unwrap().len() as u64, turns);
    // Each leg beyond the shape's is a fall of the drive to 0 and back:
    // at least that many.
    assert!(
        f["duty_zero_mid_leg"].as_u64().unwrap() >= legs - 4,
        "{f:#}"
    );
    let finding = v["finding"].as_str().unwrap();
    assert!(
        finding.starts_with(&format!("fragmented: {legs} legs and {turns} turns where umbmark-cw drives 4 and 4; likely cause: a wheel's PWM duty fell to 0")),
        "{finding}"
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: the umbmark-cw run did not complete: fragmented: "),
        "{stderr}"
    );
    // The text report says so at its head.
    let out = hil(&["run", "umbmark-cw", "--robot", FACTORY_PID]);
    assert_eq!(out.status.code(), Some(3));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("umbmark-cw (robust, seed 0): FRAGMENTED"),
        "{text}"
    );
    assert!(text.contains("  finding: fragmented: "), "{text}");
}

#[test]
fn a_fragmented_line_exits_3() {
    let out = hil(&["run", "line", "--robot", FACTORY_PID, "--json"]);
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    let v = json(&out);
    assert_eq!(v["fragments"]["shape_legs"], 1);
    assert!(v["fragments"]["legs"].as_u64().unwrap() > 1, "{v:#}");
}

#[test]
fn henrytwo_runs_its_shape_and_exits_0() {
    for test in ["umbmark-cw", "line"] {
        let out = hil(&["run", test, "--json"]);
        assert_eq!(out.status.code(), Some(0), "{test}: {out:?}");
        let v = json(&out);
        assert_eq!(v["completed"], true);
        assert!(v.get("fragments").is_none(), "{v:#}");
        assert!(v["finding"].is_null());
    }
}

/// `hil test`: the case is INCOMPLETE (exit 3), its JUnit failure names the
/// fragments.
#[test]
fn hil_test_calls_a_fragmented_case_incomplete() {
    let dir = std::env::temp_dir().join(format!("hil-fragments-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let junit = dir.join("junit.xml");
    let out = hil(&[
        "test",
        "fixtures/scenarios/line-signals.toml",
        "--leg-mm",
        "2000",
        "--robot",
        FACTORY_PID,
        "--junit",
        junit.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert!(
        xml.contains("<failure message=\"fragmented: ") && xml.contains("type=\"incomplete\""),
        "{xml}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `coarse65` with `[firmware]` gains (a gentler PID, no derivative), in a
/// fresh folder: its runs drive their shape.
fn tuned_coarse65(dir: &std::path::Path) -> std::path::PathBuf {
    let base = std::fs::read_to_string(hil::paths::workspace_root().join(COARSE)).unwrap();
    let path = dir.join("coarse65-tuned.toml");
    let gains = "\n[firmware]\nkp_left = 1.0\nki_left = 20.0\nkd_left = 0.0\n\
                 kp_right = 1.0\nki_right = 20.0\nkd_right = 0.0\n";
    std::fs::write(&path, base + gains).unwrap();
    path
}

/// The robot config's `[firmware]` gains reach the firmware: the square
/// that fragments with the factory PID drives its shape; `--param` of the
/// factory gains wins over the config's, and it fragments again.
#[test]
fn config_gains_change_the_run_and_param_overrides_them() {
    let dir = std::env::temp_dir().join(format!("hil-settings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tuned = tuned_coarse65(&dir);
    let tuned = tuned.to_str().unwrap();
    let out = hil(&["run", "umbmark-cw", "--robot", tuned, "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let v = json(&out);
    assert_eq!(v["legs"].as_array().unwrap().len(), 4, "{v:#}");
    assert_eq!(v["turns"].as_array().unwrap().len(), 4, "{v:#}");
    let factory = [
        "kp_left=2.2",
        "ki_left=36.666",
        "kd_left=0.033",
        "kp_right=2.74",
        "ki_right=45.66",
        "kd_right=0.0411",
    ];
    let mut args = vec!["run", "umbmark-cw", "--robot", tuned, "--json"];
    for p in &factory {
        args.extend(["--param", p]);
    }
    let out = hil(&args);
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    assert!(json(&out)["fragments"].is_object());
    // hil test takes --param too: the same override, the case INCOMPLETE.
    let mut args = vec![
        "test",
        "fixtures/scenarios/line-signals.toml",
        "--leg-mm",
        "2000",
        "--robot",
        tuned,
    ];
    let out = hil(&args);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    for p in &factory {
        args.extend(["--param", p]);
    }
    let out = hil(&args);
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
