//! The ATmega32U4's USB serial, served by the bench as the USB host: a
//! Leonardo sketch of our own (`fixtures/arduino/usb-serial`: `while
//! (!Serial)`, a ready line, an answer to each byte) on a Leonardo board
//! (`fixtures/boards/leonardo-usb.toml`); its bytes in a VCD and on
//! `hil serve`'s USB pty, and `hil ui`'s refusal.

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

/// `hil run --vcd` on the Leonardo: the USB serial's bytes are in the trace
/// as a USART's are (each byte's value and the line's text, both ways; no
/// 8N1 line: USB has none), the sketch's in the order it printed them and
/// the test's "aq" the other way.
#[test]
fn the_usb_serials_bytes_are_in_the_vcd() {
    let vcd = std::env::temp_dir().join(format!("hil-usb-{}-echo.vcd", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(["run", "echo", "--tests", USB_TESTS, "--board", LEONARDO])
        .args(["--robot", "fixtures/robots/uno-l298n.toml", "--vcd"])
        .arg(&vcd)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&vcd).unwrap();
    let _ = std::fs::remove_file(&vcd);
    let _ = std::fs::remove_file(vcd.with_extension("gtkw"));
    // A variable's id by its name, then its values after the header.
    let id = |name: &str| -> String {
        let decl = text
            .lines()
            .find(|l| l.starts_with("$var") && l.split_whitespace().nth(4) == Some(name))
            .unwrap_or_else(|| panic!("no {name} in the VCD's header"));
        decl.split_whitespace().nth(3).unwrap().to_string()
    };
    let body = text
        .split("$dumpvars")
        .nth(1)
        .unwrap()
        .split_once("$end")
        .unwrap()
        .1;
    let bytes = |name: &str| -> Vec<u8> {
        let id = id(name);
        body.lines()
            .filter_map(|l| l.strip_prefix('r')?.strip_suffix(&format!(" {id}")))
            .map(|v| v.parse::<f64>().unwrap() as u8)
            .collect()
    };
    assert_eq!(
        String::from_utf8(bytes("usb_serial_tx_byte")).unwrap(),
        "usb-serial ready\r\ngot a\r\ngot q\r\ndone\r\n"
    );
    assert_eq!(bytes("usb_serial_rx_byte"), b"aq");
    let shown = id("usb_serial_tx_text");
    let ready = format!("susb-serial\\x20ready\\r\\n {shown}");
    assert!(
        body.lines().any(|l| l == ready),
        "no {ready:?} in the trace"
    );
}

/// `hil serve --pty --tests` on the Leonardo: the USB pty is the USB
/// serial itself (the bench its USB host), not a USART: the sketch's ready
/// line comes on it, the command says the test starts there, and a byte
/// written to it is answered on it.
#[test]
fn hil_serve_serves_the_usb_serial_on_the_usb_pty() {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::os::unix::fs::OpenOptionsExt;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args([
            "serve", "--pty", "--speed", "10", "--tests", USB_TESTS, "--board", LEONARDO,
        ])
        .args(["--robot", "fixtures/robots/uno-l298n.toml"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    struct Killed(std::process::Child);
    impl Drop for Killed {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let _child = Killed(child);
    let mut line = |prefix: &str| {
        let mut l = String::new();
        out.read_line(&mut l).unwrap();
        l.trim()
            .strip_prefix(prefix)
            .unwrap_or_else(|| panic!("no {prefix:?} line in {l:?}"))
            .to_string()
    };
    let (_pty, usb) = (line("pty: "), line("usb pty: "));
    let mut said = String::new();
    for _ in 0..2 {
        err.read_line(&mut said).unwrap();
    }
    assert!(
        said.contains("its USB serial (the MCU's USB CDC, the bench its USB host)"),
        "{said}"
    );
    assert!(
        said.contains(&format!(
            "test echo ({USB_TESTS}) starts: send \"aq\" on the USB serial: the usb pty"
        )),
        "{said}"
    );
    let mut serial = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::libc::O_NONBLOCK | nix::libc::O_NOCTTY)
        .open(&usb)
        .unwrap();
    let read_until = |f: &mut std::fs::File, text: &str| {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        while !String::from_utf8_lossy(&got).contains(text) && std::time::Instant::now() < deadline
        {
            match f.read(&mut buf) {
                Ok(n) if n > 0 => got.extend_from_slice(&buf[..n]),
                _ => std::thread::sleep(std::time::Duration::from_millis(20)),
            }
        }
        String::from_utf8_lossy(&got).into_owned()
    };
    assert_eq!(read_until(&mut serial, "ready\r\n"), "usb-serial ready\r\n");
    serial.write_all(b"a").unwrap();
    assert_eq!(read_until(&mut serial, "got a\r\n"), "got a\r\n");
}
