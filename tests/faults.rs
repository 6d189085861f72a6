//! Faults injected into the robust firmware: its reactions match what the
//! fault library says they should be; the thesis build's are findings.

#[path = "support/mod.rs"]
mod support;

use hil::faults::{library, run_fault};

#[test]
fn robust_firmware_reacts_as_expected_to_every_fault() {
    let robust = support::firmware("robust");
    let thesis = support::firmware("thesis");
    let robot = support::robot("henrytwo-ideal");
    let mut failures = Vec::new();
    for case in library() {
        let row = run_fault(&case, &robust, Some(&thesis), &robot, 0).expect("the bench runs it");
        println!("{}: {} | thesis: {}", row.fault, row.robust, row.thesis);
        if !row.pass {
            failures.push(format!("{}: {}", row.fault, row.why));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
