//! A board TOML is checked before anything runs: each rule refuses the
//! board that breaks it with one line naming the file, the field, what is
//! wrong and what is allowed; Henrytwo's fixture and the other driver kinds
//! load.

use hil::board::{Board, BoardError, DriverKind, EncoderKind, Mcu, Problem, ProblemKind, HENRYTWO};

const MEGA: Mcu = Mcu::Atmega2560;
use rstest::rstest;

const FIXTURE: &str = include_str!("../fixtures/boards/henrytwo.toml");

/// Henrytwo's fixture with `from` replaced by `to` (which must be in it);
/// several edits are separated by `|` in both.
fn edited(from: &str, to: &str) -> String {
    let mut text = FIXTURE.to_string();
    for (from, to) in from.split('|').zip(to.split('|')) {
        assert!(text.contains(from), "{from:?} not in the fixture");
        text = text.replacen(from, to, 1);
    }
    text
}

fn problems(text: &str) -> Vec<Problem> {
    match Board::from_toml_str(text, "my.toml") {
        Err(BoardError::Invalid(p)) => p,
        other => panic!("expected problems, got {other:?}"),
    }
}

#[test]
fn henrytwos_fixture_is_the_built_in_board() {
    assert_eq!(
        Board::from_toml_str(FIXTURE, "henrytwo.toml").unwrap(),
        HENRYTWO
    );
}

/// Each rule, broken once: exactly that one problem, on that field, and
/// its line says what is allowed.
#[rstest]
#[case::pin_used_twice(
    r#"green = "D10""#, r#"green = "D9""#, "leds.green",
    ProblemKind::PinReused { pin: "D9".into(), first: "motor_driver.left.forward".into() },
    "each pin carries one signal"
)]
#[case::no_timer_channel(
    r#"forward = "D9""#, r#"forward = "D22""#, "motor_driver.left.forward",
    ProblemKind::NotPwm { pin: "D22".into(), mcu: MEGA }, "PWM pins: D4 D13 (timer 0), D11 D12 (timer 1), D9 D10 (timer 2)"
)]
#[case::encoder_a_cannot_interrupt(
    r#"a = "D2""#, r#"a = "D22""#, "encoders.left.a",
    ProblemKind::CannotInterrupt { pin: "D22".into(), line: "channel A", mcu: MEGA }, "give D2 D3 D18"
)]
#[case::uart_out_of_range(
    "usart = 1", "usart = 4", "command_uart.usart",
    ProblemKind::UartOutOfRange { usart: 4, mcu: MEGA }, "USART 0-3"
)]
#[case::uart_pin_reused(
    r#"red = "D12""#, r#"red = "D19""#, "command_uart.usart",
    ProblemKind::PinReused { pin: "D19".into(), first: "leds.red".into() }, "one signal"
)]
#[case::same_uart_twice(
    "usart = 0", "usart = 1", "debug_uart.usart",
    ProblemKind::UartReused { usart: 1, first: "command_uart".into(), mcu: MEGA }, "a USART of its own (0-3)"
)]
#[case::adc_out_of_range(
    "adc = 0", "adc = 16", "battery.adc",
    ProblemKind::AdcOutOfRange { adc: 16, mcu: MEGA }, "give 0-15"
)]
#[case::unknown_pin(
    r#"b = "D4""#, r#"b = "D70""#, "encoders.left.b",
    ProblemKind::UnknownPin { given: "D70".into(), mcu: MEGA }, r#"give "D0"-"D69", "A0"-"A15" or a port pin"#
)]
#[case::bad_baud(
    "baud = 9600             # firmware", "baud = 12345678  # firmware", "command_uart.baud",
    ProblemKind::BadBaud { baud: 12345678 }, "e.g. 9600"
)]
#[case::zero_baud(
    "baud = 9600             # firmware", "baud = 0  # firmware", "command_uart.baud",
    ProblemKind::BadBaud { baud: 0 }, "e.g. 9600"
)]
fn each_rule_refuses_its_board(
    #[case] from: &str,
    #[case] to: &str,
    #[case] field: &str,
    #[case] kind: ProblemKind,
    #[case] allowed: &str,
) {
    let p = problems(&edited(from, to));
    assert_eq!(p.len(), 1, "{p:#?}");
    assert_eq!(p[0].field, field);
    assert_eq!(p[0].kind, kind);
    let line = p[0].to_string();
    assert!(!line.contains('\n'), "{line}");
    assert!(line.starts_with(&format!("my.toml: {field}: ")), "{line}");
    assert!(line.contains(allowed), "{line}");
}

/// An unknown field or driver kind is refused by the schema, with the
/// line it is on and the names allowed.
#[rstest]
#[case::unknown_field("[leds]", "[leds]\norange = \"D13\"", "unknown field `orange`")]
#[case::unknown_kind(r#"kind = "drv8833""#, r#"kind = "l293d""#, "unknown variant `l293d`")]
#[case::pin_as_number(r#"a = "D2""#, "a = 2", "expected a string")]
fn the_schema_refuses_what_it_does_not_know(
    #[case] from: &str,
    #[case] to: &str,
    #[case] message: &str,
) {
    match Board::from_toml_str(&edited(from, to), "my.toml") {
        Err(e @ BoardError::Syntax { .. }) => {
            let line = e.to_string();
            assert!(line.starts_with("my.toml:"), "{line}");
            assert!(line.contains(message), "{line}");
            assert!(!line.contains('\n'), "{line}");
        }
        other => panic!("{other:?}"),
    }
}

/// The other driver kinds load, with direction pins as GPIO and the
/// PWM pins on their timers.
#[rstest]
#[case::l298n(
    "kind = \"l298n\"",
    "enable = \"D9\"\nin1 = \"D22\"\nin2 = \"D23\"",
    "enable = \"D46\"\nin1 = \"D24\"\nin2 = \"D25\"",
    DriverKind::L298n
)]
#[case::tb6612(
    "kind = \"tb6612\"",
    "pwm = \"D9\"\nin1 = \"D22\"\nin2 = \"D23\"",
    "pwm = \"D46\"\nin1 = \"D24\"\nin2 = \"D25\"",
    DriverKind::Tb6612
)]
#[case::pwm_dir(
    "kind = \"pwm_dir\"",
    "pwm = \"D9\"\ndir = \"D22\"",
    "pwm = \"D46\"\ndir = \"A8\"",
    DriverKind::PwmDir
)]
fn other_drivers_load(
    #[case] kind_line: &str,
    #[case] left: &str,
    #[case] right: &str,
    #[case] kind: DriverKind,
) {
    let text = edited(r#"kind = "drv8833""#, kind_line)
        .replacen(
            "forward = \"D9\"          # OC2B; the thesis' Adelante drives it with the left wheel's PID\nreverse = \"D8\"          # OC4C; Inercia_Stop_Ad brakes with it",
            left,
            1,
        )
        .replacen(
            "forward = \"D7\"          # OC4B\nreverse = \"D6\"          # OC4A",
            right,
            1,
        );
    let board = Board::from_toml_str(&text, "my.toml").unwrap();
    assert_eq!(board.driver, kind);
    assert_eq!(board.pwm_timers(), vec![2, 5]);
    assert_eq!(board.left_motor.pin2.pwm, None);
    assert_eq!(board.right_motor.pin1.pin.arduino, Some(46));
}

/// Motor PWM on timer 0's pins (D4 OC0B, D13 OC0A: PB7 also carries OC1C,
/// and the Arduino core drives it from OC0A) and timer 1's (D11 OC1A, D12
/// OC1B) is accepted: whether the firmware uses such a timer as its clock
/// is judged when it runs.
#[test]
fn timer_0_and_timer_1_pins_carry_pwm() {
    use hil::board::PwmSource;
    let text = edited(
        r#"forward = "D9"|reverse = "D8"|forward = "D7"|reverse = "D6"|b = "D4"|green = "D10"|blue = "D11"|red = "D12""#,
        r#"forward = "D4"|reverse = "D13"|forward = "D11"|reverse = "D12"|b = "D30"|green = "D31"|blue = "D32"|red = "D33""#,
    );
    let board = Board::from_toml_str(&text, "my.toml").unwrap();
    let oc = |timer, channel| Some(PwmSource { timer, channel });
    assert_eq!(board.left_motor.pin1.pwm, oc(0, 'B'));
    assert_eq!(board.left_motor.pin2.pwm, oc(0, 'A'));
    assert_eq!(board.right_motor.pin1.pwm, oc(1, 'A'));
    assert_eq!(board.right_motor.pin2.pwm, oc(1, 'B'));
    assert_eq!(board.pwm_timers(), vec![0, 1]);
}

/// A board with an input on another port and timer runs the firmware as
/// Henrytwo's does while that input is idle: with the right motor's reverse
/// input on D46 (OC5A, port L) the bench emulates timers 2, 4 and 5 and
/// reads ports H and L, and the first 1.5 s of the line test (forward only)
/// end at exactly Henrytwo's pose, D46 never driven.
#[test]
fn a_board_on_timer_5_and_port_l_runs_as_henrytwo_while_its_input_is_idle() {
    use hil::bench::{Bench, BenchOptions};
    use hil::board::{BridgeInput, Mcu, Pin, PwmSource};
    use hil::runs::line::CMD_LINE;
    use hil::runs::start::wait_ready;

    #[path = "support/mod.rs"]
    mod support;

    let mut board = HENRYTWO;
    board.right_motor.pin2 = BridgeInput {
        pin: Pin::arduino(Mcu::Atmega2560, 46).unwrap(),
        pwm: Some(PwmSource {
            timer: 5,
            channel: 'A',
        }),
    };
    assert_eq!(board.pwm_timers(), vec![2, 4, 5]);
    let run = |board: Board| {
        let mut bench = Bench::new(
            support::firmware("robust"),
            &support::robot("henrytwo-ideal"),
            BenchOptions {
                board,
                ..Default::default()
            },
        )
        .unwrap();
        wait_ready(&mut bench, None).unwrap();
        bench.send(board.command_uart.usart, &[CMD_LINE]);
        bench.run_for(1.5).unwrap();
        let core = bench.core();
        let pose = core.robot().pose();
        let pins: Vec<(u8, bool)> = core
            .pin_stats()
            .iter()
            .map(|p| (p.pin, p.active_s > 0.0))
            .collect();
        ([pose.x().0, pose.y().0, pose.theta().0], pins)
    };
    let (henrytwo, _) = run(HENRYTWO);
    let (moved, pins) = run(board);
    assert!(henrytwo[0] > 100.0, "the robot drove: {henrytwo:?}");
    assert_eq!(moved, henrytwo);
    assert_eq!(
        pins,
        vec![(7, true), (8, false), (9, true), (46, false)],
        "D46 is watched, idle"
    );
}

/// The robust firmware reads A on D2/D3 (INT4/INT5) and B on D4/D5: a board
/// with its encoders elsewhere is named, every other pin left as it is; the
/// boards of the fixtures are not.
#[test]
fn encoders_elsewhere_are_named_for_the_robust_firmware() {
    let moved = Board::from_toml_str(
        &edited("a = \"D2\"|b = \"D4\"", "a = \"D21\"|b = \"D22\""),
        "my.toml",
    )
    .expect("a valid board");
    let why = moved.firmware_encoder_mismatch().expect("named");
    assert_eq!(
        why,
        "the robust firmware reads its encoders on left A D2, B D4; right A D3, B D5 (its \
         INT4/INT5 handlers); this board has them on left A D21, B D22; right A D3, B D5: wire \
         them there, or run a firmware of your own (--tests)"
    );
    assert_eq!(HENRYTWO.firmware_encoder_mismatch(), None);
    let rover = Board::load(hil::paths::workspace_root().join("fixtures/boards/rover65.toml"))
        .expect("rover65's board loads");
    assert_eq!(rover.firmware_encoder_mismatch(), None);
    // A board with one link and no battery divider or LEDs (the Uno's).
    let uno = Board::load(hil::paths::workspace_root().join("fixtures/boards/uno-l298n.toml"))
        .expect("the Uno robot's board loads");
    assert_eq!(uno.command_uart, uno.debug_uart, "one link");
    assert_eq!(
        uno.firmware_encoder_mismatch().as_deref(),
        Some(
            "the robust firmware drives a command link apart from the debug UART, a battery \
             divider and battery LEDs; this board has no [command_uart], [battery], [leds]: add \
             them, or run a firmware of your own (--tests)"
        )
    );
}

/// `hil board check` refuses such a board (exit 2), checks it for a
/// firmware of one's own with `--own-firmware` (exit 0), and passes
/// Henrytwo's.
#[test]
fn board_check_refuses_encoders_the_robust_firmware_cannot_read() {
    let hil = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_hil"))
            .args(args)
            .current_dir(hil::paths::workspace_root())
            .output()
            .expect("hil runs")
    };
    let bad = "fixtures/bad/board-encoders-int0-int1.toml";
    let out = hil(&["board", "check", bad]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("this board has them on left A D21, B D22; right A D20, B D23"),
        "{stderr}"
    );
    assert_eq!(
        hil(&["board", "check", "--own-firmware", bad])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(
        hil(&["board", "check", "fixtures/boards/henrytwo.toml"])
            .status
            .code(),
        Some(0)
    );
}

/// A board names its MCU (`mcu`, the atmega2560 when absent): an Uno's pins
/// resolve on the ATmega328P (the L298N enables on timer 0's D5/D6, the
/// encoders on INT0/INT1), and what the 328P lacks is refused with one line
/// (its one USART). An MCU without a description is refused naming those
/// described; a pin may be named by port and bit.
#[test]
fn a_board_names_its_mcu_and_pins_by_port_and_bit() {
    let uno = r#"
mcu = "atmega328p"
[motor_driver]
kind = "l298n"
left = { enable = "D5", in1 = "D7", in2 = "D8" }
right = { enable = "D6", in1 = "D9", in2 = "D10" }
[encoders]
left = { a = "D2", b = "D4" }
right = { a = "D3", b = "D12" }
[command_uart]
usart = 1
baud = 9600
[debug_uart]
usart = 0
baud = 9600
[battery]
adc = 0
divider = 0.55
[leds]
green = "A1"
blue = "A2"
red = "PC3"
"#;
    let p = problems(uno);
    let lines: Vec<String> = p.iter().map(ToString::to_string).collect();
    assert_eq!(
        p.iter().map(|p| p.field.as_str()).collect::<Vec<_>>(),
        ["command_uart.usart"],
        "{lines:?}"
    );
    assert!(
        lines[0].contains("no USART 1; the atmega328p has USART 0"),
        "{lines:?}"
    );
    let tiny = problems(&edited(
        "[motor_driver]\n",
        "mcu = \"attiny85\"\n[motor_driver]\n",
    ));
    assert_eq!(tiny.len(), 1);
    assert_eq!(
        tiny[0].to_string(),
        "my.toml: mcu: no MCU \"attiny85\" is described; give one of atmega2560, atmega328p, atmega32u4"
    );
    // PE4 is the Mega's D2, PK7 its A15.
    let by_port = edited("a = \"D2\"|divider", "a = \"PE4\"|divider");
    assert_eq!(Board::from_toml_str(&by_port, "b.toml").unwrap(), HENRYTWO);
    let p = problems(&edited("a = \"D2\"", "a = \"PI0\""));
    assert!(
        p[0].to_string().contains("no atmega2560 pin \"PI0\""),
        "{p:?}"
    );
}

/// Pololu's Romi 32U4 board: DRV8838s on timer 1, each encoder's A xor B
/// on an interrupt pin with B on another, the left B on PE2, which has no
/// Arduino number and is named by port and bit.
#[test]
fn the_romi_board_names_xor_encoders_and_a_pin_without_a_number() {
    let path = hil::paths::workspace_root().join("fixtures/boards/romi-32u4.toml");
    let b = Board::load(path).unwrap();
    assert_eq!(b.driver, DriverKind::Drv8838);
    assert_eq!(b.pwm_timers(), vec![1]);
    let (l, r) = (b.left_encoder, b.right_encoder);
    assert_eq!((l.kind, r.kind), (EncoderKind::Xor, EncoderKind::Xor));
    let (lb, rb) = (l.b.unwrap(), r.b.unwrap());
    assert_eq!((l.a.name(), lb.name()), ("D8".into(), "PE2".into()));
    assert_eq!((lb.port, lb.bit, lb.arduino), ('E', 2, None));
    assert_eq!((r.a.name(), rb.name()), ("D7".into(), "D23".into()));
    assert_eq!(l.a.interrupt_vector(), Some(9), "PCINT0");
    assert_eq!(r.a.interrupt_vector(), Some(7), "INT6");
    assert_eq!(l.line_names(), ["XOR", "B"]);
    // A xor B on the interrupt pin, B on its own.
    assert!(r.interrupt_line(true, false) && !r.interrupt_line(true, true));
    assert!(b.firmware_encoder_mismatch().unwrap().contains("DRV8838"));
}

/// What a Romi-like board may not do, one line each: a motor-driver input
/// without an Arduino number, an encoder with both `a` and `xor` (or
/// neither), an xor line without B, an xor line on a pin that cannot
/// interrupt, PWM on timer 4
/// (the Leonardo's `analogWrite` on D6 and D13: simavr's 32U4 core has no
/// timer 4, so the bench cannot run it exactly).
#[rstest]
#[case::driver_pin_without_a_number(
    r#"phase = "D16""#,
    r#"phase = "PE2""#,
    "motor_driver.left.phase",
    "PE2 has no Arduino number; a motor-driver input needs one"
)]
#[case::a_and_xor(
    r#"xor = "D8""#,
    r#"xor = "D8"
a = "D8""#,
    "encoders.left",
    "both `a` and `xor` given"
)]
#[case::neither(r#"xor = "D8""#, "", "encoders.left", "no `a` or `xor`")]
#[case::xor_cannot_interrupt(
    r#"xor = "D8""#,
    r#"xor = "A0""#,
    "encoders.left.xor",
    "D18 cannot interrupt (no INTn or PCINTn), so the firmware would miss the A xor B line's edges"
)]
#[case::timer_4_oc4a(
    r#"enable = "D10""#,
    r#"enable = "D13""#,
    "motor_driver.left.enable",
    "D13 is on timer 4: the atmega32u4's timer 4 (10-bit, high speed) is not emulated (simavr lacks it too)"
)]
#[case::timer_4_oc4d(
    r#"enable = "D9""#,
    r#"enable = "D6""#,
    "motor_driver.right.enable",
    "D6 is on timer 4: the atmega32u4's timer 4"
)]
#[case::xor_without_b(
    r#"b = "PE2""#,
    "",
    "encoders.left.b",
    "no `b`: an A xor B line is decoded with channel B; give B's pin"
)]
#[case::pe2_twice(
    r#"xor = "D7""#,
    r#"xor = "PE2""#,
    "encoders.right.xor",
    "PE2 is already used by encoders.left.b"
)]
fn romi_board_rules(
    #[case] from: &str,
    #[case] to: &str,
    #[case] field: &str,
    #[case] message: &str,
) {
    let text = std::fs::read_to_string(
        hil::paths::workspace_root().join("fixtures/boards/romi-32u4.toml"),
    )
    .unwrap();
    assert!(text.contains(from), "{from}");
    let text = text.replacen(from, to, 1);
    let p = match Board::from_toml_str(&text, "romi.toml") {
        Err(BoardError::Invalid(p)) => p,
        other => panic!("{other:?}"),
    };
    let fields: Vec<&str> = p.iter().map(|p| p.field.as_str()).collect();
    assert!(fields.contains(&field), "{p:#?}");
    let line = p.iter().find(|p| p.field == field).unwrap().to_string();
    assert!(line.contains(message), "{line}");
    assert!(!line.contains('\n'), "{line}");
}

/// One-channel encoders (channel A alone, no `b`): A on INT0/INT1 or a
/// pin-change pin, checked as quadrature A is (a pin that cannot interrupt
/// is refused in one line naming channel A); B is on no pin.
#[test]
fn a_one_channel_encoder_is_channel_a_alone() {
    let path = hil::paths::workspace_root().join("fixtures/boards/uno-one-channel.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let b = Board::load(&path).unwrap();
    let (l, r) = (b.left_encoder, b.right_encoder);
    assert_eq!(
        (l.kind, r.kind),
        (EncoderKind::OneChannel, EncoderKind::OneChannel)
    );
    assert_eq!((l.a.name(), l.b), ("D2".into(), None));
    assert_eq!((r.a.name(), r.b), ("D3".into(), None));
    assert_eq!(l.lines().len(), 1);
    assert!(l.interrupt_line(true, false) && l.interrupt_line(true, true));
    // A on a pin-change pin (D11, PCINT3) is as good as on INT1.
    let pcint = text.replacen(r#"a = "D3""#, r#"a = "D11""#, 1);
    let b = Board::from_toml_str(&pcint, "one.toml").unwrap();
    assert_eq!(b.right_encoder.a.interrupt_vector(), Some(3), "PCINT0");
    // The same pins on a Mega: its D4 (PG5) has no INTn or PCINTn.
    let mega =
        text.replacen("mcu = \"atmega328p\"", "", 1)
            .replacen(r#"a = "D3""#, r#"a = "D4""#, 1);
    let p = match Board::from_toml_str(&mega, "one.toml") {
        Err(BoardError::Invalid(p)) => p,
        other => panic!("{other:?}"),
    };
    let line = p
        .iter()
        .find(|p| p.field == "encoders.right.a")
        .unwrap_or_else(|| panic!("{p:#?}"))
        .to_string();
    assert!(
        line.contains(
            "D4 cannot interrupt (no INTn or PCINTn), so the firmware would miss channel A's edges"
        ),
        "{line}"
    );
}

/// Every pin a timer's compare output reaches has an Arduino number on each
/// described MCU (the Arduino cores give every OCnx pin one), so a PWM input
/// named by port and bit is never refused for lacking one: "PB5" on the
/// Romi is its D9, OC1A, as the board's "D9" is. Only a direction input can
/// be on a pin with no number (the 32U4's PE2), and that is refused.
#[test]
fn every_pwm_pin_has_an_arduino_number_and_may_be_named_by_port() {
    for mcu in Mcu::ALL {
        let chip = mcu.chip();
        let mut pwm_pins = 0;
        for port in chip.ports {
            for bit in 0..port.bits {
                let Some(pin) = hil::board::Pin::on_port(mcu, port.letter, bit) else {
                    continue;
                };
                if !pin.pwm_sources().is_empty() {
                    pwm_pins += 1;
                    assert!(pin.arduino.is_some(), "{mcu} P{}{bit}", port.letter);
                }
            }
        }
        // ATmega2560: 15 OCnx pins (OC0A and OC1C share PB7); 328P: 6; 32U4: 7
        // (PB7 OC0A/OC1C, PD0, PB5 OC1A, PB6 OC1B/OC4B, PC6, PC7, PD7; the
        // complementary outputs are not described).
        let expected = match mcu {
            Mcu::Atmega2560 => 15,
            Mcu::Atmega328p => 6,
            Mcu::Atmega32u4 => 7,
        };
        assert_eq!(pwm_pins, expected, "{mcu}");
    }
    let text = std::fs::read_to_string(
        hil::paths::workspace_root().join("fixtures/boards/romi-32u4.toml"),
    )
    .unwrap();
    assert!(text.contains(r#"enable = "D9""#));
    let by_port = Board::from_toml_str(
        &text.replacen(r#"enable = "D9""#, r#"enable = "PB5""#, 1),
        "r.toml",
    )
    .unwrap();
    let by_number =
        Board::load(hil::paths::workspace_root().join("fixtures/boards/romi-32u4.toml")).unwrap();
    assert_eq!(by_port, by_number);
}
