//! The bad-input corpus (fixtures/bad/cases.toml): every case a command line,
//! with the files it reads in fixtures/bad/, its expected exit code and a
//! fragment of its message. Each case is run with a time limit; every failing
//! case is reported at once, not only the first. A case fails on a panic, an
//! exit code other than its own, a message without its fragment, a run past
//! its limit, or a path left as it should not be.
//!
//! The next round of bad inputs joins the corpus as cases; this file stays.

#[path = "support/mod.rs"]
mod support;

use std::io::Read;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde::Deserialize;

/// The corpus file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Corpus {
    case: Vec<Case>,
}

/// One case. In `args`, `prepare` and `after`: `{bad}` is fixtures/bad,
/// `{fixtures}` fixtures/, `{tmp}` a fresh folder of the case's own (also
/// its working folder).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    name: String,
    args: Vec<String>,
    exit: i32,
    stderr_contains: String,
    /// Also on stdout (a listing, a path).
    #[serde(default)]
    stdout_contains: Option<String>,
    /// Limit of the whole command, seconds: refusals come at once.
    #[serde(default = "default_timeout")]
    timeout_s: f64,
    /// What to make in `{tmp}` first, each `KIND:PATH`: `fifo` (a named pipe,
    /// read to its end while the case runs), `dir`, `file` (empty), `symlink`
    /// (to a file `PATH.target` holding `old`), `fulldev` (a character device
    /// like /dev/full: root only, the case is skipped otherwise).
    #[serde(default)]
    prepare: Vec<String>,
    /// What each path must be after the run, `KIND:PATH`: `fifo`, `chardev`,
    /// `symlink`, `absent`, `file`, `dir`; `fifo-read:PATH` also asks that the
    /// reader got bytes.
    #[serde(default)]
    after: Vec<String>,
}

/// The start of a `prepare` error that skips its case rather than fails it.
const SKIP: &str = "skip: ";

fn default_timeout() -> f64 {
    10.0
}

fn expand(s: &str, tmp: &Path) -> String {
    let fixtures = hil::paths::workspace_root().join("fixtures");
    s.replace("{bad}", &fixtures.join("bad").display().to_string())
        .replace("{fixtures}", &fixtures.display().to_string())
        .replace("{tmp}", &tmp.display().to_string())
}

/// A pipe's reader: the path, the bytes it got (joined after the case), and
/// a handle that holds the pipe open for reading and writing while the case
/// runs. Held, it lets the reader's open return at once and keeps it reading
/// until dropped, even if the command never opens the pipe or replaces it.
type Reader = (PathBuf, std::thread::JoinHandle<usize>, std::fs::File);

fn prepare(spec: &str, tmp: &Path) -> Result<Option<Reader>, String> {
    let (kind, path) = spec
        .split_once(':')
        .ok_or_else(|| format!("prepare {spec:?}: give KIND:PATH"))?;
    let path = PathBuf::from(expand(path, tmp));
    let path = if path.is_relative() {
        tmp.join(path)
    } else {
        path
    };
    let fail = |e: String| format!("prepare {spec}: {e}");
    match kind {
        "dir" => std::fs::create_dir_all(&path).map_err(|e| fail(e.to_string()))?,
        "file" => std::fs::write(&path, b"").map_err(|e| fail(e.to_string()))?,
        "symlink" => {
            let target = path.with_extension("target");
            std::fs::write(&target, b"old").map_err(|e| fail(e.to_string()))?;
            std::os::unix::fs::symlink(&target, &path).map_err(|e| fail(e.to_string()))?;
        }
        "fulldev" => {
            // A device like /dev/full, of the case's own: a check that breaks
            // must not replace the machine's /dev/full with a regular file.
            use nix::sys::stat::{makedev, mknod, Mode, SFlag};
            mknod(
                &path,
                SFlag::S_IFCHR,
                Mode::S_IRUSR | Mode::S_IWUSR,
                makedev(1, 7),
            )
            .map_err(|e| format!("{SKIP}mknod needs root ({e})"))?;
        }
        "fifo" => {
            nix::unistd::mkfifo(&path, nix::sys::stat::Mode::S_IRWXU)
                .map_err(|e| fail(e.to_string()))?;
            let hold = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .open(&path)
                .map_err(|e| fail(e.to_string()))?;
            let p = path.clone();
            let reader = std::thread::spawn(move || {
                let mut bytes = Vec::new();
                if let Ok(mut f) = std::fs::File::open(&p) {
                    let _ = f.read_to_end(&mut bytes);
                }
                bytes.len()
            });
            return Ok(Some((path, reader, hold)));
        }
        other => return Err(fail(format!("unknown kind {other:?}"))),
    }
    Ok(None)
}

/// The pipe's reader joined: the held handle closed, the pipe has no writer
/// left and the reader sees its end.
fn finish_reader((_, reader, hold): Reader) -> usize {
    drop(hold);
    reader.join().unwrap_or(0)
}

fn check_after(spec: &str, tmp: &Path, read: &[(PathBuf, usize)]) -> Result<(), String> {
    let (kind, path) = spec
        .split_once(':')
        .ok_or_else(|| format!("after {spec:?}: give KIND:PATH"))?;
    let path = PathBuf::from(expand(path, tmp));
    let path = if path.is_relative() {
        tmp.join(path)
    } else {
        path
    };
    let meta = path.symlink_metadata();
    let t = meta.as_ref().map(|m| m.file_type());
    let ok = match kind {
        "absent" => meta.is_err(),
        "fifo" => t.is_ok_and(|t| t.is_fifo()),
        "chardev" => t.is_ok_and(|t| t.is_char_device()),
        "symlink" => {
            t.is_ok_and(|t| t.is_symlink())
                && std::fs::read(path.with_extension("target")).is_ok_and(|b| b == b"old")
        }
        "file" => t.is_ok_and(|t| t.is_file()),
        "dir" => t.is_ok_and(|t| t.is_dir()),
        "fifo-read" => read.iter().any(|(p, n)| *p == path && *n > 0),
        other => return Err(format!("after {spec:?}: unknown kind {other:?}")),
    };
    if ok {
        Ok(())
    } else {
        Err(format!("after: {path:?} is not {kind} ({t:?})"))
    }
}

/// Run one case; Err says every way it failed.
fn run(case: &Case, root: &Path) -> Result<Duration, String> {
    let tmp = root.join(&case.name);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp).map_err(|e| e.to_string())?;
    let mut readers = Vec::new();
    for p in &case.prepare {
        readers.extend(prepare(p, &tmp)?);
    }

    let args: Vec<String> = case.args.iter().map(|a| expand(a, &tmp)).collect();
    let limit = Duration::from_secs_f64(case.timeout_s);
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(&args)
        .current_dir(&tmp)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("hil does not start: {e}"))?;
    // Both pipes drained while the command runs, so that a long message
    // cannot stall it.
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = Vec::new();
            let _ = r.read_to_end(&mut s);
            String::from_utf8_lossy(&s).into_owned()
        })
    };
    let out = drain(Box::new(child.stdout.take().expect("piped")));
    let err = drain(Box::new(child.stderr.take().expect("piped")));
    let mut timed_out = false;
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if start.elapsed() > limit {
            timed_out = true;
            let _ = child.kill();
            break child.wait().map_err(|e| e.to_string())?;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let took = start.elapsed();
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    let read: Vec<(PathBuf, usize)> = readers
        .into_iter()
        .map(|r| (r.0.clone(), finish_reader(r)))
        .collect();
    let mut problems = Vec::new();
    if timed_out {
        problems.push(format!("still running after {limit:?}: killed"));
    }
    if stderr.contains("panicked at") {
        problems.push("panicked".into());
    }
    if status.code() != Some(case.exit) {
        problems.push(format!("exit {:?}, expected {}", status.code(), case.exit));
    }
    let fragment = expand(&case.stderr_contains, &tmp);
    if !stderr.contains(&fragment) {
        problems.push(format!("stderr lacks {fragment:?}"));
    }
    if let Some(s) = &case.stdout_contains {
        if !stdout.contains(&expand(s, &tmp)) {
            problems.push(format!("stdout lacks {s:?}"));
        }
    }
    for a in &case.after {
        if let Err(e) = check_after(a, &tmp, &read) {
            problems.push(e);
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    if problems.is_empty() {
        Ok(took)
    } else {
        Err(format!(
            "{} (hil {}): {}\n    stderr: {}",
            case.name,
            args.join(" "),
            problems.join("; "),
            stderr.trim_end().replace('\n', "\n            ")
        ))
    }
}

#[test]
fn every_bad_input_of_the_corpus_is_handled() {
    let _ = support::firmware_path("robust");
    let file = hil::paths::workspace_root().join("fixtures/bad/cases.toml");
    let text = std::fs::read_to_string(&file).expect("fixtures/bad/cases.toml");
    let corpus: Corpus = toml::from_str(&text).expect("the corpus parses");
    let mut names = std::collections::BTreeSet::new();
    for c in &corpus.case {
        assert!(names.insert(c.name.as_str()), "case {} twice", c.name);
    }
    let root = std::env::temp_dir().join(format!("hil-bad-inputs-{}", std::process::id()));
    let start = Instant::now();
    let mut failures = Vec::new();
    for case in &corpus.case {
        match run(case, &root) {
            Ok(took) => eprintln!("ok   {:<44} {:>6.2} s", case.name, took.as_secs_f64()),
            Err(e) if e.starts_with(SKIP) => eprintln!("skip {:<44} {e}", case.name),
            Err(e) => {
                eprintln!("FAIL {}", case.name);
                failures.push(e);
            }
        }
    }
    let _ = std::fs::remove_dir_all(&root);
    eprintln!(
        "{} cases in {:.1} s",
        corpus.case.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        corpus.case.len(),
        failures.join("\n")
    );
}
