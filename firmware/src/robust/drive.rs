//! The drive: both H-bridges, both encoders, and each wheel's run through
//! the current segment (its stage, its PID, its watchdog window).

use crate::io::{Bridges, Side};
use crate::pid::{rpm_table, thesis_rpm, TablePid};
use crate::robot;

/// Counts per control period the lookup tables cover (the wheels' PIDs and
/// [`Speeds::of_counts`]): Henrytwo at the set-point makes about 13; its
/// motors' top speed is below 30. A robot whose encoders make more per
/// period takes the multiplying path for those (correct, slower).
pub const TABLE_COUNTS: usize = 64;

/// Thesis RPM of one count in one control period on Henrytwo (1.107),
/// evaluated at compile time.
pub const THESIS_RPM_PER_COUNT: f32 = thesis_rpm(1, robot::SAMPLE_PERIOD_S);
/// Henrytwo's thesis RPM of 0..TABLE_COUNTS counts in one control period,
/// evaluated at compile time: [`Speeds`] scales it, so Henrytwo's speeds are
/// the thesis formula's bit for bit (the MCU's own float division and
/// product need not round as the compiler's exact ones do).
static THESIS_RPM_OF_COUNTS: [f32; TABLE_COUNTS] = rpm_table(robot::SAMPLE_PERIOD_S);

/// The conversion from counts per control period to thesis "RPM" for the
/// robot's counts per wheel turn, computed when that changes (never in the
/// control tick): Henrytwo's scaled by `602.22 / counts_per_wheel_rev` (the
/// thesis' factor 0.0016605 is its 1 / 602.22), which is 1 exactly for
/// Henrytwo.
pub struct Speeds {
    /// Counts per wheel turn it was computed for.
    pub(crate) counts_per_wheel_rev: f32,
    /// Thesis RPM of one count in one period.
    pub(crate) per_count: f32,
    /// Thesis RPM of 0..TABLE_COUNTS counts in one period.
    pub(crate) of_counts: [f32; TABLE_COUNTS],
}

impl Speeds {
    /// Not computed yet (all zero; [`Speeds::set`] before a segment).
    pub const fn new() -> Self {
        Speeds { counts_per_wheel_rev: 0.0, per_count: 0.0, of_counts: [0.0; TABLE_COUNTS] }
    }

    /// The conversion for `counts_per_wheel_rev` counts per wheel turn.
    pub fn set(&mut self, counts_per_wheel_rev: f32) {
        self.counts_per_wheel_rev = counts_per_wheel_rev;
        let scale = robot::COUNTS_PER_WHEEL_REV / counts_per_wheel_rev;
        self.per_count = THESIS_RPM_PER_COUNT * scale;
        for (t, &r) in self.of_counts.iter_mut().zip(THESIS_RPM_OF_COUNTS.iter()) {
            *t = r * scale;
        }
    }
}

impl Default for Speeds {
    fn default() -> Self {
        Self::new()
    }
}

/// Where a wheel is within its segment.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Stage {
    /// Under PID control on its drive input.
    Driving,
    /// Cut (drive input 0), waiting for the counter-pulse.
    Coast,
    /// Counter-pulse: the opposite input at 255.
    Pulse,
    /// Both inputs 0.
    Done,
}

/// One wheel's state.
pub struct Wheel {
    /// The wheel's drive input is its forward one.
    pub(crate) forward: bool,
    pub(crate) stage: Stage,
    /// Deadline of the `Coast` or `Pulse` stage.
    pub(crate) until: u32,
    pub(crate) pid: TablePid<TABLE_COUNTS>,
    /// Count at the last control period.
    pub(crate) last_count: i32,
    /// Count at the segment start.
    pub(crate) start_count: i32,
    /// Duty applied during the current control period.
    pub(crate) applied: u8,
    /// Stall watchdog: count at the start of the current window (the last
    /// period not judged, or the last net progress of
    /// [`super::progress::STALL_PROGRESS_COUNTS`]), low 16 bits: within a
    /// window the count stays far closer to it than 2^15 (forward it
    /// restarts the window, backward the wrong-way check stops the wheel) ...
    pub(crate) mark: i16,
    /// ... periods judged since then (driven at or above the stall duty) ...
    pub(crate) still: u16,
    /// ... and counts moved since then, each period's change either way
    /// (valid while `still` > 0).
    pub(crate) travel: u16,
    /// Periods left before the watchdog judges this wheel.
    pub(crate) grace: u8,
}

impl Wheel {
    /// A wheel at rest, not in a segment.
    pub const fn new() -> Self {
        Wheel {
            forward: true,
            stage: Stage::Done,
            until: 0,
            pid: TablePid::new(robot::GAINS_LEFT, robot::ROBUST_SETPOINT, robot::SAMPLE_PERIOD_S),
            last_count: 0,
            start_count: 0,
            applied: 0,
            mark: 0,
            still: 0,
            travel: 0,
            grace: 0,
        }
    }
}

impl Default for Wheel {
    fn default() -> Self {
        Self::new()
    }
}

/// Motors, encoders and both wheels: everything the control tick touches.
pub struct Drive<M, E> {
    /// The H-bridges.
    pub motors: M,
    /// The encoders.
    pub encoders: E,
    pub(crate) left: Wheel,
    pub(crate) right: Wheel,
    /// Counts per period to speed, for the robot's encoders.
    pub(crate) speeds: Speeds,
}

impl<M: Bridges, E> Drive<M, E> {
    /// The drive at rest: both wheels out of any segment.
    #[inline(always)]
    pub const fn new(motors: M, encoders: E) -> Self {
        Drive { motors, encoders, left: Wheel::new(), right: Wheel::new(), speeds: Speeds::new() }
    }

    /// Sets one bridge input: the wheel's forward (`forward_input`) or
    /// reverse input.
    pub(crate) fn set(&mut self, side: Side, forward_input: bool, duty: u8) {
        match (side, forward_input) {
            (Side::Left, true) => self.motors.set_forward(Side::Left, duty),
            (Side::Left, false) => self.motors.set_reverse(Side::Left, duty),
            (Side::Right, true) => self.motors.set_forward(Side::Right, duty),
            (Side::Right, false) => self.motors.set_reverse(Side::Right, duty),
        }
    }

    pub(crate) fn wheel(&mut self, side: Side) -> &mut Wheel {
        match side {
            Side::Left => &mut self.left,
            Side::Right => &mut self.right,
        }
    }

    /// One wheel, and the speed conversion its PID's tables are made from.
    pub(crate) fn wheel_and_speeds(&mut self, side: Side) -> (&mut Wheel, &Speeds) {
        match side {
            Side::Left => (&mut self.left, &self.speeds),
            Side::Right => (&mut self.right, &self.speeds),
        }
    }
}
