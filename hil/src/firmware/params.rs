//! What the firmware is told about the robot, and what it then believes.
//!
//! The robust firmware knows its robot only through run-time parameters
//! (`protocol/README.md`, "Parameters"): distance per count, counts per
//! wheel turn, wheelbase, set-points. Its factory values are Henrytwo's. So
//! before a run the bench tells it the robot config's nominal geometry (the
//! wheel size as a builder states it: one diameter, the mean of the two the
//! config gives; the wheelbase as written; the encoder's counts per wheel
//! turn), sending only what differs from the factory values. A build that
//! cannot be told (the thesis' sketch, with its odometry compiled in) or a
//! run told to keep the firmware's values is warned about when its geometry
//! is not the robot's.
//!
//! Every report that turns counts into distances or speeds uses
//! [`Believed`], the firmware's values in force during the run, never a
//! constant.

use henrytwo_protocol::Param;
use plant_model::RobotConfig;

use crate::board::Board;
use crate::firmware::elf::Firmware;

/// Whether the bench tells the firmware the robot's geometry before a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub enum Tell {
    /// Send the robot config's nominal geometry (what differs from the
    /// firmware's factory values).
    #[default]
    Robot,
    /// Send nothing: the firmware keeps what it has (its factory values on
    /// the bench, whose EEPROM starts erased).
    Keep,
}

/// The firmware's values that turn counts into distances and speeds.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Believed {
    /// Distance per count before correction, mm (left, right).
    pub mm_per_count: [f64; 2],
    /// Borenstein's correction factors c_L, c_R.
    pub correction: [f64; 2],
    pub counts_per_wheel_rev: f64,
    pub wheelbase_mm: f64,
    /// Speed set-points, thesis "RPM" (wheel RPM / 6) (left, right).
    pub setpoint_rpm: [f64; 2],
}

fn f(p: Param) -> f64 {
    p.factory_default() as f64
}

impl Believed {
    /// The robust firmware's factory values (Henrytwo's), which the thesis
    /// build has compiled in.
    pub fn factory() -> Self {
        Believed {
            mm_per_count: [f(Param::MmPerCountLeft), f(Param::MmPerCountRight)],
            correction: [f(Param::CorrLeft), f(Param::CorrRight)],
            counts_per_wheel_rev: f(Param::CountsPerWheelRev),
            wheelbase_mm: f(Param::WheelbaseMm),
            setpoint_rpm: [f(Param::SetpointLeft), f(Param::SetpointRight)],
        }
    }

    /// The factory values with `params` set in order, as the firmware
    /// applies its SET_PARAMs (a later value of the same parameter wins).
    pub fn after(mut self, params: &[(Param, f32)]) -> Self {
        for &(p, v) in params {
            let v = v as f64;
            match p {
                Param::MmPerCountLeft => self.mm_per_count[0] = v,
                Param::MmPerCountRight => self.mm_per_count[1] = v,
                Param::CorrLeft => self.correction[0] = v,
                Param::CorrRight => self.correction[1] = v,
                Param::CountsPerWheelRev => self.counts_per_wheel_rev = v,
                Param::WheelbaseMm => self.wheelbase_mm = v,
                Param::SetpointLeft => self.setpoint_rpm[0] = v,
                Param::SetpointRight => self.setpoint_rpm[1] = v,
                _ => {}
            }
        }
        self
    }

    /// Corrected distance per count of wheel `i` (0 left, 1 right), mm.
    pub fn mm_per_corrected_count(&self, i: usize) -> f64 {
        self.mm_per_count[i] * self.correction[i]
    }

    /// The firmware's odometry of a straight leg: the mean corrected
    /// distance of the two wheels' counts, mm.
    pub fn distance_mm(&self, left: i64, right: i64) -> f64 {
        (left as f64 * self.mm_per_corrected_count(0)
            + right as f64 * self.mm_per_corrected_count(1))
            / 2.0
    }

    /// Counts per second wheel `i` makes at its set-point (thesis RPM is
    /// wheel RPM / 6, so 10 counts per wheel turn per second per RPM). A
    /// wheel with correction c is held at set-point / c in counts.
    pub fn setpoint_counts_per_s(&self, i: usize) -> f64 {
        self.setpoint_rpm[i] * 6.0 / 60.0 * self.counts_per_wheel_rev / self.correction[i]
    }
}

/// The robot config's nominal geometry as the firmware's parameters.
pub fn nominal(robot: &RobotConfig) -> [(Param, f32); 4] {
    let g = &robot.geometry;
    let counts = robot.encoder.gear_ratio * robot.encoder.a_edges_per_motor_rev as f64;
    let wheel = (g.wheel_diameter_left_mm + g.wheel_diameter_right_mm) / 2.0;
    let mm = (std::f64::consts::PI * wheel / counts) as f32;
    [
        (Param::MmPerCountLeft, mm),
        (Param::MmPerCountRight, mm),
        (Param::CountsPerWheelRev, counts as f32),
        (Param::WheelbaseMm, g.wheelbase_mm as f32),
    ]
}

/// The robot's nominal geometry (as [`nominal`] tells it) where it lies outside what the
/// robust firmware accepts (`henrytwo_protocol::limits`, the one table of the firmware's
/// ranges): one "name = value (it takes RANGE)" per parameter, none when it all fits. A
/// robot the firmware would refuse is refused before a run, not warned about after one.
pub fn beyond_firmware_limits(robot: &RobotConfig) -> Vec<String> {
    nominal(robot)
        .into_iter()
        .filter(|&(p, v)| p.check(v).is_err())
        .map(|(p, v)| format!("{} = {v} (it takes {})", p.name(), p.range()))
        .collect()
}

/// What of [`nominal`] and of the board's driver wiring the firmware does
/// not hold already (its factory values), geometry first: Henrytwo on its
/// own board needs nothing.
pub fn to_send(robot: &RobotConfig, board: &Board) -> Vec<(Param, f32)> {
    nominal(robot)
        .into_iter()
        .chain(board.firmware_params())
        .filter(|&(p, v)| v != p.factory_default())
        .collect()
}

/// Whether the firmware takes parameters over the framed protocol. The
/// thesis' sketch (its selector variable `HT_SELECTOR` marks it) takes only
/// its single selector bytes.
pub fn takes_params(firmware: &Firmware) -> bool {
    firmware.symbol("HT_SELECTOR").is_err()
}

/// The parameters to send before a run of `firmware` on `robot` wired by
/// `board` (the nominal geometry and the driver wiring, the robot config's
/// `[firmware]` settings, derived gains when the config gives none and the
/// factory gains would chatter ([`crate::firmware::tune::automatic`]), then
/// `extra` in its order: a later value wins), what the firmware then
/// believes, and a warning when its geometry is not the robot's.
pub fn plan(
    firmware: &Firmware,
    robot: &RobotConfig,
    board: &Board,
    tell: Tell,
    extra: &[(Param, f32)],
) -> (Vec<(Param, f32)>, Believed, Option<String>) {
    let mut send = Vec::new();
    let mut refused = None;
    if tell == Tell::Robot && takes_params(firmware) {
        send = to_send(robot, board);
        // The robot config's [firmware] settings, checked when it was
        // loaded; a config built in code that was not is named, not sent.
        match crate::firmware::settings::of(robot) {
            Ok(settings) => send.extend(
                settings
                    .into_iter()
                    .filter(|&(p, v)| v != p.factory_default()),
            ),
            Err(e) => refused = Some(format!("the robot config's {e}: none of it was sent")),
        }
        // A robot whose config gives no gains and on which the factory
        // gains are predicted to chatter gets derived ones (Henrytwo never),
        // unless the run is given gains of its own (--param).
        let given = extra
            .iter()
            .any(|(p, _)| crate::firmware::tune::GAINS.contains(p));
        if let Some((gains, note)) = crate::firmware::tune::automatic(robot).filter(|_| !given) {
            crate::firmware::tune::note_once(&note);
            send.extend(gains);
        }
        // Likewise the stop timing and thresholds, each unless given.
        if let Some((stop, note)) = crate::firmware::stop::automatic(robot) {
            let stop: Vec<_> = stop
                .into_iter()
                .filter(|(p, _)| !extra.iter().any(|(q, _)| q == p))
                .collect();
            if !stop.is_empty() {
                if let Some(note) = note {
                    crate::firmware::tune::note_once(&note);
                }
                send.extend(stop);
            }
        }
    }
    if takes_params(firmware) {
        send.extend_from_slice(extra);
    }
    let believed = Believed::factory().after(&send);
    let warning = mismatch(
        &believed,
        &Believed::factory().after(&nominal(robot)),
        firmware,
    );
    let warning = match (warning, refused) {
        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
        (a, b) => a.or(b),
    };
    (send, believed, warning)
}

/// A warning when the firmware refused any of the `sent` parameters (its
/// SET_PARAM replies in `bluetooth_out` carry an error status): then it
/// does not believe what the bench told it.
pub fn refusals(bluetooth_out: &[u8], sent: usize) -> Option<String> {
    let set_param = crate::firmware::link::Command::SetParam(Param::CorrLeft, 1.0)
        .id()
        .reply_id();
    let refused: Vec<String> = crate::firmware::link::replies(bluetooth_out)
        .into_iter()
        .filter(|r| r.id == set_param && !r.ok)
        .map(|r| r.status)
        .collect();
    (!refused.is_empty()).then(|| {
        format!(
            "the firmware refused {} of the {sent} parameters sent ({}): what it drove is not \
             what the bench told it",
            refused.len(),
            refused.join(", ")
        )
    })
}

/// A warning naming each value where the firmware's geometry differs from
/// the robot's by more than f32 rounding.
fn mismatch(firmware: &Believed, robot: &Believed, fw: &Firmware) -> Option<String> {
    let differs = |a: f64, b: f64| (a - b).abs() > 1e-6 * b.abs();
    let mut parts = Vec::new();
    for (i, side) in ["left", "right"].iter().enumerate() {
        if differs(firmware.mm_per_count[i], robot.mm_per_count[i]) {
            parts.push(format!(
                "{side} {:.6} mm per count (the robot's {:.6})",
                firmware.mm_per_count[i], robot.mm_per_count[i]
            ));
        }
    }
    if differs(firmware.counts_per_wheel_rev, robot.counts_per_wheel_rev) {
        parts.push(format!(
            "{:.2} counts per wheel turn (the robot's {:.2})",
            firmware.counts_per_wheel_rev, robot.counts_per_wheel_rev
        ));
    }
    if differs(firmware.wheelbase_mm, robot.wheelbase_mm) {
        parts.push(format!(
            "wheelbase {:.2} mm (the robot's {:.2})",
            firmware.wheelbase_mm, robot.wheelbase_mm
        ));
    }
    if parts.is_empty() {
        return None;
    }
    let why = if takes_params(fw) {
        "it was told to keep its own values"
    } else {
        "it cannot be told (no framed protocol): its geometry is compiled in"
    };
    Some(format!(
        "the firmware {} uses {}; {why}, so its legs and turns are not the robot's",
        fw.name(),
        parts.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Henrytwo's config is what the firmware's factory values describe:
    /// nothing to send, to the last f32 bit.
    #[test]
    fn henrytwo_needs_nothing() {
        assert_eq!(to_send(&RobotConfig::default(), &Board::default()), vec![]);
        let robot = Believed::factory().after(&nominal(&RobotConfig::default()));
        assert_eq!(robot, Believed::factory());
    }

    #[test]
    fn another_robot_gets_its_geometry() {
        let mut r = RobotConfig::default();
        r.geometry.wheel_diameter_left_mm = 64.0;
        r.geometry.wheel_diameter_right_mm = 66.0;
        r.geometry.wheelbase_mm = 180.0;
        r.encoder.gear_ratio = 30.0;
        r.encoder.a_edges_per_motor_rev = 12;
        let sent = to_send(&r, &Board::default());
        let mm = (std::f64::consts::PI * 65.0 / 360.0) as f32;
        assert_eq!(
            sent,
            vec![
                (Param::MmPerCountLeft, mm),
                (Param::MmPerCountRight, mm),
                (Param::CountsPerWheelRev, 360.0),
                (Param::WheelbaseMm, 180.0),
            ]
        );
        let b = Believed::factory().after(&sent);
        // 3527 counts of 0.567232 mm (pi * 65 / 360) on each wheel: 2000.63 mm.
        assert!((b.distance_mm(3527, 3527) - 2000.63).abs() < 0.01);
        assert!((b.distance_mm(3526, 3528) - 2000.63).abs() < 0.01);
        // 14.47 thesis RPM = 86.82 wheel RPM = 520.9 counts/s at 360 per turn.
        assert!((b.setpoint_counts_per_s(0) - 520.92).abs() < 0.01);
    }

    #[test]
    fn a_later_value_wins_and_corrections_scale_distance() {
        let b = Believed::factory().after(&[
            (Param::CorrLeft, 1.1),
            (Param::WheelbaseMm, 120.0),
            (Param::WheelbaseMm, 125.0),
        ]);
        assert_eq!(b.wheelbase_mm, 125.0);
        let f = Believed::factory();
        assert!((b.mm_per_corrected_count(0) - 1.1 * f.mm_per_count[0]).abs() < 1e-7);
        assert_eq!(b.mm_per_corrected_count(1), f.mm_per_count[1]);
    }
}
