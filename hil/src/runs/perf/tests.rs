//! The report's text.

use super::*;

fn speed(overhead_ratio: f64, round_ratios: Vec<f64>) -> BuildSpeed {
    let m = Measured::new(10.0, 0.1);
    BuildSpeed {
        bench: m,
        raw_without_pwm_timers: m,
        raw: None,
        overhead_ratio,
        round_ratios,
        awake_fraction: 0.02,
        callbacks_per_robot_s: 1800.0,
        lean_edge_fraction: 0.75,
        quiet_b_read_fraction: 0.73,
        completed: true,
    }
}

fn report(robust: BuildSpeed, thesis: Option<BuildSpeed>, repeats: usize) -> BenchReport {
    BenchReport {
        test: "umbmark-cw".into(),
        firmware: "robust".into(),
        rtf_robust_umbmark: 250.0,
        rtf_thesis: thesis.as_ref().map(|_| 5.6),
        rtf_raw_simavr: None,
        rtf_raw_simavr_without_pwm_timers: 318.0,
        overhead_ratio: robust.overhead_ratio,
        thesis_overhead_ratio: thesis.as_ref().map(|t| t.overhead_ratio),
        awake_fraction: 0.02,
        callbacks_per_robot_s: 1800.0,
        robot_s: 74.3,
        thesis_robot_s: thesis.as_ref().map(|_| 32.8),
        sketch_overhead_ratio: None,
        repeats,
        robust,
        thesis,
        sketch: None,
    }
}

#[test]
fn the_report_shows_the_rounds_spread_and_warns_when_it_is_wide() {
    let steady = report(speed(1.26, vec![1.27, 1.26, 1.29]), None, 3);
    let text = steady.render();
    assert!(text.contains("1.26x to 1.29x robust"), "{text}");
    assert!(!text.contains("busy"), "{text}");
    // One round of the thesis build timed while the machine was loaded.
    let loaded = report(
        speed(1.26, vec![1.27, 1.26]),
        Some(speed(1.04, vec![1.05, 1.31])),
        2,
    );
    let text = loaded.render();
    assert!(text.contains("1.05x to 1.31x thesis"), "{text}");
    assert!(text.contains("the machine was busy"), "{text}");
    // One round: no spread to show.
    let once = report(speed(1.26, vec![1.26]), None, 1);
    assert!(!once.render().contains("round by round"));
}

/// A replay is held to the whole of the MCU's SRAM: on the Uno's ATmega328P
/// from 0x100 (where its variables are) to RAMEND 0x8FF, not the
/// ATmega2560's 0x200-0x21FF.
#[test]
fn the_fingerprint_is_the_mcus_sram() {
    let seen = std::cell::RefCell::new(Vec::new());
    let f = record::fingerprint(&crate::mcu::chip::ATMEGA328P, |a| {
        seen.borrow_mut().push(a);
        a as u8
    });
    let seen = seen.into_inner();
    assert_eq!((seen.first(), seen.last()), (Some(&0x100), Some(&0x8ff)));
    assert_eq!((f.len(), seen.len()), (2048, 2048));
}
