//! `hil serve --pty` as plain clients meet it: one client at a time on the
//! pty (a second open is refused, the first gets every reply whole), the
//! robot's bytes kept while no client is there and delivered to the next,
//! and the thesis build's USB serial (USART0) readable on the second pty.
//! The clients here are plain file opens, as `cat` or a script's `open()`
//! would make (no serial library sets the exclusive mode for them), and
//! Debian's pyserial.

#[path = "support/mod.rs"]
mod support;

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::fs::{MetadataExt, OpenOptionsExt};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use henrytwo_protocol::message::{Command as Cmd, NOTIFY_TEST_DONE};
use henrytwo_protocol::param::Param;
use hil::clients::station::client::{Link, LinkOptions};
use hil::firmware::link::{frame, replies};

/// `hil serve --pty` of `build` at 10x: the child, the pty and the USB pty.
fn serve(build: &str) -> (Killed, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["serve", "--pty", "--speed", "10", "--elf"])
        .arg(support::firmware_path(build))
        .arg("--robot")
        .arg(hil::paths::robot_config("henrytwo-ideal"))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("hil serve starts");
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut line = |prefix: &str| {
        let mut l = String::new();
        out.read_line(&mut l).unwrap();
        l.trim()
            .strip_prefix(prefix)
            .unwrap_or_else(|| panic!("no {prefix:?} line in {l:?}"))
            .to_string()
    };
    let pty = line("pty: ");
    let usb = line("usb pty: ");
    (Killed(child), pty, usb)
}

/// The pty opened as a plain file, never blocking.
fn open(path: &str) -> File {
    std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(nix::libc::O_NONBLOCK | nix::libc::O_NOCTTY)
        .open(path)
        .unwrap_or_else(|e| panic!("open {path}: {e}"))
}

/// Read from `f` until `done` holds of everything read, or `secs` pass.
fn read_until(f: &mut File, secs: u64, done: impl Fn(&[u8]) -> bool) -> Vec<u8> {
    let deadline = Instant::now() + Duration::from_secs(secs);
    let mut got = Vec::new();
    let mut buf = [0u8; 256];
    while !done(&got) && Instant::now() < deadline {
        match f.read(&mut buf) {
            Ok(n) if n > 0 => got.extend_from_slice(&buf[..n]),
            _ => std::thread::sleep(Duration::from_millis(20)),
        }
    }
    got
}

/// Open `path` from another process, as an ordinary user would: without
/// `CAP_SYS_ADMIN`, which the kernel lets through a tty's exclusive mode
/// (dropped with setpriv when the tests run as root). Its stderr on failure.
fn second_open(path: &str) -> Result<(), String> {
    let open = ["sh", "-c", "exec 3<>\"$0\"", path];
    // /proc/self belongs to the process's effective user.
    let root = std::fs::metadata("/proc/self").is_ok_and(|m| m.uid() == 0);
    let mut cmd = if root {
        let mut c = Command::new("setpriv");
        c.args(["--bounding-set=-sys_admin", "--"]).args(open);
        c
    } else {
        let mut c = Command::new(open[0]);
        c.args(&open[1..]);
        c
    };
    let out = cmd.output().expect("sh (and setpriv, as root) run");
    if out.status.success() {
        Ok(())
    } else {
        Err(String::from_utf8_lossy(&out.stderr).into_owned())
    }
}

/// The emulator sees a client come or go within a slice; a few here.
fn settle() {
    std::thread::sleep(Duration::from_millis(300));
}

#[test]
fn a_second_client_is_refused_and_the_first_gets_every_reply_whole() {
    let (_serve, pty, _) = serve("robust");
    let mut first = open(&pty);
    settle();
    let refused = second_open(&pty).expect_err("a second client opened the pty");
    assert!(refused.contains("busy"), "{refused}");

    for _ in 0..10 {
        first.write_all(&frame(&Cmd::Ping)).unwrap();
    }
    let ping = Cmd::Ping.id().reply_id();
    let got = read_until(&mut first, 20, |b| replies(b).len() >= 10);
    let r = replies(&got);
    assert_eq!(r.len(), 10, "{r:?}");
    assert!(r.iter().all(|r| r.id == ping && r.ok), "{r:?}");

    // A client that closes lets the next one in.
    drop(first);
    settle();
    second_open(&pty).expect("the pty is free again");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_notification_sent_with_no_client_reaches_the_next_one() {
    let (_serve, pty, _) = serve("robust");
    {
        let mut a = Link::open_serial(&pty, 9600, LinkOptions::default()).unwrap();
        a.set_param(Param::LegLengthMm, 200.0).await.unwrap();
        a.start(henrytwo_protocol::message::Test::Line)
            .await
            .unwrap();
    }
    // 200 mm and the braking take about 3 s of robot time: 0.3 s here;
    // the TEST_DONE goes out while no client has the pty.
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let mut b = open(&pty);
    let got = read_until(&mut b, 10, |bytes| {
        replies(bytes).iter().any(|r| r.id == NOTIFY_TEST_DONE)
    });
    let r = replies(&got);
    assert!(r.iter().any(|r| r.id == NOTIFY_TEST_DONE), "{r:?}");
}

#[test]
fn the_thesis_builds_usb_serial_is_on_the_second_pty() {
    let (_serve, pty, usb) = serve("thesis");
    assert_ne!(pty, usb);
    // Its greeting, printed at boot before any client came.
    let mut serial = open(&usb);
    let greeting = b"Realizacion de test...\r\n";
    let got = read_until(&mut serial, 10, |b| b.ends_with(greeting));
    assert_eq!(got, greeting, "{}", String::from_utf8_lossy(&got));
    // The selector byte on the Bluetooth UART, echoed on the USB serial.
    let mut bluetooth = open(&pty);
    settle();
    bluetooth.write_all(&[1]).unwrap();
    let got = read_until(&mut serial, 10, |b| b.ends_with(b"1\r\n"));
    assert_eq!(got, b"1\r\n", "{}", String::from_utf8_lossy(&got));
}

/// Debian's pyserial (python3-serial, under the system's python3) as a
/// script would use it: `serial.Serial(pty, 9600)`, which sets the line up
/// and flushes its input right after opening, then three PINGs written.
#[test]
fn pyserial_gets_its_pings_answered() {
    let (_serve, pty, _) = serve("robust");
    let script = r#"
import sys, time, serial
port = serial.Serial(sys.argv[1], 9600, timeout=0.1)
port.write(bytes.fromhex(sys.argv[2]) * 3)
got, quiet_since = b"", time.time()
while time.time() - quiet_since < (1.0 if got else 10.0):
    chunk = port.read(256)
    if chunk:
        got, quiet_since = got + chunk, time.time()
print(got.hex())
"#;
    let ping: String = frame(&Cmd::Ping)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let out = Command::new("/usr/bin/python3")
        .args(["-c", script, &pty, &ping])
        .output()
        .expect("the system's python3 runs (tools/setup.sh installs python3-serial)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let hex = String::from_utf8_lossy(&out.stdout);
    let got: Vec<u8> = (0..hex.trim().len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex.trim()[i..i + 2], 16).unwrap())
        .collect();
    let r = replies(&got);
    assert_eq!(r.len(), 3, "{r:?}");
    assert!(
        r.iter().all(|r| r.id == Cmd::Ping.id().reply_id() && r.ok),
        "{r:?}"
    );
}

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}
