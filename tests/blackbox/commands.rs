//! The commands with a described firmware (`--tests`): `hil test`'s serial
//! text in its reports, `hil line`, `--gdb`, `hil serve`, `hil bench`
//! and `hil faults` (`hil ui`: tests/station_described.rs).

use super::*;

/// `hil` in the repository's root with `args`: exit code, stdout, stderr.
fn hil_cli(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh path in the temporary folder for an output file.
fn temp_file(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("hil-blackbox-{}-{name}", std::process::id()))
}

/// The sketch's `Serial` prints (USART0, the board's `debug_uart`) are in
/// `hil test`'s JSON, bytes and text, and in its JUnit case's system-out;
/// the command link (`command_uart`) is named too, though the sketch sends
/// nothing on it.
#[test]
fn a_sketchs_serial_text_is_in_the_json_and_the_junit_report() {
    let junit = temp_file("serial.xml");
    let (code, out, err) = hil_cli(&[
        "test",
        "fixtures/arduino/square-demo/square.toml",
        "--tests",
        DEMO_TESTS,
        "--json",
        "--junit",
        junit.to_str().unwrap(),
    ]);
    let xml = std::fs::read_to_string(&junit).unwrap_or_default();
    let _ = std::fs::remove_file(&junit);
    assert_eq!(code, Some(0), "{err}\n{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let case = &v[0];
    assert_eq!(case["firmware"], "square-demo", "{case}");
    let uarts = case["uarts"].as_array().expect("uarts");
    let serial = &uarts[0];
    assert_eq!(
        (&serial["name"], &serial["usart"], &serial["baud"]),
        (
            &serde_json::json!("debug_uart"),
            &serde_json::json!(0),
            &serde_json::json!(9600)
        ),
        "{serial}"
    );
    let text = serial["text"].as_str().unwrap();
    assert!(
        text.starts_with("square-demo ready: send 'g' on Serial1\r\nstart\r\nleg 1\r\n")
            && text.ends_with("\r\ndone\r\n"),
        "{text}"
    );
    let bytes: Vec<u8> = serial["bytes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_u64().unwrap() as u8)
        .collect();
    assert_eq!(bytes, text.as_bytes());
    assert_eq!(uarts[1]["name"], "command_uart", "{}", uarts[1]);
    assert_eq!(uarts[1]["usart"], 1);
    assert!(
        xml.contains("<system-out>debug_uart (USART0, 9600 baud): ")
            && xml.contains("  | square-demo ready: send &apos;g&apos; on Serial1\n")
            && xml.contains("  | done\n"),
        "{xml}"
    );
}

/// `hil line --tests` runs the description's line (its own 400 mm) and
/// reports it as `hil run line` does, the sketch's Serial text included.
#[test]
fn hil_line_runs_a_described_line() {
    let (code, out, err) = hil_cli(&["line", "--tests", THESIS_TESTS, "--deterministic", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (&v["test"], &v["firmware"], &v["completed"]),
        (
            &serde_json::json!("line"),
            &serde_json::json!("henrytwo-thesis"),
            &serde_json::json!(true)
        )
    );
    let legs = v["legs"].as_array().unwrap();
    assert_eq!(legs.len(), 1, "{v}");
    let mm = legs[0]["plant_distance_mm"].as_f64().unwrap();
    assert!((mm - 400.0).abs() < 20.0, "{mm}");
    assert!(
        v["uarts"][0]["text"]
            .as_str()
            .unwrap()
            .contains("Realizacion de test"),
        "{}",
        v["uarts"][0]
    );
    let (code, _, err) = hil_cli(&["line", "--tests", THESIS_TESTS, "--length-mm", "300"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("legs are 400 mm"), "{err}");
}

/// `--gdb` debugs a described firmware: paused at its reset vector until
/// avr-gdb continues, then the run without a debugger, byte for byte.
#[test]
fn a_described_run_is_debugged_as_it_runs_without_gdb() {
    use std::io::{BufRead, BufReader, Read};
    use std::process::Stdio;
    let args = [
        "run",
        "line",
        "--tests",
        THESIS_TESTS,
        "--deterministic",
        "--json",
    ];
    let (code, plain, err) = hil_cli(&args);
    assert_eq!(code, Some(0), "{err}");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(args)
        .args(["--gdb", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    stderr.read_line(&mut line).unwrap();
    let addr = line
        .rsplit("target remote ")
        .next()
        .and_then(|a| a.trim().strip_suffix('\''))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    let mut stdout = child.stdout.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        stdout.read_to_string(&mut s).unwrap();
        s
    });
    let (_, fw) = described(THESIS_TESTS);
    let gdb = Command::new("avr-gdb")
        .args(["-q", "-nx", "-batch"])
        .arg(&fw.path)
        .args(["-ex", &format!("target remote {addr}")])
        .args(["-ex", "print/x $pc", "-ex", "continue"])
        .output()
        .expect("avr-gdb runs (tools/setup.sh installs gdb-avr)");
    let gdb = format!(
        "{}{}",
        String::from_utf8_lossy(&gdb.stdout),
        String::from_utf8_lossy(&gdb.stderr)
    );
    let status = child.wait().unwrap();
    let debugged = reader.join().unwrap();
    assert!(status.success(), "{gdb}");
    assert!(
        gdb.contains("$1 = 0x0"),
        "paused at the reset vector: {gdb}"
    );
    assert!(gdb.contains("exited normally"), "{gdb}");
    assert!(debugged == plain, "{debugged}\n--- without gdb:\n{plain}");
}

/// `hil serve --tests` serves a described firmware: ready as its
/// description says (its boot text on the USB pty), told nothing, its test
/// started by the bytes the description names, which the command prints.
#[test]
fn hil_serve_serves_a_described_firmware() {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::os::unix::fs::OpenOptionsExt;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .current_dir(hil::paths::workspace_root())
        .args(["serve", "--pty", "--speed", "10", "--tests", DEMO_TESTS])
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
    let (pty, usb) = (line("pty: "), line("usb pty: "));
    let mut said = String::new();
    for _ in 0..2 {
        err.read_line(&mut said).unwrap();
    }
    assert!(
        said.contains(&format!(
            "test umbmark-ccw ({DEMO_TESTS}) starts: send \"g\" on USART1: the pty"
        )),
        "{said}"
    );
    let open = |p: &str| {
        std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(nix::libc::O_NONBLOCK | nix::libc::O_NOCTTY)
            .open(p)
            .unwrap()
    };
    let (mut command, mut serial) = (open(&pty), open(&usb));
    let read_until = |f: &mut std::fs::File, text: &str| {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        while !contains(&got, text.as_bytes()) && std::time::Instant::now() < deadline {
            match f.read(&mut buf) {
                Ok(n) if n > 0 => got.extend_from_slice(&buf[..n]),
                _ => std::thread::sleep(std::time::Duration::from_millis(20)),
            }
        }
        String::from_utf8_lossy(&got).into_owned()
    };
    let boot = read_until(&mut serial, "square-demo ready");
    assert!(boot.contains("square-demo ready"), "{boot:?}");
    command.write_all(b"g").unwrap();
    let started = read_until(&mut serial, "leg 1\r\n");
    assert!(started.contains("start\r\nleg 1\r\n"), "{started:?}");
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

/// `hil bench --tests` times the described firmware against raw simavr on
/// the same inputs, labelled by its name.
#[test]
fn hil_bench_times_a_described_firmware() {
    let (code, out, err) = hil_cli(&[
        "bench",
        "--tests",
        THESIS_TESTS,
        "--test",
        "line",
        "--repeats",
        "1",
        "--without-simavr-pwm",
        "--json",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["firmware"], "henrytwo-thesis", "{v}");
    assert_eq!(v["robust"]["completed"], true, "{v}");
    assert!(v["overhead_ratio"].as_f64().unwrap() > 0.0, "{v}");
    assert!(v["thesis"].is_null() && v["sketch"].is_null(), "{v}");
    let (code, _, err) = hil_cli(&["bench", "--tests", DEMO_TESTS, "--test", "line"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("describes no line test"), "{err}");
}

/// `hil faults --tests` names the described firmware, not "robust", in its
/// text, JSON and JUnit (with what it printed on each USART).
#[test]
fn hil_faults_labels_a_described_firmware_by_its_name() {
    let junit = temp_file("faults.xml");
    let (code, out, err) = hil_cli(&[
        "faults",
        "--tests",
        THESIS_TESTS,
        "--fault",
        "motor-stall",
        "--junit",
        junit.to_str().unwrap(),
    ]);
    let xml = std::fs::read_to_string(&junit).unwrap_or_default();
    let _ = std::fs::remove_file(&junit);
    assert!(matches!(code, Some(0 | 1)), "{err}");
    assert!(out.contains("\n  henrytwo-thesis "), "{out}");
    assert!(!out.contains("\n  robust "), "{out}");
    assert!(
        xml.contains("<property name=\"firmware\" value=\"henrytwo-thesis\"/>")
            && xml.contains("henrytwo-thesis: ")
            && xml.contains("debug_uart (USART0, 9600 baud): "),
        "{xml}"
    );
}
