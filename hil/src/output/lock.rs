//! One writer at a time: an advisory lock (`flock`) on `.D.hil-lock`
//! beside the folder `D`. Beside, not inside: `D` itself is replaced by each
//! writer, and a lock on a file in it would be on the old folder.
//!
//! A second writer is refused at once, not made to wait: two jobs writing one
//! `--out` is a mistake in a pipeline, and waiting would leave whichever
//! finished last, exit 0 for both. The lock goes with the process (a kill
//! releases it); the empty lock file stays, as removing it races with a
//! writer that has just opened it.

use std::fs::File;
use std::path::{Path, PathBuf};

use nix::errno::Errno;
use nix::fcntl::{Flock, FlockArg};

use super::OutputError;

/// The lock file of the folder `name` in `parent`.
pub(super) fn lock_path(parent: &Path, name: &std::ffi::OsStr) -> PathBuf {
    parent.join(format!(".{}.hil-lock", name.to_string_lossy()))
}

/// Held while a writer works; released when dropped (or by the kernel when
/// the process dies).
#[derive(Debug)]
pub(super) struct Held(#[allow(dead_code)] Flock<File>);

/// Take the lock at `path` (`dir` for messages), exclusive or shared,
/// without waiting: [`OutputError::Busy`] when another process holds it
/// against us.
pub(super) fn take(path: &Path, dir: &Path, exclusive: bool) -> Result<Held, OutputError> {
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(path)
        .map_err(OutputError::io(path))?;
    let how = if exclusive {
        FlockArg::LockExclusiveNonblock
    } else {
        FlockArg::LockSharedNonblock
    };
    match Flock::lock(file, how) {
        Ok(lock) => Ok(Held(lock)),
        Err((_, Errno::EWOULDBLOCK)) => Err(OutputError::Busy {
            dir: dir.display().to_string(),
            lock: path.display().to_string(),
        }),
        Err((_, e)) => Err(OutputError::Io {
            path: path.display().to_string(),
            source: e.into(),
        }),
    }
}

/// A shard writer's hold on a folder it adds one file to (`hil umbmark
/// --shard`): shards of one plan write into one folder side by side, so
/// they share the lock, and a writer replacing the folder as a whole is
/// refused while they run (and they while it does).
#[derive(Debug)]
pub struct SharedLock(#[allow(dead_code)] Option<Held>);

/// Share the lock of `dir` (see [`SharedLock`]). Where no lock file can be
/// made beside `dir` (a read-only parent, as a volume mounted at `/results`
/// has), or `dir` names no folder of its own (`.`), the shards go on
/// without one, as they did before there was a lock: each writes one file
/// of its own, whole.
pub fn share(dir: &Path) -> Result<SharedLock, OutputError> {
    let Some((parent, name)) = super::split(dir) else {
        return Ok(SharedLock(None));
    };
    if std::fs::create_dir_all(&parent).is_err() {
        return Ok(SharedLock(None));
    }
    match take(&lock_path(&parent, &name), dir, false) {
        Ok(held) => Ok(SharedLock(Some(held))),
        Err(e @ OutputError::Busy { .. }) => Err(e),
        Err(_) => Ok(SharedLock(None)),
    }
}
