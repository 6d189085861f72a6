//! The bench's gdb stub driven by the real avr-gdb in batch mode (issue 22),
//! and by a raw RSP client for what a batch script cannot do (Ctrl-C):
//! the run under a debugger is the run without one (only continuing, after a
//! breakpoint, with watchpoints, after a refused `load`, after Ctrl-C and
//! steps), a `watch` stops with the old and new values, `monitor reset` and
//! an unknown monitor command, the memory map, a second client refused, the
//! stub's reasons for a refused watchpoint or `load` on gdb's console, and a
//! run killed or abandoned by its debugger ending with exit 3 and saying so.
//!
//! Each session is a `hil run line --leg-mm 300 --deterministic --json`
//! (about 4 s of robot time, under a second of wall time under a debugger);
//! every process is waited for with a deadline, so a hang fails the test.

#[path = "support/mod.rs"]
mod support;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Longer than any session here takes, short enough for CI.
const DEADLINE: Duration = Duration::from_secs(60);

const RUN: [&str; 6] = [
    "run",
    "line",
    "--leg-mm",
    "300",
    "--deterministic",
    "--json",
];

/// What a finished process printed.
struct Finished {
    success: bool,
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Read a pipe to its end on a thread.
fn drain(mut r: impl Read + Send + 'static) -> JoinHandle<String> {
    std::thread::spawn(move || {
        let mut s = String::new();
        let _ = r.read_to_string(&mut s);
        s
    })
}

/// Wait for `child` (its pipes drained by `out` and `err`) at most
/// [`DEADLINE`]; past it the child is killed and the test fails.
fn finish(
    mut child: Child,
    out: JoinHandle<String>,
    err: JoinHandle<String>,
    what: &str,
) -> Finished {
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{what} still running after {DEADLINE:?} (killed); stderr so far:\n{}",
                err.join().unwrap()
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Finished {
        success: status.success(),
        code: status.code(),
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// The run without a debugger: what every debugged run must print.
fn plain_run() -> &'static str {
    static PLAIN: OnceLock<String> = OnceLock::new();
    PLAIN.get_or_init(|| {
        let _ = support::firmware_path("robust");
        let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
            .args(RUN)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("hil runs");
        let (out, err) = (
            drain(child.stdout.take().unwrap()),
            drain(child.stderr.take().unwrap()),
        );
        let f = finish(child, out, err, "hil run");
        assert!(f.success, "{}", f.stderr);
        let v: serde_json::Value = serde_json::from_str(&f.stdout).unwrap();
        assert_eq!(v["completed"], true, "the plain run completes");
        f.stdout
    })
}

/// `hil run ... --gdb 0`, paused at reset: its address, read from the
/// line it prints first.
struct Debugged {
    child: Child,
    addr: String,
    out: JoinHandle<String>,
    err: JoinHandle<String>,
}

impl Debugged {
    fn start() -> Self {
        let _ = support::firmware_path("robust");
        let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
            .args(RUN)
            .args(["--gdb", "0"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("hil runs");
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let mut line = String::new();
        stderr.read_line(&mut line).unwrap();
        let addr = line
            .rsplit("target remote ")
            .next()
            .and_then(|a| a.trim().strip_suffix('\''))
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_string();
        assert!(addr.starts_with("127.0.0.1:"), "loopback only: {addr}");
        let out = drain(child.stdout.take().unwrap());
        let err = drain(stderr);
        Self {
            child,
            addr,
            out,
            err,
        }
    }

    fn finish(self) -> Finished {
        finish(self.child, self.out, self.err, "hil run --gdb")
    }
}

/// avr-gdb in batch mode on the robust ELF, connected to `addr`, running
/// `commands` in order: what it printed (stdout and stderr together, as a
/// user sees them) and whether it succeeded.
fn avr_gdb(addr: &str, commands: &[&str]) -> (String, bool) {
    let elf = support::firmware_path("robust");
    let mut cmd = Command::new("avr-gdb");
    cmd.args(["-q", "-nx", "-batch"])
        .arg(&elf)
        .args(["-ex", &format!("target remote {addr}")]);
    for c in commands {
        cmd.args(["-ex", c]);
    }
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("avr-gdb runs (tools/setup.sh installs gdb-avr)");
    let (out, err) = (
        drain(child.stdout.take().unwrap()),
        drain(child.stderr.take().unwrap()),
    );
    let f = finish(child, out, err, "avr-gdb");
    (format!("{}{}", f.stdout, f.stderr), f.success)
}

/// A debugged run with `commands`, then what hil and avr-gdb printed.
fn session(commands: &[&str]) -> (Finished, String) {
    let hil = Debugged::start();
    let (gdb, _) = avr_gdb(&hil.addr, commands);
    (hil.finish(), gdb)
}

/// The debugged run ended as the plain run does, its output the same.
fn assert_same_run(run: &Finished, gdb: &str, how: &str) {
    assert!(
        run.success,
        "{how}: hil failed: {}\ngdb:\n{gdb}",
        run.stderr
    );
    assert!(
        run.stdout == plain_run(),
        "{how}: the run under avr-gdb differs from the run without it\ngdb:\n{gdb}\n--- without:\n{}\n--- with:\n{}",
        plain_run(),
        run.stdout
    );
    assert!(gdb.contains("exited normally"), "{how}: {gdb}");
}

#[test]
fn the_run_is_the_same_with_and_without_avr_gdb() {
    let (run, gdb) = session(&["continue"]);
    assert_same_run(&run, &gdb, "continue only");

    let (run, gdb) = session(&[
        "break ht_control_tick",
        "continue",
        "print $pc",
        "delete",
        "continue",
    ]);
    assert!(
        gdb.contains("Breakpoint 1, ") && gdb.contains("<robust::ht_control_tick"),
        "the breakpoint is hit: {gdb}"
    );
    assert_same_run(&run, &gdb, "a breakpoint hit, then continue");
}

#[test]
fn a_watchpoint_on_a_firmware_static_stops_with_old_and_new_value() {
    // The ELF's statics carry no type for gdb: cast, in C.
    let (run, gdb) = session(&[
        "set language c",
        "watch *(unsigned char *)&HT_STATE",
        "continue",
        // Between the state's two changes the firmware reads the leg length
        // (a byte at a time) the bench wrote.
        "rwatch *(float *)&HT_LEG_LENGTH_MM",
        "continue",
        "delete 2",
        "continue",
        "delete",
        "continue",
    ]);
    assert!(
        gdb.contains("Hardware watchpoint 1: *(unsigned char *)&HT_STATE"),
        "a hardware watchpoint, not a software one: {gdb}"
    );
    // Idle once initialised, then driving the line on the start command.
    let first = "Old value = 0 '\\000'\nNew value = 1 '\\001'";
    let second = "Old value = 1 '\\001'\nNew value = 2 '\\002'";
    assert!(gdb.contains(first) && gdb.contains(second), "{gdb}");
    assert!(
        gdb.contains("Hardware read watchpoint 2") && gdb.contains("Value = 300"),
        "the firmware reads the leg length the bench wrote: {gdb}"
    );
    assert_same_run(&run, &gdb, "after watchpoints");
}

#[test]
fn monitor_reset_restarts_the_mcu_and_an_unknown_command_is_an_error() {
    let (run, gdb) = session(&[
        "set language c",
        "monitor bogus",
        "break ht_control_tick",
        "continue",
        "delete",
        "monitor reset",
        "maintenance flush register-cache",
        "print/x $pc",
        // MCUSR: the reset pin's flag, EXTRF.
        "print/x *(unsigned char *)0x800054 & 2",
        "kill",
    ]);
    assert!(
        gdb.contains("monitor: unknown command \"bogus\"; monitor commands: cycle")
            && gdb.contains("reset (reset the MCU"),
        "names the command and the ones that exist: {gdb}"
    );
    assert!(gdb.contains("Protocol error with Rcmd"), "an error: {gdb}");
    assert!(gdb.contains("reset at cycle "), "{gdb}");
    assert!(gdb.contains("$1 = 0x0\n"), "at the reset vector: {gdb}");
    assert!(gdb.contains("$2 = 0x2\n"), "EXTRF set: {gdb}");
    assert_eq!(run.code, Some(3), "{}", run.stderr);
    assert!(
        run.stderr.contains("the debugger killed it"),
        "{}",
        run.stderr
    );
}

#[test]
fn the_memory_map_is_shown_and_load_is_refused() {
    let thesis = support::firmware_path("thesis");
    let load = format!("load {}", thesis.display());
    let (run, gdb) = session(&[
        "set language c",
        "info mem",
        "x/2xh 0",
        &load,
        "x/2xh 0",
        "set {char}0 = 1",
        "continue",
    ]);
    assert!(
        gdb.contains("Using memory regions provided by the target.")
            && gdb.contains("0x00000000 0x00040000 flash blocksize 0x100")
            && gdb.contains("0x00800000 0x00802200 rw"),
        "flash (256 KiB, 256-byte pages) and the data space: {gdb}"
    );
    assert!(
        gdb.contains("Error erasing flash"),
        "gdb says the load failed: {gdb}"
    );
    assert!(
        run.stderr.contains("gdb: refused a flash write"),
        "hil says why: {}",
        run.stderr
    );
    assert!(
        gdb.contains("hil: the load was refused: flash is read-only"),
        "the stub's reason on gdb's console: {gdb}"
    );
    assert!(
        gdb.contains("Writing to flash memory forbidden"),
        "the map makes flash read-only for gdb too: {gdb}"
    );
    // The robust image's reset vector, before and after: flash unchanged,
    // and the run is the robust run.
    assert_eq!(gdb.matches(":\t0x940c\t0x00b8").count(), 2, "{gdb}");
    assert_same_run(&run, &gdb, "after a refused load");
}

#[test]
fn a_refused_watchpoint_says_why_on_gdbs_console_and_the_run_goes_on_without_it() {
    let (run, gdb) = session(&[
        "set language c",
        "watch *(unsigned char *)0x80005f",
        "continue",
        "delete",
        "continue",
    ]);
    assert!(
        gdb.contains("hil: the watchpoint at 0x80005f (1 byte) is refused: SREG is not kept"),
        "the stub's reason on gdb's console: {gdb}"
    );
    assert!(
        run.stderr.contains("gdb: refused a watchpoint at 0x80005f"),
        "{}",
        run.stderr
    );
    assert_same_run(&run, &gdb, "after a refused watchpoint");
}

#[test]
fn a_run_killed_or_abandoned_by_its_debugger_exits_3_and_says_so() {
    let (run, gdb) = session(&["stepi", "kill"]);
    assert_eq!(run.code, Some(3), "killed: {}\ngdb:\n{gdb}", run.stderr);
    assert!(
        run.stderr
            .contains("did not complete: the debugger killed it"),
        "{}",
        run.stderr
    );
    assert!(
        run.stdout.is_empty(),
        "no report of a run that was not run: {}",
        run.stdout
    );
    // A debugger that goes away while the run is paused: gdb batch mode
    // quitting without a detach is such a debugger.
    let hil = Debugged::start();
    let mut client = Client::connect(&hil.addr);
    assert_eq!(client.ask("?"), "S05");
    drop(client);
    let run = hil.finish();
    assert_eq!(run.code, Some(3), "abandoned: {}", run.stderr);
    assert!(
        run.stderr.contains("connection closed without a detach"),
        "{}",
        run.stderr
    );
}

/// A raw RSP client: one packet out, one reply back.
struct Client(TcpStream);

impl Client {
    fn connect(addr: &str) -> Self {
        let s = TcpStream::connect(addr).unwrap();
        s.set_read_timeout(Some(DEADLINE)).unwrap();
        Self(s)
    }

    fn send_raw(&mut self, body: &str) {
        let sum = body.bytes().fold(0u8, |s, b| s.wrapping_add(b));
        write!(self.0, "${body}#{sum:02x}").unwrap();
    }

    /// The next reply packet's body (acks skipped, checksum checked).
    fn reply(&mut self) -> String {
        let mut byte = [0u8; 1];
        loop {
            self.0.read_exact(&mut byte).unwrap();
            if byte[0] == b'$' {
                break;
            }
        }
        let mut body = Vec::new();
        loop {
            self.0.read_exact(&mut byte).unwrap();
            if byte[0] == b'#' {
                break;
            }
            body.push(byte[0]);
        }
        let mut sum = [0u8; 2];
        self.0.read_exact(&mut sum).unwrap();
        let expected = body.iter().fold(0u8, |s, b| s.wrapping_add(*b));
        assert_eq!(
            u8::from_str_radix(std::str::from_utf8(&sum).unwrap(), 16).unwrap(),
            expected
        );
        self.0.write_all(b"+").unwrap();
        String::from_utf8(body).unwrap()
    }

    fn ask(&mut self, body: &str) -> String {
        self.send_raw(body);
        self.reply()
    }
}

/// A little-endian hex number.
fn le(hex: &str) -> u64 {
    (0..hex.len()).step_by(2).rev().fold(0, |v, i| {
        v << 8 | u64::from_str_radix(&hex[i..i + 2], 16).unwrap()
    })
}

#[test]
fn a_second_avr_gdb_is_refused_while_one_is_connected() {
    let hil = Debugged::start();
    let mut first = Client::connect(&hil.addr);
    assert_eq!(first.ask("?"), "S05", "the first is served");
    let (gdb, ok) = avr_gdb(&hil.addr, &["info registers pc"]);
    assert!(!ok, "the second avr-gdb fails: {gdb}");
    assert!(
        gdb.contains("the bench serves one debugger at a time and one is connected"),
        "and says why: {gdb}"
    );
    // The first is still served, and its run goes on after it detaches.
    assert_eq!(le(&first.ask("p22")), 0, "still paused at reset");
    assert_eq!(first.ask("D"), "OK");
    let run = hil.finish();
    assert!(run.success, "{}", run.stderr);
    assert!(
        run.stderr.contains("gdb: refused a second debugger"),
        "{}",
        run.stderr
    );
    assert_eq!(run.stdout, plain_run(), "a refused client changes nothing");
}

/// What avr-gdb's batch mode cannot send: steps, register and memory
/// writes, Ctrl-C while running; then a detach, and the run is the plain run.
#[test]
fn raw_client_steps_writes_interrupts_and_detaches_without_changing_the_run() {
    let robust = support::firmware("robust");
    let state = robust.variable("HT_STATE", 1).unwrap() as u32;
    let hil = Debugged::start();
    let mut c = Client::connect(&hil.addr);
    assert!(c
        .ask("qSupported:swbreak+")
        .contains("qXfer:memory-map:read+"));
    assert_eq!(c.ask("?"), "S05");
    let regs = c.ask("g");
    assert_eq!(regs.len(), 39 * 2, "r0-r31, SREG, SP, PC");
    assert_eq!(le(&regs[70..78]), 0, "paused at reset");
    for _ in 0..100 {
        assert_eq!(c.ask("s"), "S05");
    }
    assert_ne!(le(&c.ask("p22")), 0, "the steps moved the PC");
    // Writes go where reads come from: every register back as read, the
    // PC alone, a byte of SRAM (the same values: the run goes on as it
    // would have).
    let regs = c.ask("g");
    assert_eq!(c.ask(&format!("G{regs}")), "OK");
    assert_eq!(c.ask("g"), regs);
    assert_eq!(c.ask(&format!("P22={}", &regs[70..78])), "OK");
    let byte = c.ask(&format!("m{:x},1", 0x80_0000 + state));
    assert_eq!(c.ask(&format!("M{:x},1:{byte}", 0x80_0000 + state)), "OK");
    // Flash reads from 0 (the reset vector is a jmp, 0x940c); writes to it
    // are refused; off the map an error, not a crash.
    assert_eq!(c.ask("m0,2"), "0c94");
    assert!(c.ask("M0,2:0000").starts_with('E'), "flash is read-only");
    assert_eq!(c.ask("m0,2"), "0c94");
    assert_eq!(c.ask("m900000,2"), "E01");
    // Run free, then Ctrl-C; one step; detach.
    c.send_raw("c");
    std::thread::sleep(Duration::from_millis(50));
    c.0.write_all(&[0x03]).unwrap();
    assert_eq!(c.reply(), "S02");
    assert_eq!(c.ask("s"), "S05", "one step");
    assert_eq!(c.ask("D"), "OK");
    let run = hil.finish();
    assert!(run.success, "{:?}: {}", run.code, run.stderr);
    assert_eq!(run.stdout, plain_run(), "the debugger only paused the run");
}
