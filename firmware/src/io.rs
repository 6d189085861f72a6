//! What the application logic asks of the hardware: small traits, and the
//! plain values that cross them.
//!
//! The robust build's logic ([`crate::robust`]) is written against these
//! traits only, so it compiles and is unit-tested on the host with fakes;
//! the AVR drivers implement them ([`crate::encoder::Encoders`],
//! [`crate::driver::Driver`], [`crate::motors::Motors`], [`crate::clock::Clock`], the ADC, the LEDs, the
//! USARTs). An implementation must keep the behaviour each method states: the
//! logic's timing and its stop rules rely on it.

use crate::settings::DriverWiring;
use crate::Error;

/// Both counts at one instant.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Counts {
    /// Left wheel count.
    pub left: i32,
    /// Right wheel count.
    pub right: i32,
}

/// Which wheel.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    /// Left wheel (INT4, D2/D4).
    Left,
    /// Right wheel (INT5, D3/D5).
    Right,
}

/// Tripped-mask bit: the left wheel's trip fired.
pub const TRIP_LEFT: u8 = 1;
/// Tripped-mask bit: the right wheel's trip fired.
pub const TRIP_RIGHT: u8 = 2;

/// The two H-bridges: each wheel has a forward and a reverse input, each a
/// PWM duty with `analogWrite` semantics (0 low, 255 high).
pub trait Bridges {
    /// Sets `side`'s forward input.
    fn set_forward(&mut self, side: Side, duty: u8);
    /// Sets `side`'s reverse input.
    fn set_reverse(&mut self, side: Side, duty: u8);
    /// All four inputs to 0: the forward ones (right, left), then the reverse
    /// ones (right, left), like the thesis' stop routines.
    fn all_off(&mut self);
    /// Whether the bridges are wired as `w` says already (a driver that
    /// cannot be rewired says no, so the caller checks `w` each time).
    fn drives(&self, _w: &DriverWiring) -> bool {
        false
    }
    /// Drives the wiring `w` from now on, which has passed
    /// [`DriverWiring::check`]: the old inputs low and released first, the
    /// new ones at 0. Nothing when it is the wiring already (or the bridges'
    /// wiring is fixed).
    fn rewire(&mut self, _w: &DriverWiring) {}
}

/// The two wheel encoders: counts that change on every edge (in an
/// interrupt handler), and one trip per wheel that fires on the edge that
/// brings its count to a given value.
pub trait WheelEncoders {
    /// Both counts, read at one instant.
    fn counts(&self) -> Counts;
    /// Arms `side`'s trip at count `at`, reached going `up` (count rising) or
    /// down. If the count is already there, it fires at once.
    fn arm(&mut self, side: Side, up: bool, at: i32);
    /// Disarms both trips and forgets fired ones.
    fn disarm_all(&mut self);
    /// The trips fired since the last call ([`TRIP_LEFT`], [`TRIP_RIGHT`]
    /// bits) and both counts at this instant.
    fn take_tripped(&mut self) -> (u8, Counts);
}

/// The control tick and a monotonic clock in timer clocks
/// ([`crate::time`]), with one alarm that wakes the main loop.
pub trait TickClock {
    /// The current time, timer clocks (wrapping; compare with
    /// [`crate::time::reached`]).
    fn now(&self) -> u32;
    /// Ticks since the previous call (0 if none; more than 1 when the main
    /// loop missed a period).
    fn take_ticks(&mut self) -> u32;
    /// Starts a fresh control period now (a pending tick dropped), the clock
    /// continuous, the alarm off.
    fn restart_period(&mut self);
    /// Wakes the main loop at `at`, or returns false (no alarm) when `at` has
    /// already come: the caller handles it now.
    fn arm_alarm(&mut self, at: u32) -> bool;
    /// Cancels the alarm.
    fn disarm_alarm(&mut self);
}

/// The battery divider's analog input: one conversion at a time.
pub trait BatteryInput {
    /// Starts a conversion.
    fn start(&mut self);
    /// True while a conversion runs.
    fn busy(&self) -> bool;
    /// The last result, 0..=1023.
    fn result(&self) -> u16;
}

/// Which battery LED is lit (chosen by [`crate::battery`]'s thresholds).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Colour {
    /// D11 (charged).
    Blue,
    /// D10.
    Green,
    /// D12 (low).
    Red,
}

/// The battery LEDs.
pub trait BatteryLeds {
    /// Lights `c` alone; writes nothing when it is already lit.
    fn show_if_changed(&mut self, c: Colour);
}

/// A serial line that never waits: reads what was received, queues what is
/// sent.
pub trait Line {
    /// Bytes the receive buffer holds: the most one poll of the line reads.
    const RX_LEN: usize;
    /// Takes the oldest received byte, if any.
    fn read(&mut self) -> Option<u8>;
    /// Queues all of `bytes`, or nothing ([`Error::TxFull`]).
    fn write_all(&mut self, bytes: &[u8]) -> Result<(), Error>;
}
