//! Whether a motor driver wiring can be driven: the rules a wiring passes
//! before the driver applies it (at START_TEST and at boot).

use henrytwo_protocol::{DriverKind, NO_PIN};

use crate::hal::mega_pins;
use crate::io::Side;
use crate::settings::DriverWiring;

/// What is wrong with one pin of a wiring (or its kind).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum WiringFault {
    /// The kind is no `DriverKind`.
    UnknownKind,
    /// The kind needs this pin and it is `NO_PIN`.
    Missing,
    /// The kind has no use for this pin (pin 3 of `TwoPwm`, `PwmDir`): it
    /// must be `NO_PIN`.
    Unused,
    /// No Arduino Mega pin has this number.
    NotAMegaPin,
    /// A PWM input on a pin without a compare output of timer 2, 3, 4 or 5
    /// (timer 0 is the Arduino core's, timer 1 the robust build's clock).
    NotPwm,
    /// A pin the firmware uses for something else (encoders D2-D5, USART0
    /// D0/D1, USART1 D18/D19, battery LEDs D10-D12, battery sense A0).
    Reserved,
    /// The same pin named twice.
    Twice,
}

/// Where a wiring fails: the side and pin (1-3; 0 with `side` `None` for
/// the kind), the pin's number, and why.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct WiringError {
    /// The motor, `None` for the kind.
    pub side: Option<Side>,
    /// Pin 1-3 of that motor (0 for the kind).
    pub index: u8,
    /// The value given (the pin's number, or the kind).
    pub value: u8,
    /// What is wrong.
    pub fault: WiringFault,
}

/// Pins the firmware drives or reads for something other than the motor
/// driver (`board.rs`): D0/D1 USART0, D2-D5 encoders, D10-D12 battery LEDs,
/// D18/D19 USART1, D54 (A0) battery sense.
pub const RESERVED: [u8; 12] = [0, 1, 2, 3, 4, 5, 10, 11, 12, 18, 19, 54];

/// Whether `v` may be set as a single driver pin: a Mega pin or `NO_PIN`
/// (the rest of the rules wait for the whole wiring, since pins are moved
/// one at a time).
pub const fn settable_pin(v: u8) -> bool {
    v == NO_PIN || v < mega_pins::COUNT
}

impl DriverWiring {
    /// Checks the wiring: a known kind; each pin the kind needs a Mega pin,
    /// not reserved ([`RESERVED`]), not named twice; each PWM pin (pin 1, and
    /// pin 2 of `TwoPwm`) on a channel of timer 2-5; pin 3 `NO_PIN` unless the
    /// kind is `EnableTwoDir`. The first failing pin, left before right, 1
    /// before 3, is the error.
    pub fn check(&self) -> Result<(), WiringError> {
        let Some(kind) = DriverKind::from_u8(self.kind) else {
            return Err(WiringError { side: None, index: 0, value: self.kind, fault: WiringFault::UnknownKind });
        };
        let all = [self.left, self.right];
        for (s, pins) in all.iter().enumerate() {
            let side = if s == 0 { Side::Left } else { Side::Right };
            for (i, &n) in pins.iter().enumerate() {
                let fail = |fault| Err(WiringError { side: Some(side), index: i as u8 + 1, value: n, fault });
                let used = i < 2 || kind == DriverKind::EnableTwoDir;
                if !used {
                    if n != NO_PIN {
                        return fail(WiringFault::Unused);
                    }
                    continue;
                }
                if n == NO_PIN {
                    return fail(WiringFault::Missing);
                }
                let Some(pin) = mega_pins::pin(n) else { return fail(WiringFault::NotAMegaPin) };
                if RESERVED.contains(&n) {
                    return fail(WiringFault::Reserved);
                }
                let pwm = i == 0 || (i == 1 && kind == DriverKind::TwoPwm);
                if pwm && pin.oc.is_none_or(|oc| mega_pins::pwm_timer(oc.timer).is_none()) {
                    return fail(WiringFault::NotPwm);
                }
                // Named before (left's pins, then this side's earlier ones).
                let earlier = all.iter().flatten().take(s * 3 + i);
                if earlier.into_iter().any(|&m| m == n) {
                    return fail(WiringFault::Twice);
                }
            }
        }
        Ok(())
    }
}

impl ufmt::uDisplay for WiringError {
    /// `right pin 2 = 13: not on timer 2-5`, `kind = 7: unknown`.
    fn fmt<W: ufmt::uWrite + ?Sized>(&self, f: &mut ufmt::Formatter<'_, W>) -> Result<(), W::Error> {
        let why = match self.fault {
            WiringFault::UnknownKind => "unknown",
            WiringFault::Missing => "missing",
            WiringFault::Unused => "must be 255",
            WiringFault::NotAMegaPin => "not a Mega pin",
            WiringFault::NotPwm => "no PWM of timer 2-5",
            WiringFault::Reserved => "reserved",
            WiringFault::Twice => "twice",
        };
        match self.side {
            None => ufmt::uwrite!(f, "kind = {}: {}", self.value, why),
            Some(s) => {
                let side = if s == Side::Left { "left" } else { "right" };
                ufmt::uwrite!(f, "{} pin {} = {}: {}", side, self.index, self.value, why)
            }
        }
    }
}
