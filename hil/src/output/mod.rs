//! Writing results: whole files or nothing, and whole folders or nothing.
//!
//! - [`write_atomic`]: one file, written beside its target and renamed over it;
//! - [`check_file`], [`write_file`] (`file.rs`): a file at a path the user
//!   named, which may be a pipe or a device (written in place), checked before
//!   anything runs;
//! - [`OutputDir`] (`set.rs`): a folder of results (`--out D`) written in full in
//!   a folder beside it, then put in its place in one rename, by one writer at a
//!   time (`lock.rs`).
//!
//! The names a writer leaves beside or in `D` while it works, each recognised
//! (and removed) by the next writer, never taken for results:
//!
//! | name | what |
//! |---|---|
//! | `.D.hil-lock` | the lock file; stays, empty |
//! | `.D.hil-new-PID` | the new set being written (after a kill: an unfinished set, or the old one being removed) |
//! | `.D.hil-old-PID` | the old set moved aside, on a file system without an atomic exchange |
//! | `D/.FILE.tmpPID` | one file being written ([`write_atomic`]) |

use std::io::Write;
use std::path::{Path, PathBuf};

use thiserror::Error;

mod file;
pub mod junit;
mod lock;
mod set;
pub mod vcd;

pub use file::{check_file, write_file, Kind, Refused, StreamedFile};
pub use lock::{share, SharedLock};
pub use set::OutputDir;

/// The temporary file a write of `path` goes to before its rename: in the
/// same folder (created), so the rename stays on one file system.
pub(crate) fn temp_beside(path: &Path) -> std::io::Result<std::path::PathBuf> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    Ok(dir.join(format!(".{name}.tmp{}", std::process::id())))
}

/// Write `bytes` to `path` atomically: a temporary file in the same folder,
/// flushed, then renamed over the target. A reader never sees half a file,
/// and a crash leaves the old one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = temp_beside(path)?;
    {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    std::fs::rename(&tmp, path)
}

/// Why a folder of results was not written. [`OutputError::Busy`],
/// [`OutputError::Foreign`] and [`OutputError::Unusable`] come before anything
/// runs ([`OutputDir::claim`]).
#[derive(Debug, Error)]
pub enum OutputError {
    #[error("--out {dir}: another hil process is writing this folder (it holds {lock}); nothing was run; run again when it is done")]
    Busy { dir: String, lock: String },
    #[error("--out {dir}: it holds {entries}, which this command does not write; the folder is replaced as a whole: give a new or empty folder")]
    Foreign { dir: String, entries: String },
    #[error("--out {dir}: {why}")]
    Unusable { dir: String, why: &'static str },
    #[error("--out {dir}: {why} while the runs went on; it was left as it was, and the results were not written")]
    Changed { dir: String, why: String },
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

impl OutputError {
    /// True for a refusal before anything ran because of what `--out`
    /// names (not another writer, not an I/O failure).
    pub fn is_bad_folder(&self) -> bool {
        matches!(self, Self::Foreign { .. } | Self::Unusable { .. })
    }

    fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Self + '_ {
        move |source| Self::Io {
            path: path.display().to_string(),
            source,
        }
    }
}

/// `dir` as its parent folder (`.` for a bare name) and its own name; None
/// for a path that names no folder of its own (`.`, `..`, `/`).
fn split(dir: &Path) -> Option<(PathBuf, std::ffi::OsString)> {
    // None for a path ending in `.` alone or `..`.
    let name = dir.file_name()?.to_owned();
    let parent = dir
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    Some((parent, name))
}

#[cfg(test)]
mod tests;
