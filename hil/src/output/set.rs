//! [`OutputDir`]: a folder of results replaced as a whole.
//!
//! A writer claims `D` before it runs (the lock, the folder checked), writes
//! the complete set into `.D.hil-new-PID` beside it, then swaps the two in
//! one `renameat2(RENAME_EXCHANGE)` and removes the old set. Whenever the
//! writer dies, `D` holds the old set or the new one, never a mix; what it
//! leaves beside `D` has a name the next writer recognises and removes.

use std::ffi::{OsStr, OsString};
use std::fs::File;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use super::lock::{self, Held};
use super::OutputError;

/// A folder of results claimed by this process (see the module docs).
#[derive(Debug)]
pub struct OutputDir {
    /// `D` as given.
    dir: PathBuf,
    parent: PathBuf,
    name: OsString,
    /// Where the new set is written: `.D.hil-new-PID`.
    staging: PathBuf,
    /// The files of a set: all of them, and nothing else, make one.
    files: &'static [&'static str],
    committed: bool,
    _lock: Held,
}

impl OutputDir {
    /// Claim `dir` for a set of `files`, before anything runs: the lock
    /// beside it taken ([`OutputError::Busy`] if another writer has it),
    /// whatever an earlier writer left unfinished removed, and `dir` checked:
    /// absent, or a folder holding only files of such a set (a folder with
    /// anything else is refused, as replacing it would delete what this
    /// command did not write). The folder where the new set goes is made
    /// now, so that a parent that cannot hold it is found before the run.
    pub fn claim(dir: &Path, files: &'static [&'static str]) -> Result<Self, OutputError> {
        let unusable = |why| OutputError::Unusable {
            dir: dir.display().to_string(),
            why,
        };
        let (parent, name) = super::split(dir).ok_or_else(|| {
            unusable("name the folder itself (not `.`, `..` or `/`): it is replaced as a whole")
        })?;
        std::fs::create_dir_all(&parent).map_err(OutputError::io(&parent))?;
        let lock = lock::take(&lock::lock_path(&parent, &name), dir, true)?;
        sweep(&parent, &name, dir)?;
        check(dir, &parent, files)?;
        let staging = parent.join(temp_name(&name, NEW, std::process::id()));
        std::fs::create_dir(&staging).map_err(OutputError::io(&staging))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            parent,
            name,
            staging,
            files,
            committed: false,
            _lock: lock,
        })
    }

    /// The folder to write the new set into.
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// The set is written: put it in place of `D` as a whole and return the
    /// paths of its files in `D`. Every file of the set must be in
    /// [`OutputDir::staging`], nothing else.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, OutputError> {
        for f in self.files {
            let path = self.staging.join(f);
            File::open(&path)
                .and_then(|f| f.sync_all())
                .map_err(OutputError::io(&path))?;
        }
        let extra = foreign(&self.staging, self.files, false)?;
        if !extra.is_empty() {
            return Err(OutputError::Io {
                path: self.staging.display().to_string(),
                source: std::io::Error::other(format!("not part of the set: {extra}")),
            });
        }
        sync_dir(&self.staging)?;
        // Something may have been put in `D`'s place while the set was computed.
        check(&self.dir, &self.parent, self.files).map_err(|e| match e {
            OutputError::Foreign { dir, entries } => OutputError::Changed {
                dir,
                why: format!("{entries} appeared in it"),
            },
            OutputError::Unusable { dir, why } => OutputError::Changed {
                dir,
                why: format!("it changed ({why})"),
            },
            e => e,
        })?;
        if self.dir.symlink_metadata().is_ok() {
            match exchange(&self.staging, &self.dir) {
                // The old set is now at the staging name: remove it.
                Ok(()) => remove(&self.staging)?,
                Err(e) if exchange_unsupported(&e) => self.replace_in_two_renames()?,
                Err(e) => return Err(OutputError::io(&self.dir)(e)),
            }
        } else {
            std::fs::rename(&self.staging, &self.dir).map_err(OutputError::io(&self.dir))?;
        }
        self.committed = true;
        sync_dir(&self.parent)?;
        Ok(self.files.iter().map(|f| self.dir.join(f)).collect())
    }

    /// Where the file system has no atomic exchange: the old set moved
    /// aside, the new one renamed in. A writer killed between the two
    /// leaves no `D`; the next writer puts the old set back first (see
    /// [`sweep`]).
    pub(super) fn replace_in_two_renames(&self) -> Result<(), OutputError> {
        let old = self
            .parent
            .join(temp_name(&self.name, OLD, std::process::id()));
        std::fs::rename(&self.dir, &old).map_err(OutputError::io(&self.dir))?;
        std::fs::rename(&self.staging, &self.dir).map_err(OutputError::io(&self.dir))?;
        remove(&old)
    }
}

impl Drop for OutputDir {
    /// A writer that stops before [`OutputDir::commit`] leaves `D` as it
    /// was, and nothing beside it but the lock file.
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// The two kinds of folder a writer leaves beside `D`.
const NEW: &str = "hil-new";
const OLD: &str = "hil-old";

fn temp_name(name: &OsStr, kind: &str, pid: u32) -> String {
    format!(".{}.{kind}-{pid}", name.to_string_lossy())
}

/// The kind of an entry of the parent folder that a writer of `D` left,
/// from its name.
pub(super) fn temp_kind(entry: &OsStr, name: &OsStr) -> Option<&'static str> {
    let entry = entry.to_str()?;
    let rest = entry.strip_prefix('.')?.strip_prefix(name.to_str()?)?;
    [NEW, OLD].into_iter().find(|kind| {
        rest.strip_prefix('.')
            .and_then(|r| r.strip_prefix(kind))
            .and_then(|r| r.strip_prefix('-'))
            .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// Under the lock: what earlier writers left beside `D` is removed; an old
/// set moved aside by a writer killed before it renamed the new one in is
/// put back as `D` first.
fn sweep(parent: &Path, name: &OsStr, dir: &Path) -> Result<(), OutputError> {
    let mut left = Vec::new();
    for entry in std::fs::read_dir(parent).map_err(OutputError::io(parent))? {
        let entry = entry.map_err(OutputError::io(parent))?;
        if let Some(kind) = temp_kind(&entry.file_name(), name) {
            left.push((kind, entry.path()));
        }
    }
    left.sort();
    for (kind, path) in left {
        if kind == OLD && dir.symlink_metadata().is_err() {
            std::fs::rename(&path, dir).map_err(OutputError::io(dir))?;
        } else {
            remove(&path)?;
        }
    }
    Ok(())
}

/// `dir` may be replaced by a set of `files`: absent, or a real folder (not
/// a link, not a mount point) holding nothing but such files and the
/// temporary files of a writer.
fn check(dir: &Path, parent: &Path, files: &[&str]) -> Result<(), OutputError> {
    let unusable = |why| OutputError::Unusable {
        dir: dir.display().to_string(),
        why,
    };
    let meta = match dir.symlink_metadata() {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(OutputError::io(dir)(e)),
    };
    if meta.file_type().is_symlink() {
        return Err(unusable(
            "is a symbolic link; give the folder it points to (the folder is replaced as a whole)",
        ));
    }
    if !meta.is_dir() {
        return Err(unusable("is a file, not a folder"));
    }
    let parent_dev = parent.metadata().map_err(OutputError::io(parent))?.dev();
    if meta.dev() != parent_dev {
        return Err(unusable(
            "is a mount point, which cannot be replaced as a whole; give a folder inside it",
        ));
    }
    let extra = foreign(dir, files, true)?;
    if extra.is_empty() {
        Ok(())
    } else {
        Err(OutputError::Foreign {
            dir: dir.display().to_string(),
            entries: extra,
        })
    }
}

/// The entries of `dir` that are not among `files` (nor, with `temps`, a
/// writer's temporary file), named for a message; empty when none.
fn foreign(dir: &Path, files: &[&str], temps: bool) -> Result<String, OutputError> {
    let mut extra: Vec<String> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(OutputError::io(dir))? {
        let name = entry.map_err(OutputError::io(dir))?.file_name();
        let name = name.to_string_lossy();
        if !(files.contains(&name.as_ref()) || temps && is_temp_file(&name)) {
            extra.push(name.into_owned());
        }
    }
    extra.sort();
    const SHOWN: usize = 5;
    let more = extra.len().saturating_sub(SHOWN);
    extra.truncate(SHOWN);
    let mut s = extra.join(", ");
    if more > 0 {
        s.push_str(&format!(" and {more} more"));
    }
    Ok(s)
}

/// A file a writer leaves inside `D` while it works: `.FILE.tmpPID`
/// ([`super::write_atomic`]), or `.tmp-PID` (the folder earlier versions
/// of the bench wrote plots in).
pub(super) fn is_temp_file(name: &str) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    name.strip_prefix(".tmp-").is_some_and(digits)
        || name
            .strip_prefix('.')
            .and_then(|n| n.rsplit_once(".tmp"))
            .is_some_and(|(file, pid)| !file.is_empty() && digits(pid))
}

fn remove(path: &Path) -> Result<(), OutputError> {
    let gone = match path.symlink_metadata() {
        Ok(m) if m.is_dir() => std::fs::remove_dir_all(path),
        Ok(_) => std::fs::remove_file(path),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    };
    gone.map_err(OutputError::io(path))
}

/// Make a folder's entries (a rename into or out of it) durable.
fn sync_dir(dir: &Path) -> Result<(), OutputError> {
    File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(OutputError::io(dir))
}

/// Swap the folders `a` and `b` in one step.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use nix::fcntl::{renameat2, RenameFlags};
    renameat2(None, a, None, b, RenameFlags::RENAME_EXCHANGE).map_err(std::io::Error::from)
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<()> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// The exchange failed because the system or file system has none (not
/// because of the folders).
fn exchange_unsupported(e: &std::io::Error) -> bool {
    use nix::libc::{EINVAL, ENOSYS, EOPNOTSUPP};
    e.kind() == std::io::ErrorKind::Unsupported
        || matches!(e.raw_os_error(), Some(EINVAL | ENOSYS | EOPNOTSUPP))
}
