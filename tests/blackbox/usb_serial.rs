//! The ATmega32U4's USB serial, served by the bench as the USB host: a
//! Leonardo sketch of our own (`fixtures/arduino/usb-serial`: `while
//! (!Serial)`, a ready line, an answer to each byte) on a Leonardo board
//! (`fixtures/boards/leonardo-usb.toml`).

use super::*;
use hil::bench::{Bench, UsbState, USB_SERIAL};

const USB_TESTS: &str = "fixtures/arduino/usb-serial/tests.toml";
const LEONARDO: &str = "fixtures/boards/leonardo-usb.toml";

fn leonardo() -> hil::board::Board {
    hil::board::Board::load(hil::paths::workspace_root().join(LEONARDO)).expect("the board loads")
}

/// A description's path of this process's own, in the temporary folder.
fn temp_file(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("hil-usb-{}-{name}.toml", std::process::id()))
}

/// The echo test, recorded (every byte with its cycle).
fn echo() -> TestRun {
    let (d, fw) = described(USB_TESTS);
    let opts = TestOptions {
        leg_mm: d.leg_mm(None, 2000.0).unwrap(),
        bench: BenchOptions {
            board: leonardo(),
            ..Default::default()
        },
        record: true,
        description: Some(d),
        ..Default::default()
    };
    run_test(
        fw,
        &support::robot("uno-l298n"),
        TestName::parse("echo").unwrap(),
        &opts,
    )
    .expect("the bench runs the sketch")
}

/// From reset, the host sees the sketch attach, resets the bus and
/// enumerates it request by request up to the open port (DTR set): the
/// state `while (!Serial)` waits for, after which the sketch's first line
/// comes.
#[test]
fn the_host_enumerates_the_leonardo_and_opens_its_serial() {
    let (_, fw) = described(USB_TESTS);
    let opts = BenchOptions {
        board: leonardo(),
        ..Default::default()
    };
    let mut bench = Bench::new(fw, &support::robot("uno-l298n"), opts).unwrap();
    bench.run_for(0.5).unwrap();
    assert_eq!(bench.usb_state(), Some(&UsbState::Open));
    let events: Vec<&str> = bench.usb_events().iter().map(|(_, e)| *e).collect();
    assert_eq!(
        events,
        [
            "attached",
            "bus reset",
            "GET_DESCRIPTOR (device)",
            "SET_ADDRESS",
            "GET_DESCRIPTOR (configuration, 9 bytes)",
            "GET_DESCRIPTOR (configuration)",
            "SET_CONFIGURATION",
            "SET_LINE_CODING",
            "SET_CONTROL_LINE_STATE (DTR)",
        ]
    );
    let cycles: Vec<u64> = bench.usb_events().iter().map(|(c, _)| *c).collect();
    assert!(cycles.windows(2).all(|w| w[0] < w[1]), "{cycles:?}");
    assert_eq!(bench.uart_output(USB_SERIAL), b"usb-serial ready\r\n");
}

/// The sketch's prints arrive in the report as the USARTs' do, and the
/// bytes the test sends reach it: it answers each ('a', then 'q'), in
/// order, and the run ends at its "done".
#[test]
fn the_sketch_prints_and_answers_over_usb_in_the_report() {
    let r = echo();
    assert!(r.completed, "{:?}", r.finding);
    let usb = r
        .uarts
        .iter()
        .find(|u| u.name == "usb_serial")
        .expect("the report has the USB serial");
    assert_eq!(usb.usart, USB_SERIAL);
    assert_eq!(usb.text, "usb-serial ready\r\ngot a\r\ngot q\r\ndone\r\n");
    let sent: Vec<u8> = r
        .uart_rx
        .iter()
        .filter(|(_, n, _)| *n == USB_SERIAL)
        .map(|(_, _, b)| *b)
        .collect();
    assert_eq!(sent, b"aq");
    let text = hil::runs::experiment::uarts::render(&r.uarts, "");
    assert!(
        text.contains("usb_serial (USB CDC): 38 bytes, text:\n  | usb-serial ready\n"),
        "{text}"
    );
}

/// The same run twice: the same bytes, each way, at the same cycles.
#[test]
fn a_usb_run_repeats_to_the_cycle() {
    let usb = |r: &TestRun| {
        let f = |log: &[(u64, u8, u8)]| -> Vec<(u64, u8)> {
            log.iter()
                .filter(|(_, n, _)| *n == USB_SERIAL)
                .map(|(c, _, b)| (*c, *b))
                .collect()
        };
        (f(&r.uart), f(&r.uart_rx))
    };
    let (a, b) = (usb(&echo()), usb(&echo()));
    assert_eq!(a.0.len(), 38);
    assert_eq!(a, b);
}

/// Text awaited on the USB serial that never comes says where the host got
/// with the device: here the ready wait ends before the bus reset (100 ms
/// after the sketch attaches), so the sketch never enumerated.
#[test]
fn a_sketch_not_enumerated_within_the_wait_says_so() {
    let file = temp_file("unenumerated");
    let text = std::fs::read_to_string(hil::paths::workspace_root().join(USB_TESTS))
        .unwrap()
        .replace("after_s = 2.0", "after_s = 0.05")
        .replace(
            "../../../firmware",
            &hil::paths::workspace_root()
                .join("firmware")
                .display()
                .to_string(),
        );
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(["run", "echo", "--tests"])
        .arg(&file)
        .args([
            "--board",
            LEONARDO,
            "--robot",
            "fixtures/robots/uno-l298n.toml",
        ])
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&file);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("did not send \"usb-serial ready\" on the USB serial after reset (ready.text); USB: attached, waiting for the bus reset"),
        "{err}"
    );
}

/// A description that names the USB serial, for a board whose MCU has
/// none: one line, exit 2, before the run.
#[test]
fn usb_on_an_mcu_without_usb_is_refused() {
    let file = temp_file("uno-usb");
    let text = std::fs::read_to_string(
        hil::paths::workspace_root().join("fixtures/arduino/uno-l298n/tests.toml"),
    )
    .unwrap()
    .replace("[end]                   # it prints \"done\" after its counts, once stopped after its spin\nuart = 0", "[end]\nuart = \"usb\"")
    .replace("../../../firmware", &hil::paths::workspace_root().join("firmware").display().to_string());
    assert!(text.contains("uart = \"usb\""));
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(["run", "leg-and-spin", "--tests"])
        .arg(&file)
        .args([
            "--board",
            "fixtures/boards/uno-l298n.toml",
            "--robot",
            "fixtures/robots/uno-l298n.toml",
        ])
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&file);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(
        err.trim(),
        format!(
            "error: {}: end.uart = \"usb\": the board's atmega328p has no USB; give one of its USARTs (0)",
            file.display()
        )
    );
}
