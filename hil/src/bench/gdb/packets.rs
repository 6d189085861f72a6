//! The protocol's framing (`$body#sum`, acks, Ctrl-C) over the debugger's
//! socket, and the hex and number forms its packets carry.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;

/// What came from the debugger.
pub(super) enum Packet {
    Command(String),
    Interrupt,
    Closed,
}

/// One debugger's connection: bytes received and not yet parsed kept.
pub(super) struct Link {
    stream: TcpStream,
    pending: Vec<u8>,
}

impl Link {
    pub(super) fn new(stream: TcpStream) -> std::io::Result<Self> {
        stream.set_nodelay(true)?;
        Ok(Self {
            stream,
            pending: Vec::new(),
        })
    }

    /// The next packet (acknowledged) or a Ctrl-C; waits for one.
    pub(super) fn next_packet(&mut self) -> std::io::Result<Packet> {
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

    /// While running: Some(true) on Ctrl-C, Some(false) when the debugger
    /// went away, None otherwise. Never waits.
    pub(super) fn poll_interrupt(&mut self) -> std::io::Result<Option<bool>> {
        self.stream.set_nonblocking(true)?;
        let mut buf = [0u8; 256];
        let got = match self.stream.read(&mut buf) {
            Ok(0) => Some(false),
            Ok(k) => {
                self.pending.extend_from_slice(&buf[..k]);
                None
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => None,
            Err(e) => return Err(e),
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

    pub(super) fn send(&mut self, body: &str) -> std::io::Result<()> {
        self.stream.write_all(frame(body).as_bytes())
    }
}

/// `$body#sum`.
pub(super) fn frame(body: &str) -> String {
    format!("${body}#{:02x}", checksum(body.as_bytes()))
}

pub(super) fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0u8, |s, b| s.wrapping_add(*b))
}

pub(super) fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

pub(super) fn unhex(s: &str) -> Option<Vec<u8>> {
    if s.len() % 2 != 0 {
        return None;
    }
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(s.get(i..i + 2)?, 16).ok())
        .collect()
}

/// Console text for the debugger to print: an `O` packet.
pub(super) fn console(text: &str) -> String {
    format!("O{}", hex(text.as_bytes()))
}

pub(super) fn parse_addr_len(s: &str) -> Option<(u32, usize)> {
    let (a, l) = s.split_once(',')?;
    Some((
        u32::from_str_radix(a, 16).ok()?,
        usize::from_str_radix(l, 16).ok()?,
    ))
}

/// A break- or watchpoint packet: `Ztype,addr,kind` / `ztype,addr,kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Point {
    pub insert: bool,
    /// 0 software breakpoint, 1 hardware breakpoint, 2 write, 3 read,
    /// 4 access watchpoint.
    pub kind: u8,
    pub addr: u32,
    /// Bytes watched (a breakpoint's instruction size).
    pub len: u32,
}

pub(super) fn parse_point(cmd: &str) -> Option<Point> {
    let insert = cmd.starts_with('Z');
    let mut parts = cmd.get(1..)?.split(',');
    let kind = parts.next()?.parse().ok()?;
    let addr = u32::from_str_radix(parts.next()?, 16).ok()?;
    // A breakpoint's kind may carry conditions after a ';'.
    let len = parts.next()?.split(';').next()?;
    Some(Point {
        insert,
        kind,
        addr,
        len: u32::from_str_radix(len, 16).ok()?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_frame_and_parse() {
        assert_eq!(checksum(b"OK"), 0x9a);
        assert_eq!(frame("OK"), "$OK#9a");
        assert_eq!(hex(&[0x00, 0xab]), "00ab");
        assert_eq!(unhex("00ab"), Some(vec![0x00, 0xab]));
        assert_eq!(unhex("0"), None);
        assert_eq!(console("hi\n"), "O68690a");
        assert_eq!(parse_addr_len("800100,4"), Some((0x800100, 4)));
        let p = parse_point("Z0,1a2,2").unwrap();
        assert_eq!((p.insert, p.kind, p.addr, p.len), (true, 0, 0x1a2, 2));
        let p = parse_point("z2,800123,4").unwrap();
        assert_eq!((p.insert, p.kind, p.addr, p.len), (false, 2, 0x800123, 4));
        assert_eq!(parse_point("Z0,zz,2"), None);
    }
}
