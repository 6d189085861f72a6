//! The bench's calls into the operating system that no safe crate wraps,
//! each behind a safe function. With [`crate::mcu::sim`], the only module allowed
//! `unsafe`.

use std::os::fd::{AsRawFd, BorrowedFd};

/// Put the tty behind `tty` in exclusive mode (`TIOCEXCL`): a further open
/// fails with EBUSY, except for a process holding `CAP_SYS_ADMIN`. The mode
/// outlives the descriptor: [`clear_tty_exclusive`] ends it.
pub fn set_tty_exclusive(tty: BorrowedFd<'_>) -> std::io::Result<()> {
    // SAFETY: TIOCEXCL takes no argument and only sets a flag of the tty
    // behind the descriptor, which the borrow keeps open.
    let rc = unsafe { nix::libc::ioctl(tty.as_raw_fd(), nix::libc::TIOCEXCL) };
    if rc == -1 {
        Err(std::io::Error::last_os_error())
    } else {
        Ok(())
    }
}

/// Clear the exclusive mode (`TIOCEXCL`) of the tty behind `tty`, so that
/// the next process may open it.
pub fn clear_tty_exclusive(tty: BorrowedFd<'_>) -> std::io::Result<()> {
    // SAFETY: TIOCNXCL takes no argument and only clears a flag of the tty
    // behind the descriptor, which the borrow keeps open.
    let rc = unsafe { nix::libc::ioctl(tty.as_raw_fd(), nix::libc::TIOCNXCL) };
    if rc == -1 {
        Err(std::io::Error::last_os_error())
    } else {
        Ok(())
    }
}
