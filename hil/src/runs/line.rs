//! The straight-line test: command byte 4 on the Bluetooth UART, the robot
//! drives until its own odometry says `length_mm`, brakes and stops.

use plant_model::{Pose, RobotConfig, Side, World};

use crate::bench::{Bench, BenchError, BenchOptions, Cutoff, PinStats, Sample};
use crate::firmware::elf::Firmware;
use crate::firmware::params::{Believed, Tell};

/// The command byte of the straight-line test.
pub const CMD_LINE: u8 = 4;

#[derive(Debug, Clone)]
pub struct LineOptions {
    pub length_mm: f64,
    pub bench: BenchOptions,
    /// Whether the robot config's geometry is sent before the start.
    pub tell: Tell,
    /// Parameters to set after the robot's geometry (theirs win).
    pub params: Vec<(crate::firmware::link::Param, f32)>,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct WheelSummary {
    /// Net A-channel edges the plant produced (signed, forward positive).
    pub plant_edges: i64,
    /// A edges raised on the MCU pin, signed as the firmware's decoder counts.
    pub raised_edges: i64,
    /// The firmware's counter, read from SRAM at the end.
    pub firmware_count: i32,
    /// The firmware's counter when it cut the motors (HT_STOP_*).
    pub stop_count: i32,
    /// Wheel arc travelled, by the plant.
    pub distance_mm: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Wheels {
    pub left: WheelSummary,
    pub right: WheelSummary,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct PwmPin {
    pub pin: String,
    pub hz: f64,
    pub mean_active_duty: f64,
    pub active_s: f64,
}

/// Host-side measurements: not part of the simulation's result.
#[derive(Debug, Clone, serde::Serialize)]
pub struct HostTiming {
    pub wall_s: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct LineSummary {
    pub test: &'static str,
    pub firmware: String,
    pub length_mm: f64,
    pub completed: bool,
    /// Robot time from reset to the end of the test (braking and waits included).
    pub robot_time_s: f64,
    /// Robot time from the command byte to the motors' cut-off.
    pub drive_time_s: f64,
    /// Real-time factor (robot time / wall time); null when not measured.
    pub rtf: Option<f64>,
    pub pwm_hz: f64,
    /// Mean of the two wheels' corrected distances at cut-off by the
    /// firmware's own distance per count (see [`LineSummary::believed`]).
    pub distance_firmware_mm: f64,
    /// Mean of the two wheels' arcs at cut-off, by the plant.
    pub distance_plant_mm: f64,
    /// Mean wheel arc at the end, after braking and coasting.
    pub distance_plant_final_mm: f64,
    /// Where the robot ended, by the plant.
    #[serde(serialize_with = "pose_mm")]
    pub pose: Pose<World>,
    pub wheels: Wheels,
    pub pwm: Vec<PwmPin>,
    pub cycles: u64,
    pub awake_fraction: f64,
    pub cutoff_cycle: Option<u64>,
    pub firmware_log: String,
    /// What the firmware believed about the robot.
    #[serde(skip)]
    pub believed: Believed,
    /// E.g. a firmware whose geometry is not the robot's.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// A pose as the line's JSON has always written it: `x_mm`, `y_mm`,
/// `theta_rad` (the plant's pose has no serde of its own).
fn pose_mm<S: serde::Serializer>(pose: &Pose<World>, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = s.serialize_struct("Pose", 3)?;
    st.serialize_field("x_mm", &pose.x().0)?;
    st.serialize_field("y_mm", &pose.y().0)?;
    st.serialize_field("theta_rad", &pose.theta().0)?;
    st.end()
}

/// Everything a line run produced.
#[derive(Debug, Clone)]
pub struct LineRun {
    pub summary: LineSummary,
    pub trace: Vec<Sample>,
    pub cutoffs: Vec<Cutoff>,
    pub pins: Vec<PinStats>,
    /// Cycle at which the command byte was sent.
    pub start_cycle: u64,
}

/// A bench with the firmware booted and the leg length set, ready for a
/// command: (bench, HT_DONE_COUNT before the test, the cycle it was ready).
pub fn ready_bench(
    firmware: Firmware,
    robot: &RobotConfig,
    options: BenchOptions,
    leg_mm: f64,
) -> Result<(Bench, u16, u64), BenchError> {
    let mut bench = Bench::new(firmware, robot, options)?;
    let (done_before, start_cycle) = make_ready(&mut bench, leg_mm)?;
    Ok((bench, done_before, start_cycle))
}

/// [`ready_bench`] on a bench already made (one a debugger drives from
/// reset): ready, the leg length set; (HT_DONE_COUNT, the cycle) then.
pub fn make_ready(bench: &mut Bench, leg_mm: f64) -> Result<(u16, u64), BenchError> {
    crate::runs::start::wait_ready(bench, None)?;
    let vars = *bench.vars()?;
    bench.write_f32(vars.leg_length_mm, leg_mm as f32);
    Ok((bench.read_u16(vars.done_count), bench.cycle()))
}

pub fn run_line(
    firmware: Firmware,
    robot: &RobotConfig,
    opts: &LineOptions,
) -> Result<LineRun, BenchError> {
    let name = firmware.name();
    let (mut bench, done_before, start_cycle) =
        ready_bench(firmware, robot, opts.bench, opts.length_mm)?;
    let vars = *bench.vars()?;
    let (params, believed, warning) = crate::firmware::params::plan(
        bench.firmware(),
        robot,
        bench.board(),
        opts.tell,
        &opts.params,
    );
    crate::runs::start::start_test(
        &mut bench,
        &params,
        false,
        crate::firmware::link::ProtoTest::Line,
    );
    // Generous: a third of the nominal speed, plus braking and waits.
    let limit = opts.length_mm / 50.0 + 5.0;
    let completed = bench.run_until(limit, |b| {
        b.read_u16(vars.done_count) != done_before && b.is_idle()
    })?;
    if !completed {
        return Err(BenchError::Timeout {
            what: format!(
                "the straight line of {} mm did not complete (HT_DONE_COUNT unchanged, state {:?})",
                opts.length_mm,
                bench.run_state()
            ),
            robot_s: limit,
            at: bench.location(),
        });
    }
    // Let the firmware's end-of-test line drain from the UART (about 1 ms per
    // byte at 9600 baud).
    bench.run_for(0.1)?;
    let core = bench.core();
    // The first cut-off that lasted (a stale level is none).
    let stale = core.stale_level_cycles();
    let cutoff = core
        .cutoffs()
        .iter()
        .find(|c| c.at.cycle > start_cycle && c.lasted(stale))
        .map(|c| c.at);
    let clock = bench.clock();
    let stop_left = bench.read_i32(vars.stop_left);
    let stop_right = bench.read_i32(vars.stop_right);
    let robot = core.robot();
    let pose = robot.pose();
    let wheel = |side: Side, idx: usize, count_addr: u16, stop: i32| WheelSummary {
        plant_edges: robot.counted_edges(side),
        raised_edges: core.edges_raised()[idx],
        firmware_count: bench.read_i32(count_addr),
        stop_count: stop,
        distance_mm: robot.distance_travelled(side).0,
    };
    let wheels = Wheels {
        left: wheel(Side::Left, 0, vars.left_count, stop_left),
        right: wheel(Side::Right, 1, vars.right_count, stop_right),
    };
    // Plant distance at cut-off from the edges the plant had produced then:
    // the trace is coarse, the cut-off snapshot is exact.
    let distance_plant_mm = cutoff
        .map(|c| (c.left_mm + c.right_mm) / 2.0)
        .unwrap_or(f64::NAN);
    let pins = core.pin_stats();
    let pwm_hz = pins.iter().map(|p| p.hz).fold(0.0, f64::max);
    let summary = LineSummary {
        test: "line",
        firmware: name,
        length_mm: opts.length_mm,
        completed,
        robot_time_s: bench.robot_time_s(),
        drive_time_s: cutoff
            .map(|c| clock.seconds(c.cycle - start_cycle).0)
            .unwrap_or(f64::NAN),
        rtf: None,
        pwm_hz,
        distance_firmware_mm: believed.distance_mm(stop_left as i64, stop_right as i64),
        distance_plant_mm,
        distance_plant_final_mm: (wheels.left.distance_mm + wheels.right.distance_mm) / 2.0,
        pose,
        wheels,
        pwm: pins
            .iter()
            .map(|p| PwmPin {
                pin: format!("D{}", p.pin),
                hz: p.hz,
                mean_active_duty: p.mean_active_duty,
                active_s: p.active_s,
            })
            .collect(),
        cycles: bench.cycle(),
        awake_fraction: bench.awake_fraction(),
        cutoff_cycle: cutoff.map(|c| c.cycle),
        firmware_log: String::from_utf8_lossy(bench.uart_output(bench.board().debug_uart.usart))
            .into_owned(),
        believed,
        warnings: warning
            .into_iter()
            .chain(crate::firmware::params::refusals(
                bench.uart_output(bench.board().command_uart.usart),
                params.len(),
            ))
            .collect(),
    };
    Ok(LineRun {
        summary,
        trace: core.trace().to_vec(),
        cutoffs: core.cutoffs().to_vec(),
        pins,
        start_cycle,
    })
}

impl LineSummary {
    /// The human-readable summary.
    pub fn render(&self) -> String {
        let mut s = String::new();
        use std::fmt::Write;
        let _ = writeln!(
            s,
            "straight line, {} mm ({})",
            self.length_mm, self.firmware
        );
        let _ = writeln!(
            s,
            "  robot time     {:.3} s total, {:.3} s driving",
            self.robot_time_s, self.drive_time_s
        );
        if let Some(rtf) = self.rtf {
            let _ = writeln!(s, "  real-time x    {rtf:.1}");
        }
        let _ = writeln!(
            s,
            "  distance       {:.1} mm by firmware odometry, {:.1} mm by the plant at cut-off ({:.1} mm after braking)",
            self.distance_firmware_mm, self.distance_plant_mm, self.distance_plant_final_mm
        );
        let _ = writeln!(
            s,
            "  final pose     x {:.1} mm, y {:.1} mm, theta {:.4} rad ({:.2} deg)",
            self.pose.x().0,
            self.pose.y().0,
            self.pose.theta().0,
            self.pose.theta().0.to_degrees()
        );
        for (name, w) in [("left", &self.wheels.left), ("right", &self.wheels.right)] {
            let _ = writeln!(
                s,
                "  {name:<5} wheel    plant edges {}, raised {}, firmware count {} (at cut-off {}), {}",
                w.plant_edges,
                w.raised_edges,
                w.firmware_count,
                w.stop_count,
                if w.plant_edges == w.firmware_count as i64 {
                    "equal"
                } else {
                    "DIFFERENT"
                }
            );
        }
        for p in &self.pwm {
            let _ = writeln!(
                s,
                "  PWM {:<3}        {:.2} Hz, mean duty {:.3} over {:.3} s",
                p.pin, p.hz, p.mean_active_duty, p.active_s
            );
        }
        let _ = writeln!(
            s,
            "  CPU            {} cycles, awake {:.2} %",
            self.cycles,
            self.awake_fraction * 100.0
        );
        for w in &self.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        s
    }
}
