//! Faults injected into the robust firmware: its reactions match what the
//! fault library says they should be; the thesis build's are findings.

#[path = "support/mod.rs"]
mod support;

use hil::runs::faults::{library, run_fault, FaultOptions, Verdict};

/// Faults the robust build is known not to meet, with why (the library
/// says so in their expectations). Each must still fail: one that passes
/// (the firmware fixed, or the bench lost the behaviour that breaks it)
/// fails this test until it leaves the list.
const KNOWN_FAILING: [(&str, &str); 0] = [];

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
        let known = KNOWN_FAILING.iter().find(|(name, _)| *name == row.fault);
        match (row.pass, known) {
            (false, None) => failures.push(format!("{}: {}", row.fault, row.why)),
            (true, Some((_, why))) => failures.push(format!(
                "{}: passes, but is listed as failing ({why}): {}",
                row.fault, row.why
            )),
            _ => {}
        }
        // The thesis build does not restart its test after a reset either:
        // its selector is a RAM variable the C runtime clears at boot.
        if row.fault == "reset-mid-test" {
            let again = row.thesis_observed.as_ref().map(|o| o.driven_again_after_s);
            if again != Some(None) {
                failures.push(format!("reset-mid-test: thesis driven again: {again:?}"));
            }
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

/// A scheduled action the plant refuses (a slip outside [0, 1]) is not
/// applied, nor logged as applied: the run ends with an error naming it,
/// rather than go on without the fault it was asked for.
#[test]
fn an_action_the_plant_refuses_ends_the_run_naming_it() {
    use hil::bench::{Action, Bench, BenchError, BenchOptions, Trigger};
    use plant_model::Side;
    let mut bench = Bench::new(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    let good = Action::SlipBurst {
        side: Side::Left,
        slip: 0.5,
    };
    let bad = Action::SlipBurst {
        side: Side::Right,
        slip: 1.5,
    };
    bench.schedule(Trigger::Time { s: 0.05 }, good.clone(), None);
    bench.schedule(Trigger::Time { s: 0.1 }, bad.clone(), None);
    let err = bench
        .run_for(0.5)
        .expect_err("the refused action ends the run");
    assert!(err.to_string().contains("SlipBurst"), "{err}");
    match err {
        BenchError::ActionRefused { action, at, .. } => {
            assert_eq!(*action, bad);
            assert!((0.1..0.1001).contains(&at.robot_time_s), "{at}");
        }
        other => panic!("not the refused action: {other}"),
    }
    let applied: Vec<&Action> = bench.core().applied().iter().map(|a| &a.1).collect();
    assert_eq!(applied, [&good]);
}

/// `reset-mid-test` fails for a firmware that starts its test again after
/// the reset: here the robust build, sent the line's start byte again 0.5 s
/// after the reset, does what such a firmware does by itself. (The reset
/// alone drives the motors' pins low, and a check of that, over a window
/// shorter than the line, passed whatever the firmware did next.)
#[test]
fn reset_mid_test_fails_for_a_firmware_that_restarts_its_test() {
    use hil::bench::{Action, ScheduledFault, Trigger};
    let mut case = library()
        .into_iter()
        .find(|c| c.name == "reset-mid-test")
        .unwrap();
    case.faults.push(ScheduledFault::new(
        Trigger::Time { s: 4.5 },
        Action::HostSend {
            bytes: vec![hil::runs::experiment::Test::Line.command_byte()],
        },
    ));
    let row = run_fault(
        &case,
        &support::firmware("robust"),
        None,
        &support::robot("henrytwo-ideal"),
        &FaultOptions::default(),
    )
    .expect("the bench runs it");
    assert_eq!(row.verdict, Verdict::Fail, "{}: {}", row.robust, row.why);
    let again = row
        .robust_observed
        .driven_again_after_s
        .expect("driven again");
    assert!((0.5..1.0).contains(&again), "{again}");
    assert!(row.why.contains("driven again"), "{}", row.why);
}
