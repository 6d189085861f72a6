//! A folder of results is replaced as a whole, by one writer at a time, and
//! whatever a killed writer left is recognised and removed by the next.

use std::path::{Path, PathBuf};

use super::*;

const FILES: &[&str] = &["report.json", "plot.svg"];

/// A fresh, empty folder for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hil-output-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Sorted (name, content) of the files in `dir`.
fn contents(dir: &Path) -> Vec<(String, String)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let text = std::fs::read_to_string(e.path()).unwrap_or_else(|_| "<dir>".into());
            (e.file_name().to_string_lossy().into_owned(), text)
        })
        .collect();
    v.sort();
    v
}

fn names(dir: &Path) -> Vec<String> {
    contents(dir).into_iter().map(|(n, _)| n).collect()
}

/// Write a set whose every file holds `tag`.
fn write_set(dir: &Path, tag: &str) -> Vec<PathBuf> {
    let out = OutputDir::claim(dir, FILES).unwrap();
    for f in FILES {
        std::fs::write(out.staging().join(f), tag).unwrap();
    }
    out.commit().unwrap()
}

fn set_of(tag: &str) -> Vec<(String, String)> {
    let mut v: Vec<_> = FILES.iter().map(|f| (f.to_string(), tag.into())).collect();
    v.sort();
    v
}

#[test]
fn a_new_set_replaces_the_old_one_whole_and_leaves_only_the_lock_beside_it() {
    let root = scratch("replace");
    let d = root.join("D");
    let written = write_set(&d, "one");
    assert_eq!(written, vec![d.join("report.json"), d.join("plot.svg")]);
    assert_eq!(contents(&d), set_of("one"));
    // A file of the old set that the new one has too is replaced, and a
    // temporary file an earlier writer left in D goes with the old set.
    std::fs::write(d.join(".report.json.tmp999"), "half").unwrap();
    write_set(&d, "two");
    assert_eq!(contents(&d), set_of("two"));
    assert_eq!(names(&root), vec![".D.hil-lock", "D"]);
}

#[test]
fn a_writer_that_stops_before_commit_leaves_the_old_set() {
    let root = scratch("abandon");
    let d = root.join("D");
    write_set(&d, "old");
    {
        let out = OutputDir::claim(&d, FILES).unwrap();
        std::fs::write(out.staging().join("report.json"), "new").unwrap();
        // Dropped: an error in the run, or a panic.
    }
    assert_eq!(contents(&d), set_of("old"));
    assert_eq!(names(&root), vec![".D.hil-lock", "D"]);
}

#[test]
fn a_set_missing_a_file_is_not_committed() {
    let root = scratch("missing");
    let d = root.join("D");
    write_set(&d, "old");
    let out = OutputDir::claim(&d, FILES).unwrap();
    std::fs::write(out.staging().join("report.json"), "new").unwrap();
    assert!(matches!(out.commit(), Err(OutputError::Io { .. })));
    assert_eq!(contents(&d), set_of("old"));
}

/// What a writer killed at any step leaves: an unfinished new set, an old
/// set being removed, an old set moved aside with no D (the two-rename
/// path), temporary files in D. The next writer removes each, puts the old
/// set back where D is missing, and writes its set.
#[test]
fn the_next_writer_removes_what_a_killed_writer_left() {
    let root = scratch("killed");
    let d = root.join("D");
    write_set(&d, "old");
    std::fs::create_dir(root.join(".D.hil-new-41")).unwrap();
    std::fs::write(root.join(".D.hil-new-41/report.json"), "half").unwrap();
    std::fs::create_dir(root.join(".D.hil-old-42")).unwrap();
    std::fs::write(d.join(".plot.svg.tmp43"), "half").unwrap();
    std::fs::create_dir(d.join(".tmp-44")).unwrap();
    // Not a writer's: kept.
    std::fs::write(root.join(".D.hil-new-x"), "mine").unwrap();
    std::fs::write(root.join("E"), "mine").unwrap();
    write_set(&d, "new");
    assert_eq!(contents(&d), set_of("new"));
    assert_eq!(names(&root), vec![".D.hil-lock", ".D.hil-new-x", "D", "E"]);

    // Killed between moving the old set aside and renaming the new one in.
    let aside = root.join(".D.hil-old-45");
    std::fs::rename(&d, &aside).unwrap();
    std::fs::create_dir(root.join(".D.hil-new-45")).unwrap();
    let out = OutputDir::claim(&d, FILES).unwrap();
    assert_eq!(contents(&d), set_of("new"), "the old set is put back first");
    drop(out);
    assert!(!aside.exists());
}

#[test]
fn without_an_atomic_exchange_two_renames_replace_the_set() {
    let root = scratch("two-renames");
    let d = root.join("D");
    write_set(&d, "old");
    let out = OutputDir::claim(&d, FILES).unwrap();
    for f in FILES {
        std::fs::write(out.staging().join(f), "new").unwrap();
    }
    out.replace_in_two_renames().unwrap();
    drop(out);
    assert_eq!(contents(&d), set_of("new"));
    assert_eq!(names(&root), vec![".D.hil-lock", "D"]);
}

#[test]
fn a_second_writer_is_refused_while_the_first_holds_the_folder() {
    let root = scratch("second");
    let d = root.join("D");
    let first = OutputDir::claim(&d, FILES).unwrap();
    let second = OutputDir::claim(&d, FILES).unwrap_err();
    assert!(matches!(second, OutputError::Busy { .. }), "{second}");
    assert!(share(&d).is_err(), "a shard waits for no whole-set writer");
    drop(first);
    let shard = share(&d).unwrap();
    let _other_shard = share(&d).unwrap();
    assert!(matches!(
        OutputDir::claim(&d, FILES),
        Err(OutputError::Busy { .. })
    ));
    drop((shard, _other_shard));
    OutputDir::claim(&d, FILES).unwrap();
}

#[test]
fn a_folder_with_files_this_command_did_not_write_is_refused_untouched() {
    let root = scratch("foreign");
    let d = root.join("D");
    std::fs::create_dir(&d).unwrap();
    std::fs::write(d.join("notes.txt"), "mine").unwrap();
    std::fs::write(d.join("report.json"), "old").unwrap();
    let e = OutputDir::claim(&d, FILES).unwrap_err();
    assert!(e.is_bad_folder());
    assert!(e.to_string().contains("notes.txt"), "{e}");
    assert_eq!(names(&d), vec!["notes.txt", "report.json"]);
    assert_eq!(names(&root), vec![".D.hil-lock", "D"]);

    std::fs::write(root.join("F"), "a file").unwrap();
    assert!(OutputDir::claim(&root.join("F"), FILES)
        .unwrap_err()
        .is_bad_folder());
    std::os::unix::fs::symlink(&d, root.join("L")).unwrap();
    assert!(OutputDir::claim(&root.join("L"), FILES)
        .unwrap_err()
        .is_bad_folder());
    for p in [".", "..", "/", "x/.."] {
        assert!(
            OutputDir::claim(Path::new(p), FILES)
                .unwrap_err()
                .is_bad_folder(),
            "{p}"
        );
    }
}

#[test]
fn temporary_names_are_told_from_results() {
    use std::ffi::OsStr;
    let kind = |e: &str| super::set::temp_kind(OsStr::new(e), OsStr::new("D"));
    assert_eq!(kind(".D.hil-new-12"), Some("hil-new"));
    assert_eq!(kind(".D.hil-old-3"), Some("hil-old"));
    for not in [
        ".D.hil-new-",
        ".D.hil-new-1a",
        "D.hil-new-1",
        ".DD.hil-new-1",
        ".D.hil-lock",
    ] {
        assert_eq!(kind(not), None, "{not}");
    }
    let temp = super::set::is_temp_file;
    assert!(temp(".report.json.tmp123") && temp(".tmp-9"));
    assert!(!temp("report.json") && !temp(".tmp") && !temp(".report.json.tmp") && !temp(".tmp123"));
}
