//! The bench's GDB Remote Serial Protocol stub, on loopback only.
//!
//! simavr has a stub of its own, but it listens on every interface; this one
//! binds 127.0.0.1 and is a [`Debugger`] of the bench's own run loop: the run
//! is the run without a debugger, step for step (the plant, the faults, the
//! host's commands and the end of the run included), and the debugger only
//! pauses it.
//!
//! | file | part |
//! | --- | --- |
//! | `mod.rs` | the listener, the session's start (paused at reset) and end |
//! | `packets.rs` | framing, acks, Ctrl-C, the hex forms |
//! | `session.rs` | the commands, the stops, the memory map |
//! | `watch.rs` | the data accesses watchpoints see |
//! | `refuse.rs` | a second debugger refused while one is connected |
//!
//! What it speaks: `qSupported`, `?`, `g`/`G` (r0-r31, SREG, SP, PC: 39
//! bytes, avr-gdb's order), `p`/`P` (register 32 is SREG, 33 SP, 34 PC),
//! `m`/`M` (avr-gdb's map: flash from 0, data space from 0x800000; flash is
//! read-only), `qXfer:memory-map:read`, `c`, `s`, `Z0`/`z0` breakpoints
//! (compared with the PC after each step, flash is never patched),
//! `Z2`/`Z3`/`Z4` watchpoints (write, read, access on data space), Ctrl-C,
//! `k`, `D`, and `monitor cycle`, `monitor reset`. Anything else gets the
//! empty reply ("not supported"), as the protocol asks.

use std::net::{Ipv4Addr, SocketAddr, TcpListener};

use thiserror::Error;

use crate::bench::{Bench, BenchError, Debugger};

mod packets;
mod refuse;
mod session;
mod watch;

use session::{Resume, Session};

#[derive(Debug, Error)]
pub enum GdbError {
    #[error("cannot listen for gdb on 127.0.0.1:{port}: {source} (pick another port, or 0 for any free one)")]
    Bind { port: u16, source: std::io::Error },
    #[error("the gdb connection failed: {0}")]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Bench(#[from] BenchError),
    /// The debugger ended the run before its end: `kill`, or its
    /// connection closed without a detach.
    #[error("the run did not complete: {0}")]
    Ended(String),
}

/// A listening stub: bind first (the port is known before anyone connects),
/// then [`GdbServer::attach`].
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

    /// Wait for one debugger and serve it with the bench paused where it
    /// is (at reset, for a fresh bench), until the debugger continues or
    /// steps; from then on the debugger drives every run loop of `bench`.
    /// Other debuggers are refused while this one is connected.
    /// [`GdbError::Ended`]: the debugger killed the run, or left without a
    /// detach, before it started.
    pub fn attach(self, bench: &mut Bench) -> Result<(), GdbError> {
        let (stream, _) = self.listener.accept()?;
        let refuser = refuse::Refuser::spawn(self.listener)?;
        let mut session = Session::new(stream, bench, refuser)?;
        match session.serve(bench)? {
            Resume::Run => {
                bench.set_debugger(Some(Box::new(session)));
                Ok(())
            }
            Resume::Detach => Ok(()),
            r => Err(GdbError::Ended(r.ended().unwrap_or("ended").into())),
        }
    }
}

/// The run on `bench` is over: its debugger, if still attached, is told the
/// program exited (status 0 when the run completed, 1 otherwise) and let go.
pub fn run_over(bench: &mut Bench, completed: bool) {
    if let Some(mut d) = bench.take_debugger() {
        d.run_over(bench, completed);
    }
}

impl Debugger for Session {
    fn before_step(&mut self, bench: &Bench) {
        self.note_before(bench);
    }

    fn after_step(&mut self, bench: &mut Bench, slept: bool) -> Result<bool, BenchError> {
        let Some(reply) = self.stop_after(bench, slept) else {
            return Ok(true);
        };
        self.stop_and_serve(bench, &reply)
    }

    fn fault(&mut self, bench: &mut Bench) {
        // The run ends with the crash whatever the debugger does; it may
        // look at where and why first.
        let _ = self.stop_and_serve(bench, "S0b");
    }

    fn run_over(&mut self, _bench: &Bench, completed: bool) {
        self.exited(completed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binds_loopback_only() {
        let s = GdbServer::bind(0).unwrap();
        assert!(s.local_addr().unwrap().ip().is_loopback());
    }
}
