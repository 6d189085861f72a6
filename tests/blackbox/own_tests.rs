//! Tests of a firmware's own (docs/reference/test-description.md): any name,
//! its own end in place of the description's, its own shape judged.

use super::*;

/// square-demo's `half-square`: the sketch's square under a name of its
/// own, ended by its own end (the text after the second turn), not the
/// description's `done`. It completes in its shape, 2 legs and 2 turns to
/// the left, reported as for any test; with the description's end it would
/// drive the whole square and fail its shape.
#[test]
fn a_test_of_its_own_ends_by_its_own_end_in_its_shape() {
    let r = run_described(
        DEMO_TESTS,
        TestName::parse("half-square").unwrap(),
        0,
        false,
    );
    assert_eq!(r.test.name(), "half-square");
    assert!(r.completed, "{:?}", r.finding);
    assert_eq!(
        (r.legs.len(), r.turns.len()),
        (2, 2),
        "{:?} {:?}",
        r.legs,
        r.turns
    );
    for t in &r.turns {
        assert!((t.plant_angle_deg - 90.0).abs() < 8.0, "{t:?}");
    }
    // The firmware's own counts, as for the thesis' tests.
    let mean = |l: &hil::runs::experiment::Leg| {
        (l.firmware_count_left.unwrap() + l.firmware_count_right.unwrap()) / 2
    };
    assert!(r.legs.iter().all(|l| (3000..3010).contains(&mean(l))));
    let text = &r.uarts[0].text;
    assert!(text.contains("turn 2 end"), "{text}");
    assert!(!text.contains("done"), "{text}");
    // The end error is against the shape's ideal end: two legs of 501 mm
    // with a quarter turn left between, at (501, 501) mm.
    let shape = r.shape.expect("judged by its shape");
    let (ix, iy) = shape.ideal_end(501.0);
    assert!(
        (ix - 501.0).abs() < 1e-9 && (iy - 501.0).abs() < 1e-9,
        "{ix} {iy}"
    );
    let (x, y) = (r.final_pose.x_mm - 501.0, r.final_pose.y_mm - 501.0);
    assert!((r.x_cm - x / 10.0).abs() < 1e-9 && (r.y_cm - y / 10.0).abs() < 1e-9);
}

/// The same test with a shape it does not drive (3 legs where it drives 2):
/// `hil run` says what differs and exits 3, as for a run that did not
/// complete; a name the description lacks is refused before anything runs.
#[test]
fn a_run_that_misses_its_shape_exits_3_and_an_unknown_test_2() {
    let root = hil::paths::workspace_root();
    let text = std::fs::read_to_string(root.join(DEMO_TESTS)).unwrap();
    let wrong = text.replacen("legs = 2\nturns = 2", "legs = 3\nturns = 2", 1);
    assert_ne!(wrong, text, "the fixture's shape is 2 legs, 2 turns");
    let file = std::env::temp_dir().join(format!("hil-own-{}.toml", std::process::id()));
    std::fs::write(&file, wrong).unwrap();
    let elf = root.join("firmware/target/arduino/square-demo.elf");
    let run = |test: &str| {
        Command::new(env!("CARGO_BIN_EXE_hil"))
            .current_dir(&root)
            .args(["run", test, "--tests"])
            .arg(&file)
            .arg("--elf")
            .arg(&elf)
            .output()
            .unwrap()
    };
    let unknown = run("spiral");
    let out = run("half-square");
    let _ = std::fs::remove_file(&file);
    let err = String::from_utf8_lossy(&unknown.stderr);
    assert_eq!(unknown.status.code(), Some(2), "{err}");
    assert!(err.contains("describes no spiral test"), "{err}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains(
            "did not drive the shape of half-square: drove 2 legs and 2 turns where the \
             test's shape is 3 legs and 2 turns"
        ),
        "{err}"
    );
}
