//! Framing: `START, LEN, payload[LEN], CRC`, and a byte-at-a-time parser.
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | [`START`] = 0xA5 |
//! | 1 | 1 | `LEN`, payload length, 1..=[`MAX_PAYLOAD`] |
//! | 2 | LEN | payload (first byte: message id) |
//! | 2 + LEN | 1 | CRC-8/SMBUS over `LEN` and the payload |
//!
//! The parser resynchronises on its own:
//! - outside a frame, a byte that is not `START` is handed out as
//!   [`Event::Raw`] (the thesis' single-byte selectors);
//! - a `LEN` of 0 or above [`MAX_PAYLOAD`] gives [`FrameError::BadLength`],
//!   a wrong CRC gives [`FrameError::BadCrc`]; after either, the parser
//!   discards bytes (no events, not even raw ones: they may be the rest of a
//!   damaged frame) until the next `START` or until the line has been quiet
//!   for the timeout;
//! - a frame that stops arriving gives [`FrameError::Truncated`] once the
//!   caller's clock shows no byte for the timeout ([`Parser::poll`]).

use crate::crc::{crc8_update, INIT};

/// First byte of every frame. Not one of the raw selector bytes (2..=5).
pub const START: u8 = 0xA5;
/// Largest payload a frame may carry.
pub const MAX_PAYLOAD: usize = 32;
/// Bytes a frame adds around its payload (start, length, CRC).
pub const OVERHEAD: usize = 3;
/// Largest frame on the wire.
pub const MAX_FRAME: usize = MAX_PAYLOAD + OVERHEAD;

/// Why [`encode_frame`] refused.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum EncodeError {
    /// The payload is empty or longer than [`MAX_PAYLOAD`].
    BadLength,
    /// The output buffer is shorter than the frame.
    BufferTooSmall,
}

/// Writes the frame carrying `payload` to the start of `out`; returns its
/// length (`payload.len() + 3`).
pub fn encode_frame(payload: &[u8], out: &mut [u8]) -> Result<usize, EncodeError> {
    let n = payload.len();
    if n == 0 || n > MAX_PAYLOAD {
        return Err(EncodeError::BadLength);
    }
    let total = n + OVERHEAD;
    let Some(out) = out.get_mut(..total) else {
        return Err(EncodeError::BufferTooSmall);
    };
    let len = n as u8;
    let mut crc = crc8_update(INIT, len);
    let mut bytes = out.iter_mut();
    let mut put = |b: u8| {
        if let Some(slot) = bytes.next() {
            *slot = b;
        }
    };
    put(START);
    put(len);
    for &b in payload {
        crc = crc8_update(crc, b);
        put(b);
    }
    put(crc);
    Ok(total)
}

/// A framing error the parser detected.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FrameError {
    /// `LEN` was 0 or above [`MAX_PAYLOAD`].
    BadLength,
    /// The CRC byte did not match.
    BadCrc,
    /// The frame stopped arriving (no byte for the timeout).
    Truncated,
}

/// What one byte (or the passing of time) produced.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Event<'a> {
    /// A byte outside any frame that is not [`START`].
    Raw(u8),
    /// A complete frame with a good CRC: its payload (1..=32 bytes).
    Frame(&'a [u8]),
    /// A damaged or incomplete frame.
    Error(FrameError),
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum State {
    /// Between frames.
    Idle,
    /// After `START`, waiting for `LEN`.
    Length,
    /// Receiving the payload.
    Payload,
    /// Waiting for the CRC byte.
    Crc,
    /// After a framing error: dropping bytes until `START` or silence.
    Discard,
}

/// Byte-at-a-time frame parser with an inter-byte timeout.
///
/// Times are `u32` in any unit the caller likes (milliseconds, timer clocks)
/// and may wrap: only differences are used. The caller must call
/// [`Parser::poll`] with the current time before each [`Parser::push`] and
/// whenever time passes without bytes (for example on a periodic tick), so
/// that a silent line ends a partial frame.
#[derive(Clone, Debug)]
pub struct Parser {
    state: State,
    len: u8,
    got: u8,
    crc: u8,
    last: u32,
    timeout: u32,
    buf: [u8; MAX_PAYLOAD],
}

impl Parser {
    /// A parser between frames whose inter-byte timeout is `timeout` (in the
    /// caller's time unit).
    pub const fn new(timeout: u32) -> Self {
        Parser {
            state: State::Idle,
            len: 0,
            got: 0,
            crc: INIT,
            last: 0,
            timeout,
            buf: [0; MAX_PAYLOAD],
        }
    }

    /// The timeout given to [`Parser::new`].
    pub const fn timeout(&self) -> u32 {
        self.timeout
    }

    /// True while a frame is partly received (the caller may then want to
    /// call [`Parser::poll`] once the timeout can have passed).
    pub const fn in_frame(&self) -> bool {
        matches!(self.state, State::Length | State::Payload | State::Crc)
    }

    /// True when nothing is pending: between frames, not discarding.
    pub const fn is_idle(&self) -> bool {
        matches!(self.state, State::Idle)
    }

    /// Time of the last byte pushed.
    pub const fn last_byte_at(&self) -> u32 {
        self.last
    }

    /// Ends a partial frame (giving [`FrameError::Truncated`]) or a discard
    /// phase (silently) if no byte came for the timeout up to `now`.
    pub fn poll(&mut self, now: u32) -> Option<Event<'_>> {
        if matches!(self.state, State::Idle) || now.wrapping_sub(self.last) < self.timeout {
            return None;
        }
        let was_in_frame = self.in_frame();
        self.state = State::Idle;
        if was_in_frame {
            Some(Event::Error(FrameError::Truncated))
        } else {
            None
        }
    }

    /// Takes one received byte, received at `now`.
    pub fn push(&mut self, byte: u8, now: u32) -> Option<Event<'_>> {
        self.last = now;
        match self.state {
            State::Idle => {
                if byte == START {
                    self.state = State::Length;
                    None
                } else {
                    Some(Event::Raw(byte))
                }
            }
            State::Discard => {
                if byte == START {
                    self.state = State::Length;
                }
                None
            }
            State::Length => {
                if byte == 0 || byte as usize > MAX_PAYLOAD {
                    self.state = State::Discard;
                    Some(Event::Error(FrameError::BadLength))
                } else {
                    self.len = byte;
                    self.got = 0;
                    self.crc = crc8_update(INIT, byte);
                    self.state = State::Payload;
                    None
                }
            }
            State::Payload => {
                if let Some(slot) = self.buf.get_mut(self.got as usize) {
                    *slot = byte;
                }
                self.crc = crc8_update(self.crc, byte);
                self.got += 1;
                if self.got >= self.len {
                    self.state = State::Crc;
                }
                None
            }
            State::Crc => {
                if byte == self.crc {
                    self.state = State::Idle;
                    self.buf.get(..self.len as usize).map(Event::Frame)
                } else {
                    self.state = State::Discard;
                    Some(Event::Error(FrameError::BadCrc))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::vec::Vec;

    #[derive(Debug, PartialEq)]
    enum Ev {
        Raw(u8),
        Frame(Vec<u8>),
        Error(FrameError),
    }

    fn own(e: Option<Event<'_>>) -> Option<Ev> {
        e.map(|e| match e {
            Event::Raw(b) => Ev::Raw(b),
            Event::Frame(p) => Ev::Frame(p.to_vec()),
            Event::Error(x) => Ev::Error(x),
        })
    }

    /// Feeds bytes one time unit apart (poll before each push, as required).
    fn feed(p: &mut Parser, t0: u32, bytes: &[u8]) -> Vec<Ev> {
        let mut out = Vec::new();
        for (i, &b) in bytes.iter().enumerate() {
            let now = t0 + i as u32;
            if let Some(e) = own(p.poll(now)) {
                out.push(e);
            }
            if let Some(e) = own(p.push(b, now)) {
                out.push(e);
            }
        }
        out
    }

    fn frame(payload: &[u8]) -> Vec<u8> {
        let mut buf = [0u8; MAX_FRAME];
        let n = encode_frame(payload, &mut buf).unwrap();
        buf[..n].to_vec()
    }

    #[test]
    fn encodes_the_documented_layout() {
        // GET_STATE: payload [0x20]; CRC over [0x01, 0x20].
        let f = frame(&[0x20]);
        assert_eq!(f, [START, 0x01, 0x20, crate::crc8(&[0x01, 0x20])]);
        assert_eq!(f[3], 0xF5);
    }

    #[test]
    fn refuses_bad_payload_lengths_and_small_buffers() {
        let mut buf = [0u8; MAX_FRAME];
        assert_eq!(encode_frame(&[], &mut buf), Err(EncodeError::BadLength));
        assert_eq!(
            encode_frame(&[0; MAX_PAYLOAD + 1], &mut buf),
            Err(EncodeError::BadLength)
        );
        assert_eq!(
            encode_frame(&[1, 2], &mut buf[..4]),
            Err(EncodeError::BufferTooSmall)
        );
        assert_eq!(encode_frame(&[0; MAX_PAYLOAD], &mut buf), Ok(MAX_FRAME));
    }

    #[test]
    fn round_trips_every_length() {
        let mut p = Parser::new(50);
        for n in 1..=MAX_PAYLOAD {
            let payload: Vec<u8> = (0..n as u8).map(|i| i.wrapping_mul(37) ^ 0xA5).collect();
            let ev = feed(&mut p, 1000 * n as u32, &frame(&payload));
            assert_eq!(ev, [Ev::Frame(payload)], "length {n}");
            assert!(p.is_idle());
        }
    }

    #[test]
    fn raw_bytes_between_frames() {
        let mut p = Parser::new(50);
        let mut bytes = std::vec![4u8, 2];
        bytes.extend(frame(&[0x11]));
        bytes.push(5);
        assert_eq!(
            feed(&mut p, 0, &bytes),
            [
                Ev::Raw(4),
                Ev::Raw(2),
                Ev::Frame(std::vec![0x11]),
                Ev::Raw(5)
            ]
        );
    }

    #[test]
    fn start_byte_inside_a_payload_is_data() {
        let mut p = Parser::new(50);
        let payload = [0x30, START, START, 0x00, START, 0x01];
        assert_eq!(
            feed(&mut p, 0, &frame(&payload)),
            [Ev::Frame(payload.to_vec())]
        );
    }

    #[test]
    fn bad_crc_then_discard_until_start() {
        let mut p = Parser::new(50);
        let mut f = frame(&[0x10, 4]);
        *f.last_mut().unwrap() ^= 0x01;
        let mut bytes = f;
        // Leftovers of a damaged frame: dropped, not taken as raw selectors.
        bytes.extend([3u8, 4]);
        bytes.extend(frame(&[0x20]));
        assert_eq!(
            feed(&mut p, 0, &bytes),
            [Ev::Error(FrameError::BadCrc), Ev::Frame(std::vec![0x20])]
        );
    }

    #[test]
    fn bad_length_then_discard_until_silence() {
        let mut p = Parser::new(50);
        assert_eq!(
            feed(&mut p, 0, &[START, 0, 4, 4]),
            [Ev::Error(FrameError::BadLength)]
        );
        assert_eq!(
            feed(&mut p, 10, &[START, 33]),
            [Ev::Error(FrameError::BadLength)]
        );
        // Still discarding 49 units after the last byte...
        assert_eq!(own(p.poll(11 + 49)), None);
        assert_eq!(feed(&mut p, 11 + 49, &[4]), []);
        // ...quiet for 50: back to idle, raw bytes count again.
        assert_eq!(own(p.poll(60 + 50)), None);
        assert!(p.is_idle());
        assert_eq!(feed(&mut p, 200, &[4]), [Ev::Raw(4)]);
    }

    #[test]
    fn a_gap_truncates_a_partial_frame() {
        let mut p = Parser::new(50);
        let f = frame(&[0x30, 4, 0, 0, 0xFA, 0x44]);
        assert_eq!(feed(&mut p, 0, &f[..4]), []);
        assert!(p.in_frame());
        // Last byte at t = 3: not yet at 52, truncated at 53.
        assert_eq!(own(p.poll(52)), None);
        assert_eq!(own(p.poll(53)), Some(Ev::Error(FrameError::Truncated)));
        assert_eq!(own(p.poll(54)), None);
        // A fresh frame parses normally afterwards.
        assert_eq!(
            feed(&mut p, 100, &f),
            [Ev::Frame(f[2..f.len() - 1].to_vec())]
        );
    }

    #[test]
    fn every_truncation_point_is_reported_once() {
        let f = frame(&[0x31, 4]);
        for cut in 1..f.len() {
            let mut p = Parser::new(50);
            assert_eq!(feed(&mut p, 0, &f[..cut]), [], "cut at {cut}");
            assert_eq!(
                own(p.poll(cut as u32 + 100)),
                Some(Ev::Error(FrameError::Truncated))
            );
            assert!(p.is_idle());
        }
    }

    #[test]
    fn time_may_wrap() {
        let mut p = Parser::new(50);
        let f = frame(&[0x20]);
        let t0 = u32::MAX - 1;
        assert_eq!(own(p.poll(t0)), None);
        assert_eq!(own(p.push(f[0], t0)), None);
        assert_eq!(own(p.poll(t0.wrapping_add(40))), None);
        assert_eq!(
            own(p.poll(t0.wrapping_add(50))),
            Some(Ev::Error(FrameError::Truncated))
        );
    }

    #[test]
    fn slow_but_steady_bytes_are_not_truncated() {
        let mut p = Parser::new(50);
        let f = frame(&[0x21]);
        let mut out = Vec::new();
        for (i, &b) in f.iter().enumerate() {
            let now = 49 * i as u32;
            if let Some(e) = own(p.poll(now)) {
                out.push(e);
            }
            if let Some(e) = own(p.push(b, now)) {
                out.push(e);
            }
        }
        assert_eq!(out, [Ev::Frame(std::vec![0x21])]);
    }

    /// Every single-bit error in a frame is caught (bad CRC, bad length or a
    /// frame that never completes), never delivered as a good frame.
    #[test]
    fn no_single_bit_error_gets_through() {
        let f = frame(&[0x30, 8, 0x00, 0x00, 0x80, 0x3F]);
        for byte in 1..f.len() {
            for bit in 0..8 {
                let mut g = f.clone();
                g[byte] ^= 1 << bit;
                let mut p = Parser::new(50);
                let mut ev = feed(&mut p, 0, &g);
                if let Some(e) = own(p.poll(1000)) {
                    ev.push(e);
                }
                assert!(
                    !ev.iter().any(|e| matches!(e, Ev::Frame(_))),
                    "byte {byte} bit {bit}: {ev:?}"
                );
                assert!(!ev.is_empty(), "byte {byte} bit {bit}: silently lost");
            }
        }
    }
}
