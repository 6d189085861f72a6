//! Critical sections: code run with interrupts off, so that what a handler
//! shares with the main loop is read or written in one piece.
//!
//! On the AVR these are `avr-device`'s. On the host (the unit tests of the
//! logic) no handler runs: a critical section is a plain call.

#[cfg(target_arch = "avr")]
pub use avr_device::interrupt::{free, CriticalSection};

/// A token proving interrupts are off (host: nothing to prove).
#[cfg(not(target_arch = "avr"))]
#[derive(Clone, Copy, Debug)]
pub struct CriticalSection<'cs>(core::marker::PhantomData<&'cs ()>);

/// Runs `f` "with interrupts off" (host: just runs it).
#[cfg(not(target_arch = "avr"))]
pub fn free<F, R>(f: F) -> R
where
    F: for<'cs> FnOnce(CriticalSection<'cs>) -> R,
{
    f(CriticalSection(core::marker::PhantomData))
}
