//! One USART of the emulated robot on a pseudo-terminal: one client at a
//! time, and the robot's bytes kept for the next client while none is there.
//!
//! Linux keeps no count of a pty's clients that a program can read. The
//! port watches its slave's inode with inotify (every open, by any path,
//! and every last close of an open file is an event), and on each event
//! counts the processes holding the slave in `/proc`: inotify merges two
//! like events not yet read (two closes in a row are one), so the events
//! say when to count, not how many. A client of another user is not seen
//! by an emulator that is neither root nor that user.
//!
//! - **One client.** Once a client has the slave open, the port sets the
//!   tty's exclusive mode (`TIOCEXCL`): a further open fails with EBUSY
//!   ("Device or resource busy"). The kernel lets a process holding
//!   `CAP_SYS_ADMIN` through; the port sees the second open, says so on
//!   stderr and holds the robot's bytes until one of the two closes, so no
//!   frame is split between two readers. When the last client closes, the
//!   exclusive mode is cleared (serial libraries set it themselves, and it
//!   outlives their close) and the line is put back to raw.
//! - **Kept until read.** While no client has the port, the robot's bytes
//!   wait in a queue of [`QUEUE_CAP`] bytes and reach the next client in
//!   order; bytes a client left unread in the tty when it closed are taken
//!   back to the queue's front. Beyond the cap the oldest bytes are dropped,
//!   and stderr says so when it starts and how many once the queue drains.

use std::collections::VecDeque;
use std::fs::File;
use std::io::{ErrorKind, Read, Write};
use std::os::fd::AsFd;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use nix::sys::inotify::{AddWatchFlags, InitFlags, Inotify};
use nix::sys::termios::Termios;

use super::EmulatorError;

/// Bytes from the robot kept for a client, per port: about 68 s of a 9600
/// baud line sending without a pause.
pub const QUEUE_CAP: usize = 64 * 1024;

/// How long a new client has to set its port up before the queue is sent:
/// pyserial, for one, flushes its input right after it opens the port, and
/// bytes delivered before that flush would be lost.
const SETTLE: Duration = Duration::from_millis(50);

/// A pty serving one USART, as its client sees it.
pub(super) struct PtyPort {
    /// How the port is named in messages (`pty`, `usb pty`).
    label: &'static str,
    master: File,
    /// The port's own handle on the slave, opened before the watch (so its
    /// own open is not counted) and never read while a client is there: it
    /// keeps the line's settings and is how the port sets and clears the
    /// exclusive mode and takes back what a client left unread.
    slave: File,
    raw: Termios,
    path: PathBuf,
    opens: Inotify,
    /// Processes holding the slave open, the port aside.
    clients: usize,
    /// When the current client came (None: no client).
    connected_at: Option<Instant>,
    queue: VecDeque<u8>,
    /// How many bytes at the queue's front were taken back from the tty
    /// since the last client left: older than every byte queued after them.
    taken_back: usize,
    /// Bytes dropped since the last report.
    dropped: u64,
}

impl PtyPort {
    /// A new pty in raw mode (no echo, no line editing, no CR/LF
    /// translation: the framed protocol is binary), never blocking the
    /// slice loop.
    pub(super) fn open(label: &'static str) -> Result<Self, EmulatorError> {
        use nix::fcntl::{fcntl, FcntlArg, OFlag};
        use nix::sys::termios::{cfmakeraw, tcgetattr, tcsetattr, SetArg};
        use std::os::fd::AsRawFd;
        let pty = nix::pty::openpty(None, None).map_err(EmulatorError::Pty)?;
        let mut raw = tcgetattr(&pty.slave).map_err(EmulatorError::Pty)?;
        cfmakeraw(&mut raw);
        tcsetattr(&pty.slave, SetArg::TCSANOW, &raw).map_err(EmulatorError::Pty)?;
        let path = nix::unistd::ttyname(&pty.slave).map_err(EmulatorError::Pty)?;
        for fd in [pty.master.as_raw_fd(), pty.slave.as_raw_fd()] {
            fcntl(fd, FcntlArg::F_SETFL(OFlag::O_NONBLOCK)).map_err(EmulatorError::Pty)?;
        }
        let watch = |source| EmulatorError::Watch {
            path: path.clone(),
            source,
        };
        let opens = Inotify::init(InitFlags::IN_NONBLOCK | InitFlags::IN_CLOEXEC).map_err(watch)?;
        opens
            .add_watch(&path, AddWatchFlags::IN_OPEN | AddWatchFlags::IN_CLOSE)
            .map_err(watch)?;
        Ok(Self {
            label,
            master: File::from(pty.master),
            slave: File::from(pty.slave),
            raw,
            path,
            opens,
            clients: 0,
            connected_at: None,
            queue: VecDeque::new(),
            taken_back: 0,
            dropped: 0,
        })
    }

    /// The slave, for the client to open as a serial port.
    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    /// Follow the clients that came and went since the last call.
    pub(super) fn follow_clients(&mut self) {
        // EAGAIN: no event. An overflowed event queue (16 384 events
        // between two slices) is an event like any other: it asks for a
        // count.
        let mut opened = false;
        let mut changed = false;
        while let Ok(events) = self.opens.read_events() {
            if events.is_empty() {
                break;
            }
            changed = true;
            opened |= events
                .iter()
                .any(|e| e.mask.contains(AddWatchFlags::IN_OPEN));
        }
        if opened {
            // At once, before the count: the window in which a second
            // client gets in is this slice, not this slice and a scan.
            // A failure (not a tty) leaves the port open to anyone.
            let _ = crate::mcu::sim::sys::set_tty_exclusive(self.slave.as_fd());
        }
        if changed {
            let clients = self.holders().unwrap_or(usize::from(opened));
            self.clients_now(clients);
        }
        if self.clients == 0 {
            // What the kernel had still in flight when the client left.
            self.take_back();
        }
    }

    fn clients_now(&mut self, clients: usize) {
        let before = std::mem::replace(&mut self.clients, clients);
        if clients == 0 {
            use nix::sys::termios::{tcsetattr, SetArg};
            self.connected_at = None;
            // Raw first: a client left in canonical mode would hold back
            // partial lines from the read below.
            let _ = tcsetattr(&self.slave, SetArg::TCSANOW, &self.raw);
            self.take_back();
            let _ = crate::mcu::sim::sys::clear_tty_exclusive(self.slave.as_fd());
            return;
        }
        if before == 0 {
            self.connected_at = Some(Instant::now());
            self.taken_back = 0;
        }
        if clients > 1 && clients > before {
            eprintln!(
                "{} {}: {clients} processes have it open (one with CAP_SYS_ADMIN passes its \
                 exclusive mode); the robot's bytes wait until one is left",
                self.label,
                self.path.display(),
            );
        }
    }

    /// How many processes hold the slave open, the port's own handle aside
    /// (`hil ui` opens its emulator's pty from the same process); None when
    /// `/proc` cannot be read.
    fn holders(&self) -> Option<usize> {
        use std::os::fd::AsRawFd;
        let me = std::process::id();
        let own = self.slave.as_raw_fd().to_string();
        let mut n = 0;
        for process in std::fs::read_dir("/proc").ok()?.flatten() {
            let Some(pid) = process
                .file_name()
                .to_str()
                .and_then(|s| s.parse::<u32>().ok())
            else {
                continue;
            };
            // Gone since, or another user's: not counted.
            let Ok(fds) = std::fs::read_dir(process.path().join("fd")) else {
                continue;
            };
            let holds = fds.flatten().any(|fd| {
                !(pid == me && fd.file_name().to_str() == Some(own.as_str()))
                    && std::fs::read_link(fd.path()).is_ok_and(|t| t == self.path)
            });
            n += usize::from(holds);
        }
        Some(n)
    }

    /// Move what the robot sent and no client read from the tty back to
    /// the queue, after what was taken back before and before what came
    /// since.
    fn take_back(&mut self) {
        let mut back = Vec::new();
        let mut buf = [0u8; 256];
        loop {
            match self.slave.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => back.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                // WouldBlock: nothing left.
                Err(_) => break,
            }
        }
        if back.is_empty() {
            return;
        }
        let later = self.queue.split_off(self.taken_back);
        self.taken_back += back.len();
        self.queue.extend(back);
        self.queue.extend(later);
        self.enforce_cap();
    }

    /// What the client wrote since the last call, appended to `out`.
    pub(super) fn take_host_bytes(&mut self, out: &mut Vec<u8>) {
        let mut buf = [0u8; 256];
        loop {
            match self.master.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                // Nothing waiting (WouldBlock): an idle line.
                Err(_) => break,
            }
        }
    }

    /// Bytes the robot sent, for the client.
    pub(super) fn queue(&mut self, bytes: &[u8]) {
        self.queue.extend(bytes);
        self.enforce_cap();
    }

    fn enforce_cap(&mut self) {
        let Some(extra) = self.queue.len().checked_sub(QUEUE_CAP).filter(|&n| n > 0) else {
            return;
        };
        if self.dropped == 0 {
            eprintln!(
                "{} {}: {QUEUE_CAP} bytes from the robot wait for a client to read them; \
                 the oldest are dropped from now on (counted when the queue drains)",
                self.label,
                self.path.display()
            );
        }
        self.queue.drain(..extra);
        self.taken_back = self.taken_back.saturating_sub(extra);
        self.dropped += extra as u64;
    }

    /// Send the queue to the client, when there is exactly one and it has
    /// had [`SETTLE`] to set its port up.
    pub(super) fn deliver(&mut self) {
        let settled = self.connected_at.is_some_and(|t| t.elapsed() >= SETTLE);
        if self.clients != 1 || !settled {
            return;
        }
        while !self.queue.is_empty() {
            let (a, _) = self.queue.as_slices();
            match self.master.write(a) {
                Ok(n) if n > 0 => {
                    self.queue.drain(..n);
                    self.taken_back = self.taken_back.saturating_sub(n);
                }
                Ok(_) => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                // WouldBlock: the client reads slower than the robot sends.
                Err(_) => break,
            }
        }
        if self.queue.is_empty() {
            self.report_dropped();
        }
    }

    fn report_dropped(&mut self) {
        if self.dropped > 0 {
            eprintln!(
                "{} {}: {} bytes from the robot were dropped, no client reading them \
                 (the queue keeps {QUEUE_CAP})",
                self.label,
                self.path.display(),
                self.dropped
            );
            self.dropped = 0;
        }
    }
}

impl Drop for PtyPort {
    fn drop(&mut self) {
        self.report_dropped();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_queue_drops_the_oldest_bytes_and_counts_them() {
        let mut port = PtyPort::open("pty").unwrap();
        let sent: Vec<u8> = (0..QUEUE_CAP + 10).map(|i| (i % 251) as u8).collect();
        port.queue(&sent[..QUEUE_CAP]);
        assert_eq!((port.queue.len(), port.dropped), (QUEUE_CAP, 0));
        port.queue(&sent[QUEUE_CAP..]);
        assert_eq!((port.queue.len(), port.dropped), (QUEUE_CAP, 10));
        // The newest kept, in order: what a client reads next starts 10
        // bytes in.
        assert!(port.queue.iter().eq(&sent[10..]));
    }
}
