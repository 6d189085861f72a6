//! The robust build's logic: the thesis' four tests with the thesis' control
//! law, driven by the framed protocol or the thesis' selector bytes, with
//! the faults that stop the motors. `src/bin/robust.rs` wires it to the
//! ATmega2560; everything here reaches the hardware only through the traits
//! of [`crate::io`], so it runs on the host too (the unit tests).
//!
//! Parts:
//! - [`drive`]: the H-bridges, the encoders and each wheel's state;
//! - [`control`]: one control period (speed, PID, output stage);
//! - [`progress`]: the watchdog of each wheel's progress;
//! - [`sequencer`]: a test's segments, their stop rules, braking, waits,
//!   faults;
//! - [`dispatch`]: commands and selector bytes in, replies and notices out;
//! - [`persist`]: the settings kept in the EEPROM (layout, load, writes).
//! - [`wiring`]: the motor driver's wiring checked and applied at START_TEST.
//!
//! [`App::poll`] looks at every event source once; the firmware calls it
//! after each wake-up.

pub mod control;
pub mod dispatch;
pub mod drive;
pub mod persist;
pub mod progress;
pub mod sequencer;
pub mod wiring;

#[cfg(test)]
mod fake;

use henrytwo_protocol::{Fault, FaultNotice, Parser, Status, NOTIFY_FAULT};

use crate::bench;
use crate::io::{BatteryInput, BatteryLeds, Bridges, Line, TickClock, WheelEncoders};
use crate::robot;
use crate::selector::Isolation;

use control::StallLimits;
use dispatch::{INTER_BYTE_TIMEOUT, RAW_QUIET};
pub use drive::Drive;
use persist::{ByteStore, Stored};
use sequencer::Mode;

/// The hardware the application runs on: one type per part.
pub trait Hardware {
    /// The H-bridges.
    type Motors: Bridges;
    /// The encoders.
    type Encoders: WheelEncoders;
    /// The clock and the control tick.
    type Clock: TickClock;
    /// The battery LEDs.
    type Leds: BatteryLeds;
    /// The battery input.
    type Adc: BatteryInput;
    /// The command link (Bluetooth UART).
    type Link: Line;
    /// The debug UART (text lines).
    type Debug: Line + ufmt::uWrite;
    /// Where the settings are kept: on the AVR the MCU's EEPROM unless a
    /// board says otherwise.
    #[cfg(target_arch = "avr")]
    type Store: ByteStore = crate::hal::eeprom::Eeprom;
    /// Where the settings are kept.
    #[cfg(not(target_arch = "avr"))]
    type Store: ByteStore;

    /// One control period ([`control::tick`]). The firmware overrides this
    /// with its out-of-line, named copy, so a timing tool finds the tick's
    /// entry and exit.
    #[inline(always)]
    fn control_tick(d: &mut Drive<Self::Motors, Self::Encoders>, n: u32, stall: StallLimits) -> Fault {
        control::tick(d, n, stall, control::Factory)
    }

    /// The same with thresholds other than the factory ones (a second copy:
    /// the factory one keeps its constants).
    #[inline(always)]
    fn control_tick_tuned(
        d: &mut Drive<Self::Motors, Self::Encoders>,
        n: u32,
        stall: StallLimits,
        t: control::Tuned,
    ) -> Fault {
        control::tick(d, n, stall, t)
    }
}

/// The robust application: the drive, the rest of the hardware, and where
/// the robot is in its work.
pub struct App<H: Hardware> {
    pub(crate) drive: Drive<H::Motors, H::Encoders>,
    pub(crate) clock: H::Clock,
    pub(crate) leds: H::Leds,
    pub(crate) adc: H::Adc,
    pub(crate) adc_running: bool,
    pub(crate) bluetooth: H::Link,
    pub(crate) debug: H::Debug,
    pub(crate) parser: Parser,
    /// The isolation rule for raw selector bytes.
    pub(crate) raw: Isolation,
    /// The settings, and the EEPROM they are kept in.
    pub(crate) stored: Stored<H::Store>,
    pub(crate) mode: Mode,
    /// Leg length of the running test (read at its start).
    pub(crate) leg_mm: f32,
    /// Ticks since the segment started, and its limit.
    pub(crate) segment_ticks: u32,
    pub(crate) segment_limit: u32,
    /// The settings' watchdog thresholds when they are not the factory
    /// ones, taken at each segment start.
    pub(crate) tuned: Option<control::Tuned>,
    /// In a turn with a stop lead: each wheel's count at which it is cut
    /// without one, while its trip is the look-ahead before it (`None`:
    /// the trip is the cut).
    pub(crate) turn_ahead: [Option<i32>; 2],
}

impl<H: Hardware> App<H> {
    /// Idle, with the settings `stored` (the firmware loads them from the
    /// EEPROM, [`Stored::load`]); the speed conversion computed for them.
    #[inline(always)]
    pub fn new(
        mut drive: Drive<H::Motors, H::Encoders>,
        clock: H::Clock,
        leds: H::Leds,
        adc: H::Adc,
        bluetooth: H::Link,
        debug: H::Debug,
        stored: Stored<H::Store>,
    ) -> Self {
        drive.speeds.set(stored.settings.counts_per_wheel_rev);
        App {
            drive,
            clock,
            leds,
            adc,
            adc_running: false,
            bluetooth,
            debug,
            parser: Parser::new(INTER_BYTE_TIMEOUT),
            raw: Isolation::new(RAW_QUIET),
            stored,
            mode: Mode::Idle,
            leg_mm: robot::DEFAULT_LEG_MM,
            segment_ticks: 0,
            segment_limit: 0,
            tuned: None,
            turn_ahead: [None; 2],
        }
    }

    /// Looks at every event source once. Called after each wake-up.
    #[inline(always)]
    pub fn poll(&mut self) {
        let (tripped, counts) = self.drive.encoders.take_tripped();
        if tripped != 0 {
            self.on_trips(tripped, counts);
        }
        if self.next_deadline().is_some() {
            self.on_time(self.clock.now());
        }
        let n = self.clock.take_ticks();
        if n > 0 {
            self.on_tick(n);
        }
        self.poll_commands();
        self.arm_next_deadline();
        if self.stored.pending() {
            self.stored.step();
        }
    }

    /// Queues `line` on the debug UART (dropped if it does not fit).
    #[inline(always)]
    pub fn debug_line(&mut self, line: &[u8]) {
        let _ = self.debug.write_all(line);
    }

    /// Reports a reset by the MCU watchdog: the fault, and its notice.
    #[inline(always)]
    pub fn report_watchdog_reset(&mut self) {
        bench::set_fault(Fault::WatchdogReset as u8);
        bench::set_phase(henrytwo_protocol::Phase::Fault);
        let notice = FaultNotice { fault: Fault::WatchdogReset as u8, ..FaultNotice::default() };
        self.send(NOTIFY_FAULT, Status::Ok, &notice.to_bytes());
    }
}

#[cfg(test)]
mod tests {
    use henrytwo_protocol::{Fault, FaultNotice, Phase, Status, NOTIFY_FAULT};

    use super::fake::{self, Fake};
    use super::App;
    use crate::bench;

    /// A debug line goes out on the debug UART, not on the link.
    #[test]
    fn a_debug_line_goes_to_the_debug_uart() {
        let _bench = fake::lock();
        let mut app = App::<Fake>::fake();
        let _ = app.sent();
        let before = app.debug.text();
        app.debug_line(b"henrytwo robust\r\n");
        assert_eq!(app.debug.text(), format!("{before}henrytwo robust\r\n"));
        assert!(app.sent().is_empty());
    }

    /// A reset by the watchdog is reported as its fault: in the bench
    /// variables and in one fault notice on the link.
    #[test]
    fn a_watchdog_reset_is_reported_as_a_fault() {
        let _bench = fake::lock();
        let mut app = App::<Fake>::fake();
        let _ = app.sent();
        app.report_watchdog_reset();
        assert_eq!((bench::phase_code(), bench::fault()), (Phase::Fault as u8, Fault::WatchdogReset as u8));
        let sent = app.sent();
        assert_eq!(sent.len(), 1, "{sent:?}");
        assert_eq!((sent[0].0, sent[0].1), (NOTIFY_FAULT, Status::Ok as u8));
        assert_eq!(FaultNotice::decode(&sent[0].2).unwrap().fault, Fault::WatchdogReset as u8);
    }
}
