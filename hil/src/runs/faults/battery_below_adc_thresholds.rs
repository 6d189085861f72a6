//! The battery runs down during a leg: from a charged 2S pack (8.4 V, blue
//! LED) to 7.6 V, below the firmware's low-battery threshold (ADC 901 of
//! 1023: 8.01 V through the 0.55 divider), still far above what the
//! regulator needs.

use super::{FaultCase, Observed};
use crate::bench::{Action, ScheduledFault, Trigger};
use crate::runs::experiment::Test;

/// The drop below the threshold, s of robot time.
const DROP_AT_S: f64 = 3.0;

pub fn case() -> FaultCase {
    let volts = |v| Action::BatteryVolts { volts: Some(v) };
    FaultCase {
        name: "battery-below-adc-thresholds",
        what: "battery at 8.4 V from the start of a 2 m line, 7.6 V (below the red-LED threshold) from 3 s",
        expected: "the battery LED turns from blue to red within 45 ms (three control ticks) of the drop; the PID holds the set-points at the lower voltage: the line completes without a fault code",
        test: Test::Line,
        leg_mm: 2000.0,
        faults: vec![
            ScheduledFault::new(Trigger::Time { s: 0.0 }, volts(8.4)),
            ScheduledFault::new(Trigger::Time { s: DROP_AT_S }, volts(7.6)),
        ],
        limit_s: 30.0,
        framed: false,
        check: Some(check),
    }
}

fn check(o: &Observed) -> Result<String, String> {
    let before = o.led_changes.iter().rev().find(|(t, _)| *t < DROP_AT_S);
    // `show` lights the new LED before it darkens the old one: the
    // microseconds with two lit are not a colour.
    let after = o
        .led_changes
        .iter()
        .find(|(t, c)| *t >= DROP_AT_S && c != "several");
    let code = o.fault_code.unwrap_or(0);
    match (before, after) {
        (Some((_, b)), Some((t, a)))
            if b == "blue" && a == "red" && t - DROP_AT_S <= 0.045 && o.completed && code == 0 =>
        {
            Ok(format!(
                "LED blue to red {:.0} ms after the drop; completed without a fault",
                (t - DROP_AT_S) * 1e3
            ))
        }
        _ => Err(format!(
            "expected blue, then red within 45 ms, and a completed line; LED changes {:?}, completed {}, code {code}",
            o.led_changes, o.completed
        )),
    }
}
