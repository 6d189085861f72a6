//! The robust build's rule for the thesis' raw selector bytes on the
//! Bluetooth UART: a byte outside a frame counts only when it arrives
//! **isolated** on the line, with no other byte received within the quiet
//! time before it and within the quiet time after it.
//!
//! A frame's bytes come back to back (about 1.04 ms apart at 9600 baud), so
//! no byte of a frame, damaged or not, is isolated: noise on the link (a
//! frame whose `START` byte arrives damaged is read as raw bytes) cannot
//! start a test. A host or a person sending one selector byte leaves the line
//! quiet around it; the byte is acted upon once the quiet time after it has
//! passed.
//!
//! Times are timer 1 clocks ([`crate::time`]), compared through differences.
//! No byte since reset counts as silence.

use crate::time::reached;

/// The line's recent past, as far as the isolation rule needs it.
pub struct Isolation {
    /// The quiet time, in timer clocks.
    quiet: u32,
    /// When the last byte was received; `None` once the line has been quiet
    /// for the quiet time (and at reset).
    last: Option<u32>,
    /// The last byte received, when it was preceded by silence and the
    /// caller holds it as a selector.
    held: Option<u8>,
}

impl Isolation {
    /// A quiet line; `quiet` in timer clocks.
    pub const fn new(quiet: u32) -> Self {
        Isolation { quiet, last: None, held: None }
    }

    /// Notes a byte received at `now` (every byte, before the frame parser
    /// sees it): drops the held byte, which was not followed by silence.
    /// Returns true when the line had been quiet for the quiet time before
    /// this byte.
    pub const fn received(&mut self, now: u32) -> bool {
        let quiet = match self.last {
            Some(t) => reached(now, t.wrapping_add(self.quiet)),
            None => true,
        };
        self.last = Some(now);
        self.held = None;
        quiet
    }

    /// Holds `byte`, the byte just noted by [`Isolation::received`] (which
    /// returned true), until the line has been quiet after it.
    pub const fn hold(&mut self, byte: u8) {
        self.held = Some(byte);
    }

    /// Ages the line to `now`: returns the held byte once the quiet time has
    /// passed since it with no other byte. Call it at least every few
    /// seconds (the control tick does), so the last byte's time never wraps.
    pub const fn poll(&mut self, now: u32) -> Option<u8> {
        match self.last {
            Some(t) if reached(now, t.wrapping_add(self.quiet)) => {
                self.last = None;
                self.held.take()
            }
            _ => None,
        }
    }
}

// The rule at 9600 baud (a byte every 260 timer clocks) with a 50 ms quiet
// time (12 500 clocks).
const _: () = {
    const Q: u32 = 12_500;
    const BYTE: u32 = 260;
    // An isolated byte: taken once the line stayed quiet after it, once.
    let mut s = Isolation::new(Q);
    assert!(s.received(1000));
    s.hold(4);
    assert!(s.poll(1000 + Q - 1).is_none());
    assert!(matches!(s.poll(1000 + Q), Some(4)));
    assert!(s.poll(1000 + 2 * Q).is_none());
    // A START_TEST frame (A5 02 10 02 8F) with one bit flipped in every byte
    // (25 03 11 06 8E): back to back, no byte is isolated.
    let mut s = Isolation::new(Q);
    assert!(s.received(0));
    s.hold(0x25);
    let mut k = 1;
    while k < 5 {
        assert!(!s.received(k * BYTE));
        k += 1;
    }
    assert!(s.poll(10 * Q).is_none());
    // A byte after a quiet line is dropped if another follows within the
    // quiet time; that one had no silence before it; after a quiet time the
    // next byte has.
    let mut s = Isolation::new(Q);
    assert!(s.received(0));
    s.hold(3);
    assert!(!s.received(Q - 1));
    assert!(s.poll(3 * Q).is_none());
    assert!(s.received(3 * Q));
    // Across the clock's wrap.
    let mut s = Isolation::new(Q);
    assert!(s.received(u32::MAX - 10));
    s.hold(5);
    assert!(s.poll(Q - 12).is_none());
    assert!(matches!(s.poll(Q - 11), Some(5)));
};
