//! The PWM the firmware really produces, as the bench's waveform model sees
//! it: timers 2 and 4 at 31 372.55 Hz, duties in steps of 1/255.

#[path = "support/mod.rs"]
mod support;

use hil::bench::{Bench, BenchOptions};
use hil::runs::line::CMD_LINE;
use hil::runs::start::wait_ready;

/// Drive for a second and check every bridge input the firmware used.
#[test]
fn firmware_pwm_is_31372_hz_with_8_bit_duty() {
    let mut bench = Bench::new(
        support::firmware("robust"),
        &support::robot("henrytwo-ideal"),
        BenchOptions::default(),
    )
    .unwrap();
    wait_ready(&mut bench, None).unwrap();
    bench.send(1, &[CMD_LINE]);
    bench.run_for(1.5).unwrap();
    let core = bench.core();
    let pins = core.pin_stats();
    // Forward inputs: D7 (right) and D9 (left) are driven with PWM.
    for pin in [7u8, 9] {
        let p = pins.iter().find(|p| p.pin == pin).unwrap();
        assert!(
            (p.hz - 31_372.55).abs() / 31_372.55 < 1e-4,
            "D{pin}: {} Hz",
            p.hz
        );
        assert!(p.active_s > 1.0, "D{pin} active only {} s", p.active_s);
    }
    let log: Vec<_> = core
        .drive_log()
        .iter()
        .filter(|e| e.pin == 7 || e.pin == 9)
        .collect();
    assert!(
        log.len() > 20,
        "the PID changed the duty only {} times",
        log.len()
    );
    for e in log {
        let steps = e.duty * 255.0;
        assert!(
            (steps - steps.round()).abs() < 1e-9,
            "duty {} on D{} is not k/255",
            e.duty,
            e.pin
        );
    }
}
