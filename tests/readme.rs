//! Every `hil` example of the README runs as written: each line of its `sh` blocks that
//! starts with `hil ` is run with the built binary, from a folder that holds the
//! repository's `fixtures/` and `firmware/` (so the README's relative paths resolve and its
//! outputs land in a temporary folder), and must exit 0 having printed something. The
//! README's other lines are the two commands and set-up, which are this test's own harness.

#[path = "support/mod.rs"]
mod support;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The `hil` command lines of `markdown`'s `sh` code blocks, in order.
fn hil_examples(markdown: &str) -> Vec<String> {
    let mut in_sh = false;
    let mut found = Vec::new();
    for line in markdown.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && t == "```sh";
            continue;
        }
        if in_sh && t.starts_with("hil ") {
            found.push(t.split(" #").next().unwrap_or(t).trim().to_owned());
        }
    }
    found
}

#[test]
fn the_readme_examples_are_found_in_its_sh_blocks_only() {
    let md = "text\n```sh\nhil run line   # a comment\ntools/run.sh\n```\n```text\nhil not this\n```\nhil nor this\n";
    assert_eq!(hil_examples(md), ["hil run line"]);
}

#[test]
fn every_hil_example_of_the_readme_runs_as_written() {
    let root = hil::paths::workspace_root();
    let readme = std::fs::read_to_string(root.join("README.md")).expect("the README");
    let examples = hil_examples(&readme);
    // The tour has a command per step: a README that lost its examples is a failure too.
    assert!(examples.len() >= 7, "{examples:?}");
    let _ = support::firmware_path("robust");
    let dir = std::env::temp_dir().join(format!("hil-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("out")).unwrap();
    for part in ["fixtures", "firmware"] {
        std::os::unix::fs::symlink(root.join(part), dir.join(part)).unwrap();
    }
    let mut failed = Vec::new();
    for example in &examples {
        if let Err(why) = run(&dir, example, Duration::from_secs(900)) {
            failed.push(format!("{example}\n    {why}"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        failed.is_empty(),
        "README examples that fail:\n{}",
        failed.join("\n")
    );
}

/// Run `example` (a `hil ...` line, no quoting) in `dir`: Ok when it exits 0 and prints.
fn run(dir: &Path, example: &str, limit: Duration) -> Result<(), String> {
    let args: Vec<&str> = example.split_whitespace().skip(1).collect();
    let mut child = Command::new(env!("CARGO_BIN_EXE_hil"))
        .args(&args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("does not start: {e}"))?;
    let start = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {limit:?}"));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let last = stderr.lines().last().unwrap_or_default();
    if !out.status.success() {
        return Err(format!("exit {:?}: {last}", out.status.code()));
    }
    if out.stdout.is_empty() {
        return Err(format!("printed nothing; stderr: {last}"));
    }
    Ok(())
}
