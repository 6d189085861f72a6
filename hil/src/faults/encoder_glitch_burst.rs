//! Bursts of glitch pulses on the left encoder's channel A (the motor's
//! brushes and PWM couple into an unshielded encoder cable): every pulse is
//! two extra edges on the interrupt pin, 16 cycles apart.

use super::{FaultCase, Observed};
use plant_model::Side;

use crate::bench::{Action, ScheduledFault, Trigger};
use crate::experiment::Test;
use crate::inject::Channel;

/// When the bursts come, s of robot time.
const BURSTS_AT_S: [f64; 5] = [3.0, 3.5, 4.0, 4.5, 5.0];

pub fn case() -> FaultCase {
    let faults = BURSTS_AT_S
        .iter()
        .map(|&s| {
            ScheduledFault::new(
                Trigger::Time { s },
                Action::EncoderGlitch {
                    side: Side::Left,
                    channel: Channel::A,
                    pulses: 20,
                    width_us: 1.0,
                    period_us: 100.0,
                },
            )
        })
        .collect();
    FaultCase {
        name: "encoder-glitch-burst",
        what: "5 bursts of 20 glitch pulses (1 us wide, every 100 us) on the left encoder's channel A, 3 to 5 s into a 2 m line",
        expected: EXPECTED,
        test: Test::Line,
        leg_mm: 2000.0,
        faults,
        limit_s: 30.0,
        framed: false,
        check: Some(check),
    }
}

/// The INT4 handler reads channel A within 16 cycles of the vector, so it
/// sees each edge of a 1 us pulse at its own level: the two counts of a
/// pulse cancel. An edge merged into a pending interrupt (while interrupts
/// are off, or next to a real edge) is the only way a pulse can miscount.
const EXPECTED: &str = "the two edges of each 1 us pulse cancel in the count (the encoder handler reads A within 16 cycles): the line completes with no fault code, the left count within 5 of the plant's edges";

fn check(o: &Observed) -> Result<String, String> {
    let err = o.first_leg_count_error.map(|e| e.0);
    let code = o.fault_code.unwrap_or(0);
    match err {
        Some(e) if o.completed && code == 0 && e.abs() <= 5 => Ok(format!(
            "completed without a fault; the left count ended {e:+} off the plant's edges"
        )),
        e => Err(format!(
            "expected completion, no fault code, the left count within 5 of the plant; completed {}, code {code}, count error {e:?}",
            o.completed
        )),
    }
}
