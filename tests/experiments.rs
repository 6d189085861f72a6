//! The firmware's tests on the emulated robot: every selector byte runs its
//! test to the end, turns end at the counts the firmware intends, braking
//! pulses have the thesis' shape, and a sharded UMBmark merges into exactly
//! the single-machine result.

#[path = "support/mod.rs"]
mod support;

use hil::bench::BenchOptions;
use hil::runs::experiment::{run_test, Test, TestOptions, TestRun};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

const LEG_MM: f64 = 600.0;

/// One run per (build, test), shared by the tests of this file.
fn run(build: &str, test: Test) -> TestRun {
    static RUNS: OnceLock<Mutex<HashMap<(String, Test), TestRun>>> = OnceLock::new();
    let runs = RUNS.get_or_init(Default::default);
    if let Some(r) = runs.lock().unwrap().get(&(build.to_string(), test)) {
        return r.clone();
    }
    let opts = TestOptions {
        leg_mm: LEG_MM,
        bench: BenchOptions::default(),
        limit_s: Some(120.0),
        ..Default::default()
    };
    let r = run_test(
        support::firmware(build),
        &support::robot("henrytwo-ideal"),
        test,
        &opts,
    )
    .expect("the bench runs the test");
    runs.lock()
        .unwrap()
        .insert((build.to_string(), test), r.clone());
    r
}

/// The robust build: each selector byte runs its test to the end, with the
/// legs and turns the thesis prescribes, each turn close to its angle.
#[test]
fn robust_runs_every_test_with_its_legs_and_turns() {
    for test in Test::ALL {
        let r = run("robust", test);
        let (legs, turns, angle) = test.shape();
        assert!(r.completed, "{}: {:?}", test.name(), r.finding);
        assert_eq!(r.legs.len(), legs, "{}: legs", test.name());
        assert_eq!(r.turns.len(), turns, "{}: turns", test.name());
        for l in &r.legs {
            assert!(
                (l.plant_distance_mm - LEG_MM).abs() < 30.0,
                "{}: leg {l:?}",
                test.name()
            );
        }
        for t in &r.turns {
            // Coasting after the cut adds a few degrees on the ideal robot.
            assert!(
                (t.plant_angle_deg - angle).abs() < 10.0,
                "{}: turn of {} deg, expected {angle}",
                test.name(),
                t.plant_angle_deg
            );
        }
    }
}

/// Each robust turn cuts each motor when that wheel's own count reaches the
/// target (612 counts for 90 degrees, 815.5 for 120 degrees: >= 816), read
/// from SRAM at the cycle the bridge input went to zero.
#[test]
fn robust_turns_end_at_the_intended_counts() {
    for (test, target) in [
        (Test::UmbmarkCw, 612),
        (Test::UmbmarkCcw, 612),
        (Test::Triangle, 816),
    ] {
        let r = run("robust", test);
        for t in &r.turns {
            for c in [t.count_left_at_cutoff, t.count_right_at_cutoff] {
                let c = c.expect("each motor is cut inside the turn").abs();
                assert!(
                    (target..target + 3).contains(&c),
                    "{}: cut at {c}, target {target}",
                    test.name()
                );
            }
        }
    }
}

/// After each leg the thesis brakes: 20 ms with every input off, then the
/// reverse inputs (D6, D8) at full duty for 5 ms, then off again.
#[test]
fn braking_pulse_has_the_thesis_shape() {
    let r = run("robust", Test::Line);
    let cut = r.legs[0].cutoff_cycle;
    let after: Vec<_> = r.drive.iter().filter(|e| e.cycle >= cut).collect();
    let on: Vec<_> = after
        .iter()
        .filter(|e| (e.pin == 6 || e.pin == 8) && e.duty == 1.0)
        .collect();
    assert_eq!(on.len(), 2, "both reverse inputs pulse: {after:?}");
    let off = after
        .iter()
        .find(|e| (e.pin == 6 || e.pin == 8) && e.duty == 0.0 && e.cycle > on[0].cycle)
        .expect("the pulse ends");
    let ms = |c: u64| c as f64 / 16_000.0;
    let gap = ms(on[0].cycle - cut);
    let width = ms(off.cycle - on[0].cycle);
    assert!((gap - 20.0).abs() < 0.1, "{gap} ms off before the pulse");
    assert!((width - 5.0).abs() < 0.1, "{width} ms pulse");
}

/// The per-leg and per-turn counts of the robust build's UMBmark CW.
#[test]
fn robust_umbmark_cw_snapshot() {
    let r = run("robust", Test::UmbmarkCw);
    let legs: Vec<_> = r
        .legs
        .iter()
        .map(|l| {
            (
                l.firmware_count_left
                    .expect("the robust build's counters are known"),
                l.firmware_count_right
                    .expect("the robust build's counters are known"),
                l.plant_distance_mm.round(),
            )
        })
        .collect();
    let turns: Vec<_> = r
        .turns
        .iter()
        .map(|t| {
            (
                t.count_left_at_cutoff,
                t.count_right_at_cutoff,
                (t.plant_angle_deg * 10.0).round() / 10.0,
            )
        })
        .collect();
    insta::assert_debug_snapshot!("robust_umbmark_cw", (legs, turns));
}

/// The thesis build's legs and turns per selector byte: (straight legs,
/// turns, sign of every turn: +1 left, -1 right). The thesis' wiring mirrors
/// its turns (see `thesis_turn_logic_next_to_robust`): its "UMBmark CW"
/// spins left, its CCW and its triangle spin right.
fn thesis_shape(test: Test) -> (usize, usize, f64) {
    match test {
        Test::UmbmarkCw => (4, 4, 1.0),
        Test::UmbmarkCcw => (4, 4, -1.0),
        Test::Line => (1, 0, 0.0),
        Test::Triangle => (3, 3, -1.0),
    }
}

/// The thesis build: each selector byte runs its own test to the end, with
/// that test's legs, number of turns and turn direction (mirrored, see
/// [`thesis_shape`]), each turn within 10 degrees of its angle and each leg
/// its length, in one piece: the period after a turn in which the PID holds
/// one wheel at zero and the stale levels of its pin writes are no cut-off
/// (they used to split a leg into a ~16 mm piece and the rest).
#[test]
fn thesis_build_runs_each_selector_byte() {
    for test in Test::ALL {
        let r = run("thesis", test);
        let name = test.name();
        assert!(r.completed, "{name}: {:?}", r.finding);
        let (legs, turns, sign) = thesis_shape(test);
        assert_eq!(r.legs.len(), legs, "{name}: legs {:?}", r.legs);
        for l in &r.legs {
            let mm = l.plant_distance_mm;
            assert!((mm - LEG_MM).abs() < 30.0, "{name}: a leg of {mm} mm");
        }
        assert_eq!(r.turns.len(), turns, "{name}: turns");
        let angle = test.shape().2.abs();
        for t in &r.turns {
            assert_eq!(
                t.plant_angle_deg.signum(),
                sign,
                "{name}: turn of {} deg",
                t.plant_angle_deg
            );
            assert!(
                (t.plant_angle_deg.abs() - angle).abs() < 10.0,
                "{name}: turn of {} deg, expected {angle}",
                t.plant_angle_deg
            );
        }
    }
}

/// The printed turn logic next to the robust build's: with the thesis' wiring
/// the thesis' "UMBmark CW" turns counter-clockwise, and each motor is cut
/// when the OTHER wheel's count reaches 612 (the printed code then zeroes
/// that count, so the count read at the cut is near 0 for one wheel); it does
/// not hang. The robust build turns clockwise and cuts each motor on its own
/// wheel's count.
#[test]
fn thesis_turn_logic_next_to_robust() {
    let thesis = run("thesis", Test::UmbmarkCw);
    let robust = run("robust", Test::UmbmarkCw);
    println!("turn | thesis angle, cut-off L/R | robust angle, cut-off L/R");
    for (i, (t, r)) in thesis.turns.iter().zip(&robust.turns).enumerate() {
        println!(
            "{} | {:+.1} deg, {:?}/{:?} | {:+.1} deg, {:?}/{:?}",
            i + 1,
            t.plant_angle_deg,
            t.count_left_at_cutoff,
            t.count_right_at_cutoff,
            r.plant_angle_deg,
            r.count_left_at_cutoff,
            r.count_right_at_cutoff
        );
    }
    assert!(
        thesis.completed,
        "the printed turn logic does not hang: {:?}",
        thesis.finding
    );
    assert_eq!(thesis.turns.len(), 4);
    for t in &thesis.turns {
        assert!(
            t.plant_angle_deg > 60.0,
            "thesis CW turns left: {}",
            t.plant_angle_deg
        );
        let near_zero = [t.count_left_at_cutoff, t.count_right_at_cutoff]
            .iter()
            .flatten()
            .any(|c| c.abs() < 50);
        assert!(
            near_zero,
            "one wheel's count was reset by the other's cut-off: {t:?}"
        );
    }
    for r in &robust.turns {
        assert!(
            r.plant_angle_deg < -60.0,
            "robust CW turns right: {}",
            r.plant_angle_deg
        );
    }
}

/// Encoder channel B is raised lazily (right before the firmware reads its
/// PIN register) unless the true waveform is wanted (a VCD): the firmware
/// must not notice. Every bridge change happens at the same cycle with the
/// same counts, on the default robot (noise, effects) and a whole UMBmark
/// square, and the edges raised lazily are a subset in time of the true ones.
#[test]
fn lazy_channel_b_is_invisible_to_the_firmware() {
    let go = |record: bool| {
        let opts = TestOptions {
            leg_mm: LEG_MM,
            bench: BenchOptions {
                seed: 3,
                ..BenchOptions::default()
            },
            limit_s: Some(120.0),
            record,
            ..Default::default()
        };
        run_test(
            support::firmware("robust"),
            &support::robot("henrytwo"),
            Test::UmbmarkCw,
            &opts,
        )
        .expect("the bench runs the test")
    };
    let (lazy, full) = (go(false), go(true));
    assert!(lazy.completed && full.completed);
    let key = |r: &TestRun| -> Vec<String> {
        r.motions
            .iter()
            .map(|m| {
                format!(
                    "{:?} {} {:?} {:?}",
                    m.motion, m.at.cycle, m.at.left_count, m.at.right_count
                )
            })
            .collect()
    };
    assert!(key(&lazy).len() > 8, "{:?}", key(&lazy));
    assert_eq!(key(&lazy), key(&full), "bridge changes differ");
    // The firmware's side, exactly: every count at every cut-off.
    let counts = |r: &TestRun| -> Vec<String> {
        r.legs
            .iter()
            .map(|l| {
                format!(
                    "{:?}",
                    (
                        l.firmware_count_left,
                        l.firmware_count_right,
                        l.start_cycle,
                        l.cutoff_cycle,
                    )
                )
            })
            .chain(r.turns.iter().map(|t| {
                format!(
                    "{:?}",
                    (
                        t.count_left_at_cutoff,
                        t.count_right_at_cutoff,
                        t.cutoff_left_cycle,
                        t.cutoff_right_cycle,
                    )
                )
            }))
            .collect()
    };
    assert_eq!(counts(&lazy), counts(&full));
    // The plant steps the pose on a fixed grid and at the motion's changes,
    // not where it is advanced: the extra B instants change nothing.
    assert_eq!(lazy.final_pose, full.final_pose);
}
