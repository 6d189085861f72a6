//! The "robust" build: the thesis' four tests (straight line, UMBmark CW and
//! CCW, triangle) with the thesis' control law, driven by a framed command
//! protocol (`henrytwo-protocol`) or the thesis' single-byte selectors on
//! the Bluetooth UART.
//!
//! What it does differently from the thesis (README.md has the full table):
//! - the control tick is timer 1 (exactly 15 ms), the PID's constant factors
//!   are folded, the CPU sleeps whenever nothing is due;
//! - a segment ends on an encoder-handler trip, so the cut-off happens
//!   within one count of the target and the CPU is not woken per edge;
//! - in a spin turn each wheel is cut when its own count reaches its target,
//!   then gets its own braking pulse;
//! - stall (no net progress), encoder-inconsistent, wrong-direction and
//!   segment time-out faults stop the motors; the MCU watchdog resets a main
//!   loop that stops running;
//! - every wait is a deadline on the timer 1 clock: no busy loop anywhere.
//!
//! The logic is the library's (`henrytwo_firmware::robust`, tested on the
//! host); this file wires it to the ATmega2560: the interrupt vectors, the
//! drivers behind the logic's traits, and the main loop.

#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use avr_device::atmega2560::{Peripherals, USART0, USART1};
use avr_device::interrupt;

use henrytwo_firmware::battery::Leds;
use henrytwo_firmware::bench;
use henrytwo_firmware::board;
use henrytwo_firmware::clock::{self, Clock};
use henrytwo_firmware::driver::{Driver, Mmio, StaticState};
use henrytwo_firmware::encoder::Encoders;
use henrytwo_firmware::hal::adc::Adc;
use henrytwo_firmware::hal::eeprom::Eeprom;
use henrytwo_firmware::hal::exint::ExtInts;
use henrytwo_firmware::hal::sleep::Sleeper;
use henrytwo_firmware::hal::usart::{self, Serial};
use henrytwo_firmware::hal::wdt::{self, Watchdog};
use henrytwo_firmware::robust::control::{self, StallLimits};
use henrytwo_firmware::robust::persist::Stored;
use henrytwo_firmware::robust::{App, Drive, Hardware};
use henrytwo_firmware::settings::Settings;
use henrytwo_protocol::{Fault, RunState};

// ---- interrupt vectors of this build ----
//
// INT4 and INT5 (the encoders) are the library's assembly handlers
// (`henrytwo_firmware::encoder`), the same in both builds.

#[avr_device::interrupt(atmega2560)]
fn TIMER1_COMPA() {
    // SAFETY: this is the TIMER1_COMPA vector.
    unsafe { clock::on_tick() }
}

#[avr_device::interrupt(atmega2560)]
fn TIMER1_COMPB() {
    // SAFETY: this is the TIMER1_COMPB vector.
    unsafe { clock::on_alarm() }
}

// Both USARTs' RX-complete and data-register-empty vectors.
henrytwo_firmware::usart_vectors!();

/// Boot message on the debug UART.
const BOOT_LINE: &[u8] = b"henrytwo robust ready\r\n";

/// The motor driver, wired at run time.
type DriveMotors = Driver<Mmio, StaticState>;

/// The robot's parts behind the logic's traits.
struct Mega;

impl Hardware for Mega {
    type Motors = DriveMotors;
    type Encoders = Encoders;
    type Clock = Clock;
    type Leds = Leds;
    type Adc = Adc;
    type Link = Serial<USART1>;
    type Debug = Serial<USART0>;

    #[inline(always)]
    fn control_tick(d: &mut Drive<DriveMotors, Encoders>, n: u32, stall: StallLimits) -> Fault {
        ht_control_tick(d, n, stall)
    }

    #[inline(always)]
    fn control_tick_tuned(
        d: &mut Drive<DriveMotors, Encoders>,
        n: u32,
        stall: StallLimits,
        t: control::Tuned,
    ) -> Fault {
        ht_control_tick_tuned(d, n, stall, t)
    }
}

/// One control period ([`control::tick`]). Not inlined and named, so a
/// timing tool can find its entry and exit.
#[inline(never)]
#[no_mangle]
pub fn ht_control_tick(d: &mut Drive<DriveMotors, Encoders>, n: u32, stall: StallLimits) -> Fault {
    control::tick(d, n, stall, control::Factory)
}

/// The control period with the settings' watchdog thresholds, when they are
/// not the factory ones (`stall_progress_counts`, `wrong_way_counts`).
#[inline(never)]
#[no_mangle]
pub fn ht_control_tick_tuned(
    d: &mut Drive<DriveMotors, Encoders>,
    n: u32,
    stall: StallLimits,
    t: control::Tuned,
) -> Fault {
    control::tick(d, n, stall, t)
}

#[avr_device::entry]
fn main() -> ! {
    // SAFETY: first thing after reset, called once; every peripheral is then
    // moved into exactly one driver.
    let dp = unsafe { Peripherals::steal() };
    // The watchdog first: after a watchdog reset it runs with its shortest
    // period until WDRF is cleared and it is turned off.
    let reset_cause = wdt::take_reset_cause(&dp.CPU);
    let mut watchdog = Watchdog::disabled(dp.WDT);
    let pins = board::Pins::new(dp.PORTB, dp.PORTD, dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);

    // The settings kept in the EEPROM; a stored wiring that cannot be
    // driven gives way to the factory one.
    let mut stored = Stored::load(Eeprom::new(dp.EEPROM), Settings::DEFAULT);
    if stored.settings.driver.check().is_err() {
        stored.settings.driver = Settings::DEFAULT.driver;
    }
    // Motors first, so the bridge inputs are low from the start. The driver
    // programs the pins its wiring names and timers 2-5 itself: their PAC
    // handles and the Henrytwo bridge pins are dropped unused here.
    let _ = (dp.TC2, dp.TC3, dp.TC4, dp.TC5);
    let _ = (pins.right_reverse, pins.right_forward, pins.left_reverse, pins.left_forward);
    // SAFETY: nothing else in this build touches timers 2-5, and the checked
    // wiring names none of the pins the other drivers below use; the static
    // state is taken once, here, and no handler uses the driver.
    let motors = unsafe { Driver::with_state(Mmio::new(), StaticState::take(), &stored.settings.driver) };
    let encoders = Encoders::new(
        ExtInts::new(dp.EXINT),
        pins.left_encoder_a,
        pins.left_encoder_b,
        pins.right_encoder_a,
        pins.right_encoder_b,
    );
    let leds = Leds::new(pins.led_green, pins.led_blue, pins.led_red);
    let _battery_pin = pins.battery_sense;
    let adc = Adc::new(dp.ADC);
    let debug = Serial::new(dp.USART0, board::DEBUG_BAUD);
    let bluetooth = Serial::new(dp.USART1, board::BLUETOOTH_BAUD);
    let mut sleeper = Sleeper::new(dp.CPU);
    let clock = Clock::start(dp.TC1);

    let mut app = App::<Mega>::new(Drive::new(motors, encoders), clock, leds, adc, bluetooth, debug, stored);

    // SAFETY: every handler's state is initialised above.
    unsafe { interrupt::enable() };
    app.debug_line(BOOT_LINE);
    if reset_cause & wdt::WDRF != 0 {
        app.report_watchdog_reset();
    }
    watchdog.enable_250ms();
    bench::set_state(RunState::Idle);

    loop {
        app.poll();
        watchdog.feed();
        sleeper.idle();
    }
}
