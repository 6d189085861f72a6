//! The bench interface: variables the host bench reads and writes by ELF
//! symbol name (data address = symbol address - 0x800000 in simavr).
//!
//! They are `#[no_mangle] pub static mut` so their names and types are fixed,
//! and the firmware touches them only through the volatile accessors below so
//! that no access is optimised away or cached in a register. The multi-byte
//! ones that an interrupt handler writes are read here with interrupts off
//! (the accessors take a `CriticalSection`). See README.md for the table.

use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use avr_device::interrupt::CriticalSection;

/// Left encoder count since reset (the INT4 handler's counter). Never reset.
#[no_mangle]
pub static mut HT_LEFT_COUNT: i32 = 0;
/// Right encoder count since reset (the INT5 handler's counter). Never reset.
#[no_mangle]
pub static mut HT_RIGHT_COUNT: i32 = 0;
/// Control ticks (timer 1 compare matches, 15 ms) since reset.
#[no_mangle]
pub static mut HT_TICKS: u32 = 0;
/// 0 booting, 1 idle, 2 driving a leg, 3 braking/waiting. See [`State`].
#[no_mangle]
pub static mut HT_STATE: u8 = 0;
/// Tests completed since reset.
#[no_mangle]
pub static mut HT_DONE_COUNT: u16 = 0;
/// Leg length in millimetres, read at the start of each test. In `.data`.
#[no_mangle]
pub static mut HT_LEG_LENGTH_MM: f32 = crate::robot::DEFAULT_LEG_MM;
/// Left count at the instant the motors were cut at the end of the last leg.
#[no_mangle]
pub static mut HT_STOP_LEFT: i32 = 0;
/// Right count at the instant the motors were cut at the end of the last leg.
#[no_mangle]
pub static mut HT_STOP_RIGHT: i32 = 0;
/// Last measured left wheel speed, thesis "RPM" (wheel RPM / 6).
#[no_mangle]
pub static mut HT_SPEED_LEFT: f32 = 0.0;
/// Last measured right wheel speed, thesis "RPM" (wheel RPM / 6).
#[no_mangle]
pub static mut HT_SPEED_RIGHT: f32 = 0.0;
/// Last left PID output (duty on D9, 0..=255).
#[no_mangle]
pub static mut HT_DUTY_LEFT: u8 = 0;
/// Last right PID output (duty on D7, 0..=255).
#[no_mangle]
pub static mut HT_DUTY_RIGHT: u8 = 0;

/// Values of `HT_STATE`.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum State {
    /// Reset until initialisation is complete.
    Booting = 0,
    /// Ready for a command byte.
    Idle = 1,
    /// Driving a leg under PID control.
    Driving = 2,
    /// Braking and the waits after a leg.
    Braking = 3,
}

macro_rules! volatile_rw {
    ($get:ident, $set:ident, $var:ident, $t:ty) => {
        #[doc = concat!("Reads `", stringify!($var), "`.")]
        #[inline(always)]
        pub fn $get() -> $t {
            // SAFETY: a plain static only main-loop code writes; the volatile
            // read keeps the bench's writes visible.
            unsafe { read_volatile(addr_of!($var)) }
        }
        #[doc = concat!("Writes `", stringify!($var), "`.")]
        #[inline(always)]
        pub fn $set(v: $t) {
            // SAFETY: only the main loop writes this static (no handler does),
            // so there is no concurrent Rust access; volatile so the bench sees it.
            unsafe { write_volatile(addr_of_mut!($var), v) }
        }
    };
}

volatile_rw!(done_count, set_done_count, HT_DONE_COUNT, u16);
volatile_rw!(leg_length_mm, set_leg_length_mm, HT_LEG_LENGTH_MM, f32);
volatile_rw!(stop_left, set_stop_left, HT_STOP_LEFT, i32);
volatile_rw!(stop_right, set_stop_right, HT_STOP_RIGHT, i32);
volatile_rw!(speed_left, set_speed_left, HT_SPEED_LEFT, f32);
volatile_rw!(speed_right, set_speed_right, HT_SPEED_RIGHT, f32);
volatile_rw!(duty_left, set_duty_left, HT_DUTY_LEFT, u8);
volatile_rw!(duty_right, set_duty_right, HT_DUTY_RIGHT, u8);

/// Reads `HT_STATE`.
#[inline(always)]
pub fn state() -> State {
    // SAFETY: single byte, written only by the main loop.
    match unsafe { read_volatile(addr_of!(HT_STATE)) } {
        0 => State::Booting,
        1 => State::Idle,
        2 => State::Driving,
        _ => State::Braking,
    }
}

/// Writes `HT_STATE`.
#[inline(always)]
pub fn set_state(s: State) {
    // SAFETY: single byte, written only by the main loop.
    unsafe { write_volatile(addr_of_mut!(HT_STATE), s as u8) }
}

/// Reads `HT_TICKS` (written by the timer 1 handler, hence the `cs`).
#[inline(always)]
pub fn ticks(_cs: CriticalSection) -> u32 {
    // SAFETY: interrupts are off, so the handler cannot write half of it.
    unsafe { read_volatile(addr_of!(HT_TICKS)) }
}

/// Reads both encoder counts at one instant (written by the INT4/INT5
/// handlers, hence the `cs`): `(left, right)`.
#[inline(always)]
pub fn counts(_cs: CriticalSection) -> (i32, i32) {
    // SAFETY: interrupts are off, so neither handler can run between the
    // bytes or between the two reads.
    unsafe { (read_volatile(addr_of!(HT_LEFT_COUNT)), read_volatile(addr_of!(HT_RIGHT_COUNT))) }
}

/// Adds `step` to `HT_LEFT_COUNT`. For the INT4 handler only.
///
/// # Safety
/// Call only with interrupts disabled (inside the handler), so the four-byte
/// read-modify-write cannot be interrupted.
#[inline(always)]
pub unsafe fn isr_add_left(step: i32) {
    // SAFETY: the caller runs with interrupts off, the only writer.
    unsafe {
        let p = addr_of_mut!(HT_LEFT_COUNT);
        write_volatile(p, read_volatile(p).wrapping_add(step));
    }
}

/// Adds `step` to `HT_RIGHT_COUNT`. For the INT5 handler only.
///
/// # Safety
/// As [`isr_add_left`].
#[inline(always)]
pub unsafe fn isr_add_right(step: i32) {
    // SAFETY: the caller runs with interrupts off, the only writer.
    unsafe {
        let p = addr_of_mut!(HT_RIGHT_COUNT);
        write_volatile(p, read_volatile(p).wrapping_add(step));
    }
}

/// Adds one to `HT_TICKS`. For the timer 1 handler only.
///
/// # Safety
/// As [`isr_add_left`].
#[inline(always)]
pub unsafe fn isr_count_tick() {
    // SAFETY: the caller runs with interrupts off, the only writer.
    unsafe {
        let p = addr_of_mut!(HT_TICKS);
        write_volatile(p, read_volatile(p).wrapping_add(1));
    }
}
