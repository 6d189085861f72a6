//! One debugger's session: the commands it sends while the run is paused,
//! and the checks after each step that pause it (a single step done, a
//! breakpoint, a watchpoint, Ctrl-C).

use std::collections::BTreeSet;
use std::net::TcpStream;

use super::packets::{console, hex, parse_addr_len, parse_point, unhex, Link, Packet};
use super::refuse::Refuser;
use super::watch::{accesses, hit, Access, Regs, Watch, WatchKind};
use crate::bench::{Bench, BenchError};
use crate::firmware::elf::DATA_OFFSET;

/// Registers in avr-gdb's `g` order.
const REG_SREG: usize = 32;
const REG_SP: usize = 33;
const REG_PC: usize = 34;
const G_BYTES: usize = 32 + 1 + 2 + 4;
/// Steps between looks at the socket for a Ctrl-C while running.
const POLL_EVERY: u64 = 256;
const SIGINT: u8 = 2;
const SIGTRAP: u8 = 5;
/// Above the data space, avr-gdb puts EEPROM (0x810000): not served.
const EEPROM_OFFSET: u32 = 0x81_0000;
/// The ATmega2560's flash page: the unit gdb would erase in.
const FLASH_PAGE: u32 = 256;
/// The register file (0x00-0x1f) is touched by nearly every instruction,
/// and SREG's data byte (0x5f) is not kept while running: neither can be
/// watched exactly, so neither is offered.
const WATCH_FROM: u32 = 0x20;
const SREG_DATA: u32 = 0x5f;

const MONITOR_HELP: &str = "monitor commands: cycle (the emulated cycle and robot time), reset (reset the MCU as its reset pin would; the plant carries on)\n";

/// What the debugger asked for when it let the run go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Resume {
    Run,
    Detach,
    /// gdb's `kill`.
    Kill,
    /// The connection closed without a detach or a kill: gdb quit or died.
    Gone,
}

impl Resume {
    /// Why the run ended, for a run the debugger ended.
    pub(super) fn ended(self) -> Option<&'static str> {
        match self {
            Resume::Kill => Some("the debugger killed it (gdb's kill)"),
            Resume::Gone => {
                Some("the debugger's connection closed without a detach (gdb quit or died)")
            }
            Resume::Run | Resume::Detach => None,
        }
    }
}

pub(super) struct Session {
    link: Link,
    /// Breakpoint PCs (flash byte addresses).
    breakpoints: BTreeSet<u32>,
    watches: Vec<Watch>,
    /// Stop after the next step.
    single: bool,
    /// Steps since the session started, for the Ctrl-C poll.
    steps: u64,
    /// Before the step: its PC, its decoded accesses, the watched bytes.
    pc_before: u32,
    planned: Vec<Access>,
    watched_before: Vec<(u16, u8)>,
    flash_size: u32,
    data_size: u32,
    /// Watchpoints accepted but not served, each with the reason: gdb 13
    /// prints no text of a refused `Z` packet, so the refusal is said at
    /// the resume (an `O` packet, then a stop), where gdb's console shows it.
    refused: Vec<(String, String)>,
    /// The stub's reasons for what it refused (a `load`) that gdb's reply
    /// handling cannot show: said on gdb's console at the next resume.
    notes: Vec<String>,
    _refuser: Refuser,
}

impl Session {
    pub(super) fn new(stream: TcpStream, bench: &Bench, refuser: Refuser) -> std::io::Result<Self> {
        Ok(Self {
            link: Link::new(stream)?,
            breakpoints: BTreeSet::new(),
            watches: Vec::new(),
            single: false,
            steps: 0,
            pc_before: 0,
            planned: Vec::new(),
            watched_before: Vec::new(),
            flash_size: bench.mcu().flash_size(),
            data_size: bench.mcu().data_size(),
            refused: Vec::new(),
            notes: Vec::new(),
            _refuser: refuser,
        })
    }

    /// Before a step: what it will touch, when anything is watched.
    pub(super) fn note_before(&mut self, bench: &Bench) {
        let mcu = bench.mcu();
        self.pc_before = mcu.pc();
        if self.watches.is_empty() {
            return;
        }
        let word = |a: u16| u16::from_le_bytes([mcu.data(a), mcu.data(a + 1)]);
        let regs = Regs {
            x: word(26),
            y: word(28),
            z: word(30),
            sp: mcu.sp(),
        };
        let pc = self.pc_before;
        self.planned = accesses(mcu.flash_word(pc), mcu.flash_word(pc + 2), &regs);
        self.watched_before = self
            .watches
            .iter()
            .flat_map(|w| w.addr..w.addr + w.len)
            .map(|a| (a, mcu.data(a)))
            .collect();
    }

    /// After a step: the stop reply, when the run pauses here.
    pub(super) fn stop_after(&mut self, bench: &Bench, slept: bool) -> Option<String> {
        self.steps += 1;
        if !self.watches.is_empty() {
            let mcu = bench.mcu();
            // A sleep or a reset hold runs no instruction: its decoded
            // accesses did not happen.
            let planned: &[Access] = if slept { &[] } else { &self.planned };
            let changed: Vec<u16> = self
                .watched_before
                .iter()
                .filter(|(a, v)| mcu.data(*a) != *v)
                .map(|(a, _)| *a)
                .collect();
            if let Some(what) = hit(&self.watches, planned, &changed, DATA_OFFSET) {
                self.single = false;
                return Some(format!("T{SIGTRAP:02x}{what}"));
            }
        }
        let pc = bench.mcu().pc();
        // On a breakpoint when the step got there (not a sleep that stayed).
        let on_breakpoint = self.breakpoints.contains(&pc) && (pc != self.pc_before || !slept);
        if std::mem::take(&mut self.single) || on_breakpoint {
            return Some(format!("S{SIGTRAP:02x}"));
        }
        if self.steps % POLL_EVERY == 0 {
            match self.link.poll_interrupt() {
                Ok(Some(true)) => return Some(format!("S{SIGINT:02x}")),
                // Gone: the next serve sees the closed link and kills.
                Ok(Some(false)) | Err(_) => return Some(String::new()),
                Ok(None) => {}
            }
        }
        None
    }

    /// Report a stop (an empty reply: none, the link is gone) and serve the
    /// debugger until it lets the run go. Ok(false): detached.
    pub(super) fn stop_and_serve(
        &mut self,
        bench: &mut Bench,
        reply: &str,
    ) -> Result<bool, BenchError> {
        let gone = |e: std::io::Error| BenchError::Debugger(format!("the connection failed: {e}"));
        if !reply.is_empty() {
            self.link.send(reply).map_err(gone)?;
        }
        match self.serve(bench).map_err(gone)? {
            Resume::Run => Ok(true),
            Resume::Detach => Ok(false),
            r => Err(BenchError::Debugger(r.ended().unwrap_or("ended").into())),
        }
    }

    /// The program exited (gdb's `W` reply); the link closes after it.
    pub(super) fn exited(&mut self, completed: bool) {
        // Best effort: a debugger gone by now has nothing to be told.
        let _ = self.link.send(if completed { "W00" } else { "W01" });
    }

    /// Answer commands while paused, until one lets the run go.
    pub(super) fn serve(&mut self, bench: &mut Bench) -> std::io::Result<Resume> {
        loop {
            let cmd = match self.link.next_packet()? {
                Packet::Command(c) => c,
                Packet::Interrupt => continue, // already paused
                Packet::Closed => return Ok(Resume::Gone),
            };
            let resumes = matches!(cmd.as_bytes().first(), Some(b'c' | b's'));
            if resumes {
                for note in std::mem::take(&mut self.notes) {
                    self.link.send(&console(&note))?;
                }
            }
            if resumes && !self.refused.is_empty() {
                // Not run: the reasons, then a stop where it is.
                for (_, why) in &self.refused {
                    self.link.send(&console(why))?;
                }
                self.link.send(&format!("S{SIGTRAP:02x}"))?;
                continue;
            }
            match cmd.as_bytes().first().copied() {
                Some(b'c') => {
                    if let Some(pc) = cmd.get(1..).and_then(|a| u32::from_str_radix(a, 16).ok()) {
                        bench.mcu_mut().set_pc(pc);
                    }
                    return Ok(Resume::Run);
                }
                Some(b's') => {
                    self.single = true;
                    return Ok(Resume::Run);
                }
                Some(b'k') => return Ok(Resume::Kill),
                Some(b'D') => {
                    self.link.send("OK")?;
                    return Ok(Resume::Detach);
                }
                _ => {
                    let reply = self.answer(bench, &cmd);
                    self.link.send(&reply)?;
                }
            }
        }
    }

    /// The reply to a command that does not resume the run.
    fn answer(&mut self, bench: &mut Bench, cmd: &str) -> String {
        let err = || "E01".to_string();
        match cmd.as_bytes().first().copied() {
            Some(b'?') => format!("S{SIGTRAP:02x}"),
            Some(b'g') => hex(&read_registers(bench)),
            Some(b'G') => unhex(&cmd[1..])
                .filter(|b| b.len() == G_BYTES)
                .map(|b| write_registers(bench, &b))
                .map_or_else(err, |_| "OK".into()),
            Some(b'p') => usize::from_str_radix(&cmd[1..], 16)
                .ok()
                .and_then(|n| register_bytes(bench, n))
                .map_or_else(err, |b| hex(&b)),
            Some(b'P') => cmd[1..]
                .split_once('=')
                .and_then(|(n, v)| {
                    set_register(bench, usize::from_str_radix(n, 16).ok()?, &unhex(v)?)
                })
                .map_or_else(err, |_| "OK".into()),
            Some(b'm') => parse_addr_len(&cmd[1..])
                .and_then(|(addr, len)| read_memory(bench, addr, len))
                .map_or_else(err, |b| hex(&b)),
            Some(b'M') => self.write_memory(bench, &cmd[1..]),
            Some(b'Z') | Some(b'z') => self.point(cmd),
            Some(b'H') => "OK".into(),
            _ if cmd.starts_with("qSupported") => "PacketSize=1000;qXfer:memory-map:read+".into(),
            _ if cmd == "qAttached" => "1".into(),
            _ if cmd.starts_with("qXfer:memory-map:read::") => {
                self.memory_map(&cmd["qXfer:memory-map:read::".len()..])
            }
            _ if cmd.starts_with("vFlash") => {
                let what = cmd.split(':').next().unwrap_or(cmd);
                eprintln!("gdb: refused a flash write ({what}): the bench runs the ELF it started with; restart hil with the other ELF");
                let note = "hil: the load was refused: flash is read-only, the bench runs the ELF it started with (restart hil with --elf FILE to run another)\n";
                if !self.notes.iter().any(|n| n == note) {
                    self.notes.push(note.into());
                }
                "E.flash is read-only: the bench runs the ELF it started with".into()
            }
            _ if cmd.starts_with("qRcmd,") => self.monitor(bench, &cmd[6..]),
            _ => String::new(),
        }
    }

    /// `M addr,len:bytes`: data space only; flash is the ELF the run
    /// started with (a `load` must not turn the run into another one).
    fn write_memory(&mut self, bench: &mut Bench, args: &str) -> String {
        let Some((addr, bytes)) = args.split_once(':').and_then(|(al, data)| {
            let (addr, len) = parse_addr_len(al)?;
            Some((addr, unhex(data).filter(|b| b.len() == len)?))
        }) else {
            return "E01".into();
        };
        if addr < DATA_OFFSET {
            eprintln!("gdb: refused a write of {} bytes to flash at 0x{addr:x}: flash is the ELF the run started with", bytes.len());
            return "E.flash is read-only: the bench runs the ELF it started with".into();
        }
        let ok = addr < EEPROM_OFFSET && bench.mcu_mut().write_data(addr - DATA_OFFSET, &bytes);
        if ok { "OK" } else { "E01" }.into()
    }

    /// `Z`/`z`: breakpoints and data watchpoints.
    fn point(&mut self, cmd: &str) -> String {
        let Some(p) = parse_point(cmd) else {
            return "E01".into();
        };
        // Hardware breakpoints too: with flash in the memory map gdb asks
        // for those; both are the same PC comparison here.
        if p.kind <= 1 {
            if p.insert {
                self.breakpoints.insert(p.addr);
            } else {
                self.breakpoints.remove(&p.addr);
            }
            return "OK".into();
        }
        let Some(kind) = WatchKind::of(p.kind) else {
            return String::new();
        };
        let data = p.addr.wrapping_sub(DATA_OFFSET);
        let end = data as u64 + p.len as u64;
        let sreg = (data..data + p.len).contains(&SREG_DATA);
        let why = if p.addr < DATA_OFFSET || p.len == 0 {
            Some("it is not in the data space (flash cannot be watched)")
        } else if data < WATCH_FROM {
            Some("the registers r0-r31 are touched by nearly every instruction and cannot be watched exactly; watch the variable in memory")
        } else if sreg {
            Some("SREG is not kept in the data space while the MCU runs; break where it matters and look at $sreg")
        } else if end > self.data_size as u64 {
            Some("it is beyond the end of the data space")
        } else {
            None
        };
        if let Some(why) = why {
            let key = cmd[1..].to_string();
            if p.insert {
                eprintln!("gdb: refused a watchpoint at 0x{:x}: {why}", p.addr);
                let line = format!(
                    "hil: the watchpoint at 0x{:x} ({} byte{}) is refused: {why}; delete it to continue\n",
                    p.addr,
                    p.len,
                    if p.len == 1 { "" } else { "s" }
                );
                self.refused.push((key, line));
            } else if let Some(i) = self.refused.iter().position(|r| r.0 == key) {
                self.refused.remove(i);
            }
            return "OK".into();
        }
        let w = Watch {
            kind,
            addr: data as u16,
            len: p.len as u16,
        };
        if p.insert {
            self.watches.push(w);
        } else if let Some(i) = self.watches.iter().position(|x| *x == w) {
            self.watches.remove(i);
        }
        "OK".into()
    }

    /// `qXfer:memory-map:read::offset,length`: flash from 0 (read-only
    /// here, see [`Self::write_memory`]), the data space from 0x800000.
    fn memory_map(&self, args: &str) -> String {
        let Some((offset, len)) = parse_addr_len(args) else {
            return "E01".into();
        };
        let xml = format!(
            concat!(
                "<?xml version=\"1.0\"?>\n",
                "<!DOCTYPE memory-map PUBLIC \"+//IDN gnu.org//DTD GDB Memory Map V1.0//EN\" ",
                "\"http://sourceware.org/gdb/gdb-memory-map.dtd\">\n",
                "<memory-map>\n",
                "  <memory type=\"flash\" start=\"0x0\" length=\"0x{:x}\">\n",
                "    <property name=\"blocksize\">0x{:x}</property>\n",
                "  </memory>\n",
                "  <memory type=\"ram\" start=\"0x{:x}\" length=\"0x{:x}\"/>\n",
                "</memory-map>\n"
            ),
            self.flash_size, FLASH_PAGE, DATA_OFFSET, self.data_size
        );
        let from = (offset as usize).min(xml.len());
        let to = (from + len).min(xml.len());
        let more = if to < xml.len() { 'm' } else { 'l' };
        format!("{more}{}", &xml[from..to])
    }

    /// `qRcmd`: `monitor cycle`, `monitor reset`; anything else is an
    /// error that says what exists.
    fn monitor(&mut self, bench: &mut Bench, hex_text: &str) -> String {
        let text = unhex(hex_text)
            .map(|b| String::from_utf8_lossy(&b).trim().to_string())
            .unwrap_or_default();
        match text.as_str() {
            "cycle" => hex(format!(
                "cycle {} (robot time {:.9} s)\n",
                bench.cycle(),
                bench.robot_time_s()
            )
            .as_bytes()),
            "reset" => {
                bench.external_reset();
                hex(format!(
                    "reset at cycle {}: the MCU starts from its reset vector, the plant carries on (`maintenance flush register-cache` to see the registers anew)\n",
                    bench.cycle()
                )
                .as_bytes())
            }
            "" | "help" => hex(MONITOR_HELP.as_bytes()),
            other => {
                // Text first (gdb prints it), then the error reply.
                let line = format!("monitor: unknown command {other:?}; {MONITOR_HELP}");
                if self.link.send(&console(&line)).is_err() {
                    return "E01".into();
                }
                "E01".into()
            }
        }
    }
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

fn read_memory(bench: &Bench, addr: u32, len: usize) -> Option<Vec<u8>> {
    match addr {
        a if a < DATA_OFFSET => bench.mcu().read_flash(a, len),
        a if a < EEPROM_OFFSET => bench.mcu().read_data(a - DATA_OFFSET, len),
        _ => None,
    }
}
