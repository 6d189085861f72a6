//! `hil test`: a scenario file's expectations judged on the robust build, a
//! passing and a failing case, the exit codes, the JUnit XML (valid against
//! Jenkins' junit-10.xsd by xmllint, parsed with python3's xml.etree) and the
//! triage files of a failed case.

use std::path::Path;
use std::process::{Command, Output};

fn hil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .output()
        .expect("hil runs")
}

/// `report` valid against Jenkins' junit-10.xsd (tests/schemas/), by
/// Debian's xmllint as a CI job would run it.
fn assert_valid_junit(report: &Path) {
    let schema = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/schemas/junit-10.xsd");
    let out = Command::new("xmllint")
        .args(["--noout", "--schema", schema])
        .arg(report)
        .output()
        .expect("xmllint runs (tools/setup.sh installs libxml2-utils)");
    assert!(
        out.status.success(),
        "{} is not valid junit-10: {}\n{}",
        report.display(),
        String::from_utf8_lossy(&out.stderr),
        std::fs::read_to_string(report).unwrap_or_default()
    );
}

/// The property names a report's suites carry, in order, each suite's.
fn property_names(report: &Path) -> Vec<Vec<String>> {
    let xml = std::fs::read_to_string(report).unwrap();
    xml.split("<properties>")
        .skip(1)
        .map(|p| {
            p.split("</properties>")
                .next()
                .unwrap()
                .split("<property name=\"")
                .skip(1)
                .map(|n| n.split('"').next().unwrap().to_string())
                .collect()
        })
        .collect()
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
    assert_valid_junit(&junit);
    for f in [
        "dropout-line-length.vcd",
        "dropout-line-length.gtkw",
        "dropout-line-length.state.json",
    ] {
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
# time is wall seconds, as JUnit's readers take it (never the robot seconds, which
# are a property of their own); how many depends on the machine, not checked here.
suite = [s for s in root.findall("testsuite") if s.find("testcase/failure") is not None][0]
robot = {p.get("name"): p.get("value") for p in suite.findall("properties/property")}["robot_time_s"]
assert float(robot) > 1.0 and float(failed[0].get("time")) >= 0.0 and abs(float(failed[0].get("time")) - float(robot)) > 1e-3, (robot, failed[0].get("time"))
# GitLab's attachment form, relative to the report.
out = failed[0].find("system-out").text.splitlines()
assert "[[ATTACHMENT|report-artifacts/dropout-line-length.vcd]]" in out, out
assert "[[ATTACHMENT|report-artifacts/dropout-line-length.gtkw]]" in out, out
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

/// The fixture's expectations with each condition turned round: a wrong
/// test byte in the frame, text the robust build never sends, the LEDs'
/// levels swapped (the lit one low throughout: it is low at reset), another fault code, the motors driven at the end.
const SIGNALS: &str = "fixtures/scenarios/line-signals.toml";
const TURNED: [(&str, &str); 6] = [
    ("data = [4]", "data = [2]"),
    (r#"bytes = [0xC0], dir = "tx""#, r#"text = "TEST_DONE""#),
    (
        "within_ms = 1000.0\nthat = { on = \"pin\", pin = \"D12\", level = \"high\" }",
        "throughout = true\nthat = { on = \"pin\", pin = \"D12\", level = \"low\" }",
    ),
    (
        r#"pin = "D10", level = "low""#,
        r#"pin = "D10", level = "high""#,
    ),
    ("eq = 0", "eq = 1"),
    (r#"state = "off""#, r#"state = "forward""#),
];

#[test]
fn frame_uart_pin_var_and_motor_conditions_pass_and_each_fails_turned_round() {
    let out = hil(&["test", SIGNALS, "--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let mut text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(SIGNALS),
    )
    .unwrap();
    for (from, to) in TURNED {
        assert_eq!(text.matches(from).count(), 1, "{from} once in the fixture");
        text = text.replace(from, to);
    }
    let turned = std::env::temp_dir().join(format!("hil-turned-{}.toml", std::process::id()));
    std::fs::write(&turned, text).unwrap();
    let out = hil(&["test", turned.to_str().unwrap(), "--json"]);
    let _ = std::fs::remove_file(&turned);
    assert_eq!(out.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let verdicts = report[0]["expectations"].as_array().unwrap();
    assert_eq!(verdicts.len(), TURNED.len());
    for v in verdicts {
        assert_eq!(v["pass"], false, "turned round, still passes: {v}");
    }
}

#[test]
fn faults_junit_has_a_case_per_fault_and_the_failed_reaction() {
    let dir = std::env::temp_dir().join(format!("hil-faults-junit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (good, bad) = (dir.join("robust.xml"), dir.join("thesis.xml"));
    let run = |firmware: &str, junit: &std::path::Path| {
        hil(&[
            "faults",
            "--fault",
            "encoder-dropout",
            "--firmware",
            firmware,
            "--junit",
            junit.to_str().unwrap(),
        ])
    };
    assert_eq!(run("robust", &good).status.code(), Some(0));
    // The thesis build has no encoder-loss watchdog: the reaction fails.
    assert_eq!(run("thesis", &bad).status.code(), Some(1));
    // A scenario's faults are run, not judged: a skipped case.
    let skipped = dir.join("scenario.xml");
    let out = hil(&[
        "faults",
        "--scenario",
        PASS,
        "--junit",
        skipped.to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::read_to_string(&skipped)
        .unwrap()
        .contains("<skipped "));
    let test_report = dir.join("test.xml");
    assert_eq!(
        hil(&["test", PASS, "--junit", test_report.to_str().unwrap()])
            .status
            .code(),
        Some(0)
    );
    for report in [&good, &bad, &skipped, &test_report] {
        assert_valid_junit(report);
    }
    // The same properties from both commands (hil test adds its file's).
    let faults = &property_names(&good)[0];
    let test = &property_names(&test_report)[0];
    assert_eq!(faults[..], test[..faults.len()], "{faults:?} vs {test:?}");
    assert!(faults.contains(&"robot_time_s".to_string()), "{faults:?}");
    let check = r#"
import sys, xml.etree.ElementTree as ET
for path, failures in ((sys.argv[1], 0), (sys.argv[2], 1)):
    root = ET.parse(path).getroot()
    assert root.get("tests") == "1" and root.get("failures") == str(failures), root.attrib
    case = root.find("testsuite/testcase")
    assert case.get("name") == "encoder-dropout" and case.get("classname") == "hil.faults"
    props = {p.get("name"): p.get("value") for p in root.findall("testsuite/properties/property")}
    assert float(props["robot_time_s"]) > 3.0, props
    assert float(case.get("time")) >= 0.0 and abs(float(case.get("time")) - float(props["robot_time_s"])) > 1e-3, "time is wall seconds"
    failure = case.find("failure")
    if failures:
        assert props["firmware"] == "thesis", props
        assert failure.get("type") == "reaction"
        assert "never all off" in failure.get("message"), failure.get("message")
    else:
        assert props["firmware"] == "robust" and failure is None, props
print("ok")
"#;
    let py = Command::new("python3")
        .args(["-c", check, good.to_str().unwrap(), bad.to_str().unwrap()])
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
fn a_report_that_cannot_be_written_is_refused_before_anything_runs() {
    // A file where a folder should be: nothing can be written below it.
    let blocker = std::env::temp_dir().join(format!("hil-blocker-{}", std::process::id()));
    std::fs::write(&blocker, "").unwrap();
    let report = blocker.join("report.xml");
    for args in [
        vec![
            "faults",
            "--fault",
            "encoder-dropout",
            "--junit",
            report.to_str().unwrap(),
        ],
        vec!["test", PASS, "--junit", report.to_str().unwrap()],
        vec!["run", "line", "--vcd", report.to_str().unwrap()],
    ] {
        let out = hil(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("is not a folder"), "{err}");
    }
    let _ = std::fs::remove_file(&blocker);
}
