//! The thesis' tests on the emulated robot: a command byte on the Bluetooth
//! UART, the firmware drives legs and spin turns, and the bench measures what
//! a person on the floor would: each leg's distance, each turn's angle, the
//! end position relative to the start.
//!
//! Legs and turns are found from the H-bridge inputs ([`Motion`] events), not
//! from the firmware's own idea of them, so the same analysis holds for the
//! thesis build and the robust build.

use plant_model::{RobotConfig, Side};

use crate::bench::{
    Action, Bench, BenchError, BenchOptions, DriveEvent, LedEvent, Motion, MotionEvent, Observer,
    PinEvent, Sample, ScheduledFault, Snapshot,
};
use crate::description::Description;
use crate::elf::Firmware;
use crate::firmware_params::{Believed, Tell};
use crate::line::ready_bench;

/// The tests the firmware's selector knows: the protocol's own, shared with
/// the firmware (their names, selector bytes and shapes are defined there).
pub use henrytwo_protocol::Test;

#[derive(Debug, Clone)]
pub struct TestOptions {
    pub leg_mm: f64,
    pub bench: BenchOptions,
    /// Robot time allowed for the whole test before the bench calls it a hang.
    pub limit_s: Option<f64>,
    /// Record pin-level detail (encoder edges, drive events, UART bytes) for traces.
    pub record: bool,
    /// Faults to inject: when, what, and what undoes it how much later (s).
    pub faults: Vec<ScheduledFault>,
    /// Start the test with a framed command (the robust build's protocol)
    /// instead of the thesis' raw selector byte.
    pub framed: bool,
    /// Parameters to set over the protocol before the start (implies framed),
    /// after the robot's geometry (see [`TestOptions::tell`]).
    pub params: Vec<(crate::link::Param, f32)>,
    /// Whether the robot config's geometry is sent first.
    pub tell: Tell,
    /// Stop the run as hung after this much robot time without progress
    /// (see [`crate::hang`]); None: only `limit_s` ends an unfinished run.
    pub hang_after_s: Option<f64>,
    /// How a firmware without the bench interface is run (see
    /// [`crate::description`]); None: the firmware's `HT_` interface.
    pub description: Option<std::sync::Arc<Description>>,
}

impl Default for TestOptions {
    fn default() -> Self {
        Self {
            leg_mm: 2000.0,
            bench: BenchOptions::default(),
            limit_s: None,
            record: false,
            faults: Vec::new(),
            framed: false,
            params: Vec::new(),
            tell: Tell::Robot,
            hang_after_s: None,
            description: None,
        }
    }
}

/// One straight leg.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Leg {
    /// Straight-line distance the robot's axle centre moved, from the leg's
    /// start to rest (coasting included), by the plant.
    pub plant_distance_mm: f64,
    /// Mean of the two wheels' arcs from the leg's start to rest, by the plant.
    pub plant_arc_mm: f64,
    /// Heading change during the leg (curvature), degrees.
    pub plant_heading_change_deg: f64,
    /// Firmware counts over the leg, at the motors' cut-off (None: a
    /// firmware whose counters the bench does not know).
    pub firmware_count_left: Option<i32>,
    pub firmware_count_right: Option<i32>,
    /// Net A edges the plant made over the same span: what a perfect
    /// decoder would have counted.
    pub plant_edges_left: i64,
    pub plant_edges_right: i64,
    pub start_cycle: u64,
    pub cutoff_cycle: u64,
}

/// One spin turn.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Turn {
    /// Firmware counts (relative to the turn's start) when each motor was cut;
    /// None when that motor was never cut inside the turn.
    pub count_left_at_cutoff: Option<i32>,
    pub count_right_at_cutoff: Option<i32>,
    /// Heading change from the turn's start to rest, degrees (positive CCW).
    pub plant_angle_deg: f64,
    /// The plant's wheel arcs over the turn (mm, signed).
    pub plant_left_mm: f64,
    pub plant_right_mm: f64,
    pub start_cycle: u64,
    pub cutoff_left_cycle: Option<u64>,
    pub cutoff_right_cycle: Option<u64>,
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FinalPose {
    pub x_mm: f64,
    pub y_mm: f64,
    pub theta_deg: f64,
}

/// One run of a test.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TestRun {
    pub test: Test,
    pub firmware: String,
    pub seed: u64,
    pub completed: bool,
    /// Why it did not complete (a hang, a fault): a finding, not an error.
    pub finding: Option<String>,
    /// Where the firmware was when the bench found it hung (see
    /// [`TestOptions::hang_after_s`]).
    pub hang: Option<crate::hang::HangReport>,
    pub legs: Vec<Leg>,
    pub turns: Vec<Turn>,
    pub final_pose: FinalPose,
    /// End position error (end minus ideal end) in cm, start frame: x along
    /// the first leg, y to the left.
    pub x_cm: f64,
    pub y_cm: f64,
    pub robot_time_s: f64,
    pub awake_fraction: f64,
    #[serde(skip)]
    pub trace: Vec<Sample>,
    /// What the motors did, from the start on, without stale levels (see
    /// `debounced`).
    #[serde(skip)]
    pub motions: Vec<MotionEvent>,
    /// Fault actions applied: (cycle, action).
    pub applied: Vec<(u64, Action)>,
    /// The firmware's fault code at the end (`HT_FAULT`), when it has one.
    pub fault_code: Option<u8>,
    /// The bytes the firmware sent on the Bluetooth UART.
    pub bluetooth_out: Vec<u8>,
    /// Pin-level detail, when recorded (see [`TestOptions::record`]).
    #[serde(skip)]
    pub edges: Vec<PinEvent>,
    #[serde(skip)]
    pub drive: Vec<DriveEvent>,
    #[serde(skip)]
    pub uart: Vec<(u64, u8, u8)>,
    /// Battery LED changes.
    #[serde(skip)]
    pub leds: Vec<LedEvent>,
    /// Brown-out resets: robot times (s) the detector pulled the reset and
    /// let it go (None: still held at the end).
    pub brownouts: Vec<(f64, Option<f64>)>,
    /// What the firmware believed about the robot during the run.
    #[serde(skip)]
    pub believed: Believed,
    /// Things the run did that its numbers alone do not show (e.g. a
    /// firmware whose geometry is not the robot's).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Run `test` from a fresh reset.
pub fn run_test(
    firmware: Firmware,
    robot: &RobotConfig,
    test: Test,
    opts: &TestOptions,
) -> Result<TestRun, BenchError> {
    run_test_observed(firmware, robot, test, opts, None).map(|(run, _)| run)
}

/// Run `test` from a fresh reset with `observer` watching every step from
/// the command byte on; returns the observer too.
pub fn run_test_observed(
    firmware: Firmware,
    robot: &RobotConfig,
    test: Test,
    opts: &TestOptions,
    observer: Option<Box<dyn Observer>>,
) -> Result<(TestRun, Option<Box<dyn Observer>>), BenchError> {
    if let Some(d) = &opts.description {
        return crate::description::run_described(firmware, robot, test, opts, d, observer);
    }
    let name = firmware.name();
    let (mut bench, done_before, start_cycle) =
        ready_bench(firmware, robot, opts.bench, opts.leg_mm)?;
    let vars = *bench.vars()?;
    bench.set_observer(observer);
    let told = start(&mut bench, robot, test, opts);
    let limit = limit_s(test, opts);
    bench.set_hang_after(opts.hang_after_s);
    let outcome = bench.run_until(limit, |b| {
        b.read_u16(vars.done_count) != done_before && b.is_idle()
    });
    bench.set_hang_after(None);
    // A hang is what the firmware did: a finding of the run, not an error.
    let (completed, hang) = match outcome {
        Ok(done) => (done, None),
        Err(BenchError::Hang(report)) => (false, Some(report)),
        Err(e) => return Err(e),
    };
    let finding = match &hang {
        Some(h) => Some(format!(
            "hung: busy in the test without progress for {:.1} s of robot time, {h}",
            h.still_s
        )),
        None => (!completed).then(|| {
            format!(
                "did not complete within {limit:.0} s of robot time; the firmware is {}",
                bench.location()
            )
        }),
    };
    // Let the last coast and the UART drain.
    if completed {
        bench.run_for(0.1)?;
    }
    let observer = bench.take_observer();
    let mut run = analyse(&bench, test, name, opts, start_cycle, completed, finding);
    run.hang = hang;
    told.apply(&mut run);
    Ok((run, observer))
}

/// What the firmware was told before a run: what it then believed, and a
/// warning when that is not the robot.
struct Told {
    believed: Believed,
    warning: Option<String>,
    sent: usize,
}

impl Told {
    /// Records what the firmware believed, and says so when it refused any
    /// of the parameters sent (then it does not believe what we think).
    fn apply(self, run: &mut TestRun) {
        run.believed = self.believed;
        run.warnings.extend(self.warning);
        run.warnings.extend(crate::firmware_params::refusals(
            &run.bluetooth_out,
            self.sent,
        ));
    }
}

/// Faults scheduled, recording on, the robot's geometry and the run's
/// parameters sent, and the host's start command: what follows the
/// firmware's ready state.
fn start(bench: &mut Bench, robot: &RobotConfig, test: Test, opts: &TestOptions) -> Told {
    for f in &opts.faults {
        bench.schedule(f.trigger, f.action.clone(), f.undo.clone());
    }
    if opts.record {
        bench.true_waveforms();
        bench.start_recording();
    }
    let (params, believed, warning) = crate::firmware_params::plan(
        bench.firmware(),
        robot,
        bench.board(),
        opts.tell,
        &opts.params,
    );
    crate::firmware_params::start_test(bench, &params, opts.framed, test);
    Told {
        believed,
        warning,
        sent: params.len(),
    }
}

/// Robot time allowed from the start command to the end of the test.
pub(crate) fn limit_s(test: Test, opts: &TestOptions) -> f64 {
    let (legs, turns, _) = test.shape();
    // Each leg at a third of the nominal 145 mm/s, each turn 5 s, 3 s of
    // braking and waits per segment: generous, so a slow robot is not a hang.
    opts.limit_s
        .unwrap_or(legs as f64 * (opts.leg_mm / 50.0 + 3.0) + turns as f64 * 8.0 + 5.0)
}

/// Run `test` under a debugger: the MCU paused at its reset vector until
/// the debugger continues. The bench plays the host as [`run_test`] does
/// (the start command once the firmware is idle); after a detach the run
/// goes on to its end without the debugger. None when the debugger killed
/// the run.
pub fn run_test_debugged(
    firmware: Firmware,
    robot: &RobotConfig,
    test: Test,
    opts: &TestOptions,
    server: crate::gdb::GdbServer,
) -> Result<Option<TestRun>, crate::gdb::GdbError> {
    use crate::gdb::{Flow, SessionEnd};
    let name = firmware.name();
    let mut bench = Bench::new(firmware, robot, opts.bench)?;
    let vars = *bench.vars()?;
    let limit = limit_s(test, opts);
    // (HT_DONE_COUNT before the start, the start's cycle), once started.
    let mut started: Option<(u16, u64)> = None;
    let mut told: Option<Told> = None;
    let mut host = |b: &mut Bench, started: &mut Option<(u16, u64)>| -> Flow {
        match *started {
            None if b.is_idle() => {
                b.write_f32(vars.leg_length_mm, opts.leg_mm as f32);
                *started = Some((b.read_u16(vars.done_count), b.cycle()));
                told = Some(start(b, robot, test, opts));
                Flow::Continue
            }
            Some((done_before, at))
                if (b.read_u16(vars.done_count) != done_before && b.is_idle())
                    || b.cycle() >= at + b.clock().cycles_in(plant_model::Seconds(limit)) =>
            {
                Flow::Finished
            }
            _ => Flow::Continue,
        }
    };
    let end = server.serve(&mut bench, &mut |b: &mut Bench| host(b, &mut started))?;
    if end == SessionEnd::Killed {
        return Ok(None);
    }
    if end == SessionEnd::Detached {
        if started.is_none() {
            crate::line::wait_ready(&mut bench)?;
            host(&mut bench, &mut started);
        }
        let left = |b: &Bench, at: u64| limit - b.clock().seconds(b.cycle() - at).0;
        if let Some((done_before, at)) = started {
            let remaining = left(&bench, at).max(0.0);
            bench.run_until(remaining, |b| {
                b.read_u16(vars.done_count) != done_before && b.is_idle()
            })?;
        }
    }
    let (done_before, start_cycle) = started.unwrap_or((0, bench.cycle()));
    let completed = bench.read_u16(vars.done_count) != done_before && bench.is_idle();
    let finding = (!completed).then(|| {
        format!(
            "did not complete within {limit:.0} s of robot time; the firmware is {}",
            bench.location()
        )
    });
    let mut run = analyse(&bench, test, name, opts, start_cycle, completed, finding);
    if let Some(told) = told {
        told.apply(&mut run);
    }
    Ok(Some(run))
}

pub(crate) fn analyse(
    bench: &Bench,
    test: Test,
    firmware: String,
    opts: &TestOptions,
    start_cycle: u64,
    completed: bool,
    finding: Option<String>,
) -> TestRun {
    let core = bench.core();
    let motions: Vec<MotionEvent> = core
        .motions()
        .iter()
        .filter(|m| m.at.cycle >= start_cycle)
        .copied()
        .collect();
    let end = bench_now(bench);
    let clock = bench.clock();
    let pulse_cycles = clock.cycles_in(plant_model::Seconds(PULSE_MAX_S));
    let stale = core.stale_level_cycles();
    let motions = debounced(&motions, stale);
    let segments = segments(&motions, pulse_cycles);
    let mut legs = Vec::new();
    let mut turns = Vec::new();
    for (k, seg) in segments.iter().enumerate() {
        let start = motions[seg.start].at;
        let stop = motions.get(seg.stop).map(|e| e.at).unwrap_or(end);
        // At rest: when the next segment starts (after braking and waits),
        // or at the end of the run.
        let rest = segments
            .get(k + 1)
            .map(|n| motions[n.start].at)
            .unwrap_or(end);
        match motions[seg.start].motion {
            Motion::Forward => legs.push(Leg {
                plant_distance_mm: (rest.x_mm - start.x_mm).hypot(rest.y_mm - start.y_mm),
                plant_arc_mm: ((rest.left_mm - start.left_mm) + (rest.right_mm - start.right_mm))
                    / 2.0,
                plant_heading_change_deg: (rest.theta_rad - start.theta_rad).to_degrees(),
                firmware_count_left: diff(stop.left_count, start.left_count),
                firmware_count_right: diff(stop.right_count, start.right_count),
                plant_edges_left: stop.left_edges - start.left_edges,
                plant_edges_right: stop.right_edges - start.right_edges,
                start_cycle: start.cycle,
                cutoff_cycle: stop.cycle,
            }),
            Motion::SpinCw | Motion::SpinCcw => {
                // A motor's cut-off may come after the other's braking pulse
                // has begun: look until the next segment starts.
                let until = segments
                    .get(k + 1)
                    .map_or(u64::MAX, |n| motions[n.start].at.cycle);
                let cutoff = |side: Side| {
                    core.cutoffs()
                        .iter()
                        .find(|c| {
                            c.side == side
                                && c.at.cycle >= start.cycle
                                && c.at.cycle < until
                                && c.lasted(stale)
                        })
                        .map(|c| c.at)
                };
                let left = cutoff(Side::Left);
                let right = cutoff(Side::Right);
                turns.push(Turn {
                    count_left_at_cutoff: left.and_then(|c| diff(c.left_count, start.left_count)),
                    count_right_at_cutoff: right
                        .and_then(|c| diff(c.right_count, start.right_count)),
                    plant_angle_deg: (rest.theta_rad - start.theta_rad).to_degrees(),
                    plant_left_mm: rest.left_mm - start.left_mm,
                    plant_right_mm: rest.right_mm - start.right_mm,
                    start_cycle: start.cycle,
                    cutoff_left_cycle: left.map(|c| c.cycle),
                    cutoff_right_cycle: right.map(|c| c.cycle),
                });
            }
            _ => {}
        }
    }
    let (ix, iy) = test.ideal_end(opts.leg_mm);
    TestRun {
        test,
        firmware,
        seed: opts.bench.seed,
        completed,
        finding,
        hang: None,
        legs,
        turns,
        final_pose: FinalPose {
            x_mm: end.x_mm,
            y_mm: end.y_mm,
            theta_deg: end.theta_rad.to_degrees(),
        },
        x_cm: (end.x_mm - ix) / 10.0,
        y_cm: (end.y_mm - iy) / 10.0,
        robot_time_s: bench.robot_time_s(),
        awake_fraction: bench.awake_fraction(),
        trace: core.trace().to_vec(),
        motions,
        applied: core.applied().to_vec(),
        fault_code: bench
            .firmware()
            .variable("HT_FAULT", 1)
            .ok()
            .map(|a| bench.read_u8(a)),
        bluetooth_out: bench.uart_output(1).to_vec(),
        edges: core.recording().unwrap_or_default().to_vec(),
        drive: core.drive_log().to_vec(),
        uart: core.uart_log().to_vec(),
        leds: core.leds().to_vec(),
        brownouts: core
            .brownouts()
            .iter()
            .map(|(on, off)| {
                let s = |c: u64| bench.clock().seconds(c).0;
                (s(*on), off.map(s))
            })
            .collect(),
        believed: Believed::factory(),
        warnings: never_fired(bench, opts),
    }
}

/// "scenario fault 2 (encoder at 90 s) never fired", for each fault of
/// `opts` the run did not reach: its numbers show no fault, not a firmware
/// that survived one.
fn never_fired(bench: &Bench, opts: &TestOptions) -> Vec<String> {
    bench
        .faults_never_fired()
        .into_iter()
        .filter_map(|i| {
            let f = opts.faults.get(i)?;
            Some(format!(
                "scenario fault {} ({} {}) never fired",
                i + 1,
                f.action.name(),
                f.trigger
            ))
        })
        .collect()
}

/// A counter's change between two snapshots, when the bench reads it.
fn diff(to: Option<i32>, from: Option<i32>) -> Option<i32> {
    Some(to? - from?)
}

/// `motions` without the changes that lasted less than `stale` cycles
/// (a stale level while the firmware writes a bridge's inputs one after the
/// other is no cut-off), and with repeats merged.
fn debounced(motions: &[MotionEvent], stale: u64) -> Vec<MotionEvent> {
    let mut out: Vec<MotionEvent> = Vec::with_capacity(motions.len());
    for (i, m) in motions.iter().enumerate() {
        let lasted = motions
            .get(i + 1)
            .is_none_or(|next| next.at.cycle - m.at.cycle >= stale);
        if lasted && out.last().is_none_or(|l| l.motion != m.motion) {
            out.push(*m);
        }
    }
    out
}

/// Driven phases shorter than this are braking pulses, not legs or turns
/// (the thesis brakes with 5 ms of full reverse).
const PULSE_MAX_S: f64 = 0.03;

/// A leg or turn: motion events `start..stop`, where `stop` is the first
/// event at which no motor drives any more (or the end).
#[derive(Debug, Clone, Copy)]
struct Segment {
    start: usize,
    stop: usize,
}

fn segments(motions: &[MotionEvent], pulse_cycles: u64) -> Vec<Segment> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < motions.len() {
        let driven = matches!(
            motions[i].motion,
            Motion::Forward | Motion::SpinCw | Motion::SpinCcw | Motion::Reverse
        );
        if !driven {
            i += 1;
            continue;
        }
        // A turn goes on through phases where one motor is already cut; a
        // leg through a control period or two where one wheel's drive is
        // zero (the thesis' PID clamps a negative output to 0) and back.
        let mut j = i + 1;
        while j < motions.len()
            && (motions[j].motion == Motion::OneWheel
                || (motions[j].motion == motions[i].motion
                    && motions[j - 1].motion == Motion::OneWheel
                    && motions[i].motion == Motion::Forward))
        {
            j += 1;
        }
        let long = motions
            .get(j)
            .is_none_or(|e| e.at.cycle - motions[i].at.cycle > pulse_cycles);
        if long && motions[i].motion != Motion::Reverse {
            out.push(Segment { start: i, stop: j });
        }
        i = j;
    }
    out
}

fn bench_now(bench: &Bench) -> Snapshot {
    let core = bench.core();
    let pose = core.robot().pose();
    let counts = bench.counts();
    Snapshot {
        cycle: bench.cycle(),
        x_mm: pose.x().0,
        y_mm: pose.y().0,
        theta_rad: pose.theta().0,
        left_count: counts.map(|c| c[0]),
        right_count: counts.map(|c| c[1]),
        left_edges: core.robot().a_edges(plant_model::Side::Left),
        right_edges: core.robot().a_edges(plant_model::Side::Right),
        left_mm: core.robot().distance_travelled(plant_model::Side::Left).0,
        right_mm: core.robot().distance_travelled(plant_model::Side::Right).0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(motion: Motion, cycle: u64) -> MotionEvent {
        MotionEvent {
            motion,
            at: Snapshot {
                cycle,
                x_mm: 0.0,
                y_mm: 0.0,
                theta_rad: 0.0,
                left_count: None,
                right_count: None,
                left_edges: 0,
                right_edges: 0,
                left_mm: 0.0,
                right_mm: 0.0,
            },
        }
    }

    const MS: u64 = 16_000;

    /// A leg with a 1 us stale level (both inputs low while the firmware
    /// writes the second) is one leg; a stop of a PWM period or more is two.
    #[test]
    fn a_level_shorter_than_a_pwm_period_does_not_split_a_leg() {
        let stale = 510; // one period of the 31.37 kHz PWM
        let leg = |gap: u64| {
            vec![
                at(Motion::Forward, 0),
                at(Motion::Stopped, 1000 * MS),
                at(Motion::Forward, 1000 * MS + gap),
                at(Motion::Stopped, 2000 * MS),
            ]
        };
        let n = |m: &[MotionEvent]| segments(&debounced(m, stale), 30 * MS).len();
        assert_eq!(n(&leg(16)), 1);
        assert_eq!(n(&leg(509)), 1);
        assert_eq!(n(&leg(510 + 30 * MS)), 2);
    }

    /// A control period with one wheel at zero inside a leg is the same leg;
    /// a turn goes on through the phase with one motor cut.
    #[test]
    fn a_leg_goes_on_through_a_period_with_one_wheel_at_zero() {
        let m = vec![
            at(Motion::Forward, 0),
            at(Motion::OneWheel, 500 * MS),
            at(Motion::Forward, 515 * MS),
            at(Motion::Stopped, 2000 * MS),
            at(Motion::SpinCw, 4000 * MS),
            at(Motion::OneWheel, 4500 * MS),
            at(Motion::Stopped, 4600 * MS),
        ];
        let s = segments(&debounced(&m, 510), 30 * MS);
        assert_eq!(s.len(), 2, "{s:?}");
        assert_eq!((s[0].start, s[0].stop), (0, 3));
        assert_eq!((s[1].start, s[1].stop), (4, 6));
    }
}
