//! Byte ring buffer shared between an interrupt handler and the main loop.
//!
//! Every access takes a `CriticalSection` (through `interrupt::Mutex`), so the
//! buffer needs no atomics and never panics: a full buffer refuses the byte.

use core::cell::Cell;

/// A FIFO of at most `N` bytes; `N` must be a power of two no larger than 128.
pub struct Ring<const N: usize> {
    buf: [Cell<u8>; N],
    /// Index of the oldest byte.
    head: Cell<u8>,
    /// Number of bytes stored.
    len: Cell<u8>,
}

impl<const N: usize> Ring<N> {
    const CHECK: () = assert!(N.is_power_of_two() && N <= 128);
    const MASK: u8 = (N - 1) as u8;

    /// An empty buffer (usable in a `static`).
    pub const fn new() -> Self {
        let () = Self::CHECK;
        Ring { buf: [const { Cell::new(0) }; N], head: Cell::new(0), len: Cell::new(0) }
    }

    /// Appends `byte`; returns false (and drops it) when the buffer is full.
    #[inline]
    pub fn push(&self, byte: u8) -> bool {
        let len = self.len.get();
        if len as usize >= N {
            return false;
        }
        let idx = self.head.get().wrapping_add(len) & Self::MASK;
        self.buf[idx as usize].set(byte);
        self.len.set(len + 1);
        true
    }

    /// Takes the oldest byte.
    #[inline]
    pub fn pop(&self) -> Option<u8> {
        let len = self.len.get();
        if len == 0 {
            return None;
        }
        // Masking again lets the compiler see the index is in range (no
        // bounds-check panic path); `head` is always masked already.
        let head = self.head.get() & Self::MASK;
        let byte = self.buf[head as usize].get();
        self.head.set(head.wrapping_add(1) & Self::MASK);
        self.len.set(len - 1);
        Some(byte)
    }

    /// Number of bytes stored.
    #[inline]
    pub fn len(&self) -> usize {
        self.len.get() as usize
    }

    /// True when no byte is stored.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len.get() == 0
    }

    /// Free space in bytes.
    #[inline]
    pub fn free(&self) -> usize {
        N - self.len.get() as usize
    }
}

impl<const N: usize> Default for Ring<N> {
    fn default() -> Self {
        Self::new()
    }
}
