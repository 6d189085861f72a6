//! One result file at a path the user named (`--vcd`, `--trace-csv`,
//! `--junit`, `--markdown`, `golden record --out`, a shard's partial result):
//! checked before anything runs, written when the work is done.
//!
//! | the path is | written |
//! |---|---|
//! | absent, or a regular file | atomically ([`super::write_atomic`]): a reader sees the old file or the new one |
//! | a named pipe, a character device (a terminal, `/dev/null`, `/dev/full`) | in place: opened and written, never replaced (a rename would put a regular file where the pipe or device was) |
//! | a symbolic link | refused, as `--out DIR` refuses one: renaming over it would replace the link and leave its target as it was |
//! | a folder, a socket, a block device | refused |

use std::fs::FileType;
use std::io::Write;
use std::os::unix::fs::FileTypeExt;
use std::path::Path;

use thiserror::Error;

/// How a checked output path is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A new or regular file, replaced as a whole.
    Replace,
    /// A pipe or a character device, written in place.
    InPlace,
}

/// An output path refused before anything ran; the message names the path.
#[derive(Debug, Error)]
#[error("{path}: {why}")]
pub struct Refused {
    pub path: String,
    pub why: String,
}

/// What `path` is and whether a result can be written there: see the module
/// docs. A path to be replaced must be below a folder this process can write
/// in (the nearest that exists: the missing ones are made); a probe file is
/// created there and removed, so that a run's result is not lost at its end.
pub fn check_file(path: &Path) -> Result<Kind, Refused> {
    let refused = |why: String| Refused {
        path: path.display().to_string(),
        why,
    };
    match path.symlink_metadata() {
        Ok(meta) => {
            let kind = kind_of(meta.file_type()).map_err(|why| refused(why.into()))?;
            if kind == Kind::InPlace {
                return Ok(kind);
            }
        }
        // Absent, or below a file: the nearest path that exists says which.
        Err(e)
            if matches!(
                e.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
            ) => {}
        Err(e) => return Err(refused(e.to_string())),
    }
    let mut dir = parent(path);
    while !dir.exists() {
        dir = parent(dir);
    }
    if !dir.is_dir() {
        return Err(refused(format!("{} is not a folder", dir.display())));
    }
    let probe = dir.join(format!(".hil-probe{}", std::process::id()));
    std::fs::File::create(&probe)
        .map_err(|e| refused(format!("cannot write in {}: {e}", dir.display())))?;
    let _ = std::fs::remove_file(&probe);
    Ok(Kind::Replace)
}

/// Write `bytes` to `path` as [`check_file`] says: atomically, or in place
/// for a pipe or a device. The path is looked at again: it may have changed
/// since it was checked.
pub fn write_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let kind = match path.symlink_metadata() {
        Ok(meta) => kind_of(meta.file_type())
            .map_err(|why| std::io::Error::new(std::io::ErrorKind::InvalidInput, why))?,
        Err(_) => Kind::Replace,
    };
    match kind {
        Kind::Replace => super::write_atomic(path, bytes),
        Kind::InPlace => {
            // No truncation, no creation: a pipe or a device is written as it is.
            let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
            f.write_all(bytes)?;
            f.flush()
        }
    }
}

/// A result file written while the work goes (a trace as the run makes
/// it), as [`write_file`] writes one at the end: into a temporary file in
/// the same folder, renamed over `path` by [`StreamedFile::commit`] (and
/// removed when dropped uncommitted: a run that failed leaves no half
/// file); a pipe or a device in place.
pub struct StreamedFile {
    file: std::fs::File,
    path: std::path::PathBuf,
    tmp: Option<std::path::PathBuf>,
}

impl StreamedFile {
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let kind = match path.symlink_metadata() {
            Ok(meta) => kind_of(meta.file_type())
                .map_err(|why| std::io::Error::new(std::io::ErrorKind::InvalidInput, why))?,
            Err(_) => Kind::Replace,
        };
        let (file, tmp) = match kind {
            Kind::Replace => {
                let tmp = super::temp_beside(path)?;
                (std::fs::File::create(&tmp)?, Some(tmp))
            }
            Kind::InPlace => (std::fs::OpenOptions::new().write(true).open(path)?, None),
        };
        Ok(Self {
            file,
            path: path.to_path_buf(),
            tmp,
        })
    }

    /// Everything written: the file in its place.
    pub fn commit(mut self) -> std::io::Result<()> {
        self.file.flush()?;
        if let Some(tmp) = self.tmp.take() {
            self.file.sync_all()?;
            std::fs::rename(&tmp, &self.path)?;
        }
        Ok(())
    }
}

impl Write for StreamedFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Drop for StreamedFile {
    fn drop(&mut self) {
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

fn kind_of(t: FileType) -> Result<Kind, &'static str> {
    if t.is_file() {
        Ok(Kind::Replace)
    } else if t.is_fifo() || t.is_char_device() {
        Ok(Kind::InPlace)
    } else if t.is_symlink() {
        Err("it is a symbolic link: give the path it points to (a result file replaces the file at its path, and would replace the link, not what it points to)")
    } else if t.is_dir() {
        Err("it is a folder: give a file's path")
    } else {
        Err("it is a socket or a block device: give a file's path, a pipe or a character device")
    }
}

fn parent(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("hil-output-file-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_new_or_regular_file_is_replaced() {
        let d = temp("regular");
        let p = d.join("sub/out.txt");
        assert_eq!(check_file(&p).unwrap(), Kind::Replace);
        write_file(&p, b"one").unwrap();
        write_file(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
    }

    #[test]
    fn a_symlink_and_a_folder_are_refused() {
        let d = temp("refused");
        let target = d.join("target.txt");
        std::fs::write(&target, b"old").unwrap();
        let link = d.join("link.txt");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let e = check_file(&link).unwrap_err();
        assert!(e.to_string().contains("symbolic link"), "{e}");
        assert!(write_file(&link, b"new").is_err());
        assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        let e = check_file(&d).unwrap_err();
        assert!(e.to_string().contains("folder"), "{e}");
    }

    #[test]
    fn a_device_is_written_in_place() {
        let null = Path::new("/dev/null");
        assert_eq!(check_file(null).unwrap(), Kind::InPlace);
        write_file(null, b"x").unwrap();
        assert!(null.metadata().unwrap().file_type().is_char_device());
        let full = Path::new("/dev/full");
        if full.exists() {
            assert!(write_file(full, b"x").is_err(), "a full device reports it");
            assert!(full.metadata().unwrap().file_type().is_char_device());
        }
    }

    #[test]
    fn a_fifo_is_written_in_place() {
        let d = temp("fifo");
        let p = d.join("pipe");
        nix::unistd::mkfifo(&p, nix::sys::stat::Mode::S_IRWXU).unwrap();
        assert_eq!(check_file(&p).unwrap(), Kind::InPlace);
        let reader = {
            let p = p.clone();
            std::thread::spawn(move || std::fs::read(p).unwrap())
        };
        write_file(&p, b"through").unwrap();
        assert_eq!(reader.join().unwrap(), b"through");
        assert!(p.symlink_metadata().unwrap().file_type().is_fifo());
    }
}
