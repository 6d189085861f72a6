#![allow(dead_code)] // each test file uses a part
//! Shared by the tests that prove a speed lever changes nothing: a run as
//! text, where two runs first part, a described firmware, and the fault
//! library's cases as test options.

use std::sync::Arc;

use hil::firmware::description::Description;
use hil::firmware::elf::Firmware;
use hil::runs::experiment::{Test, TestOptions, TestRun};
use hil::runs::faults::library;

/// Everything a run shows, as text: the report's JSON (results, the UARTs'
/// bytes, the applied faults, the awake fraction), the trace and the
/// motions with their cycles.
pub fn everything(r: &TestRun) -> String {
    format!(
        "{}\n{:?}\n{:?}\n{:?}",
        serde_json::to_string(r).expect("a run serialises"),
        r.trace,
        r.motions,
        r.bluetooth_out
    )
}

/// Fails, naming `what` and the first line where the two runs part (each
/// side under its label), unless they show the same.
pub fn assert_same(what: &str, (la, a): (&str, &TestRun), (lb, b): (&str, &TestRun)) {
    assert!(!a.trace.is_empty(), "{what}: no trace to compare");
    let (a, b) = (everything(a), everything(b));
    if a == b {
        return;
    }
    let at = a
        .lines()
        .zip(b.lines())
        .position(|(x, y)| x != y)
        .unwrap_or(0);
    let cut = |s: &str| {
        s.lines()
            .nth(at)
            .unwrap_or("")
            .chars()
            .take(600)
            .collect::<String>()
    };
    panic!(
        "{what}: the runs part at line {at}\n{la}: {}\n{lb}: {}",
        cut(&a),
        cut(&b)
    );
}

/// The description at `file` (from the workspace root) and the ELF it names.
pub fn described(file: &str) -> (Arc<Description>, Firmware) {
    let d = Description::load(hil::paths::workspace_root().join(file)).expect("description loads");
    let elf = d.elf.clone().expect("the description names its ELF");
    let fw = Firmware::load(&elf).unwrap_or_else(|e| panic!("{e} (run tools/setup.sh)"));
    (Arc::new(d), fw)
}

/// The fault library's case `name`: its test and the options that run it,
/// recording.
pub fn fault_case(name: &str) -> (Test, TestOptions) {
    let case = library()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no fault {name} in the library"));
    let opts = TestOptions {
        leg_mm: case.leg_mm,
        limit_s: Some(case.limit_s),
        faults: case.faults.clone(),
        framed: case.framed,
        record: true,
        ..Default::default()
    };
    (case.test, opts)
}
