//! The golden file's checks and the comparison's arithmetic, without a run.

use super::*;
use crate::runs::experiment::Test;

fn q(name: &str, kind: Kind, value: f64) -> Quantity {
    Quantity {
        name: name.into(),
        kind,
        value,
    }
}

fn in_force() -> InForce {
    InForce {
        firmware: "robust".into(),
        elf: None,
        elf_hash: "00aa".into(),
        robot: "fixtures/robots/henrytwo.toml".into(),
        robot_hash: "11bb".into(),
        board: None,
        seed: 0,
        params: vec![],
        keep_firmware_params: false,
        scenario: None,
        tests: None,
    }
}

fn golden() -> Golden {
    Golden::new(
        Test::Line.into(),
        300.0,
        in_force(),
        Tolerances::default(),
        vec![
            q("leg 1 end x (mm)", Kind::LegMm, 300.0),
            q("leg 1 duty left (mean)", Kind::Duty, 0.5),
        ],
    )
}

#[test]
fn a_golden_file_reads_back_as_written() {
    let g = golden();
    assert_eq!(Golden::parse("g.json", &g.to_json()).unwrap(), g);
}

#[test]
fn a_value_within_its_kinds_tolerance_is_ok_and_one_beyond_moved() {
    let g = golden();
    let now = [
        q("leg 1 end x (mm)", Kind::LegMm, 304.9),
        q("leg 1 duty left (mean)", Kind::Duty, 0.53),
    ];
    let rows = compare(&g.quantities, &now, &g.tolerances);
    assert!(rows[0].ok, "{rows:?}");
    assert!(!rows[1].ok, "0.03 of duty is beyond 0.02: {rows:?}");
    assert!((rows[1].delta().unwrap() - 0.03).abs() < 1e-12);
    let table = render(&rows, &[]);
    assert!(
        table.contains("1 of 2 quantities moved: leg 1 duty left (mean)"),
        "{table}"
    );
}

#[test]
fn a_quantity_on_one_side_only_has_moved() {
    let g = golden();
    let now = [
        q("leg 1 end x (mm)", Kind::LegMm, 300.0),
        q("turn 1 angle (deg)", Kind::TurnDeg, 90.0),
    ];
    let rows = compare(&g.quantities, &now, &g.tolerances);
    let moved: Vec<_> = rows.iter().filter(|r| !r.ok).map(|r| &r.quantity).collect();
    assert_eq!(moved, ["leg 1 duty left (mean)", "turn 1 angle (deg)"]);
}

#[test]
fn another_elf_is_a_difference_in_force() {
    let mut now = in_force();
    now.elf_hash = "ffff".into();
    let d = differences(&in_force(), &now);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].what, "elf hash");
    assert!(differences(&in_force(), &in_force()).is_empty());
}

#[test]
fn another_test_or_leg_is_refused() {
    let g = golden();
    assert!(g
        .check_same_test("g.json", &Test::Line.into(), 300.0)
        .is_ok());
    let e = g
        .check_same_test("g.json", &Test::UmbmarkCw.into(), 300.0)
        .unwrap_err();
    assert!(matches!(e, GoldenError::OtherTest { .. }));
    assert!(g
        .check_same_test("g.json", &Test::Line.into(), 301.0)
        .is_err());
}

#[test]
fn a_broken_file_is_refused_on_one_line() {
    let good = golden().to_json();
    let cases = [
        ("{", "not a golden file"),
        (
            &good.replace(FORMAT, "hil-golden/0") as &str,
            "format \"hil-golden/0\"",
        ),
        (
            &good.replace("\"duty\": 0.02", "\"duty\": -1.0"),
            "tolerances.duty",
        ),
        (
            &good.replace("300.0,\n  \"recorded", "0.0,\n  \"recorded"),
            "leg_mm",
        ),
        (
            &good.replace("leg 1 duty left (mean)", "leg 1 end x (mm)"),
            "given twice",
        ),
    ];
    for (text, says) in cases {
        let e = Golden::parse("g.json", text).unwrap_err().to_string();
        assert!(e.contains(says), "{e:?} should say {says:?}");
        assert!(e.starts_with("g.json: "), "{e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}
