//! `hil serve --pty` as a serial client meets it: the bench's own client
//! opens the pseudo-terminal with tokio-serial exactly as it would a real
//! port, talks the framed protocol to the emulated robot, runs a test to its
//! notification, and gets a clear error when the port goes away.

#[path = "support/mod.rs"]
mod support;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use henrytwo_protocol::message::{RunState, Test, VERSION};
use henrytwo_protocol::param::Param;
use hil::clients::station::client::{Link, LinkError, LinkOptions, Notice};

/// `hil serve --pty` at `speed`, and the pty path it printed.
fn serve(speed: &str) -> (Child, String) {
    let elf = support::firmware_path("robust");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["serve", "--pty", "--speed", speed, "--elf"])
        .arg(elf)
        .arg("--robot")
        .arg(hil::paths::robot_config("henrytwo-ideal"))
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("hil serve starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let path = line
        .trim()
        .strip_prefix("pty: ")
        .unwrap_or_else(|| panic!("no pty path in {line:?}"))
        .to_string();
    (child, path)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_served_robot_answers_on_its_pty_like_a_serial_port() {
    let (mut child, path) = serve("10");
    let mut link = Link::open_serial(&path, 9600, LinkOptions::default()).unwrap();
    assert_eq!(link.ping().await.unwrap(), VERSION);

    // Parameters round trip through the firmware's own protocol code.
    assert_eq!(
        link.set_param(Param::LegLengthMm, 300.0).await.unwrap(),
        300.0
    );
    assert_eq!(link.get_param(Param::LegLengthMm).await.unwrap(), 300.0);
    assert_eq!(link.set_param(Param::CorrLeft, 1.004).await.unwrap(), 1.004);
    assert_eq!(link.get_param(Param::CorrLeft).await.unwrap(), 1.004);
    let refused = link.set_param(Param::CorrLeft, 7.0).await.unwrap_err();
    assert!(matches!(refused, LinkError::OutOfRange { .. }), "{refused}");

    // A 300 mm line: driving shortly after the start, done by notification.
    let before = link.state().await.unwrap();
    assert_eq!(before.state, RunState::Idle as u8);
    link.start(Test::Line).await.unwrap();
    let mut moved = false;
    let mut done = None;
    for _ in 0..100 {
        let t = link.telemetry().await.unwrap();
        moved |= t.left_count > 0 && t.right_count > 0;
        if let Some(n) = link
            .wait_notices(Duration::from_millis(100))
            .await
            .unwrap()
            .into_iter()
            .find(|n| matches!(n, Notice::TestDone { .. }))
        {
            done = Some(n);
            break;
        }
    }
    assert!(moved, "the wheels never turned");
    assert_eq!(
        done,
        Some(Notice::TestDone {
            test: Test::Line as u8,
            tests_done: before.tests_done + 1
        })
    );
    // About 300 mm of counts per wheel (0.167 mm per count).
    let t = link.telemetry().await.unwrap();
    for c in [t.left_count, t.right_count] {
        assert!((1700..=1900).contains(&c), "counts {c}");
    }

    // The emulator goes away: the next command says so, it does not hang.
    child.kill().unwrap();
    child.wait().unwrap();
    let e = link.ping().await.unwrap_err();
    assert!(matches!(e, LinkError::PortGone { .. }), "{e}");
    assert!(e.to_string().contains("reconnect"), "{e}");
}

/// Clients come and go: one starts a test and leaves, the robot finishes it
/// while nobody has the pty, the next client opens the same pty (one client
/// at a time) and gets its own replies; the notification kept for it in
/// between is passed over by the client (tests/pty.rs checks it arrives).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_second_client_opens_the_pty_after_the_first() {
    let (child, path) = serve("10");
    let _kill = Killed(child);
    {
        let mut a = Link::open_serial(&path, 9600, LinkOptions::default()).unwrap();
        a.set_param(Param::LegLengthMm, 200.0).await.unwrap();
        a.start(Test::Line).await.unwrap();
    }
    // 200 mm and the braking take about 3 s of robot time: 0.3 s here.
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let mut b = Link::open_serial(&path, 9600, LinkOptions::default()).unwrap();
    assert_eq!(b.ping().await.unwrap(), VERSION);
    assert_eq!(b.get_param(Param::LegLengthMm).await.unwrap(), 200.0);
    let s = b.state().await.unwrap();
    assert_eq!((s.state, s.tests_done), (RunState::Idle as u8, 1));
}

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn serve_refuses_a_speed_of_zero_in_one_line() {
    let elf = support::firmware_path("robust");
    let out = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(["serve", "--pty", "--speed", "0", "--elf"])
        .arg(elf)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("speed 0: give a factor from 0.001 to 1000"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
}
