//! Faults injected into the robust firmware: its reactions match what the
//! fault library says they should be; the thesis build's are findings.

#[path = "support/mod.rs"]
mod support;

use hil::faults::{library, run_fault, FaultOptions};

#[test]
fn robust_firmware_reacts_as_expected_to_every_fault() {
    let robust = support::firmware("robust");
    let thesis = support::firmware("thesis");
    let robot = support::robot("henrytwo-ideal");
    let mut failures = Vec::new();
    for case in library() {
        let row = run_fault(
            &case,
            &robust,
            Some(&thesis),
            &robot,
            &FaultOptions::default(),
        )
        .expect("the bench runs it");
        println!("{}: {} | thesis: {}", row.fault, row.robust, row.thesis);
        if !row.pass {
            failures.push(format!("{}: {}", row.fault, row.why));
        }
        // The thesis build wedged in its leg loop is a hang the bench finds
        // and places (PC and symbol), as a finding of the row.
        if row.fault == "robot-wedged" {
            let hang = row.thesis_observed.as_ref().and_then(|o| o.hang.clone());
            match hang {
                Some(h)
                    if h.at.function.is_some()
                        && h.at.pc != 0
                        && h.callers.iter().any(|c| c.contains("thesis::")) =>
                {
                    assert!(row.thesis.contains("HUNG"), "{}", row.thesis)
                }
                other => failures.push(format!("robot-wedged: thesis hang not placed: {other:?}")),
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
