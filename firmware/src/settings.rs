//! The robust build's run-time parameters, read and written through the
//! protocol's `SET_PARAM` / `GET_PARAM` (ids, units and ranges:
//! `henrytwo_protocol::Param`), kept in the EEPROM (`robust::persist`). The leg length is the bench variable
//! `HT_LEG_LENGTH_MM` itself, so a bench write and a protocol write are the
//! same thing.

use henrytwo_protocol::{limits, Param};

use crate::bench;
use crate::pid::Gains;
use crate::robot;

/// Per-wheel values, left and right.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct PerWheel<T> {
    /// Left wheel.
    pub left: T,
    /// Right wheel.
    pub right: T,
}

/// Every run-time parameter except the leg length (in `HT_LEG_LENGTH_MM`).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Settings {
    /// Borenstein's distance-per-count correction factors c_L, c_R.
    pub correction: PerWheel<f32>,
    /// Wheelbase b, millimetres.
    pub wheelbase_mm: f32,
    /// UMBmark spin-turn angle, degrees.
    pub turn_umbmark_deg: f32,
    /// Triangle spin-turn angle, degrees.
    pub turn_triangle_deg: f32,
    /// Speed set-points, thesis "RPM" of a wheel of nominal size (a wheel
    /// with correction c runs at set-point / c in counts).
    pub setpoint: PerWheel<f32>,
    /// PID gains.
    pub gains: PerWheel<Gains>,
    /// Stall watchdog time, milliseconds.
    pub stall_timeout_ms: u16,
    /// Stall watchdog duty threshold.
    pub stall_duty: u8,
    /// Distance per count of each wheel before correction, millimetres.
    pub mm_per_count: PerWheel<f32>,
    /// Encoder counts per wheel turn.
    pub counts_per_wheel_rev: f32,
    /// How the motor driver is wired.
    pub driver: DriverWiring,
    /// Stop timing and watchdog thresholds.
    pub stop: StopSettings,
}

/// How a cut wheel is stopped, and the progress watchdog's thresholds
/// (factory: the thesis' constants, Henrytwo's).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct StopSettings {
    /// Coast after the cut before the counter-pulse, milliseconds.
    pub coast_ms: u16,
    /// Counter-pulse, milliseconds.
    pub pulse_ms: u16,
    /// The cut comes the distance earlier that the wheel covers in this
    /// time at its set-point, milliseconds.
    pub lead_ms: u16,
    /// Net progress a driven wheel must make within the stall time, counts.
    pub progress_counts: i16,
    /// Counts against the commanded direction that are a fault.
    pub wrong_way_counts: i16,
}

/// The motor driver's kind and pins (`henrytwo_protocol::DriverKind`),
/// Arduino Mega pin numbers, `henrytwo_protocol::NO_PIN` for none.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct DriverWiring {
    /// `DriverKind` wire value.
    pub kind: u8,
    /// Left motor's pins 1-3.
    pub left: [u8; 3],
    /// Right motor's pins 1-3.
    pub right: [u8; 3],
}

impl Settings {
    /// The thesis robot's values.
    pub const DEFAULT: Settings = Settings {
        correction: PerWheel { left: robot::DEFAULT_CORRECTION, right: robot::DEFAULT_CORRECTION },
        wheelbase_mm: robot::DEFAULT_WHEELBASE_MM,
        turn_umbmark_deg: robot::DEFAULT_TURN_UMBMARK_DEG,
        turn_triangle_deg: robot::DEFAULT_TURN_TRIANGLE_DEG,
        setpoint: PerWheel { left: robot::ROBUST_SETPOINT, right: robot::ROBUST_SETPOINT },
        gains: PerWheel { left: robot::GAINS_LEFT, right: robot::GAINS_RIGHT },
        stall_timeout_ms: robot::DEFAULT_STALL_TIMEOUT_MS,
        stall_duty: robot::DEFAULT_STALL_DUTY,
        mm_per_count: PerWheel { left: robot::MM_PER_COUNT, right: robot::MM_PER_COUNT },
        counts_per_wheel_rev: robot::COUNTS_PER_WHEEL_REV,
        driver: DriverWiring {
            kind: Param::DriverKind.factory_default() as u8,
            left: [
                Param::LeftPin1.factory_default() as u8,
                Param::LeftPin2.factory_default() as u8,
                Param::LeftPin3.factory_default() as u8,
            ],
            right: [
                Param::RightPin1.factory_default() as u8,
                Param::RightPin2.factory_default() as u8,
                Param::RightPin3.factory_default() as u8,
            ],
        },
        stop: StopSettings {
            coast_ms: Param::BrakeCoastMs.factory_default() as u16,
            pulse_ms: Param::BrakePulseMs.factory_default() as u16,
            lead_ms: Param::StopLeadMs.factory_default() as u16,
            progress_counts: Param::StallProgressCounts.factory_default() as i16,
            wrong_way_counts: Param::WrongWayCounts.factory_default() as i16,
        },
    };

    /// The value of `p` (the leg length from `HT_LEG_LENGTH_MM`).
    pub fn get(&self, p: Param) -> f32 {
        match p {
            Param::CorrLeft => self.correction.left,
            Param::CorrRight => self.correction.right,
            Param::WheelbaseMm => self.wheelbase_mm,
            Param::LegLengthMm => bench::leg_length_mm(),
            Param::TurnUmbmarkDeg => self.turn_umbmark_deg,
            Param::TurnTriangleDeg => self.turn_triangle_deg,
            Param::SetpointLeft => self.setpoint.left,
            Param::SetpointRight => self.setpoint.right,
            Param::KpLeft => self.gains.left.kp,
            Param::KiLeft => self.gains.left.ki,
            Param::KdLeft => self.gains.left.kd,
            Param::KpRight => self.gains.right.kp,
            Param::KiRight => self.gains.right.ki,
            Param::KdRight => self.gains.right.kd,
            Param::StallTimeoutMs => self.stall_timeout_ms as f32,
            Param::StallDuty => self.stall_duty as f32,
            Param::MmPerCountLeft => self.mm_per_count.left,
            Param::MmPerCountRight => self.mm_per_count.right,
            Param::CountsPerWheelRev => self.counts_per_wheel_rev,
            Param::DriverKind => self.driver.kind as f32,
            Param::LeftPin1 => self.driver.left[0] as f32,
            Param::LeftPin2 => self.driver.left[1] as f32,
            Param::LeftPin3 => self.driver.left[2] as f32,
            Param::RightPin1 => self.driver.right[0] as f32,
            Param::RightPin2 => self.driver.right[1] as f32,
            Param::RightPin3 => self.driver.right[2] as f32,
            Param::BrakeCoastMs => self.stop.coast_ms as f32,
            Param::BrakePulseMs => self.stop.pulse_ms as f32,
            Param::StopLeadMs => self.stop.lead_ms as f32,
            Param::StallProgressCounts => self.stop.progress_counts as f32,
            Param::WrongWayCounts => self.stop.wrong_way_counts as f32,
        }
    }

    /// Sets `p` to `v`, which the caller has checked with `p.check(v)` (the
    /// protocol decoder does); the whole-number ones are converted exactly.
    pub fn set(&mut self, p: Param, v: f32) {
        match p {
            Param::CorrLeft => self.correction.left = v,
            Param::CorrRight => self.correction.right = v,
            Param::WheelbaseMm => self.wheelbase_mm = v,
            Param::LegLengthMm => bench::set_leg_length_mm(v),
            Param::TurnUmbmarkDeg => self.turn_umbmark_deg = v,
            Param::TurnTriangleDeg => self.turn_triangle_deg = v,
            Param::SetpointLeft => self.setpoint.left = v,
            Param::SetpointRight => self.setpoint.right = v,
            Param::KpLeft => self.gains.left.kp = v,
            Param::KiLeft => self.gains.left.ki = v,
            Param::KdLeft => self.gains.left.kd = v,
            Param::KpRight => self.gains.right.kp = v,
            Param::KiRight => self.gains.right.ki = v,
            Param::KdRight => self.gains.right.kd = v,
            Param::StallTimeoutMs => self.stall_timeout_ms = v as u16,
            Param::StallDuty => self.stall_duty = v as u8,
            Param::MmPerCountLeft => self.mm_per_count.left = v,
            Param::MmPerCountRight => self.mm_per_count.right = v,
            Param::CountsPerWheelRev => self.counts_per_wheel_rev = v,
            Param::DriverKind => self.driver.kind = v as u8,
            Param::LeftPin1 => self.driver.left[0] = v as u8,
            Param::LeftPin2 => self.driver.left[1] = v as u8,
            Param::LeftPin3 => self.driver.left[2] = v as u8,
            Param::RightPin1 => self.driver.right[0] = v as u8,
            Param::RightPin2 => self.driver.right[1] = v as u8,
            Param::RightPin3 => self.driver.right[2] = v as u8,
            Param::BrakeCoastMs => self.stop.coast_ms = v as u16,
            Param::BrakePulseMs => self.stop.pulse_ms = v as u16,
            Param::StopLeadMs => self.stop.lead_ms = v as u16,
            Param::StallProgressCounts => self.stop.progress_counts = v as i16,
            Param::WrongWayCounts => self.stop.wrong_way_counts = v as i16,
        }
    }
}

// Every default is inside the range the protocol accepts.
const _: () = {
    let d = Settings::DEFAULT;
    assert!(Param::CorrLeft.check(d.correction.left).is_ok());
    assert!(Param::CorrRight.check(d.correction.right).is_ok());
    assert!(Param::WheelbaseMm.check(d.wheelbase_mm).is_ok());
    assert!(Param::LegLengthMm.check(robot::DEFAULT_LEG_MM).is_ok());
    assert!(Param::TurnUmbmarkDeg.check(d.turn_umbmark_deg).is_ok());
    assert!(Param::TurnTriangleDeg.check(d.turn_triangle_deg).is_ok());
    assert!(Param::SetpointLeft.check(d.setpoint.left).is_ok());
    assert!(Param::SetpointRight.check(d.setpoint.right).is_ok());
    assert!(Param::KpLeft.check(d.gains.left.kp).is_ok());
    assert!(Param::KiLeft.check(d.gains.left.ki).is_ok());
    assert!(Param::KdLeft.check(d.gains.left.kd).is_ok());
    assert!(Param::KpRight.check(d.gains.right.kp).is_ok());
    assert!(Param::KiRight.check(d.gains.right.ki).is_ok());
    assert!(Param::KdRight.check(d.gains.right.kd).is_ok());
    assert!(Param::StallTimeoutMs.check(d.stall_timeout_ms as f32).is_ok());
    assert!(Param::StallDuty.check(d.stall_duty as f32).is_ok());
    assert!(Param::MmPerCountLeft.check(d.mm_per_count.left).is_ok());
    assert!(Param::MmPerCountRight.check(d.mm_per_count.right).is_ok());
    assert!(Param::CountsPerWheelRev.check(d.counts_per_wheel_rev).is_ok());
    assert!(Param::BrakeCoastMs.check(d.stop.coast_ms as f32).is_ok());
    assert!(Param::BrakePulseMs.check(d.stop.pulse_ms as f32).is_ok());
    assert!(Param::StopLeadMs.check(d.stop.lead_ms as f32).is_ok());
    assert!(Param::StallProgressCounts.check(d.stop.progress_counts as f32).is_ok());
    assert!(Param::WrongWayCounts.check(d.stop.wrong_way_counts as f32).is_ok());
};

// `set` stores the whole-number parameters in integer fields: every value the
// protocol's limits accept must fit its field, or an accepted value would wrap.
const _: () = {
    assert!(limits::STALL_TIMEOUT_MS.min >= 0.0 && limits::STALL_TIMEOUT_MS.max <= u16::MAX as f32);
    assert!(limits::STALL_DUTY.min >= 0.0 && limits::STALL_DUTY.max <= u8::MAX as f32);
    assert!(limits::DRIVER_KIND.min >= 0.0 && limits::DRIVER_KIND.max <= u8::MAX as f32);
    assert!(limits::DRIVER_PIN.min >= 0.0 && limits::DRIVER_PIN.max <= u8::MAX as f32);
    assert!(limits::BRAKE_COAST_MS.min >= 0.0 && limits::BRAKE_COAST_MS.max <= u16::MAX as f32);
    assert!(limits::BRAKE_PULSE_MS.min >= 0.0 && limits::BRAKE_PULSE_MS.max <= u16::MAX as f32);
    assert!(limits::STOP_LEAD_MS.min >= 0.0 && limits::STOP_LEAD_MS.max <= u16::MAX as f32);
    assert!(limits::STALL_PROGRESS_COUNTS.min >= 0.0 && limits::STALL_PROGRESS_COUNTS.max <= i16::MAX as f32);
    assert!(limits::WRONG_WAY_COUNTS.min >= 0.0 && limits::WRONG_WAY_COUNTS.max <= i16::MAX as f32);
};
