//! `hil ui --tests FILE` drives a described firmware's tests: the square-demo
//! sketch (no bench protocol, started by a 'g' on USART1) offered by its
//! description's test names, its own test (half-square) started through the
//! station's HTTP API, its progress live on the event stream (legs, turns,
//! pose, the sketch's Serial text) and its report at the end: the numbers
//! `hil run half-square --tests FILE` gives, since the station runs it so.

#[path = "support/mod.rs"]
mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const DEMO_TESTS: &str = "fixtures/arduino/square-demo/tests.toml";
const ROBOT: &str = "henrytwo-ideal";

/// Kills a child process when the test ends, passed or not.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// One HTTP/1.1 request on its own connection: the status and the JSON body.
fn http(addr: &str, method: &str, path: &str, body: Option<&str>) -> (u16, serde_json::Value) {
    let mut s = TcpStream::connect(addr).unwrap();
    let body = body.unwrap_or("");
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\
         Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    let mut reply = String::new();
    s.read_to_string(&mut reply).unwrap();
    let status = reply[9..12].parse().unwrap();
    let (_, json) = reply.split_once("\r\n\r\n").unwrap();
    (
        status,
        serde_json::from_str(json).unwrap_or(serde_json::Value::Null),
    )
}

#[test]
fn the_station_runs_a_described_test_as_hil_run_does() {
    let sessions = std::env::temp_dir().join(format!("station-described-{}", std::process::id()));
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args([
            "ui",
            "--listen-port",
            "0",
            "--tests",
            DEMO_TESTS,
            "--sessions",
        ])
        .arg(&sessions)
        .current_dir(hil::paths::workspace_root())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("hil ui starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let _ui = Killed(child);
    let addr = line
        .trim()
        .strip_prefix("http://")
        .and_then(|a| a.strip_suffix('/'))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();

    // The page's list is the description's tests.
    let (_, robots) = http(&addr, "GET", "/api/robots", None);
    assert_eq!(
        robots["tests"],
        serde_json::json!(["umbmark-ccw", "half-square"])
    );
    // A real robot on a port is refused in words (no protocol to start it by).
    let (code, e) = http(
        &addr,
        "POST",
        "/api/connect",
        Some(r#"{"kind":"serial","port":"/dev/null","baud":9600}"#),
    );
    assert_eq!(code, 400, "{e}");
    assert!(
        e["error"].as_str().unwrap().contains("emulated robot"),
        "{e}"
    );
    let (code, c) = http(
        &addr,
        "POST",
        "/api/connect",
        Some(&format!(
            r#"{{"kind":"emulated","config":"{ROBOT}","speed":200}}"#
        )),
    );
    assert_eq!(code, 200, "{c}");
    assert_eq!(c["described"]["firmware"], "square-demo");

    // The event stream, open before the start.
    let mut events = TcpStream::connect(&addr).unwrap();
    write!(events, "GET /api/events HTTP/1.1\r\nHost: {addr}\r\n\r\n").unwrap();
    events
        .set_read_timeout(Some(Duration::from_secs(5)))
        .unwrap();
    let mut events = BufReader::new(events);
    // A name the description does not have is refused, naming those it has.
    let (code, e) = http(&addr, "POST", "/api/start", Some(r#"{"test":"line"}"#));
    assert_eq!(code, 400, "{e}");
    assert!(e["error"].as_str().unwrap().contains("half-square"), "{e}");
    let (code, s) = http(
        &addr,
        "POST",
        "/api/start",
        Some(r#"{"test":"half-square"}"#),
    );
    assert_eq!(code, 200, "{s}");
    assert_eq!(s["leg_mm"], 501.0);

    let mut live = Vec::new();
    let mut end = None;
    let deadline = Instant::now() + Duration::from_secs(120);
    while end.is_none() && Instant::now() < deadline {
        let mut l = String::new();
        if events.read_line(&mut l).is_err() || l.is_empty() {
            continue;
        }
        let Some(data) = l.trim().strip_prefix("data:") else {
            continue;
        };
        let ev: serde_json::Value = serde_json::from_str(data.trim()).unwrap();
        match ev["kind"].as_str() {
            Some("described") => live.push(ev),
            Some("described_end") => end = Some(ev),
            Some("error") => panic!("{ev}"),
            _ => {}
        }
    }
    let end = end.expect("the described test's end on the event stream");
    let run = &end["run"];
    assert_eq!(end["test"], "half-square");
    assert_eq!(run["completed"], true, "{run}");

    // Live: the progress went through both legs and both turns, with the
    // pose moving and the sketch's Serial text (USART0, debug_uart) as it came.
    let count = |ev: &serde_json::Value, what: &str| ev[what].as_array().unwrap().len();
    for (legs, turns) in [(1, 0), (2, 1)] {
        assert!(
            live.iter()
                .any(|e| count(e, "legs") == legs && count(e, "turns") == turns),
            "no live event with {legs} legs and {turns} turns"
        );
    }
    let moved = live
        .iter()
        .map(|e| e["pose"]["x_mm"].as_f64().unwrap())
        .fold(f64::MIN, f64::max);
    assert!(
        moved > 400.0,
        "the live pose never went along the first leg: {moved} mm"
    );
    let serial: String = live
        .iter()
        .flat_map(|e| e["uarts"].as_array().unwrap().clone())
        .filter(|u| u["usart"] == 0)
        .map(|u| u["text"].as_str().unwrap().to_string())
        .collect();
    assert!(serial.starts_with("square-demo ready"), "{serial:?}");
    assert!(serial.contains("turn 1 end"), "{serial:?}");

    // The report is hil run's, number for number.
    let out = support::hil_at_root(&[
        "run",
        "half-square",
        "--tests",
        DEMO_TESTS,
        "--robot",
        &hil::paths::robot_config(ROBOT).to_string_lossy(),
        "--json",
        "--deterministic",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let cli = support::json_report(&out);
    let cli = cli.get("runs").and_then(|r| r.get(0)).unwrap_or(&cli);
    for field in ["legs", "turns", "final_pose", "robot_time_s", "uarts"] {
        assert_eq!(run[field], cli[field], "{field}");
    }
    assert_eq!(count(run, "legs"), 2);
    assert_eq!(count(run, "turns"), 2);
    let _ = std::fs::remove_dir_all(&sessions);
}
