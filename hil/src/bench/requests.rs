//! What a callback leaves for the run loop ([`Requests`]): a callback can
//! neither return an error nor restart the MCU it runs inside.

use super::error::PendingError;

/// What a callback leaves for the run loop: an error, a reset to perform,
/// the brown-out detector letting go.
#[derive(Default)]
pub(super) struct Requests {
    error: Option<PendingError>,
    reset: bool,
    bod_release: bool,
    /// Any of them (one flag read per instruction).
    attention: bool,
}

impl Requests {
    /// Record `e`, unless an error is already waiting.
    pub(super) fn fail(&mut self, e: PendingError) {
        if self.error.is_none() {
            self.error = Some(e);
            self.attention = true;
        }
    }

    /// Restart the MCU after this step.
    pub(super) fn reset(&mut self) {
        self.reset = true;
        self.attention = true;
    }

    /// The brown-out detector let go: restart the MCU with BORF set.
    pub(super) fn bod_release(&mut self) {
        self.bod_release = true;
        self.attention = true;
    }

    /// The reset the run loop is to perform, taken.
    pub(super) fn take_reset(&mut self) -> bool {
        std::mem::take(&mut self.reset)
    }

    /// The brown-out release the run loop is to perform, taken.
    pub(super) fn take_bod_release(&mut self) -> bool {
        std::mem::take(&mut self.bod_release)
    }

    /// The error a callback recorded, taken.
    pub(super) fn take_error(&mut self) -> Option<PendingError> {
        self.error.take()
    }

    /// Something is waiting (read once per instruction).
    #[inline]
    pub(super) fn attention(&self) -> bool {
        self.attention
    }

    /// The run loop has seen the flag (it handles what is behind it next).
    pub(super) fn clear_attention(&mut self) {
        self.attention = false;
    }
}
