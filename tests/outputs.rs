//! `--out D` is replaced as a whole, by one writer at a time: `hil umbmark`
//! killed (SIGKILL) at moments spread over its run leaves D holding exactly
//! the old set or exactly the new one, byte for byte, and the next writer
//! leaves no temporary entry beside it; a second writer is refused, exit 4.

#[path = "support/mod.rs"]
mod support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// A small, fast UMBmark (10 runs of a 100 mm square, one thread): under a
/// second of CPU.
fn umbmark(seed: u64, out: &Path) -> Command {
    let _ = support::firmware_path("robust");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hil"));
    cmd.current_dir(hil::paths::workspace_root())
        .args([
            "umbmark",
            "--leg-mm",
            "100",
            "--deterministic",
            "--jobs",
            "1",
        ])
        .args(["--seed", &seed.to_string(), "--out"])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hil-outputs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A folder's files by name, with their bytes (None: no such folder).
type Set = BTreeMap<String, Vec<u8>>;

fn read_set(dir: &Path) -> Option<Set> {
    let entries = std::fs::read_dir(dir).ok()?;
    Some(
        entries
            .map(|e| {
                let e = e.unwrap();
                let bytes = std::fs::read(e.path()).unwrap_or_default();
                (e.file_name().to_string_lossy().into_owned(), bytes)
            })
            .collect(),
    )
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The complete sets of seeds 1 and 2, from runs left alone, and the wall
/// time such a run took.
fn references() -> &'static ([Set; 2], Duration) {
    static REFS: OnceLock<([Set; 2], Duration)> = OnceLock::new();
    REFS.get_or_init(|| {
        let root = scratch("refs");
        let mut wall = Duration::ZERO;
        let sets = [1, 2].map(|seed| {
            let d = root.join(format!("seed{seed}"));
            let t0 = Instant::now();
            let out = umbmark(seed, &d).output().unwrap();
            wall = wall.max(t0.elapsed());
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            read_set(&d).unwrap()
        });
        assert_eq!(sets[0].len(), hil::runs::odometry::UMBMARK_FILES.len());
        assert_ne!(sets[0], sets[1], "the two seeds must give different sets");
        (sets, wall)
    })
}

/// The entries beside D a writer may leave when killed (besides D and the
/// lock file).
fn is_writer_temp(name: &str) -> bool {
    ["hil-new-", "hil-old-"].iter().any(|k| {
        name.strip_prefix(&format!(".D.{k}"))
            .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// Every file under `root`, to two levels (D's files and those of a folder
/// beside it), but the lock file: its length and modification time.
fn files_under(root: &Path) -> BTreeMap<PathBuf, (u64, std::time::SystemTime)> {
    let mut files = BTreeMap::new();
    let mut dirs = vec![(root.to_path_buf(), 0)];
    while let Some((dir, depth)) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let Ok(meta) = e.metadata() else { continue };
            if meta.is_dir() && depth < 1 {
                dirs.push((e.path(), depth + 1));
            } else if meta.is_file() && e.file_name() != ".D.hil-lock" {
                files.insert(e.path(), (meta.len(), meta.modified().unwrap()));
            }
        }
    }
    files
}

/// Wait until the writer begins to write its set, whatever way it does it
/// (a file under `root` appears or changes: its first plot), or it ends;
/// false when it ended first.
fn wait_for_writing(root: &Path, child: &mut Child) -> bool {
    let before = files_under(root);
    loop {
        // A file that appeared or changed; not one removed (what a killed
        // writer left, cleared by this one).
        if files_under(root)
            .iter()
            .any(|(path, meta)| before.get(path) != Some(meta))
        {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_micros(200));
    }
}

/// The kill -9 campaign: 26 kills, at fixed fractions of a run's wall time
/// and at fixed delays after the writer begins to write its set (where the
/// plots, the report and the swap are), seeds alternating so that every
/// kill has an old set and a new one to tell apart. After each kill D is
/// absent (before any set was complete), exactly the old set or exactly
/// the new one; every fifth writer is left to finish, and nothing but D
/// and its lock file is left beside it then.
#[test]
fn a_killed_writer_leaves_the_old_set_or_the_new_one_and_the_next_cleans_up() {
    let ([one, two], wall) = references();
    let refs = [one, two];
    let root = scratch("kill");
    let d = root.join("D");
    // Spread over the run (golden-ratio steps over 0..1.1 of its wall time)
    // and over the writing of the set (0 to 60 ms after it begins).
    let mut moments: Vec<(bool, Duration)> = (0..20)
        .map(|k| (false, wall.mul_f64((k as f64 * 0.618_034).fract() * 1.1)))
        .collect();
    for (k, ms) in [
        0.0, 0.3, 1.0, 2.0, 4.0, 7.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0,
    ]
    .iter()
    .enumerate()
    {
        moments.insert(2 * k + 1, (true, Duration::from_secs_f64(ms / 1000.0)));
    }
    let mut held: Option<usize> = None;
    let (mut killed_writing, mut temps_seen) = (0, 0);
    for (i, &(after_first_file, delay)) in moments.iter().enumerate() {
        let next = held.map_or(0, |h| 1 - h);
        let mut child = umbmark(next as u64 + 1, &d).spawn().unwrap();
        let finish = i % 5 == 4;
        if !finish {
            let t0 = Instant::now();
            let in_time = !after_first_file || wait_for_writing(&root, &mut child);
            let start = if after_first_file { Instant::now() } else { t0 };
            while in_time && start.elapsed() < delay {
                std::thread::sleep(Duration::from_micros(100));
            }
            if child.try_wait().unwrap().is_none() {
                child.kill().unwrap();
                killed_writing += after_first_file as usize;
            }
        }
        let status = child.wait().unwrap();
        let now = read_set(&d);
        let which = match &now {
            None => {
                assert!(held.is_none(), "kill {i}: D vanished after holding a set");
                None
            }
            Some(s) => Some(
                refs.iter()
                    .position(|r| *r == s)
                    .unwrap_or_else(|| panic!("kill {i}: D holds a mixed set: {:?}", s.keys())),
            ),
        };
        assert!(
            which == held || which == Some(next),
            "kill {i}: D holds seed {which:?}, neither the old nor the new set"
        );
        held = which;
        let beside = names(&root);
        temps_seen += beside.iter().filter(|n| is_writer_temp(n)).count();
        for n in &beside {
            assert!(
                n == "D" || n == ".D.hil-lock" || is_writer_temp(n),
                "kill {i}: {n} beside D"
            );
        }
        if finish {
            assert!(status.success(), "writer {i} left to finish failed");
            assert_eq!(held, Some(next));
            assert_eq!(beside, vec![".D.hil-lock", "D"], "after writer {i}");
        }
    }
    eprintln!(
        "{} kills, {killed_writing} while the set was written, {temps_seen} temporary entries left and removed",
        moments.len() - moments.len() / 5
    );
}

fn refused_as_busy(out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("another hil process is writing"), "{err}");
}

/// A second writer to the same `--out` is refused at once, one line and
/// exit 4, and changes nothing; the first finishes with its own set.
#[test]
fn a_second_writer_is_refused_with_exit_4() {
    let ([one, _], _) = references();
    let root = scratch("second");
    let d = root.join("D");

    // Another process holds the lock: refused before anything runs.
    let lock = std::fs::File::create(root.join(".D.hil-lock")).unwrap();
    let held = nix::fcntl::Flock::lock(lock, nix::fcntl::FlockArg::LockExclusiveNonblock).unwrap();
    refused_as_busy(&umbmark(2, &d).output().unwrap());
    assert!(!d.exists());
    drop(held);

    // Two writers: the second comes while the first runs.
    let mut first = umbmark(1, &d).spawn().unwrap();
    let staging = format!(".D.hil-new-{}", first.id());
    while !root.join(&staging).exists() {
        assert!(
            first.try_wait().unwrap().is_none(),
            "the first writer ended early"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    refused_as_busy(&umbmark(2, &d).output().unwrap());
    assert!(first.wait().unwrap().success());
    assert_eq!(read_set(&d).as_ref(), Some(one));
    assert_eq!(names(&root), vec![".D.hil-lock", "D"]);
}

/// A folder holding files the command does not write is refused before
/// anything runs (exit 2) and left as it is.
#[test]
fn a_folder_with_other_files_is_refused_with_exit_2() {
    let root = scratch("foreign");
    let d = root.join("D");
    std::fs::create_dir(&d).unwrap();
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    let out = umbmark(1, &d).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("notes.txt"), "{err}");
    assert_eq!(names(&d), vec!["notes.txt"]);
}
