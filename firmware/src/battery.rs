//! Battery level on A0 and the three LEDs (thesis `Nivel_Bateria`).
//!
//! The thesis compares the 10-bit reading `Nivel`:
//! `> 942` blue, `(> 901) && (< 942)` green, `< 901` red. Exactly 901 and
//! exactly 942 match no branch, so nothing is written and the LEDs keep
//! what they showed ([`thesis_colour`] gives `None`). The robust build
//! closes both gaps: 901..=942 is green ([`robust_colour`]).

#[cfg(target_arch = "avr")]
use crate::hal::gpio::{Output, Pin, PB4, PB5, PB6};

/// Blue above this reading.
pub const BLUE_ABOVE: u16 = 942;
/// Green above this reading (thesis: and below [`BLUE_ABOVE`]).
pub const GREEN_ABOVE: u16 = 901;

/// The colour type crosses the `io` traits ([`crate::io::BatteryLeds`]), so
/// it lives there; this is the battery's name for it.
pub use crate::io::Colour;

/// The thesis' branches; `None` when no branch matches (901 and 942).
pub const fn thesis_colour(nivel: u16) -> Option<Colour> {
    if nivel > BLUE_ABOVE {
        Some(Colour::Blue)
    } else if nivel > GREEN_ABOVE && nivel < BLUE_ABOVE {
        Some(Colour::Green)
    } else if nivel < GREEN_ABOVE {
        Some(Colour::Red)
    } else {
        None
    }
}

/// The robust build's colour: 901 and 942 are green.
pub const fn robust_colour(nivel: u16) -> Colour {
    if nivel > BLUE_ABOVE {
        Colour::Blue
    } else if nivel >= GREEN_ABOVE {
        Colour::Green
    } else {
        Colour::Red
    }
}

const _: () = {
    assert!(matches!(thesis_colour(943), Some(Colour::Blue)));
    assert!(thesis_colour(942).is_none());
    assert!(matches!(thesis_colour(941), Some(Colour::Green)));
    assert!(matches!(thesis_colour(902), Some(Colour::Green)));
    assert!(thesis_colour(901).is_none());
    assert!(matches!(thesis_colour(900), Some(Colour::Red)));
    assert!(matches!(robust_colour(942), Colour::Green) && matches!(robust_colour(901), Colour::Green));
    assert!(matches!(robust_colour(943), Colour::Blue) && matches!(robust_colour(900), Colour::Red));
};

/// The three LEDs on D10 (green, PB4), D11 (blue, PB5), D12 (red, PB6).
#[cfg(target_arch = "avr")]
pub struct Leds {
    green: Pin<PB4, Output>,
    blue: Pin<PB5, Output>,
    red: Pin<PB6, Output>,
    shown: Option<Colour>,
}

#[cfg(target_arch = "avr")]
impl Leds {
    /// Makes the three pins outputs, all off (the thesis' `pinMode(..., OUTPUT)`).
    pub fn new<MG, MB, MR>(green: Pin<PB4, MG>, blue: Pin<PB5, MB>, red: Pin<PB6, MR>) -> Self {
        Leds { green: green.into_output_low(), blue: blue.into_output_low(), red: red.into_output_low(), shown: None }
    }

    /// Lights `c` alone, writing red, green, blue in that order as every
    /// branch of the thesis does (`analogWrite` with 0 or 255 is a plain
    /// digital write on these pins).
    pub fn show(&mut self, c: Colour) {
        self.red.set(c == Colour::Red);
        self.green.set(c == Colour::Green);
        self.blue.set(c == Colour::Blue);
        self.shown = Some(c);
    }

    /// Like [`Leds::show`] but writes nothing when `c` is already lit.
    pub fn show_if_changed(&mut self, c: Colour) {
        if self.shown != Some(c) {
            self.show(c);
        }
    }
}

#[cfg(target_arch = "avr")]
impl crate::io::BatteryLeds for Leds {
    #[inline(always)]
    fn show_if_changed(&mut self, c: Colour) {
        Leds::show_if_changed(self, c)
    }
}
