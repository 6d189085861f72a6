//! The firmware's `board.rs` and [`super::HENRYTWO`] name the same pins:
//! every pin, its Arduino number, the PWM channel on each bridge input and
//! the two USARTs; and `fixtures/boards/henrytwo.toml` is the built-in board.

use super::*;

#[test]
fn the_fixture_is_the_built_in_board() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/boards/henrytwo.toml"
    );
    assert_eq!(Board::load(path).unwrap(), HENRYTWO);
}

/// One pin field of board.rs's `Pins`: its doc line
/// `/// D<n> (P<port><bit>, ALT...): role` and its type `Pin<P<port><bit>, ..>`.
#[derive(Debug)]
struct BoardPin {
    doc_arduino: u8,
    doc_pin: String,
    doc_alt: Vec<String>,
    type_pin: String,
}

/// The pin fields of the firmware's board.rs, by field name.
fn board_pins(text: &str) -> std::collections::BTreeMap<String, BoardPin> {
    let mut out = std::collections::BTreeMap::new();
    let mut doc: Option<&str> = None;
    for line in text.lines().map(str::trim) {
        if let Some(d) = line.strip_prefix("/// ") {
            doc = Some(d);
            continue;
        }
        let field = line
            .strip_prefix("pub ")
            .and_then(|l| l.split_once(": Pin<"))
            .filter(|(name, _)| !name.contains(' '));
        if let (Some((name, ty)), Some(d)) = (field, doc) {
            // "D6 (PH3, OC4A): ..." ("A0 (PF0, ADC0)" is analog: no D number).
            let (head, _) = d.split_once("):").expect("a pin's doc names it");
            let (num, pins) = head.split_once(" (").expect("D<n> (P..");
            let mut parts = pins.split(", ").map(str::to_string);
            let doc_pin = parts.next().unwrap();
            out.insert(
                name.to_string(),
                BoardPin {
                    doc_arduino: num
                        .strip_prefix('D')
                        .map_or(u8::MAX, |n| n.parse().unwrap()),
                    doc_pin,
                    doc_alt: parts.collect(),
                    type_pin: ty.split(',').next().unwrap().to_string(),
                },
            );
        }
        doc = None;
    }
    out
}

fn port_bit(p: &Pin) -> String {
    format!("P{}{}", p.port, p.bit)
}

fn pwm_name(p: Option<PwmSource>) -> String {
    p.expect("a DRV8833 input is PWM").to_string()
}

/// The firmware's board.rs and this table name the same pins: each
/// signal's field in `Pins` has the table's port and bit in its type and
/// its doc, and the table's Arduino number; each bridge input's doc and
/// `DriveMotors` (right forward, right reverse, left forward, left
/// reverse) name the table's PWM channel; the Bluetooth and debug links
/// are on the table's USARTs.
#[test]
fn board_rs_names_the_same_pins() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../firmware/src/board.rs");
    let text = std::fs::read_to_string(path).expect("firmware/src/board.rs");
    let board = board_pins(&text);
    let w = HENRYTWO;
    let leds = w.battery_leds.expect("Henrytwo has its battery LEDs");
    let pins = [
        ("left_encoder_a", w.left_encoder.a),
        ("left_encoder_b", w.left_encoder.b.unwrap()),
        ("right_encoder_a", w.right_encoder.a),
        ("right_encoder_b", w.right_encoder.b.unwrap()),
        ("right_forward", w.right_motor.pin1.pin),
        ("right_reverse", w.right_motor.pin2.pin),
        ("left_forward", w.left_motor.pin1.pin),
        ("left_reverse", w.left_motor.pin2.pin),
        ("led_green", leds.green),
        ("led_blue", leds.blue),
        ("led_red", leds.red),
    ];
    for (name, pin) in pins {
        let b = board
            .get(name)
            .unwrap_or_else(|| panic!("board.rs has no pin {name}: {board:#?}"));
        assert_eq!(b.type_pin, port_bit(&pin), "{name}: type");
        assert_eq!(b.doc_pin, port_bit(&pin), "{name}: doc");
        assert_eq!(Some(b.doc_arduino), pin.arduino, "{name}: Arduino number");
    }
    let bridge = [
        ("right_forward", w.right_motor.pin1),
        ("right_reverse", w.right_motor.pin2),
        ("left_forward", w.left_motor.pin1),
        ("left_reverse", w.left_motor.pin2),
    ];
    for (name, input) in bridge {
        assert!(
            board[name].doc_alt.contains(&pwm_name(input.pwm)),
            "{name}: board.rs says {:?}, the table {}",
            board[name].doc_alt,
            pwm_name(input.pwm)
        );
    }
    let drive = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("pub type DriveMotors = Motors<"))
        .expect("board.rs defines DriveMotors");
    let channels: Vec<String> = drive
        .trim_end_matches(">;")
        .split(", ")
        .map(str::to_uppercase)
        .collect();
    let table: Vec<String> = bridge.iter().map(|(_, i)| pwm_name(i.pwm)).collect();
    assert_eq!(channels, table, "DriveMotors<RF, RR, LF, LR>");
    for (name, uart) in [
        ("bluetooth_rx", w.command_uart.usart),
        ("bluetooth_tx", w.command_uart.usart),
        ("debug_rx", w.debug_uart.usart),
        ("debug_tx", w.debug_uart.usart),
    ] {
        let dir = if name.ends_with("rx") { "RXD" } else { "TXD" };
        assert!(
            board[name].doc_alt.contains(&format!("{dir}{uart}")),
            "{name}: board.rs says {:?}, the table USART{uart}",
            board[name].doc_alt
        );
    }
}
