//! The host's client of the firmware's framed protocol over a byte stream: a
//! serial port or Bluetooth RFCOMM device (tokio-serial), the pseudo-terminal
//! of `hil serve --pty`, or an in-memory pipe in tests.
//!
//! One command at a time: the firmware queues replies on a 63-byte buffer and
//! drops what does not fit, so the protocol's README asks a host to wait for
//! each reply before the next command.
//!
//! Link faults, as an operator expects them:
//! - a reply that does not come within the timeout, or a frame the firmware
//!   could not read (reply id 0xFF), is retried for commands that do the same
//!   thing however often they arrive (queries, SET_PARAM of an absolute
//!   value, STOP);
//! - START_TEST is sent exactly once: a lost reply may mean the robot is
//!   already driving, and a second start would be refused at best or, after
//!   a short test, run it twice. The error says to check GET_STATE instead;
//! - a port that vanishes (unplugged adapter, Bluetooth link gone, `hil
//!   serve` ended) gives [`LinkError::PortGone`], never a hang.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use henrytwo_protocol::frame::{Event, Parser};
use henrytwo_protocol::message::{
    Command, FaultNotice, Reply, StateReport, Status, Telemetry, TestDoneNotice, FRAME_ERROR_ID,
    NOTIFY_FAULT, NOTIFY_TEST_DONE,
};
use henrytwo_protocol::param::Param;
use thiserror::Error;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

/// What went wrong on the link.
#[derive(Debug, Error)]
pub enum LinkError {
    #[error("cannot open {port}: {source}; check the device exists and you may use it (group dialout), or pick another port")]
    Open {
        port: String,
        source: tokio_serial::Error,
    },
    #[error("{port} is gone ({reason}): the adapter was unplugged, the Bluetooth link dropped or the emulator ended; reconnect and open the port again")]
    PortGone { port: String, reason: String },
    #[error("no reply to {command} from {port} within {timeout_ms} ms after {attempts} attempt(s); check the robot is powered, on the robust firmware, and the baud rate matches (9600 for the HC-05)")]
    NoReply {
        port: String,
        command: String,
        timeout_ms: u64,
        attempts: u32,
    },
    #[error("no reply to START_TEST from {port} within {timeout_ms} ms; it was not sent again (the test may be running already): ask GET_STATE before starting again")]
    StartUnconfirmed { port: String, timeout_ms: u64 },
    #[error("the robot refused {command}: {status:?}{hint}")]
    Refused {
        command: String,
        status: Status,
        hint: &'static str,
    },
    #[error("the robot's reply to {command} is malformed ({len} data bytes); is this the robust firmware of the same protocol version?")]
    Malformed { command: String, len: usize },
    #[error("{value} is outside the range of {param} ({min} to {max}{whole}); nothing was sent")]
    OutOfRange {
        param: &'static str,
        value: f32,
        min: f32,
        max: f32,
        whole: &'static str,
    },
}

/// Something the firmware sent unasked.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Notice {
    /// A test ran to its end.
    TestDone { test: u8, tests_done: u16 },
    /// A fault stopped the motors.
    Fault {
        fault: u8,
        test: u8,
        segment: u8,
        phase: u8,
        left: i32,
        right: i32,
    },
}

/// How patient the client is.
#[derive(Debug, Clone, Copy)]
pub struct LinkOptions {
    /// Time for a reply after the command's last byte left. At 9600 baud the
    /// longest exchange (a 6-byte command, a 29-byte reply) takes ~37 ms on
    /// the wire, plus up to one 15 ms control tick.
    pub timeout: Duration,
    /// Attempts in all for a command that may be repeated.
    pub attempts: u32,
}

impl Default for LinkOptions {
    fn default() -> Self {
        Self {
            // Generous: an RFCOMM link adds tens of milliseconds, and an
            // emulator paced to real time may lag a slice behind.
            timeout: Duration::from_millis(500),
            attempts: 3,
        }
    }
}

/// A byte stream to the robot.
pub trait Port: AsyncRead + AsyncWrite + Unpin + Send {}
impl<T: AsyncRead + AsyncWrite + Unpin + Send> Port for T {}

/// Commands a [`Link`] remembers having sent.
pub const SENT_KEPT: usize = 64;

/// The client: one command at a time over `port`.
pub struct Link {
    port: Box<dyn Port>,
    name: String,
    options: LinkOptions,
    parser: Parser,
    epoch: Instant,
    notices: VecDeque<Notice>,
    /// Replies parsed but not yet handed out (several may come in one read).
    replies: VecDeque<Frame>,
    /// The last [`SENT_KEPT`] command frames written, for tests that check
    /// what went out (the station polls for as long as it runs).
    sent: VecDeque<Command>,
}

/// A firmware frame, owned.
struct Frame {
    id: u8,
    status: Status,
    data: Vec<u8>,
}

/// Whether a command may be sent again when its reply is lost: it does the
/// same thing however often it arrives.
pub fn is_idempotent(cmd: &Command) -> bool {
    match cmd {
        Command::Ping | Command::GetState | Command::GetTelemetry | Command::GetParam(_) => true,
        // An absolute value, echoed as stored: twice is the same as once.
        Command::SetParam(..) => true,
        // Always OK, motors off: twice is the same as once.
        Command::Stop => true,
        Command::StartTest(_) => false,
    }
}

fn command_name(cmd: &Command) -> String {
    match cmd {
        Command::Ping => "PING".into(),
        Command::StartTest(t) => format!("START_TEST {t:?}"),
        Command::Stop => "STOP".into(),
        Command::GetState => "GET_STATE".into(),
        Command::GetTelemetry => "GET_TELEMETRY".into(),
        Command::SetParam(p, v) => format!("SET_PARAM {} = {v}", p.name()),
        Command::GetParam(p) => format!("GET_PARAM {}", p.name()),
    }
}

fn hint(status: Status) -> &'static str {
    match status {
        Status::Busy => " (a test is running: wait for it to end or send STOP)",
        Status::OutOfRange => " (value or test outside its range, or the leg length invalid)",
        Status::UnknownParam | Status::UnknownCommand => {
            " (the robot's firmware is older or newer than this host)"
        }
        _ => "",
    }
}

impl Link {
    /// Open a serial port (or a pseudo-terminal) at `baud`, 8N1.
    pub fn open_serial(path: &str, baud: u32, options: LinkOptions) -> Result<Self, LinkError> {
        use tokio_serial::SerialPortBuilderExt;
        let port = tokio_serial::new(path, baud)
            .data_bits(tokio_serial::DataBits::Eight)
            .parity(tokio_serial::Parity::None)
            .stop_bits(tokio_serial::StopBits::One)
            .flow_control(tokio_serial::FlowControl::None)
            .open_native_async()
            .map_err(|source| LinkError::Open {
                port: path.into(),
                source,
            })?;
        Ok(Self::new(Box::new(port), path, options))
    }

    /// A link over any byte stream; `name` names it in errors.
    pub fn new(port: Box<dyn Port>, name: &str, options: LinkOptions) -> Self {
        Self {
            port,
            name: name.into(),
            options,
            // The firmware's own inter-byte timeout: a reply's bytes come
            // back to back, so a gap this long means a torn frame.
            parser: Parser::new(50),
            epoch: Instant::now(),
            notices: VecDeque::new(),
            replies: VecDeque::new(),
            sent: VecDeque::new(),
        }
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The last commands written, in order (each attempt counts; at most
    /// [`SENT_KEPT`]).
    pub fn sent(&self) -> &VecDeque<Command> {
        &self.sent
    }

    /// Notifications received so far and not yet taken.
    pub fn take_notices(&mut self) -> Vec<Notice> {
        self.notices.drain(..).collect()
    }

    fn now_ms(&self) -> u32 {
        self.epoch.elapsed().as_millis() as u32
    }

    fn gone(&self, reason: impl std::fmt::Display) -> LinkError {
        LinkError::PortGone {
            port: self.name.clone(),
            reason: reason.to_string(),
        }
    }

    /// Read until the next complete reply frame (notifications are kept
    /// aside), or `deadline`: Ok(None) on the deadline.
    async fn next_reply(
        &mut self,
        deadline: tokio::time::Instant,
    ) -> Result<Option<Frame>, LinkError> {
        let mut buf = [0u8; 64];
        loop {
            if let Some(r) = self.replies.pop_front() {
                return Ok(Some(r));
            }
            let n = match tokio::time::timeout_at(deadline, self.port.read(&mut buf)).await {
                Err(_) => return Ok(None),
                Ok(Ok(0)) => return Err(self.gone("end of stream")),
                Ok(Ok(n)) => n,
                Ok(Err(e)) => return Err(self.gone(e)),
            };
            for &b in &buf[..n] {
                let now = self.now_ms();
                let _ = self.parser.poll(now);
                if let Some(Event::Frame(payload)) = self.parser.push(b, now) {
                    let Some(r) = Reply::decode(payload) else {
                        continue;
                    };
                    match r.id {
                        NOTIFY_TEST_DONE => {
                            if let Some(d) = TestDoneNotice::decode(r.data) {
                                self.notices.push_back(Notice::TestDone {
                                    test: d.test,
                                    tests_done: d.tests_done,
                                });
                            }
                        }
                        NOTIFY_FAULT => {
                            if let Some(f) = FaultNotice::decode(r.data) {
                                self.notices.push_back(Notice::Fault {
                                    fault: f.fault,
                                    test: f.test,
                                    segment: f.segment,
                                    phase: f.phase,
                                    left: f.left,
                                    right: f.right,
                                });
                            }
                        }
                        // A late reply to an earlier attempt may come in
                        // the same read as ours: the caller sorts them.
                        _ => self.replies.push_back(Frame {
                            id: r.id,
                            status: r.status,
                            data: r.data.to_vec(),
                        }),
                    }
                }
            }
        }
    }

    /// Collect whatever arrived while nobody asked (notifications, stale
    /// replies to an attempt that timed out), without waiting.
    pub async fn drain(&mut self) -> Result<(), LinkError> {
        let deadline = tokio::time::Instant::now() + Duration::from_millis(1);
        while self.next_reply(deadline).await?.is_some() {}
        Ok(())
    }

    /// Wait up to `wait` for notifications (returns them, possibly none).
    pub async fn wait_notices(&mut self, wait: Duration) -> Result<Vec<Notice>, LinkError> {
        let deadline = tokio::time::Instant::now() + wait;
        while self.notices.is_empty() && self.next_reply(deadline).await?.is_some() {}
        Ok(self.take_notices())
    }

    /// Send `cmd` and return its reply's data; retried per [`is_idempotent`].
    pub async fn request(&mut self, cmd: Command) -> Result<Vec<u8>, LinkError> {
        let frame = crate::firmware::link::frame(&cmd);
        let want = cmd.id().reply_id();
        let attempts = if is_idempotent(&cmd) {
            self.options.attempts.max(1)
        } else {
            1
        };
        for _ in 0..attempts {
            self.drain().await?;
            if let Err(e) = self.port.write_all(&frame).await {
                return Err(self.gone(e));
            }
            if let Err(e) = self.port.flush().await {
                return Err(self.gone(e));
            }
            if self.sent.len() == SENT_KEPT {
                self.sent.pop_front();
            }
            self.sent.push_back(cmd);
            let deadline = tokio::time::Instant::now() + self.options.timeout;
            while let Some(r) = self.next_reply(deadline).await? {
                if r.id == want {
                    return if r.status == Status::Ok {
                        Ok(r.data)
                    } else {
                        Err(LinkError::Refused {
                            command: command_name(&cmd),
                            status: r.status,
                            hint: hint(r.status),
                        })
                    };
                }
                if r.id == FRAME_ERROR_ID {
                    // The firmware could not read a frame, most likely ours
                    // damaged on the way: a repeatable command goes out
                    // again. A start is not (one attempt): the 0xFF may
                    // answer line noise while the start itself ran.
                    break;
                }
                // Another command's late reply: keep waiting for ours.
            }
        }
        let timeout_ms = self.options.timeout.as_millis() as u64;
        Err(if is_idempotent(&cmd) {
            LinkError::NoReply {
                port: self.name.clone(),
                command: command_name(&cmd),
                timeout_ms,
                attempts,
            }
        } else {
            LinkError::StartUnconfirmed {
                port: self.name.clone(),
                timeout_ms,
            }
        })
    }

    /// PING: the protocol version.
    pub async fn ping(&mut self) -> Result<u8, LinkError> {
        let d = self.request(Command::Ping).await?;
        d.first().copied().ok_or(LinkError::Malformed {
            command: "PING".into(),
            len: d.len(),
        })
    }

    pub async fn state(&mut self) -> Result<StateReport, LinkError> {
        let d = self.request(Command::GetState).await?;
        StateReport::decode(&d).ok_or(LinkError::Malformed {
            command: "GET_STATE".into(),
            len: d.len(),
        })
    }

    pub async fn telemetry(&mut self) -> Result<Telemetry, LinkError> {
        let d = self.request(Command::GetTelemetry).await?;
        Telemetry::decode(&d).ok_or(LinkError::Malformed {
            command: "GET_TELEMETRY".into(),
            len: d.len(),
        })
    }

    fn param_value(p: Param, d: &[u8], what: &str) -> Result<f32, LinkError> {
        match d {
            [id, v @ ..] if *id == p.id() && v.len() == 4 => {
                Ok(f32::from_le_bytes([v[0], v[1], v[2], v[3]]))
            }
            _ => Err(LinkError::Malformed {
                command: format!("{what} {}", p.name()),
                len: d.len(),
            }),
        }
    }

    pub async fn get_param(&mut self, p: Param) -> Result<f32, LinkError> {
        let d = self.request(Command::GetParam(p)).await?;
        Self::param_value(p, &d, "GET_PARAM")
    }

    /// SET_PARAM after checking the value against the parameter's range
    /// (nothing is sent when it is outside); returns the value as stored.
    pub async fn set_param(&mut self, p: Param, value: f32) -> Result<f32, LinkError> {
        if p.check(value).is_err() {
            let r = p.range();
            return Err(LinkError::OutOfRange {
                param: p.name(),
                value,
                min: r.min,
                max: r.max,
                whole: if r.integer { ", whole numbers" } else { "" },
            });
        }
        let d = self.request(Command::SetParam(p, value)).await?;
        Self::param_value(p, &d, "SET_PARAM")
    }

    /// START_TEST, sent once (see the module docs).
    pub async fn start(&mut self, test: henrytwo_protocol::message::Test) -> Result<(), LinkError> {
        self.request(Command::StartTest(test)).await.map(|_| ())
    }

    pub async fn stop(&mut self) -> Result<(), LinkError> {
        self.request(Command::Stop).await.map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use henrytwo_protocol::frame::{encode_frame, MAX_FRAME, MAX_PAYLOAD};
    use henrytwo_protocol::message::{CommandId, Test};
    use tokio::io::DuplexStream;

    /// A robot on the other end of a pipe that answers PING, GET_PARAM and
    /// START_TEST, and drops the replies whose numbers are in `drop`; a
    /// command numbered 0 in `drop` makes it send a stale STOP reply just
    /// before each reply, in the same write.
    async fn fake_robot(mut end: DuplexStream, drop: Vec<usize>) {
        let mut parser = Parser::new(u32::MAX);
        let mut buf = [0u8; 64];
        let mut n_cmd = 0usize;
        loop {
            let n = match end.read(&mut buf).await {
                Ok(0) | Err(_) => return,
                Ok(n) => n,
            };
            for &b in &buf[..n] {
                let Some(Event::Frame(p)) = parser.push(b, 0) else {
                    continue;
                };
                let cmd = Command::decode(p).unwrap();
                n_cmd += 1;
                if drop.contains(&n_cmd) {
                    continue;
                }
                let data: Vec<u8> = match cmd {
                    Command::Ping => vec![1],
                    Command::GetParam(p) => {
                        let mut d = vec![p.id()];
                        d.extend(1.25f32.to_le_bytes());
                        d
                    }
                    _ => vec![],
                };
                let mut payload = [0u8; MAX_PAYLOAD];
                let len = Reply {
                    id: cmd.id().reply_id(),
                    status: Status::Ok,
                    data: &data,
                }
                .encode(&mut payload)
                .unwrap();
                let mut f = [0u8; MAX_FRAME];
                let m = encode_frame(&payload[..len], &mut f).unwrap();
                let mut out = Vec::new();
                if drop.contains(&0) {
                    let stale = [CommandId::Stop.reply_id(), Status::Ok as u8];
                    let mut g = [0u8; MAX_FRAME];
                    let k = encode_frame(&stale, &mut g).unwrap();
                    out.extend(&g[..k]);
                }
                out.extend(&f[..m]);
                if end.write_all(&out).await.is_err() {
                    return;
                }
            }
        }
    }

    fn link(drop: Vec<usize>) -> Link {
        let (a, b) = tokio::io::duplex(256);
        tokio::spawn(fake_robot(b, drop));
        Link::new(
            Box::new(a),
            "pipe",
            LinkOptions {
                timeout: Duration::from_millis(100),
                attempts: 3,
            },
        )
    }

    /// The station polls for as long as it runs: what the link remembers
    /// of it stays bounded.
    #[tokio::test]
    async fn the_commands_remembered_are_bounded() {
        let mut l = link(vec![]);
        for _ in 0..SENT_KEPT + 10 {
            l.ping().await.unwrap();
        }
        assert_eq!(l.sent().len(), SENT_KEPT);
    }

    #[tokio::test]
    async fn a_lost_reply_to_a_query_is_retried() {
        let mut l = link(vec![1]);
        assert_eq!(l.get_param(Param::CorrLeft).await.unwrap(), 1.25);
        assert_eq!(l.sent().len(), 2, "{:?}", l.sent());
    }

    #[tokio::test]
    async fn a_late_reply_in_the_same_read_does_not_hide_ours() {
        let mut l = link(vec![0]);
        assert_eq!(l.get_param(Param::KpLeft).await.unwrap(), 1.25);
        assert_eq!(l.sent().len(), 1, "{:?}", l.sent());
    }

    #[tokio::test]
    async fn a_start_is_never_sent_twice() {
        let mut l = link(vec![1]);
        let e = l.start(Test::Line).await.unwrap_err();
        assert!(matches!(e, LinkError::StartUnconfirmed { .. }), "{e}");
        assert!(e.to_string().contains("GET_STATE"), "{e}");
        let starts = l
            .sent()
            .iter()
            .filter(|c| c.id() == CommandId::StartTest)
            .count();
        assert_eq!(starts, 1);
        // The link is still usable afterwards.
        assert_eq!(l.ping().await.unwrap(), 1);
    }

    #[tokio::test]
    async fn retries_give_up_with_a_message() {
        let mut l = link(vec![1, 2, 3]);
        let e = l.ping().await.unwrap_err();
        assert!(matches!(e, LinkError::NoReply { attempts: 3, .. }), "{e}");
    }

    #[tokio::test]
    async fn a_closed_stream_is_a_vanished_port() {
        let (a, b) = tokio::io::duplex(64);
        drop(b);
        let mut l = Link::new(Box::new(a), "pipe", LinkOptions::default());
        let e = l.ping().await.unwrap_err();
        assert!(matches!(e, LinkError::PortGone { .. }), "{e}");
    }

    #[tokio::test]
    async fn out_of_range_values_are_not_sent() {
        let mut l = link(vec![]);
        let e = l.set_param(Param::CorrLeft, 2.0).await.unwrap_err();
        assert!(matches!(e, LinkError::OutOfRange { .. }), "{e}");
        assert!(l.sent().is_empty());
    }
}
