//! The bench interface: variables the host bench reads and writes by ELF
//! symbol name (data address = symbol address - 0x800000 in simavr).
//!
//! They are `#[no_mangle] pub static mut` so their names and types are fixed,
//! and the firmware touches them only through the volatile accessors below so
//! that no access is optimised away or cached in a register. The multi-byte
//! ones that an interrupt handler writes are accessed here with interrupts
//! off (the accessors take a `CriticalSection`). A build contains only the
//! variables it uses (the linker drops the others); README.md lists them per
//! build.

use core::ptr::{addr_of, addr_of_mut, read_volatile, write_volatile};

use henrytwo_protocol::{Phase, RunState};

use crate::critical::CriticalSection;

/// Left encoder count (the INT4 handler's counter). The robust build never
/// resets it; the thesis build resets it where the thesis resets `leftCount`.
#[no_mangle]
pub static mut HT_LEFT_COUNT: i32 = 0;
/// Right encoder count (INT5), like `HT_LEFT_COUNT`.
#[no_mangle]
pub static mut HT_RIGHT_COUNT: i32 = 0;
/// Robust: control ticks (timer 1, 15 ms) since reset. Thesis: PID periods
/// computed (`Tiempo_s >= 15000` branches taken).
#[no_mangle]
pub static mut HT_TICKS: u32 = 0;
/// 0 booting, 1 idle, 2 driving (leg or turn), 3 braking/waiting. See
/// `henrytwo_protocol::RunState`.
#[no_mangle]
pub static mut HT_STATE: u8 = 0;
/// 0 idle, 1 leg, 2 turn, 3 braking/waiting, 4 fault. See
/// `henrytwo_protocol::Phase`.
#[no_mangle]
pub static mut HT_PHASE: u8 = 0;
/// Running or last test (selector code 2..=5), 0 before the first.
#[no_mangle]
pub static mut HT_TEST: u8 = 0;
/// Index of the current segment within the test, legs and turns numbered
/// together from 0 (leg 0, turn 1, leg 2, ...).
#[no_mangle]
pub static mut HT_SEGMENT: u8 = 0;
/// Fault code (robust build; 0 none). See `henrytwo_protocol::Fault`.
#[no_mangle]
pub static mut HT_FAULT: u8 = 0;
/// Tests completed since reset.
#[no_mangle]
pub static mut HT_DONE_COUNT: u16 = 0;
/// Leg length in millimetres. In `.data`.
#[no_mangle]
pub static mut HT_LEG_LENGTH_MM: f32 = crate::robot::DEFAULT_LEG_MM;
/// Both counts at the instant the motors were cut at the end of the last leg.
#[no_mangle]
pub static mut HT_STOP_LEFT: i32 = 0;
/// See `HT_STOP_LEFT`.
#[no_mangle]
pub static mut HT_STOP_RIGHT: i32 = 0;
/// Left count when the current segment started.
#[no_mangle]
pub static mut HT_SEG_START_LEFT: i32 = 0;
/// Right count when the current segment started.
#[no_mangle]
pub static mut HT_SEG_START_RIGHT: i32 = 0;
/// Left count minus `HT_SEG_START_LEFT` at the left cut-off of the current
/// (or last) segment.
#[no_mangle]
pub static mut HT_CUT_LEFT: i32 = 0;
/// Right count minus `HT_SEG_START_RIGHT` at the right cut-off.
#[no_mangle]
pub static mut HT_CUT_RIGHT: i32 = 0;
/// Which cut-offs happened in the current segment: bit 0 left, bit 1 right.
/// Cleared when a segment starts.
#[no_mangle]
pub static mut HT_CUT_MASK: u8 = 0;
/// Cut-off events since reset (a leg's cut of both wheels counts once, each
/// wheel's cut in a turn once).
#[no_mangle]
pub static mut HT_CUT_COUNT: u16 = 0;
/// Last measured left wheel speed, thesis "RPM" (wheel RPM / 6).
#[no_mangle]
pub static mut HT_SPEED_LEFT: f32 = 0.0;
/// Last measured right wheel speed, thesis "RPM" (wheel RPM / 6).
#[no_mangle]
pub static mut HT_SPEED_RIGHT: f32 = 0.0;
/// Last left PID output (duty 0..=255).
#[no_mangle]
pub static mut HT_DUTY_LEFT: u8 = 0;
/// Last right PID output (duty 0..=255).
#[no_mangle]
pub static mut HT_DUTY_RIGHT: u8 = 0;
/// Interval the last speed measurement used, microseconds (robust: 15000
/// per tick; thesis: its measured `Tiempo_s`).
#[no_mangle]
pub static mut HT_PERIOD_US: f32 = 0.0;
/// Last battery reading on A0, ADC counts 0..=1023.
#[no_mangle]
pub static mut HT_BATTERY_ADC: u16 = 0;

/// Thesis build: `Selector_Exp`, the last byte read from Serial1 (0..=255).
#[no_mangle]
pub static mut HT_SELECTOR: i16 = 0;
/// Thesis build: `Flag_Contador`, legs driven since reset (never cleared).
#[no_mangle]
pub static mut HT_FLAG_CONTADOR: i16 = 0;
/// Thesis build: `Flag_Giro_D` (1 while the turn waits for `rightCount`).
#[no_mangle]
pub static mut HT_FLAG_GIRO_D: i16 = 0;
/// Thesis build: `Flag_Giro_I` (1 while the turn waits for `leftCount`).
#[no_mangle]
pub static mut HT_FLAG_GIRO_I: i16 = 0;

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
volatile_rw!(seg_start_left, set_seg_start_left, HT_SEG_START_LEFT, i32);
volatile_rw!(seg_start_right, set_seg_start_right, HT_SEG_START_RIGHT, i32);
volatile_rw!(cut_left, set_cut_left, HT_CUT_LEFT, i32);
volatile_rw!(cut_right, set_cut_right, HT_CUT_RIGHT, i32);
volatile_rw!(cut_mask, set_cut_mask, HT_CUT_MASK, u8);
volatile_rw!(cut_count, set_cut_count, HT_CUT_COUNT, u16);
volatile_rw!(speed_left, set_speed_left, HT_SPEED_LEFT, f32);
volatile_rw!(speed_right, set_speed_right, HT_SPEED_RIGHT, f32);
volatile_rw!(duty_left, set_duty_left, HT_DUTY_LEFT, u8);
volatile_rw!(duty_right, set_duty_right, HT_DUTY_RIGHT, u8);
volatile_rw!(period_us, set_period_us, HT_PERIOD_US, f32);
volatile_rw!(battery_adc, set_battery_adc, HT_BATTERY_ADC, u16);
volatile_rw!(test, set_test, HT_TEST, u8);
volatile_rw!(selector, set_selector, HT_SELECTOR, i16);
volatile_rw!(flag_contador, set_flag_contador, HT_FLAG_CONTADOR, i16);
volatile_rw!(flag_giro_d, set_flag_giro_d, HT_FLAG_GIRO_D, i16);
volatile_rw!(flag_giro_i, set_flag_giro_i, HT_FLAG_GIRO_I, i16);
volatile_rw!(segment, set_segment, HT_SEGMENT, u8);
volatile_rw!(fault, set_fault, HT_FAULT, u8);
volatile_rw!(state_code, set_state_code, HT_STATE, u8);
volatile_rw!(phase_code, set_phase_code, HT_PHASE, u8);
// The thesis build counts its PID periods in `HT_TICKS` from the main loop
// (no handler writes it there); the robust build uses `isr_count_tick`.
volatile_rw!(thesis_periods, set_thesis_periods, HT_TICKS, u32);

/// Writes `HT_STATE`.
#[inline(always)]
pub fn set_state(s: RunState) {
    set_state_code(s as u8);
}

/// Writes `HT_PHASE`.
#[inline(always)]
pub fn set_phase(p: Phase) {
    set_phase_code(p as u8);
}

/// Records one cut-off: the segment-relative counts of the wheels in `mask`
/// (bit 0 left, bit 1 right) from the absolute counts `left`/`right`, the
/// mask bits, and one more cut-off event.
pub fn record_cut(mask: u8, left: i32, right: i32) {
    if mask & 1 != 0 {
        set_cut_left(left.wrapping_sub(seg_start_left()));
    }
    if mask & 2 != 0 {
        set_cut_right(right.wrapping_sub(seg_start_right()));
    }
    set_cut_mask(cut_mask() | mask);
    set_cut_count(cut_count().wrapping_add(1));
}

/// Starts segment `index`: its start counts, and no cut-off yet.
pub fn record_segment_start(index: u8, left: i32, right: i32) {
    set_segment(index);
    set_seg_start_left(left);
    set_seg_start_right(right);
    set_cut_mask(0);
}

/// Reads `HT_TICKS` (written by the timer 1 handler in the robust build,
/// hence the `cs`).
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

/// Sets `HT_LEFT_COUNT` (the thesis' `leftCount = 0`).
#[inline(always)]
pub fn set_left_count(_cs: CriticalSection, v: i32) {
    // SAFETY: interrupts are off, so the INT4 handler cannot interleave.
    unsafe { write_volatile(addr_of_mut!(HT_LEFT_COUNT), v) }
}

/// Sets `HT_RIGHT_COUNT` (the thesis' `rightCount = 0`).
#[inline(always)]
pub fn set_right_count(_cs: CriticalSection, v: i32) {
    // SAFETY: interrupts are off, so the INT5 handler cannot interleave.
    unsafe { write_volatile(addr_of_mut!(HT_RIGHT_COUNT), v) }
}

/// Adds `step` to `HT_LEFT_COUNT` and returns the new value. For the INT4
/// handler only.
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
