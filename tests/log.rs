//! The bench's own log (issue 50): `RUST_LOG=hil=debug` shows, on stderr,
//! each run's span and phase and what the bench decided at robot time (a
//! fault applied, a segment of the run, a run that did not complete), the
//! same lines for the same run; without `RUST_LOG` nothing is logged.

#[path = "support/mod.rs"]
mod support;

use std::process::Command;

/// `hil test` on the dropout scenario (a fault at 3 s of robot time) with
/// `RUST_LOG` set to `filter`, or unset: its stderr.
fn stderr_of_dropout(filter: Option<&str>) -> String {
    let _ = support::firmware_path("robust");
    let scenario = hil::paths::workspace_root().join("fixtures/scenarios/dropout-motors-off.toml");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_hil"));
    cmd.arg("test").arg(&scenario).env_remove("RUST_LOG");
    if let Some(f) = filter {
        cmd.env("RUST_LOG", f);
    }
    let out = cmd.output().expect("hil runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stderr).expect("UTF-8")
}

#[test]
fn debug_logs_the_benchs_decisions_at_robot_time_and_nothing_by_default() {
    let log = stderr_of_dropout(Some("hil=debug"));
    let line = |needle: &str| {
        log.lines()
            .find(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("no line with {needle:?} in:\n{log}"))
    };
    assert!(line("firmware ready").starts_with("DEBUG run{test=\"line\" seed=0}:ready:"));
    // The scenario's fault, at its trigger's robot time, in the drive phase.
    let fault = line("fault action applied");
    assert!(
        fault.starts_with("DEBUG run{test=\"line\" seed=0}:drive:"),
        "{fault}"
    );
    assert!(
        fault.contains("t_s=3.0 action=Encoder { side: Left, fault: Dropout }"),
        "{fault}"
    );
    assert!(line("the run did not complete").contains("finding=did not complete within 15 s"));
    // The one leg, cut when the motors stopped after the dropout.
    let leg = line("segment");
    assert!(leg.contains("motion=Forward from_s=0.0"), "{leg}");
    assert!(leg.contains("to_s=3.2"), "{leg}");
    // Robot time only: the same run logs the same lines.
    assert_eq!(stderr_of_dropout(Some("hil=debug")), log);

    let quiet = stderr_of_dropout(None);
    assert!(!quiet.contains("DEBUG"), "{quiet}");
}
