//! The thesis' tests on the emulated robot: a command byte on the Bluetooth
//! UART, the firmware drives legs and spin turns, and the bench measures what
//! a person on the floor would: each leg's distance, each turn's angle, the
//! end position relative to the start.
//!
//! Legs and turns are found from the H-bridge inputs ([`Motion`] events), not
//! from the firmware's own idea of them, so the same analysis holds for the
//! thesis build and the robust build.
//!
//! | file | part |
//! |---|---|
//! | `mod.rs` | a run: options, results, the bench interface's start and end, the debugger's run |
//! | `analyse.rs` | legs, turns and the end pose from the bridge and the plant (debounced) |
//! | `described.rs` | a run of a firmware without the interface, as its test description says |
//! | `fragments.rs` | a run with more legs or turns than its shape, and the likely cause |
//! | `uarts.rs` | what the firmware sent on each USART, named by the board ([`UartOutput`]) |

use plant_model::RobotConfig;

use crate::bench::{
    Action, Bench, BenchError, BenchOptions, DriveEvent, LedEvent, MotionEvent, Observer, PinEvent,
    Sample, ScheduledFault,
};
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::firmware::params::{Believed, Tell};

mod analyse;
pub(crate) mod described;
mod fragments;
pub mod uarts;

use analyse::{analyse, ShapeRule};
pub(crate) use described::{ended, Mark};
pub use fragments::Fragments;
pub use uarts::UartOutput;

/// A test a run drives: a thesis test, or one a test description names, and
/// the shape a test drives.
pub use crate::firmware::description::{Shape, TestName};
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
    pub params: Vec<(crate::firmware::link::Param, f32)>,
    /// Whether the robot config's geometry is sent first.
    pub tell: Tell,
    /// Stop the run as hung after this much robot time without progress
    /// (see [`crate::bench::hang`]); None: only `limit_s` ends an unfinished run.
    pub hang_after_s: Option<f64>,
    /// How a firmware without the bench interface is run (see
    /// [`crate::firmware::description`]); None: the firmware's `HT_` interface.
    pub description: Option<std::sync::Arc<Description>>,
    /// Robot time the host waits, once the firmware is ready, before it sends anything:
    /// where in the firmware's control period the run starts. A person starts runs at no
    /// particular phase of it; 0 (the default) starts at the same cycle every time.
    pub start_delay_s: f64,
    /// With [`TestOptions::record`]: where the records go as the run makes
    /// them (a trace written as the run goes, `Bench::stream_records`)
    /// instead of the pin changes kept in the run.
    pub tap: Option<crate::bench::SharedTap>,
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
            start_delay_s: 0.0,
            tap: None,
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
    pub test: TestName,
    /// The shape the run was judged by (None: a described test of the
    /// firmware's own without one; then `x_cm` and `y_cm` are the end
    /// position itself).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<Shape>,
    pub firmware: String,
    pub seed: u64,
    pub completed: bool,
    /// Why it did not complete (a hang, a fault): a finding, not an error.
    pub finding: Option<String>,
    /// Where the firmware was when the bench found it hung (see
    /// [`TestOptions::hang_after_s`]).
    pub hang: Option<crate::bench::hang::HangReport>,
    pub legs: Vec<Leg>,
    pub turns: Vec<Turn>,
    /// More legs or turns than the test's shape (see [`Fragments`]): then
    /// the run did not complete the test (`completed` false, `finding` says
    /// so) unless faults were injected (then a warning).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fragments: Option<Fragments>,
    /// Why the run did not drive its test's shape (it fragmented, or a
    /// described test drove other than its own `shape`): then `completed`
    /// is false and `finding` says the same.
    #[serde(skip)]
    pub off_shape: Option<String>,
    pub final_pose: FinalPose,
    /// End position error (end minus the shape's ideal end) in cm, start
    /// frame: x along the first leg, y to the left.
    pub x_cm: f64,
    pub y_cm: f64,
    pub robot_time_s: f64,
    pub awake_fraction: f64,
    /// Cycles fast-forwarded over polling loops (not in the report: it
    /// is the same with `--no-skip`, but for this).
    #[serde(skip)]
    pub skipped_cycles: u64,
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
    /// The bytes the firmware sent on the command link (the board's
    /// `command_uart`; in the JSON as its entry of `uarts`).
    #[serde(skip)]
    pub bluetooth_out: Vec<u8>,
    /// What the firmware sent on each USART from reset to the end, named by
    /// the board (see [`uarts::outputs`]).
    pub uarts: Vec<UartOutput>,
    /// Pin-level detail, when recorded (see [`TestOptions::record`]).
    #[serde(skip)]
    pub edges: Vec<PinEvent>,
    #[serde(skip)]
    pub drive: Vec<DriveEvent>,
    #[serde(skip)]
    pub uart: Vec<(u64, u8, u8)>,
    /// Bytes that arrived at the firmware's receivers: (cycle, USART, byte).
    #[serde(skip)]
    pub uart_rx: Vec<(u64, u8, u8)>,
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
    /// The faults of [`TestOptions::faults`] (their indices) the run never
    /// reached: named in `warnings`, and for whoever judges the run.
    #[serde(skip)]
    pub faults_never_fired: Vec<usize>,
}

impl TestRun {
    /// The cycles at which the run's segments (legs and turns) started, in
    /// order.
    pub fn segment_starts(&self) -> Vec<u64> {
        let mut starts: Vec<u64> = self.legs.iter().map(|l| l.start_cycle).collect();
        starts.extend(self.turns.iter().map(|t| t.start_cycle));
        starts.sort_unstable();
        starts
    }
}

/// The legs and turns `bench` drove from `since_cycle` on, counted as a run's
/// end counts them ([`TestRun::legs`], [`TestRun::turns`]): a test's progress
/// while it still runs (the station's live view).
pub(crate) fn legs_and_turns_so_far(
    bench: &Bench,
    test: &TestName,
    opts: &TestOptions,
    since_cycle: u64,
) -> (Vec<Leg>, Vec<Turn>) {
    let run = analyse(
        bench,
        test.clone(),
        None,
        String::new(),
        opts,
        since_cycle..u64::MAX,
        false,
        None,
    );
    (run.legs, run.turns)
}

/// Run `test` from a fresh reset (a test of the firmware's own needs its
/// description, [`TestOptions::description`]).
pub fn run_test(
    firmware: Firmware,
    robot: &RobotConfig,
    test: impl Into<TestName>,
    opts: &TestOptions,
) -> Result<TestRun, BenchError> {
    run_test_observed(firmware, robot, test, opts, None).map(|(run, _)| run)
}

/// Run `test` from a fresh reset with `observer` watching every step from
/// the command byte on; returns the observer too.
pub fn run_test_observed(
    firmware: Firmware,
    robot: &RobotConfig,
    test: impl Into<TestName>,
    opts: &TestOptions,
    observer: Option<Box<dyn Observer>>,
) -> Result<(TestRun, Option<Box<dyn Observer>>), BenchError> {
    let test = test.into();
    let _run = tracing::debug_span!("run", test = test.name(), seed = opts.bench.seed).entered();
    if let Some(d) = &opts.description {
        return described::run_described(firmware, robot, &test, opts, d, observer);
    }
    let test = thesis_only(&test)?;
    let mut bench = Bench::new(firmware, robot, opts.bench)?;
    let run = run_on(&mut bench, robot, test, opts, observer)?;
    Ok((run, bench.take_observer()))
}

/// [`run_test`]'s run of `test` on a bench fresh from reset (one a
/// debugger or a test's harness drives: the same run, step for step).
pub(crate) fn run_fresh(
    bench: &mut Bench,
    robot: &RobotConfig,
    test: &TestName,
    opts: &TestOptions,
) -> Result<TestRun, BenchError> {
    match &opts.description {
        Some(d) => described::run_described_on(bench, test, opts, d, None),
        None => thesis_only(test).and_then(|t| run_on(bench, robot, t, opts, None)),
    }
}

/// [`run_test_observed`]'s run on a bench fresh from reset (one a debugger
/// may drive: the same run, step for step).
fn run_on(
    bench: &mut Bench,
    robot: &RobotConfig,
    test: Test,
    opts: &TestOptions,
    observer: Option<Box<dyn Observer>>,
) -> Result<TestRun, BenchError> {
    let name = bench.firmware().name();
    let ready = tracing::debug_span!("ready").entered();
    let (done_before, mut start_cycle) = crate::runs::line::make_ready(bench, opts.leg_mm)?;
    if opts.start_delay_s > 0.0 {
        bench.run_for(opts.start_delay_s)?;
        start_cycle = bench.cycle();
    }
    let vars = *bench.vars()?;
    tracing::debug!(t_s = bench.robot_time_s(), "firmware ready");
    drop(ready);
    let _drive = tracing::debug_span!("drive").entered();
    bench.set_observer(observer);
    let told = start(bench, robot, test, opts);
    let limit = limit_s(Some(&Shape::of(test)), opts);
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
    if let Some(f) = &finding {
        tracing::debug!(t_s = bench.robot_time_s(), finding = %f, "the run did not complete");
    }
    let shape = Some((Shape::of(test), ShapeRule::Fragments));
    let mut run = analyse(
        bench,
        test.into(),
        shape,
        name,
        opts,
        start_cycle..u64::MAX,
        completed,
        finding,
    );
    run.hang = hang;
    told.apply(&mut run);
    Ok(run)
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
        run.warnings.extend(crate::firmware::params::refusals(
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
    record(bench, opts);
    let (params, believed, warning) = crate::firmware::params::plan(
        bench.firmware(),
        robot,
        bench.board(),
        opts.tell,
        &opts.params,
    );
    crate::runs::start::start_test(bench, &params, opts.framed, test);
    Told {
        believed,
        warning,
        sent: params.len(),
    }
}

/// Recording on when `opts` asks for it: the pin changes kept, or the
/// records given to its tap as they are made.
pub(crate) fn record(bench: &mut Bench, opts: &TestOptions) {
    if opts.record {
        bench.true_waveforms();
        match &opts.tap {
            Some(tap) => bench.stream_records(tap.clone()),
            None => bench.start_recording(),
        }
    }
}

/// Robot time allowed from the start command to the end of a test of
/// `shape` (without one: as for the longest of the thesis' tests, the
/// UMBmark's 4 legs and 4 turns).
pub(crate) fn limit_s(shape: Option<&Shape>, opts: &TestOptions) -> f64 {
    let shape = shape.copied().unwrap_or(Shape::of(Test::UmbmarkCw));
    let leg_mm = shape.leg_mm.unwrap_or(opts.leg_mm);
    // Each leg at a third of the nominal 145 mm/s, each turn 5 s, 3 s of
    // braking and waits per segment: generous, so a slow robot is not a hang.
    opts.limit_s
        .unwrap_or(shape.legs as f64 * (leg_mm / 50.0 + 3.0) + shape.turns as f64 * 8.0 + 5.0)
}

/// The thesis test `test` is, for a firmware with the bench interface;
/// a test of the firmware's own needs its description.
fn thesis_only(test: &TestName) -> Result<Test, BenchError> {
    test.thesis().ok_or_else(|| {
        BenchError::Description(format!(
            "{test} is no test of the bench's own builds (umbmark-cw, umbmark-ccw, line, \
             triangle); a test of your firmware's own runs from its test description (--tests FILE)"
        ))
    })
}

/// Run `test` under a debugger: the MCU paused at its reset vector until
/// the debugger continues, then [`run_test`]'s run, step for step (the
/// debugger only pauses it; a described firmware's as its description
/// says), the debugger told of the end.
/// [`GdbError::Ended`](crate::bench::gdb::GdbError::Ended) when the
/// debugger killed the run or left it without a detach.
pub fn run_test_debugged(
    firmware: Firmware,
    robot: &RobotConfig,
    test: impl Into<TestName>,
    opts: &TestOptions,
    server: crate::bench::gdb::GdbServer,
) -> Result<TestRun, crate::bench::gdb::GdbError> {
    let test = test.into();
    // Refused before the debugger attaches.
    if opts.description.is_none() {
        thesis_only(&test)?;
    }
    let mut bench = Bench::new(firmware, robot, opts.bench)?;
    server.attach(&mut bench)?;
    let run = run_fresh(&mut bench, robot, &test, opts);
    let run = match run {
        Ok(run) => run,
        Err(BenchError::Debugger(why)) => return Err(crate::bench::gdb::GdbError::Ended(why)),
        Err(e) => {
            crate::bench::gdb::run_over(&mut bench, false);
            return Err(e.into());
        }
    };
    crate::bench::gdb::run_over(&mut bench, run.completed);
    Ok(run)
}
