//! A minimal GDB Remote Serial Protocol stub for the bench, on loopback only.
//!
//! simavr has a stub of its own, but it listens on every interface; this one
//! binds 127.0.0.1 and drives the bench's own run loop, so the plant, the
//! faults and every bench event carry on exactly as without a debugger: the
//! debugger only pauses the simulation, it never adds or removes time.
//!
//! What it speaks (what avr-gdb needs to load symbols, look and step):
//! `qSupported`, `?`, `g`/`G` (r0-r31, SREG, SP, PC: 39 bytes, avr-gdb's
//! order), `p`/`P` (register 32 is SREG, 33 SP, 34 PC), `m`/`M` (avr-gdb's
//! address map: flash from 0, data space from 0x800000), `c`, `s`,
//! `Z0`/`z0` software breakpoints (compared with the PC after each
//! instruction, flash is never patched), Ctrl-C while running, `k` and `D`.
//! `monitor cycle` (`qRcmd`) tells the emulated cycle and robot time.
//! Anything else gets the empty reply ("not supported"), as the protocol
//! asks.

use std::collections::BTreeSet;
use std::io::{ErrorKind, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};

use thiserror::Error;

use crate::bench::{Bench, BenchError};
use crate::elf::DATA_OFFSET;

#[derive(Debug, Error)]
pub enum GdbError {
    #[error("cannot listen for gdb on 127.0.0.1:{port}: {source} (pick another port, or 0 for any free one)")]
    Bind { port: u16, source: std::io::Error },
    #[error("the gdb connection failed: {0}")]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Bench(#[from] BenchError),
}

/// What the run does after the session.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SessionEnd {
    /// `D`: the debugger left; the run may go on without it.
    Detached,
    /// `k`, or the connection closed: stop the run.
    Killed,
    /// The driver said the run is over (reported to gdb as an exit).
    Finished,
}

/// What the driver wants after looking at the bench.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// The run is over (its test completed, or its time ran out).
    Finished,
}

/// A listening stub: bind first (the port is known before anyone connects),
/// then [`GdbServer::serve`].
pub struct GdbServer {
    listener: TcpListener,
}

impl GdbServer {
    /// Listen on 127.0.0.1:`port` (0: any free port).
    pub fn bind(port: u16) -> Result<Self, GdbError> {
        let listener = TcpListener::bind((Ipv4Addr::LOCALHOST, port))
            .map_err(|source| GdbError::Bind { port, source })?;
        Ok(Self { listener })
    }

    pub fn local_addr(&self) -> Result<SocketAddr, GdbError> {
        Ok(self.listener.local_addr()?)
    }

    /// Wait for one debugger and serve it. The bench stays paused until the
    /// debugger continues or steps; `driver` is called every few hundred
    /// instructions while running (it plays the host's part: commands at the
    /// right moment) and ends the run with [`Flow::Finished`].
    pub fn serve(
        self,
        bench: &mut Bench,
        driver: &mut dyn FnMut(&mut Bench) -> Flow,
    ) -> Result<SessionEnd, GdbError> {
        let (stream, _) = self.listener.accept()?;
        stream.set_nodelay(true)?;
        Session {
            stream,
            pending: Vec::new(),
            breakpoints: BTreeSet::new(),
            executed: 0,
        }
        .run(bench, driver)
    }
}

/// Registers in avr-gdb's `g` order.
const REG_SREG: usize = 32;
const REG_SP: usize = 33;
const REG_PC: usize = 34;
const G_BYTES: usize = 32 + 1 + 2 + 4;
/// Steps between looks at the socket (Ctrl-C) and the driver.
const POLL_EVERY: u64 = 256;
const SIGINT: u8 = 2;
const SIGTRAP: u8 = 5;
const SIGSEGV: u8 = 11;

struct Session {
    stream: TcpStream,
    /// Bytes received and not yet parsed.
    pending: Vec<u8>,
    /// Breakpoint PCs (flash byte addresses).
    breakpoints: BTreeSet<u32>,
    /// Steps executed since reset: the driver runs every [`POLL_EVERY`] of
    /// them, counted across stops, so where the debugger stops changes
    /// nothing in the run.
    executed: u64,
}

enum Packet {
    Command(String),
    Interrupt,
    Closed,
}

impl Session {
    fn run(
        mut self,
        bench: &mut Bench,
        driver: &mut dyn FnMut(&mut Bench) -> Flow,
    ) -> Result<SessionEnd, GdbError> {
        loop {
            let cmd = match self.next_packet()? {
                Packet::Command(c) => c,
                Packet::Interrupt => continue, // already stopped
                Packet::Closed => return Ok(SessionEnd::Killed),
            };
            match cmd.as_bytes().first().copied() {
                Some(b'?') => self.send(&format!("S{SIGTRAP:02x}"))?,
                Some(b'g') => self.send(&hex(&read_registers(bench)))?,
                Some(b'G') => {
                    let ok = unhex(&cmd[1..])
                        .filter(|b| b.len() == G_BYTES)
                        .map(|b| write_registers(bench, &b))
                        .is_some();
                    self.send(if ok { "OK" } else { "E01" })?
                }
                Some(b'p') => {
                    let reply = usize::from_str_radix(&cmd[1..], 16)
                        .ok()
                        .and_then(|n| register_bytes(bench, n))
                        .map(|b| hex(&b))
                        .unwrap_or_else(|| "E01".into());
                    self.send(&reply)?
                }
                Some(b'P') => {
                    let ok = cmd[1..].split_once('=').and_then(|(n, v)| {
                        let n = usize::from_str_radix(n, 16).ok()?;
                        set_register(bench, n, &unhex(v)?)
                    });
                    self.send(if ok.is_some() { "OK" } else { "E01" })?
                }
                Some(b'm') => {
                    let reply = parse_addr_len(&cmd[1..])
                        .and_then(|(addr, len)| read_memory(bench, addr, len))
                        .map(|b| hex(&b))
                        .unwrap_or_else(|| "E01".into());
                    self.send(&reply)?
                }
                Some(b'M') => {
                    let ok = cmd[1..].split_once(':').and_then(|(al, data)| {
                        let (addr, len) = parse_addr_len(al)?;
                        let bytes = unhex(data).filter(|b| b.len() == len)?;
                        write_memory(bench, addr, &bytes).then_some(())
                    });
                    self.send(if ok.is_some() { "OK" } else { "E01" })?
                }
                Some(b'c') => {
                    if let Some(pc) = cmd.get(1..).and_then(|a| u32::from_str_radix(a, 16).ok()) {
                        bench.mcu_mut().set_pc(pc);
                    }
                    match self.resume(bench, driver, false)? {
                        Some(end) => return Ok(end),
                        None => continue,
                    }
                }
                Some(b's') => match self.resume(bench, driver, true)? {
                    Some(end) => return Ok(end),
                    None => continue,
                },
                Some(b'Z') | Some(b'z') => {
                    let reply = match parse_breakpoint(&cmd) {
                        Some((true, addr)) => {
                            self.breakpoints.insert(addr);
                            "OK"
                        }
                        Some((false, addr)) => {
                            self.breakpoints.remove(&addr);
                            "OK"
                        }
                        // Hardware breakpoints and watchpoints: not offered.
                        None => "",
                    };
                    self.send(reply)?
                }
                Some(b'k') => return Ok(SessionEnd::Killed),
                Some(b'D') => {
                    self.send("OK")?;
                    return Ok(SessionEnd::Detached);
                }
                Some(b'H') => self.send("OK")?,
                _ if cmd.starts_with("qSupported") => self.send("PacketSize=1000")?,
                _ if cmd == "qAttached" => self.send("1")?,
                _ if cmd.starts_with("qRcmd,") => {
                    let text = unhex(&cmd[6..])
                        .map(|b| String::from_utf8_lossy(&b).trim().to_string())
                        .unwrap_or_default();
                    let reply = match text.as_str() {
                        "cycle" => hex(format!(
                            "cycle {} (robot time {:.9} s)\n",
                            bench.cycle(),
                            bench.robot_time_s()
                        )
                        .as_bytes()),
                        _ => hex(b"monitor commands: cycle\n"),
                    };
                    self.send(&reply)?
                }
                _ => self.send("")?,
            }
        }
    }

    /// Run (one instruction, or until a breakpoint, Ctrl-C or the end), then
    /// report the stop. Some(end) when the session is over.
    fn resume(
        &mut self,
        bench: &mut Bench,
        driver: &mut dyn FnMut(&mut Bench) -> Flow,
        single: bool,
    ) -> Result<Option<SessionEnd>, GdbError> {
        loop {
            if bench.step_instruction().is_err() {
                // The firmware crashed or stopped: a stop for the debugger
                // to look at (its PC and registers say where), not an end of
                // the session.
                self.send(&format!("S{SIGSEGV:02x}"))?;
                return Ok(None);
            }
            self.executed += 1;
            if self.executed % POLL_EVERY == 0 && driver(bench) == Flow::Finished {
                self.send("W00")?;
                return Ok(Some(SessionEnd::Finished));
            }
            if single || self.breakpoints.contains(&bench.mcu().pc()) {
                self.send(&format!("S{SIGTRAP:02x}"))?;
                return Ok(None);
            }
            if self.executed % POLL_EVERY == 0 {
                match self.poll_interrupt()? {
                    Some(true) => {
                        self.send(&format!("S{SIGINT:02x}"))?;
                        return Ok(None);
                    }
                    Some(false) => return Ok(Some(SessionEnd::Killed)),
                    None => {}
                }
            }
        }
    }

    /// While running: Some(true) on Ctrl-C, Some(false) when the debugger
    /// went away, None otherwise.
    fn poll_interrupt(&mut self) -> Result<Option<bool>, GdbError> {
        self.stream.set_nonblocking(true)?;
        let mut buf = [0u8; 256];
        let got = match self.stream.read(&mut buf) {
            Ok(0) => Some(false),
            Ok(k) => {
                self.pending.extend_from_slice(&buf[..k]);
                None
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => None,
            Err(e) => return Err(e.into()),
        };
        self.stream.set_nonblocking(false)?;
        if got.is_some() {
            return Ok(got);
        }
        if let Some(i) = self.pending.iter().position(|b| *b == 0x03) {
            self.pending.remove(i);
            return Ok(Some(true));
        }
        Ok(None)
    }

    /// The next packet (acknowledged) or a Ctrl-C; waits for one.
    fn next_packet(&mut self) -> Result<Packet, GdbError> {
        loop {
            // Skip acks and noise before a packet start.
            while let Some(&b) = self.pending.first() {
                match b {
                    b'$' => break,
                    0x03 => {
                        self.pending.remove(0);
                        return Ok(Packet::Interrupt);
                    }
                    _ => {
                        self.pending.remove(0);
                    }
                }
            }
            if let Some(hash) = self.pending.iter().position(|b| *b == b'#') {
                if self.pending.len() >= hash + 3 {
                    let body = self.pending[1..hash].to_vec();
                    let sum = std::str::from_utf8(&self.pending[hash + 1..hash + 3])
                        .ok()
                        .and_then(|s| u8::from_str_radix(s, 16).ok());
                    self.pending.drain(..hash + 3);
                    let ok = sum == Some(checksum(&body));
                    self.stream.write_all(if ok { b"+" } else { b"-" })?;
                    if ok {
                        return Ok(Packet::Command(String::from_utf8_lossy(&body).into_owned()));
                    }
                    continue;
                }
            }
            let mut buf = [0u8; 4096];
            let k = self.stream.read(&mut buf)?;
            if k == 0 {
                return Ok(Packet::Closed);
            }
            self.pending.extend_from_slice(&buf[..k]);
        }
    }

    fn send(&mut self, body: &str) -> Result<(), GdbError> {
        let packet = format!("${body}#{:02x}", checksum(body.as_bytes()));
        self.stream.write_all(packet.as_bytes())?;
        Ok(())
    }
}

fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0u8, |s, b| s.wrapping_add(*b))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex(s: &str) -> Option<Vec<u8>> {
    if s.len() % 2 != 0 {
        return None;
    }
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(s.get(i..i + 2)?, 16).ok())
        .collect()
}

fn parse_addr_len(s: &str) -> Option<(u32, usize)> {
    let (a, l) = s.split_once(',')?;
    Some((
        u32::from_str_radix(a, 16).ok()?,
        usize::from_str_radix(l, 16).ok()?,
    ))
}

/// `Z0,addr,kind` / `z0,addr,kind`: (insert, addr); None for other types.
fn parse_breakpoint(cmd: &str) -> Option<(bool, u32)> {
    let insert = cmd.starts_with('Z');
    let mut parts = cmd[1..].split(',');
    if parts.next()? != "0" {
        return None;
    }
    Some((insert, u32::from_str_radix(parts.next()?, 16).ok()?))
}

fn read_registers(bench: &Bench) -> Vec<u8> {
    (0..=REG_PC)
        .flat_map(|n| register_bytes(bench, n).unwrap_or_default())
        .collect()
}

fn register_bytes(bench: &Bench, n: usize) -> Option<Vec<u8>> {
    let mcu = bench.mcu();
    Some(match n {
        0..=31 => vec![mcu.data(n as u16)],
        REG_SREG => vec![mcu.sreg()],
        REG_SP => mcu.sp().to_le_bytes().to_vec(),
        REG_PC => mcu.pc().to_le_bytes().to_vec(),
        _ => return None,
    })
}

fn set_register(bench: &mut Bench, n: usize, v: &[u8]) -> Option<()> {
    let mcu = bench.mcu_mut();
    match (n, v.len()) {
        (0..=31, 1) => mcu.set_data(n as u16, v[0]),
        (REG_SREG, 1) => mcu.set_sreg(v[0]),
        (REG_SP, 2) => mcu.set_sp(u16::from_le_bytes([v[0], v[1]])),
        (REG_PC, 4) => mcu.set_pc(u32::from_le_bytes([v[0], v[1], v[2], v[3]])),
        _ => return None,
    }
    Some(())
}

fn write_registers(bench: &mut Bench, b: &[u8]) {
    for (n, v) in b[..32].iter().enumerate() {
        bench.mcu_mut().set_data(n as u16, *v);
    }
    let _ = set_register(bench, REG_SREG, &b[32..33]);
    let _ = set_register(bench, REG_SP, &b[33..35]);
    let _ = set_register(bench, REG_PC, &b[35..39]);
}

/// Above the data space, avr-gdb puts EEPROM (0x810000): not offered.
const EEPROM_OFFSET: u32 = 0x81_0000;

fn read_memory(bench: &Bench, addr: u32, len: usize) -> Option<Vec<u8>> {
    match addr {
        a if a < DATA_OFFSET => bench.mcu().read_flash(a, len),
        a if a < EEPROM_OFFSET => bench.mcu().read_data(a - DATA_OFFSET, len),
        _ => None,
    }
}

fn write_memory(bench: &mut Bench, addr: u32, bytes: &[u8]) -> bool {
    match addr {
        a if a < DATA_OFFSET => bench.mcu_mut().write_flash(a, bytes),
        a if a < EEPROM_OFFSET => bench.mcu_mut().write_data(a - DATA_OFFSET, bytes),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_frame_and_parse() {
        assert_eq!(checksum(b"OK"), 0x9a);
        assert_eq!(hex(&[0x00, 0xab]), "00ab");
        assert_eq!(unhex("00ab"), Some(vec![0x00, 0xab]));
        assert_eq!(unhex("0"), None);
        assert_eq!(parse_addr_len("800100,4"), Some((0x800100, 4)));
        assert_eq!(parse_breakpoint("Z0,1a2,2"), Some((true, 0x1a2)));
        assert_eq!(parse_breakpoint("z0,1a2,2"), Some((false, 0x1a2)));
        assert_eq!(parse_breakpoint("Z2,1a2,2"), None);
    }

    #[test]
    fn binds_loopback_only() {
        let s = GdbServer::bind(0).unwrap();
        assert!(s.local_addr().unwrap().ip().is_loopback());
    }
}
