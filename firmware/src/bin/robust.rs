//! The "robust" build: the thesis' straight-line test (command byte 4 on the
//! Bluetooth UART) with an exact 15 ms hardware control tick, encoder counters
//! that are never reset, and a stop decided on every wake-up so the leg ends
//! within one encoder count of its length.
//!
//! The CPU sleeps whenever the main loop has nothing to do; it wakes on the
//! tick, encoder edges, UART bytes and the one-shot delay timer.

#![no_std]
#![no_main]

use avr_device::atmega2560::{Peripherals, USART0, USART1};
use avr_device::interrupt;

use henrytwo_firmware::bench::{self, State};
use henrytwo_firmware::board::{self, DriveMotors, CPU_HZ};
use henrytwo_firmware::encoder::{Counts, Encoders};
use henrytwo_firmware::hal::clock::Prescaler;
use henrytwo_firmware::hal::exint::ExtInts;
use henrytwo_firmware::hal::oneshot::{Delay, OneShot};
use henrytwo_firmware::hal::sleep::Sleeper;
use henrytwo_firmware::hal::tick::{CtcPeriod, TickTimer};
use henrytwo_firmware::hal::usart::{Serial, RX_LEN};
use henrytwo_firmware::odometry::leg_target_count_sum;
use henrytwo_firmware::pid::WheelSpeedControl;
use henrytwo_firmware::robot;
use henrytwo_firmware::ticks::TickWatch;

/// Timer 1: clock/64, OCR1A = 3749 -> exactly 15 ms at 16 MHz.
const TICK: CtcPeriod = CtcPeriod::exact_us(CPU_HZ, Prescaler::Div64, robot::SAMPLE_PERIOD_US);
const _: () = assert!(TICK.top == 3749);

/// Boot message on the debug UART.
const BOOT_LINE: &[u8] = b"henrytwo robust ready\r\n";

/// Commands received on the Bluetooth UART (one byte each, as in the thesis'
/// `switch (Selector_Exp)`).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Command {
    /// Byte 4: straight-line test (`Linear_Path_Test`).
    StraightLine,
}

impl Command {
    /// The command a byte selects; unknown bytes select nothing.
    const fn from_byte(byte: u8) -> Option<Self> {
        match byte {
            4 => Some(Command::StraightLine),
            _ => None,
        }
    }
}

/// Duties of the four bridge inputs for one step of a braking sequence.
#[derive(Clone, Copy)]
struct Duties {
    right_forward: u8,
    right_reverse: u8,
    left_forward: u8,
    left_reverse: u8,
}

const ALL_OFF: Duties = Duties { right_forward: 0, right_reverse: 0, left_forward: 0, left_reverse: 0 };

/// One step: optionally set the duties, then wait.
#[derive(Clone, Copy)]
struct BrakeStep {
    set: Option<Duties>,
    wait: Delay,
}

/// What follows the cut-off at the end of a straight leg: the thesis'
/// `Inercia_Stop_Ad` then `Stop_General`. The cut-off itself (all four to 0)
/// happens before the first step.
const STRAIGHT_BRAKE: [BrakeStep; 4] = [
    // Inercia_Stop_Ad: forward inputs already 0, wait 20 ms.
    BrakeStep { set: None, wait: Delay::from_ms(CPU_HZ, 20) },
    // Reverse pulse at full duty on D6 and D8 for 5 ms.
    BrakeStep {
        set: Some(Duties { right_forward: 0, right_reverse: 255, left_forward: 0, left_reverse: 255 }),
        wait: Delay::from_ms(CPU_HZ, 5),
    },
    // Reverse inputs off, wait 1 s.
    BrakeStep { set: Some(ALL_OFF), wait: Delay::from_ms(CPU_HZ, 1000) },
    // Stop_General: all four off, wait 1 s.
    BrakeStep { set: Some(ALL_OFF), wait: Delay::from_ms(CPU_HZ, 1000) },
];

/// Where the test is.
#[derive(Clone, Copy)]
enum Phase {
    /// Waiting for a command.
    Idle,
    /// Driving a straight leg: counts at its start and the count sum to reach.
    Driving { start: Counts, target_sum: i32 },
    /// Running step `step` of the braking sequence.
    Braking { step: usize },
}

/// Everything the per-tick control touches.
pub struct Drive {
    motors: DriveMotors,
    encoders: Encoders,
    right: WheelSpeedControl,
    left: WheelSpeedControl,
}

/// One control period while driving: measure both wheels over the last
/// period, run both PIDs, apply the duties to the forward inputs (right D7,
/// left D9; reverse inputs stay 0) and publish speeds and duties.
///
/// Not inlined and named, so a timing tool can find its entry and exit.
#[inline(never)]
#[no_mangle]
pub fn ht_control_tick(drive: &mut Drive) {
    let c = drive.encoders.counts();
    let right = drive.right.update(c.right, robot::SAMPLE_PERIOD_S);
    let left = drive.left.update(c.left, robot::SAMPLE_PERIOD_S);
    drive.motors.right.set_forward(right.duty);
    drive.motors.left.set_forward(left.duty);
    bench::set_speed_right(right.rpm);
    bench::set_speed_left(left.rpm);
    bench::set_duty_right(right.duty);
    bench::set_duty_left(left.duty);
}

struct App {
    drive: Drive,
    tick: TickTimer,
    ticks: TickWatch,
    oneshot: OneShot,
    bluetooth: Serial<USART1>,
    debug: Serial<USART0>,
    phase: Phase,
}

impl App {
    /// Looks at every event source once. Called after each wake-up.
    fn poll(&mut self) {
        if let Phase::Idle = self.phase {
            self.poll_commands();
        }
        match self.phase {
            Phase::Idle => {
                // Ticks are only counted while idle.
                self.ticks.take();
            }
            Phase::Driving { start, target_sum } => {
                // Checked on every wake-up, edges included, so the leg ends
                // within one count of its length.
                let c = self.drive.encoders.counts();
                let d_left = c.left.wrapping_sub(start.left);
                let d_right = c.right.wrapping_sub(start.right);
                if d_left.saturating_add(d_right) >= target_sum {
                    self.cut_off();
                } else if self.ticks.take() > 0 {
                    ht_control_tick(&mut self.drive);
                }
            }
            Phase::Braking { step } => {
                self.ticks.take();
                if self.oneshot.take_fired() {
                    self.brake_step(step + 1);
                }
            }
        }
    }

    /// Reads command bytes while idle. Bytes that arrive during a test stay
    /// in the receive buffer until the test is over, as with the thesis'
    /// `Serial1` buffer; unknown bytes are dropped.
    fn poll_commands(&mut self) {
        for _ in 0..RX_LEN {
            let Some(byte) = self.bluetooth.read() else { return };
            match Command::from_byte(byte) {
                Some(Command::StraightLine) => {
                    self.start_straight();
                    return;
                }
                None => {}
            }
        }
    }

    /// Starts a straight leg: target from `HT_LEG_LENGTH_MM`, count origin,
    /// PID reset, a fresh 15 ms period, both forward inputs at the start duty.
    fn start_straight(&mut self) {
        let target_sum = leg_target_count_sum(bench::leg_length_mm());
        let start = self.drive.encoders.counts();
        self.drive.right.start(start.right);
        self.drive.left.start(start.left);
        self.tick.restart_period();
        self.ticks.take();
        let duty = robot::START_DUTY;
        self.drive.motors.right.set(duty, 0);
        self.drive.motors.left.set(duty, 0);
        bench::set_duty_right(duty);
        bench::set_duty_left(duty);
        self.phase = Phase::Driving { start, target_sum };
        bench::set_state(State::Driving);
    }

    /// End of a leg: all four inputs to 0 first, then the counts at that
    /// instant, then the braking sequence.
    fn cut_off(&mut self) {
        let stop = interrupt::free(|_| {
            self.drive.motors.all_off();
            self.drive.encoders.counts()
        });
        bench::set_stop_left(stop.left);
        bench::set_stop_right(stop.right);
        bench::set_state(State::Braking);
        self.brake_step(0);
    }

    /// Runs step `step` of the braking sequence, or ends the test after the
    /// last one.
    fn brake_step(&mut self, step: usize) {
        let Some(s) = STRAIGHT_BRAKE.get(step) else {
            self.finish_test();
            return;
        };
        if let Some(d) = s.set {
            let m = &mut self.drive.motors;
            m.right.set_forward(d.right_forward);
            m.left.set_forward(d.left_forward);
            m.right.set_reverse(d.right_reverse);
            m.left.set_reverse(d.left_reverse);
        }
        self.oneshot.start(s.wait);
        self.phase = Phase::Braking { step };
    }

    /// Back to idle: count the test, then report the stop counts. The state
    /// changes before the (slow, software-division) formatting so the bench
    /// sees the end of the test right when the last wait ends.
    fn finish_test(&mut self) {
        self.phase = Phase::Idle;
        bench::set_done_count(bench::done_count().wrapping_add(1));
        bench::set_state(State::Idle);
        // The line is queued, never waited for; if the buffer were full the
        // line would be cut, which only costs debug output.
        let _ = ufmt::uwrite!(
            &mut self.debug,
            "test {} done: stop left={} right={}\r\n",
            bench::done_count(),
            bench::stop_left(),
            bench::stop_right()
        );
    }
}

#[avr_device::entry]
fn main() -> ! {
    // SAFETY: first thing after reset, called once; every peripheral is then
    // moved into exactly one driver.
    let dp = unsafe { Peripherals::steal() };
    let pins = board::Pins::new(dp.PORTB, dp.PORTD, dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);

    // Motors first, so the bridge inputs are low from the start.
    let motors = board::drive_motors(
        dp.TC4,
        dp.TC2,
        pins.right_reverse,
        pins.right_forward,
        pins.left_reverse,
        pins.left_forward,
    );
    let encoders = Encoders::new(
        ExtInts::new(dp.EXINT),
        pins.left_encoder_a,
        pins.left_encoder_b,
        pins.right_encoder_a,
        pins.right_encoder_b,
    );
    let debug = Serial::new(dp.USART0, board::DEBUG_BAUD);
    let bluetooth = Serial::new(dp.USART1, board::BLUETOOTH_BAUD);
    let oneshot = OneShot::new(dp.TC3);
    let mut sleeper = Sleeper::new(dp.CPU);
    let tick = TickTimer::start(dp.TC1, TICK);

    let mut app = App {
        drive: Drive {
            motors,
            encoders,
            right: WheelSpeedControl::new(robot::GAINS_RIGHT, robot::SETPOINT_RIGHT),
            left: WheelSpeedControl::new(robot::GAINS_LEFT, robot::SETPOINT_LEFT),
        },
        tick,
        ticks: TickWatch::new(),
        oneshot,
        bluetooth,
        debug,
        phase: Phase::Idle,
    };

    // SAFETY: every handler's state is initialised above.
    unsafe { interrupt::enable() };
    let _ = app.debug.write_all(BOOT_LINE);
    bench::set_state(State::Idle);

    loop {
        app.poll();
        sleeper.idle();
    }
}
