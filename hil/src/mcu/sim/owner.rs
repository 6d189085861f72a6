//! The identity of one [`super::Avr`]: what an [`super::Irq`] and the
//! handler's state carry so that each use can check it is with its own MCU.

use std::sync::atomic::{AtomicU64, Ordering};

/// The identity of one [`super::Avr`], unique for the life of the process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Owner(u64);

impl Owner {
    pub(super) fn next() -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        Self(NEXT.fetch_add(1, Ordering::Relaxed))
    }

    /// The id's number, for messages.
    pub(super) fn number(self) -> u64 {
        self.0
    }
}
