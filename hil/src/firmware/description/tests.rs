//! The description file: what it accepts, and one line for each thing it
//! refuses.

use super::*;
use henrytwo_protocol::Test;

const GOOD: &str = r#"
[firmware]
name = "sketch"
[ready]
after_s = 0.5
[leg]
mm = 400
[end]
idle_s = 2.5
[symbols]
left_count = "leftCount"
right_count = "rightCount"
control = "PID"
[tests.umbmark-cw]
uart = 1
bytes = [2]
[tests.line]
pin = "D30"
level = "low"
[tests.triangle]
uart = 0
text = "t"
"#;

fn parse(text: &str) -> Result<Description, String> {
    Description::from_toml_str(text, "d.toml").map_err(|e| e.to_string())
}

#[test]
fn a_full_description_reads_as_written() {
    let d = parse(GOOD).unwrap();
    assert_eq!(d.name.as_deref(), Some("sketch"));
    assert_eq!(d.ready.after_s, 0.5);
    assert_eq!(d.leg, Leg::Fixed(400.0));
    assert_eq!(d.end.idle_s, 2.5);
    assert_eq!(
        d.tests[&Test::UmbmarkCw.into()].start,
        Start::Uart {
            usart: 1,
            bytes: vec![2]
        }
    );
    assert_eq!(
        d.tests[&Test::Line.into()].start,
        Start::Pin {
            pin: "D30".into(),
            high: false
        }
    );
    assert_eq!(
        d.tests[&Test::Triangle.into()].start,
        Start::Uart {
            usart: 0,
            bytes: b"t".to_vec()
        }
    );
    assert!(d.start(Test::UmbmarkCcw).is_err());
}

/// Each bad field is one line naming the file, the field and what is allowed.
#[rstest::rstest]
#[case(
    "uart = 1\nbytes = [2]",
    "uart = 7\nbytes = [2]",
    "tests.umbmark-cw.uart = 7: give a USART, 0-3, or \"usb\" (the USB serial of an MCU with USB)"
)]
#[case(
    "uart = 1\nbytes = [2]",
    "uart = \"usb1\"\nbytes = [2]",
    "tests.umbmark-cw.uart = \"usb1\": give a USART, 0-3, or \"usb\""
)]
#[case(
    "uart = 1\nbytes = [2]",
    "uart = 1\nbytes = []",
    "tests.umbmark-cw.bytes = []: give 1 to 64 bytes"
)]
#[case(
    "uart = 1\nbytes = [2]",
    "uart = 1",
    "tests.umbmark-cw.uart = 1: give what is sent"
)]
#[case(
    "pin = \"D30\"\nlevel = \"low\"",
    "pin = \"D99\"\nlevel = \"low\"",
    "tests.line.pin = \"D99\": give a pin of the board's MCU"
)]
#[case(
    "pin = \"D30\"\nlevel = \"low\"",
    "pin = \"D30\"\nlevel = \"up\"",
    "tests.line.level = Some(\"up\"): give \"low\" or \"high\""
)]
#[case("mm = 400", "mm = 5001", "leg.mm = 5001: give 10 to 5000 mm")]
#[case("mm = 400", "mm = nan", "leg.mm = NaN: give 10 to 5000 mm")]
#[case(
    "mm = 400",
    "mm = 400\nvariable = \"D\"",
    "leg = ...: give the firmware's own leg"
)]
#[case("idle_s = 2.5", "idle_s = 0", "end.idle_s = 0: give 0.05 to 60 s")]
#[case(
    "after_s = 0.5",
    "after_s = 1e300",
    "ready.after_s = 1e300: give 0 to 60 s"
)]
#[case(
    "[tests.line]",
    "[tests.Spiral]",
    "tests.Spiral = ...: a test name is 1 to 40 of a-z"
)]
#[case(
    "[tests.line]",
    "[tests.line.shape]\nlegs = 1\n[tests.line]",
    "tests.line.shape = ...: line is the thesis' test: 1 legs, 0 turns"
)]
#[case(
    "[tests.triangle]",
    "[tests.square.shape]\nlegs = 4\nturns = 4\n[tests.square]",
    "tests.square.shape.turn_deg = (none): give each turn's angle"
)]
#[case(
    "[tests.triangle]",
    "[tests.square.shape]\nlegs = 2\nturns = 3\nturn_deg = 90\n[tests.square]",
    "tests.square.shape.turns = 3: give 0 to 2 turns"
)]
#[case(
    "[tests.triangle]",
    "[tests.square.end]\nidle_s = 99\n[tests.square]",
    "tests.square.end.idle_s = 99: give 0.05 to 60 s"
)]
#[case("[symbols]", "[symbols]\nleft = \"x\"", "unknown field `left`")]
fn a_bad_field_is_one_line_naming_it(#[case] from: &str, #[case] to: &str, #[case] says: &str) {
    assert!(GOOD.contains(from), "{from}");
    let e = parse(&GOOD.replacen(from, to, 1)).unwrap_err();
    assert!(e.starts_with("d.toml: "), "{e}");
    assert!(e.contains(says), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
}

/// A test of the firmware's own: any name, its own end in place of the
/// file's, its own shape; the thesis' names keep their shapes.
#[test]
fn a_test_of_its_own_has_its_own_end_and_shape() {
    let own = GOOD.to_string()
        + "[tests.forward-then-left]\nuart = 0\ntext = \"f\"\n\
           [tests.forward-then-left.end]\nidle_s = 1.5\n\
           [tests.forward-then-left.shape]\nlegs = 1\nturns = 1\nturn_deg = 90\n";
    let d = parse(&own).unwrap();
    let name = TestName::Own("forward-then-left".into());
    let t = d.test(name.clone()).unwrap();
    assert_eq!(
        t.start,
        Start::Uart {
            usart: 0,
            bytes: b"f".to_vec()
        }
    );
    assert_eq!(d.end_of(&name).idle_s, 1.5);
    assert_eq!(d.end_of(&name).text, None);
    assert_eq!(d.end_of(&Test::Line.into()).idle_s, 2.5);
    assert_eq!(
        t.shape,
        Some(Shape {
            legs: 1,
            turns: 1,
            turn_deg: 90.0,
            leg_mm: None
        })
    );
    assert_eq!(d.test(Test::Line).unwrap().shape, None);
    let e = d
        .test(TestName::Own("spiral".into()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("describes no spiral test"), "{e}");
}

#[test]
fn a_fixed_leg_refuses_another_length_and_a_variable_takes_any() {
    let d = parse(GOOD).unwrap();
    assert_eq!(d.leg_mm(None, 2000.0).unwrap(), 400.0);
    assert_eq!(d.leg_mm(Some(400.0), 2000.0).unwrap(), 400.0);
    let e = d.leg_mm(Some(300.0), 2000.0).unwrap_err().to_string();
    assert!(
        e.contains("legs are 400 mm and it cannot be told 300 mm"),
        "{e}"
    );
    let v = parse(&GOOD.replace("mm = 400", "variable = \"Distancia\"")).unwrap();
    assert_eq!(v.leg_mm(Some(300.0), 2000.0).unwrap(), 300.0);
    assert_eq!(v.leg_mm(None, 2000.0).unwrap(), 2000.0);
}
