//! The bench's gdb stub, driven by a raw RSP client over TCP as avr-gdb
//! would: paused at reset, registers, a breakpoint on the control tick, a
//! variable read from SRAM, Ctrl-C, detach; and the debugger changes nothing
//! in the simulation.

#[path = "support/mod.rs"]
mod support;

use std::io::{Read, Write};
use std::net::TcpStream;

use hil::bench::{Bench, BenchOptions};
use hil::gdb::{Flow, GdbServer, SessionEnd};

/// A raw RSP client: one packet out, one reply back.
struct Client(TcpStream);

impl Client {
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

fn le(hex: &str) -> u64 {
    (0..hex.len()).step_by(2).rev().fold(0, |v, i| {
        v << 8 | u64::from_str_radix(&hex[i..i + 2], 16).unwrap()
    })
}

/// What the client saw: the cycle-independent facts to compare across runs.
#[derive(Debug, PartialEq)]
struct Seen {
    first_pc: u64,
    stop_pc: u64,
    state: String,
    ticks_at_stop: u64,
    /// Every register and the firmware's counters at the stop.
    regs_at_stop: String,
    counts_at_stop: String,
    /// `monitor cycle` at the stop.
    cycle_at_stop: String,
}

/// One debugged run of the straight line: the driver plays the host (the
/// command byte once the firmware is idle).
/// `detour`: stop on the way first (steps, and a breakpoint at `detour_at`),
/// which must change nothing.
fn debug_session(
    tick: u32,
    state_addr: u32,
    ticks_addr: u32,
    detour_at: Option<u32>,
) -> (Seen, u64, SessionEnd) {
    let robust = support::firmware("robust");
    let mut bench = Bench::new(
        robust,
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    let server = GdbServer::bind(0).unwrap();
    let addr = server.local_addr().unwrap();
    assert!(addr.ip().is_loopback());
    let counts_addr = bench
        .vars()
        .expect("the robust build has the bench interface")
        .left_count as u32;
    let client = std::thread::spawn(move || {
        let mut c = Client(TcpStream::connect(addr).unwrap());
        assert!(c.ask("qSupported:swbreak+").contains("PacketSize"));
        assert_eq!(c.ask("?"), "S05");
        let regs = c.ask("g");
        assert_eq!(regs.len(), 39 * 2, "r0-r31, SREG, SP, PC");
        let first_pc = le(&regs[70..78]);
        if let Some(at) = detour_at {
            for _ in 0..100 {
                assert_eq!(c.ask("s"), "S05");
            }
            assert_eq!(c.ask(&format!("Z0,{at:x},2")), "OK");
            assert_eq!(c.ask("c"), "S05");
            assert_eq!(le(&c.ask("p22")), at as u64);
            assert_eq!(c.ask(&format!("z0,{at:x},2")), "OK");
        }
        assert_eq!(c.ask(&format!("Z0,{tick:x},2")), "OK");
        assert_eq!(c.ask("c"), "S05");
        let stop_pc = le(&c.ask("p22"));
        let regs_at_stop = c.ask("g");
        let hex: String = "cycle".bytes().map(|b| format!("{b:02x}")).collect();
        let reply = c.ask(&format!("qRcmd,{hex}"));
        let cycle_at_stop = String::from_utf8(
            (0..reply.len())
                .step_by(2)
                .map(|i| u8::from_str_radix(&reply[i..i + 2], 16).unwrap())
                .collect(),
        )
        .unwrap();
        assert!(cycle_at_stop.starts_with("cycle "), "{cycle_at_stop}");
        let counts_at_stop = c.ask(&format!("m{:x},8", 0x80_0000 + counts_addr));
        let state = c.ask(&format!("m{:x},1", 0x80_0000 + state_addr));
        let ticks_at_stop = le(&c.ask(&format!("m{:x},4", 0x80_0000 + ticks_addr)));
        // Writes go where reads come from: every register back as read,
        // the PC alone, a byte of SRAM (the same values: the run goes on
        // as it would have).
        let regs = c.ask("g");
        assert_eq!(c.ask(&format!("G{regs}")), "OK");
        assert_eq!(c.ask("g"), regs);
        assert_eq!(c.ask(&format!("P22={}", &regs[70..78])), "OK");
        assert_eq!(
            c.ask(&format!("M{:x},1:{state}", 0x80_0000 + state_addr)),
            "OK"
        );
        assert_eq!(c.ask("Z1,0,2"), "", "hardware breakpoints are not offered");
        // Flash reads from 0: the reset vector is a jmp (0x940c).
        assert_eq!(c.ask("m0,2"), "0c94");
        // Off the map: an error, not a crash.
        assert_eq!(c.ask("m900000,2"), "E01");
        assert_eq!(c.ask(&format!("z0,{tick:x},2")), "OK");
        // Run free, then Ctrl-C.
        c.send_raw("c");
        std::thread::sleep(std::time::Duration::from_millis(50));
        c.0.write_all(&[0x03]).unwrap();
        assert_eq!(c.reply(), "S02");
        assert_eq!(c.ask("s"), "S05", "one step");
        assert_eq!(c.ask("D"), "OK");
        Seen {
            first_pc,
            stop_pc,
            state,
            ticks_at_stop,
            regs_at_stop,
            counts_at_stop,
            cycle_at_stop,
        }
    });
    let mut sent = false;
    let end = server
        .serve(&mut bench, &mut |b: &mut Bench| {
            if !sent && b.is_idle() {
                b.send(1, &[4]);
                sent = true;
            }
            Flow::Continue
        })
        .unwrap();
    let seen = client.join().unwrap();
    (seen, bench.cycle(), end)
}

#[test]
fn raw_client_breaks_on_the_control_tick_and_reads_sram() {
    let robust = support::firmware("robust");
    let tick = robust.symbol("ht_control_tick").unwrap().addr;
    let state = robust.variable("HT_STATE", 1).unwrap() as u32;
    let ticks = robust.variable("HT_TICKS", 4).unwrap() as u32;
    let (seen, _, end) = debug_session(tick, state, ticks, None);
    assert_eq!(end, SessionEnd::Detached);
    assert_eq!(seen.first_pc, 0, "paused at reset");
    assert_eq!(seen.stop_pc, tick as u64, "stopped on the symbol");
    assert_eq!(seen.state, "02", "HT_STATE: driving the line");
    assert!(seen.ticks_at_stop > 0);
    // Again, stopping on the way (100 single steps, then a breakpoint on
    // the USART1 receive handler as the start command arrives): the tick
    // is reached in the same state, registers and counters included. The
    // debugger pauses; it never adds or removes time.
    let detour = robust.symbol("__vector_36").unwrap().addr;
    let (again, _, _) = debug_session(tick, state, ticks, Some(detour));
    assert_eq!(seen, again);
}

/// `hil run --gdb 0` waits paused for a debugger on loopback, says where;
/// after a detach the run completes as without one.
#[test]
fn cli_serves_gdb_and_finishes_after_detach() {
    use std::io::BufRead;
    use std::process::{Command, Stdio};
    let _ = support::firmware_path("robust");
    let ideal = hil::paths::robot_config("henrytwo-ideal");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args([
            "run",
            "line",
            "--leg-mm",
            "300",
            "--json",
            "--deterministic",
        ])
        .arg("--robot")
        .arg(&ideal)
        .args(["--gdb", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .rsplit("target remote ")
        .next()
        .and_then(|a| a.trim().strip_suffix('\''))
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    assert!(addr.starts_with("127.0.0.1:"), "{addr}");
    let mut c = Client(TcpStream::connect(&addr).unwrap());
    assert_eq!(le(&c.ask("p22")), 0, "paused at reset");
    assert_eq!(c.ask("D"), "OK");
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["completed"], true);
}
