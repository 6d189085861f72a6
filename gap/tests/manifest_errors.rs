//! Manifests: the thesis manifests load, and every kind of mistake is refused with a message
//! that names the manifest and the field.

use std::path::PathBuf;

use gap::{load_dataset, load_dir, GapError, LoadedManifest};

fn thesis_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/real/thesis")
}

/// A manifest text parsed as if it lived in the thesis directory (so its relative paths
/// resolve to the vendored data).
fn parse(text: &str) -> Result<LoadedManifest, GapError> {
    LoadedManifest::parse(text, thesis_dir().join("test.toml"))
}

const GOOD: &str = r#"
format = 1
experiment = "x-1"
robot_config = "../../robots/henrytwo-ideal.toml"

[firmware]
c_left = 1.0
c_right = 1.0
wheelbase_mm = 125.0
mm_per_count = 0.166327
leg_mm = 2000.0

[endpoints]
file = "../../thesis-data/umbmark_endpoints.csv"
layout = "umbmark_endpoints"
select_experiment = 1
frame = "thesis_gui"
length_unit = "cm"

[[endpoints.tests]]
kind = "umbmark_cw"
"#;

fn message(r: Result<LoadedManifest, GapError>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// The thesis manifests load: five endpoint experiments with 10, 10, 10, 10 and 10 runs in
/// two tests each, and the step responses; the reference comes from the plant config.
#[test]
fn thesis_manifests_load() {
    let ms = load_dir(thesis_dir()).unwrap();
    assert_eq!(ms.len(), 6);
    let (data, notes) = load_dataset(&ms).unwrap();
    assert_eq!(data.groups().len(), 10);
    assert!(data.groups().iter().all(|g| g.runs.len() == 5));
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("triangle-2"), "{notes:?}");
    let r = ms[0].reference.unwrap();
    assert_eq!(r.wheelbase_mm, 130.0);
    assert!((r.mm_per_count - 0.1669339526).abs() < 1e-6, "{r:?}");
    // The UMBmark tables are mirrored in x into the default frame: experiment 1 CW run 1 was
    // typed as (-28.6, 30.5).
    let g = &data
        .groups()
        .iter()
        .find(|g| g.id.to_string() == "umbmark-1/umbmark_cw")
        .unwrap();
    assert_eq!(g.runs[0].x_cm, 28.6);
    assert_eq!(g.runs[0].y_cm, Some(30.5));
    let t2 = data
        .groups()
        .iter()
        .find(|g| g.id.to_string() == "triangle-2/triangle_ccw")
        .unwrap();
    assert!(t2.runs.iter().all(|r| r.y_cm.is_none()));
    assert!(GOOD.contains("[endpoints]"));
    parse(GOOD).unwrap();
}

/// An unknown field is an error naming the field and the manifest.
#[test]
fn unknown_field() {
    let m = message(parse(
        &GOOD.replace("leg_mm = 2000.0", "leg_mm = 2000.0\nlegs = 4"),
    ));
    assert!(
        m.contains("test.toml") && m.contains("unknown field `legs`"),
        "{m}"
    );
}

/// A missing required field is named.
#[test]
fn missing_field() {
    let m = message(parse(&GOOD.replace("c_left = 1.0\n", "")));
    assert!(m.contains("missing field `c_left`"), "{m}");
}

/// A wrong enum value lists the accepted ones.
#[test]
fn bad_enum() {
    let m = message(parse(
        &GOOD.replace("frame = \"thesis_gui\"", "frame = \"gui\""),
    ));
    assert!(
        m.contains("unknown variant `gui`") && m.contains("thesis_gui"),
        "{m}"
    );
    let m = message(parse(
        &GOOD.replace("kind = \"umbmark_cw\"", "kind = \"square\""),
    ));
    assert!(m.contains("unknown variant `square`"), "{m}");
    let m = message(parse(&GOOD.replace("kind = \"umbmark_cw\"", "kind = 3")));
    assert!(
        m.contains("expected a test name: umbmark_cw, umbmark_ccw, line"),
        "{m}"
    );
}

/// A data file or robot config that does not exist is named with the path it resolved to.
#[test]
fn missing_files() {
    let m = message(parse(&GOOD.replace("umbmark_endpoints.csv", "umbmark.csv")));
    assert!(
        m.contains("endpoints.file") && m.contains("does not exist"),
        "{m}"
    );
    let m = message(parse(&GOOD.replace("henrytwo-ideal.toml", "nope.toml")));
    assert!(
        m.contains("robot_config") && m.contains("does not exist"),
        "{m}"
    );
}

/// A test kind that the table's layout does not hold is refused.
#[test]
fn test_kind_against_layout() {
    let m = message(parse(
        &GOOD.replace("kind = \"umbmark_cw\"", "kind = \"line\""),
    ));
    assert!(
        m.contains("endpoints.tests[0]") && m.contains("not in a"),
        "{m}"
    );
}

/// An unsupported format version, an empty name and a second data source are refused.
#[test]
fn format_name_sources() {
    let m = message(parse(&GOOD.replace("format = 1", "format = 2")));
    assert!(m.contains("`format` = 2"), "{m}");
    let m = message(parse(
        &GOOD.replace("experiment = \"x-1\"", "experiment = \"a/b\""),
    ));
    assert!(m.contains("`experiment`"), "{m}");
    let two = format!(
        "{GOOD}\n[telemetry]\nfile = \"../../thesis-data/robot.toml\"\ntest = \"line\"\n\
         sample_period_s = 0.015\nrpm_unit = \"thesis_rpm\"\n"
    );
    let m = message(parse(&two));
    assert!(m.contains("exactly one of"), "{m}");
}

/// Firmware values must be positive and set-points come in pairs.
#[test]
fn firmware_values() {
    let m = message(parse(&GOOD.replace("c_right = 1.0", "c_right = 0.0")));
    assert!(
        m.contains("firmware.c_right") && m.contains("positive"),
        "{m}"
    );
    let m = message(parse(
        &GOOD.replace("leg_mm = 2000.0", "leg_mm = 2000.0\nsetpoint_left = 15.0"),
    ));
    assert!(m.contains("setpoint_left and setpoint_right"), "{m}");
}

/// A distance per count of 1e308 mm (or any value past a robot's) is refused with its
/// range, not diagnosed.
#[test]
fn firmware_values_within_a_robots_range() {
    let m = message(parse(
        &GOOD.replace("mm_per_count = 0.166327", "mm_per_count = 1e308"),
    ));
    assert!(
        m.contains("`firmware.mm_per_count` = 1000000000") && m.contains("0.0001 to 100 mm"),
        "{m}"
    );
}

/// Without a plant config the manifest needs [reference]; with one, a [reference] that
/// disagrees with it is refused.
#[test]
fn reference_rules() {
    let thesis_layout = GOOD.replace(
        "../../robots/henrytwo-ideal.toml",
        "../../thesis-data/robot.toml",
    );
    let m = message(parse(&thesis_layout));
    assert!(m.contains("needs a physical reference"), "{m}");
    let with_ref =
        format!("{thesis_layout}\n[reference]\nwheelbase_mm = 125.0\nmm_per_count = 0.1669\n");
    assert_eq!(
        parse(&with_ref).unwrap().reference.unwrap().wheelbase_mm,
        125.0
    );
    for bad in ["0.0", "-125.0"] {
        let zero =
            format!("{thesis_layout}\n[reference]\nwheelbase_mm = {bad}\nmm_per_count = 0.1669\n");
        let m = message(parse(&zero));
        assert!(
            m.contains(&format!(
                "`reference.wheelbase_mm` = {}: give a positive number from 10 to 5000 mm",
                bad.trim_end_matches(".0")
            )),
            "{m}"
        );
    }
    let clash = format!("{GOOD}\n[reference]\nwheelbase_mm = 125.0\nmm_per_count = 0.1669\n");
    let m = message(parse(&clash));
    assert!(m.contains("disagrees with robot_config"), "{m}");
}

/// A table with a wrong run count is refused with the reader's line number.
#[test]
fn run_count_from_the_table() {
    let m = message(
        parse(&GOOD.replace(
            "length_unit = \"cm\"",
            "length_unit = \"cm\"\nruns_per_group = 6",
        ))
        .and_then(|m| m.endpoint_groups().map(|_| m)),
    );
    assert!(m.contains("line "), "{m}");
}

/// Two manifests with the same experiment name cannot be loaded together.
#[test]
fn duplicate_names() {
    let a = parse(GOOD).unwrap();
    let err = load_dataset(&[a.clone(), a]).unwrap_err().to_string();
    assert!(err.contains("used by another manifest"), "{err}");
}

/// TOML syntax errors carry the position.
#[test]
fn syntax_error() {
    let m = message(parse("format = 1\nexperiment = \n"));
    assert!(m.contains("test.toml") && m.contains("line 2"), "{m}");
}

/// A telemetry manifest with `run_of` gives its log to that experiment's group of its test;
/// one naming no such group is refused with the manifest's name and the field.
#[test]
fn telemetry_goes_to_the_group_it_is_a_run_of() {
    let dir = std::env::temp_dir().join(format!("gap-run-of-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = "t_s,rpm_left,rpm_right,pwm_left,pwm_right\n\
               0.015,0,0,200,200\n0.030,10,11,200,200\n0.045,14,14,180,190\n0.060,14,15,170,180\n";
    std::fs::write(dir.join("run.csv"), csv).unwrap();
    let robot = thesis_dir().join("../../robots/henrytwo-ideal.toml");
    let manifest = |of: &str| {
        format!(
            "format = 1\nexperiment = \"log-1\"\nrobot_config = {robot:?}\n\n[telemetry]\n\
             file = \"run.csv\"\ntest = \"umbmark_cw\"\nsample_period_s = 0.015\n\
             rpm_unit = \"thesis_rpm\"\nrun_of = \"{of}\"\n"
        )
    };
    let endpoints = parse(GOOD).unwrap();
    let log = LoadedManifest::parse(&manifest("x-1"), dir.join("log.toml")).unwrap();
    let (mut data, _) = load_dataset(std::slice::from_ref(&endpoints)).unwrap();
    let notes = gap::attach_telemetry(&mut data, &[endpoints.clone(), log]).unwrap();
    assert!(notes.is_empty(), "{notes:?}");
    let t = data.groups()[0]
        .telemetry
        .as_ref()
        .expect("the group has the log");
    assert_eq!(t.samples.len(), 4);
    assert_eq!(t.samples[2].rpm_right, 14.0);
    // The same log given to a group as it is built (as the bench's self-test does), and
    // then once more through the manifest: refused.
    let t = t.clone();
    let mut bare = data.groups()[0].clone();
    bare.telemetry = None;
    let group = bare.with_telemetry(t.clone());
    assert_eq!(group.telemetry.as_ref(), Some(&t));
    let mut built = gap::Dataset::default();
    built.push(group).unwrap();
    let err = built.attach_telemetry(&data.groups()[0].id, t).unwrap_err();
    assert!(err.to_string().contains("telemetry given twice"), "{err}");

    // A log of that run stating its firmware: the group's is accepted, another refused
    // with the field that differs; likewise a [reference] of its own.
    let stated = |firmware: &str| {
        let text =
            manifest("x-1").replace("\n\n[telemetry]", &format!("\n\n{firmware}\n[telemetry]"));
        LoadedManifest::parse(&text, dir.join("log.toml")).unwrap()
    };
    let fw = |leg: &str| {
        format!(
            "[firmware]\nc_left = 1.0\nc_right = 1.0\nwheelbase_mm = 125.0\n\
             mm_per_count = 0.166327\nleg_mm = {leg}\n"
        )
    };
    let attach = |log: LoadedManifest| {
        let (mut data, _) = load_dataset(std::slice::from_ref(&endpoints)).unwrap();
        gap::attach_telemetry(&mut data, &[log]).map(|_| data.groups()[0].telemetry.is_some())
    };
    assert!(attach(stated(&fw("2000.0"))).unwrap());
    let err = attach(stated(&fw("1000.0"))).unwrap_err().to_string();
    assert!(
        err.contains("log.toml")
            && err.contains("`firmware.leg_mm` is 1000.0 here but 2000.0 in x-1/umbmark_cw"),
        "{err}"
    );
    let other_robot = manifest("x-1").replace("henrytwo-ideal.toml", "rover65.toml");
    let log = LoadedManifest::parse(&other_robot, dir.join("log.toml")).unwrap();
    let err = attach(log).unwrap_err().to_string();
    assert!(
        err.contains("`reference.mm_per_count` is 0.34")
            && err.contains("but 0.1669339525669579 in x-1"),
        "{err}"
    );

    let stray = LoadedManifest::parse(&manifest("x-9"), dir.join("log.toml")).unwrap();
    let (mut data, _) = load_dataset(std::slice::from_ref(&endpoints)).unwrap();
    let err = gap::attach_telemetry(&mut data, &[stray])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("log.toml") && err.contains("run_of") && err.contains("x-9/umbmark_cw"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
