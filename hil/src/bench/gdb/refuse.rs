//! While one debugger is connected, every other connection is refused: it
//! gets an error packet saying why and is closed, and hil says so on
//! stderr, rather than being accepted by the kernel and never answered.

use std::io::{ErrorKind, Read, Write};
use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use super::packets::frame;

/// How often the refusing thread looks for a connection and for its end.
const POLL: Duration = Duration::from_millis(20);

/// How long a refused client has to send its first packet.
const FIRST_PACKET: Duration = Duration::from_secs(2);

/// What a second debugger is told (gdb prints an `E.` reply's text).
pub(super) const REFUSAL: &str =
    "E.the bench serves one debugger at a time and one is connected; detach it first";

/// Refuses connections on the listener until dropped (the session's end).
pub(super) struct Refuser {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Refuser {
    pub(super) fn spawn(listener: TcpListener) -> std::io::Result<Self> {
        listener.set_nonblocking(true)?;
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let thread = std::thread::spawn(move || {
            while !flag.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((mut s, peer)) => {
                        eprintln!(
                            "gdb: refused a second debugger from {peer}: one is already connected"
                        );
                        // Best effort: the refused client may already be gone.
                        let _ = refuse(&mut s);
                        let _ = s.shutdown(std::net::Shutdown::Both);
                    }
                    Err(e) if e.kind() == ErrorKind::WouldBlock => std::thread::sleep(POLL),
                    Err(_) => std::thread::sleep(POLL),
                }
            }
        });
        Ok(Self {
            stop,
            thread: Some(thread),
        })
    }
}

/// Answer the client's first packet (gdb's `qSupported`, whose error reply
/// it prints) with the refusal: a reply sent before it asks is lost.
fn refuse(s: &mut std::net::TcpStream) -> std::io::Result<()> {
    s.set_nonblocking(false)?;
    s.set_read_timeout(Some(FIRST_PACKET))?;
    let mut got = Vec::new();
    let mut buf = [0u8; 512];
    // Up to the end of the first packet: `#` and its two checksum digits.
    while got
        .iter()
        .position(|b| *b == b'#')
        .is_none_or(|h| got.len() < h + 3)
    {
        let k = s.read(&mut buf)?;
        if k == 0 {
            return Ok(());
        }
        got.extend_from_slice(&buf[..k]);
    }
    s.write_all(b"+")?;
    s.write_all(frame(REFUSAL).as_bytes())
}

impl Drop for Refuser {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
