//! The waveform generation modes of the ATmega2560's timers and what the
//! compare output mode bits do in each: table 17-2 (16-bit timers 1, 3, 4,
//! 5), tables 16-8 and 20-8 (8-bit timers 0 and 2, alike), and the COM
//! tables 16-2..16-7, 17-3..17-5 and 20-2..20-7.

/// How the counter counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Kind {
    /// Up to MAX, overflow to BOTTOM.
    Normal,
    /// Up to TOP, cleared to BOTTOM on the match (Clear Timer on Compare).
    Ctc,
    /// Single slope PWM: up to TOP, then BOTTOM.
    Fast,
    /// Dual slope PWM, OCR updated at TOP.
    PhaseCorrect,
    /// Dual slope PWM, OCR (and TOP) updated at BOTTOM.
    PhaseFrequencyCorrect,
}

/// Where TOP comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Top {
    Fixed(u32),
    Ocra,
    Icr,
}

/// When a write to OCRnx reaches the compare unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Update {
    Immediate,
    AtTop,
    AtBottom,
}

/// One waveform generation mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Mode {
    /// WGM bits (0-15 on 16-bit timers, 0-7 on the 8-bit ones).
    pub wgm: u8,
    pub kind: Kind,
    pub top: Top,
    /// MAX: 0xFF or 0xFFFF.
    pub max: u32,
}

impl Mode {
    /// Mode `wgm` of an 8-bit (timer 0, 2) or 16-bit timer; None for the
    /// reserved ones (8-bit: 4 and 6; 16-bit: 13).
    pub fn decode(wgm: u8, sixteen_bit: bool) -> Option<Mode> {
        use Kind::*;
        let (kind, top) = if sixteen_bit {
            match wgm {
                0 => (Normal, Top::Fixed(0xFFFF)),
                1 => (PhaseCorrect, Top::Fixed(0x00FF)),
                2 => (PhaseCorrect, Top::Fixed(0x01FF)),
                3 => (PhaseCorrect, Top::Fixed(0x03FF)),
                4 => (Ctc, Top::Ocra),
                5 => (Fast, Top::Fixed(0x00FF)),
                6 => (Fast, Top::Fixed(0x01FF)),
                7 => (Fast, Top::Fixed(0x03FF)),
                8 => (PhaseFrequencyCorrect, Top::Icr),
                9 => (PhaseFrequencyCorrect, Top::Ocra),
                10 => (PhaseCorrect, Top::Icr),
                11 => (PhaseCorrect, Top::Ocra),
                12 => (Ctc, Top::Icr),
                14 => (Fast, Top::Icr),
                15 => (Fast, Top::Ocra),
                _ => return None,
            }
        } else {
            match wgm {
                0 => (Normal, Top::Fixed(0xFF)),
                1 => (PhaseCorrect, Top::Fixed(0xFF)),
                2 => (Ctc, Top::Ocra),
                3 => (Fast, Top::Fixed(0xFF)),
                5 => (PhaseCorrect, Top::Ocra),
                7 => (Fast, Top::Ocra),
                _ => return None,
            }
        };
        let max = if sixteen_bit { 0xFFFF } else { 0xFF };
        Some(Mode {
            wgm,
            kind,
            top,
            max,
        })
    }

    /// The datasheet's name of the mode.
    pub fn name(&self) -> String {
        let top = match self.top {
            Top::Fixed(_) if self.kind == Kind::Normal => return "normal".into(),
            Top::Fixed(0xFF) => "8-bit",
            Top::Fixed(0x1FF) => "9-bit",
            Top::Fixed(0x3FF) => "10-bit",
            Top::Fixed(_) => unreachable!("no other fixed TOP"),
            Top::Ocra => "TOP OCRnA",
            Top::Icr => "TOP ICRn",
        };
        let kind = match self.kind {
            Kind::Normal => unreachable!("named above"),
            Kind::Ctc => "CTC",
            Kind::Fast => "fast PWM",
            Kind::PhaseCorrect => "phase-correct PWM",
            Kind::PhaseFrequencyCorrect => "phase- and frequency-correct PWM",
        };
        format!("{kind}, {top}")
    }

    pub fn is_pwm(&self) -> bool {
        matches!(
            self.kind,
            Kind::Fast | Kind::PhaseCorrect | Kind::PhaseFrequencyCorrect
        )
    }

    /// Counts up and down (phase correct, phase and frequency correct).
    pub fn dual_slope(&self) -> bool {
        matches!(self.kind, Kind::PhaseCorrect | Kind::PhaseFrequencyCorrect)
    }

    /// When OCR writes take effect (17.7.3 / 20.5: double buffered in the
    /// PWM modes, at TOP for phase correct, at BOTTOM for fast PWM and
    /// phase and frequency correct; immediate in normal and CTC).
    pub fn update(&self) -> Update {
        match self.kind {
            Kind::Normal | Kind::Ctc => Update::Immediate,
            Kind::PhaseCorrect => Update::AtTop,
            Kind::Fast | Kind::PhaseFrequencyCorrect => Update::AtBottom,
        }
    }

    /// The action COM bits `com` take on channel `channel` (0 = A) in this
    /// mode. The 8-bit timers' OCnA (timer 0's, 2's) toggles in the PWM
    /// modes with WGMn2 set (TOP = OCRnA, tables 16-3/16-4, 20-3/20-4); the 16-bit
    /// timers' OCnA in fast PWM modes 14 and 15 and in the dual slope modes
    /// 8 to 11 (tables 17-4 and 17-5); every other channel is disconnected
    /// by COM = 1 in PWM modes.
    pub fn action(&self, channel: usize, com: u8) -> Action {
        match (com, self.is_pwm()) {
            (0, _) => Action::Disconnected,
            (1, false) => Action::Toggle,
            (2, false) => Action::Clear,
            (3, false) => Action::Set,
            (1, true) => {
                let toggles = channel == 0
                    && if self.max == 0xFF {
                        self.top == Top::Ocra
                    } else {
                        matches!(self.wgm, 8..=11 | 14 | 15)
                    };
                if toggles {
                    Action::Toggle
                } else {
                    Action::Disconnected
                }
            }
            (2, true) => Action::NonInverting,
            _ => Action::Inverting,
        }
    }
}

/// What a channel's compare output does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Action {
    /// The pin is the port's.
    Disconnected,
    /// Toggle on each compare match.
    Toggle,
    /// Non-PWM modes: clear on the match (then stays low).
    Clear,
    /// Non-PWM modes: set on the match.
    Set,
    /// PWM: clear on the (up-counting) match, set at BOTTOM (down-counting
    /// match in the dual slope modes).
    NonInverting,
    /// The complement of [`Action::NonInverting`].
    Inverting,
}

/// A timer's clock select table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Prescalers {
    /// The prescaler timers 0, 1, 3, 4 and 5 share (tables 16-9 and 17-6:
    /// 1, 8, 64, 256, 1024; 6 and 7 the external clock on pin Tn).
    Shared,
    /// Timer 2's own, which the asynchronous oscillator can clock (table
    /// 20-9: 1, 8, 32, 64, 128, 256, 1024).
    Asynchronous,
}

/// The prescaler N of clock select `cs`: Some(None) when stopped, None for
/// an external clock.
pub fn prescaler(cs: u8, table: Prescalers) -> Option<Option<u32>> {
    match (cs, table) {
        (0, _) => Some(None),
        (1..=7, Prescalers::Asynchronous) => {
            Some(Some([0, 1, 8, 32, 64, 128, 256, 1024][cs as usize]))
        }
        (1..=5, Prescalers::Shared) => Some(Some([0, 1, 8, 64, 256, 1024][cs as usize])),
        _ => None,
    }
}
