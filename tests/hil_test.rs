//! `hil test`: a scenario file's expectations judged on the robust build, a
//! passing and a failing case, the exit codes, the JUnit XML (parsed with
//! python3's xml.etree) and the triage files of a failed case.

use std::process::{Command, Output};

fn hil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("hil runs")
}

const PASS: &str = "fixtures/scenarios/dropout-motors-off.toml";
const FAIL: &str = "fixtures/scenarios/dropout-line-length.toml";

#[test]
fn dropout_cuts_the_motors_within_250_ms_and_the_case_passes() {
    let out = hil(&["test", PASS]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.starts_with("pass  encoder dropout"), "{text}");
}

#[test]
fn a_failing_case_exits_1_names_what_was_seen_and_saves_its_triage_files() {
    let dir = std::env::temp_dir().join(format!("hil-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let junit = dir.join("report.xml");
    let out = hil(&["test", PASS, FAIL, "--junit", junit.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("FAIL  a line with a dropout"), "{text}");
    assert!(
        text.contains("the line ends within 1 % of 600 mm: expected pose distance 600"),
        "{text}"
    );
    let artifacts = dir.join("report-artifacts");
    for f in ["dropout-line-length.vcd", "dropout-line-length.state.json"] {
        assert!(artifacts.join(f).is_file(), "{f} saved");
    }
    let state: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(artifacts.join("dropout-line-length.state.json")).unwrap(),
    )
    .unwrap();
    assert!(state["last"]["cycle"].as_u64().unwrap() > 0, "{state}");
    assert!(state["last"]["firmware"]["HT_FAULT"].is_number(), "{state}");
    // The JUnit as a CI parser reads it.
    let check = r#"
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "testsuites" and root.get("tests") == "2" and root.get("failures") == "1", root.attrib
cases = root.findall("testsuite/testcase")
assert len(cases) == 2
props = {p.get("name"): p.get("value") for p in root.findall("testsuite/properties/property")}
assert props["seed"] == "0" and props["firmware"] == "robust", props
failed = [c for c in cases if c.find("failure") is not None]
assert len(failed) == 1
assert "600" in failed[0].find("failure").get("message")
assert float(failed[0].get("time")) > 1.0
assert "dropout-line-length.vcd" in failed[0].find("system-out").text
print("ok")
"#;
    let py = Command::new("python3")
        .args(["-c", check, junit.to_str().unwrap()])
        .output()
        .expect("python3 runs");
    assert!(
        py.status.success(),
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_without_expectations_is_refused_before_anything_runs() {
    let out = hil(&["test", "fixtures/scenarios/never-fires.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no [[expect]]"));
}
