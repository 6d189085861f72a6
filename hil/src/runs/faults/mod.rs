//! The fault library: each fault in its own file, with the reaction expected
//! of the robust firmware written next to it, and a check of that reaction.
//!
//! A fault is a list of scheduled bench actions (at a robot time, or on an
//! event such as the third turn) and the test it is injected into. `hil
//! faults` runs each fault against the robust build (pass or fail against the
//! expectation) and against the thesis build (what it does is reported as a
//! finding: a hang, a runaway, a lost turn count are results, not crashes of
//! the bench).

use plant_model::RobotConfig;
use serde::Serialize;

use crate::bench::{BenchError, BenchOptions, ScheduledFault};
use crate::firmware::elf::Firmware;
use crate::runs::experiment::{run_test, Test, TestOptions, TestRun};

mod battery_below_adc_thresholds;
mod battery_brownout_reset;
mod bluetooth_link_drop;
mod encoder_dropout;
mod encoder_glitch_burst;
mod encoder_stuck_b;
mod encoder_swapped;
mod link_corruption;
mod missed_counts;
mod motor_disconnected;
mod motor_load_step;
mod motor_overload;
mod motor_stall;
mod reset_mid_test;
mod robot_wedged;
mod turn_slip_burst;
mod uart_byte_loss;
mod uart_garbage;

/// One fault of the library.
pub struct FaultCase {
    pub name: &'static str,
    /// What is done to the robot.
    pub what: &'static str,
    /// The robust firmware's expected reaction.
    pub expected: &'static str,
    pub test: Test,
    pub leg_mm: f64,
    pub faults: Vec<ScheduledFault>,
    /// Robot time after which a run that has not completed counts as a hang.
    pub limit_s: f64,
    /// Start the test with a framed command instead of the raw selector byte.
    pub framed: bool,
    /// Judge the robust build's run: Ok(why) passes, Err(why) fails; None
    /// for a case that states no expectation (a scenario file's), which is
    /// run and reported, not judged.
    pub check: Option<Check>,
}

/// A case's judgement of the robust build's run: Ok(why) passes, Err(why)
/// fails.
pub type Check = fn(&Observed) -> Result<String, String>;

/// What `hil faults` concludes of one case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The robust build reacted as expected.
    Pass,
    /// It did not.
    Fail,
    /// Run and reported, against no expectation (a scenario file).
    NotJudged,
    /// A fault of the case never fired: the run shows no reaction to it,
    /// whatever its numbers say. A failure: nothing was tested.
    NotFired,
}

impl Verdict {
    /// Whether the command that reached it failed (its exit code).
    pub fn failed(self) -> bool {
        matches!(self, Verdict::Fail | Verdict::NotFired)
    }

    /// Its tag in the text table.
    pub fn tag(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Fail => "FAIL",
            Verdict::NotJudged => "ran, not judged",
            Verdict::NotFired => "FAIL: a fault never fired",
        }
    }
}

/// Every fault, in a fixed order.
pub fn library() -> Vec<FaultCase> {
    vec![
        encoder_dropout::case(),
        encoder_stuck_b::case(),
        encoder_swapped::case(),
        missed_counts::case(),
        encoder_glitch_burst::case(),
        motor_disconnected::case(),
        motor_stall::case(),
        motor_load_step::case(),
        motor_overload::case(),
        robot_wedged::case(),
        turn_slip_burst::case(),
        battery_below_adc_thresholds::case(),
        battery_brownout_reset::case(),
        link_corruption::case(),
        uart_byte_loss::case(),
        uart_garbage::case(),
        bluetooth_link_drop::case(),
        reset_mid_test::case(),
    ]
}

/// How `hil faults` runs the library.
#[derive(Debug, Clone)]
pub struct FaultOptions {
    pub seed: u64,
    /// How a firmware without the bench interface is run.
    pub description: Option<std::sync::Arc<crate::firmware::description::Description>>,
    /// The board the robot is wired by.
    pub board: crate::board::Board,
    /// Robot time without progress after which a busy firmware is hung
    /// (see [`crate::bench::hang`]).
    pub hang_after_s: f64,
}

impl Default for FaultOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            description: None,
            board: Default::default(),
            hang_after_s: crate::bench::hang::DEFAULT_HANG_AFTER_S,
        }
    }
}

/// The watchdog's expected reaction: all motors off within `max_s` of the
/// fault, with a fault code reported.
pub fn stopped_with_code(o: &Observed, max_s: f64) -> Result<String, String> {
    match (o.motors_off_after_s, o.fault_code) {
        (Some(t), Some(c)) if t <= max_s && c != 0 => Ok(format!(
            "motors off after {:.0} ms with fault code {c}",
            t * 1e3
        )),
        (t, c) => Err(format!(
            "expected motors off within {:.0} ms and a fault code; saw the motors {}, {}",
            max_s * 1e3,
            off_after(t),
            c.filter(|&c| c != 0)
                .map_or("no fault code".into(), |c| format!("fault code {c}"))
        )),
    }
}

/// `off after 218 ms` or `never all off`, for a verdict's message.
pub(crate) fn off_after(t: Option<f64>) -> String {
    t.map_or("never all off".into(), |t| {
        format!("off after {:.0} ms", t * 1e3)
    })
}

/// What a faulted run showed.
#[derive(Debug, Clone, Serialize)]
pub struct Observed {
    pub completed: bool,
    pub finding: Option<String>,
    /// Robot time from the first fault action to all four bridge inputs at
    /// zero, if that happened.
    pub motors_off_after_s: Option<f64>,
    pub fault_code: Option<u8>,
    pub legs: usize,
    pub turns: usize,
    pub end_x_cm: f64,
    pub end_y_cm: f64,
    /// Distance the robot's centre ended from where it started, cm.
    pub end_distance_cm: f64,
    pub robot_time_s: f64,
    /// First leg: firmware counts (mean of both wheels) and plant distance.
    pub first_leg_counts: Option<f64>,
    pub first_leg_plant_mm: Option<f64>,
    /// First leg: mean wheel arc by the plant.
    pub first_leg_arc_mm: Option<f64>,
    /// First leg: firmware count minus the plant's edges, per wheel (left,
    /// right): counts gained (+) or lost (-) between the wheel and the MCU.
    pub first_leg_count_error: Option<(i64, i64)>,
    /// First leg: robot time from its start to the motors' cut-off.
    pub first_leg_drive_s: Option<f64>,
    /// First leg: heading change, degrees (positive to the left).
    pub first_leg_heading_deg: Option<f64>,
    pub bluetooth_reply_bytes: usize,
    /// Replies and notifications on the Bluetooth link, and how many of
    /// them carry an error status.
    pub replies: usize,
    pub error_replies: usize,
    /// Where the bench found the firmware hung (see [`crate::bench::hang`]).
    pub hang: Option<crate::bench::hang::HangReport>,
    /// Battery LED changes: robot time (s since reset) and the colour shown.
    pub led_changes: Vec<(f64, String)>,
    /// The battery LED at the end.
    pub led_at_end: String,
    /// Robot time of the first fault action.
    pub fault_at_s: Option<f64>,
    /// Brown-out resets: robot times (s) the reset was pulled and released.
    pub brownouts: Vec<(f64, Option<f64>)>,
    /// The run's warnings (a scenario fault that never fired, ...).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The case's faults (1-based, as the warnings name them) the run never
    /// reached.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub faults_never_fired: Vec<usize>,
    /// Robot time from the first fault action to the first time, after the
    /// motors went all off, that a PWM bridge input was driven again: a
    /// firmware that resumed or restarted something on its own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub driven_again_after_s: Option<f64>,
    /// What the firmware sent on each USART, named by the board.
    pub uarts: Vec<crate::runs::experiment::UartOutput>,
    /// Counts per second of a wheel at the firmware's set-point (mean of the
    /// two wheels), from what the firmware believed about the robot.
    #[serde(skip)]
    pub setpoint_counts_per_s: f64,
}

impl Observed {
    /// What `run` showed, its motors wired by `board`.
    pub fn from_run(run: &TestRun, clock_hz: u32, board: &crate::board::Board) -> Self {
        let fault_cycle = run.applied.first().map(|a| a.0);
        // The PWM inputs: with all of them at zero no motor is driven,
        // whatever the direction pins of an L298N-style driver say.
        let inputs: Vec<u8> = board
            .bridge_inputs()
            .iter()
            .filter(|b| b.pwm.is_some())
            .map(|b| b.number())
            .collect();
        // Replay the drive log to find the first moment after the fault with
        // every PWM bridge input at zero, and the first one after that with
        // one of them driven again.
        let mut duty = [0.0f64; 70];
        let mut off_at = None;
        let mut again_at = None;
        if let Some(fc) = fault_cycle {
            for e in &run.drive {
                duty[e.pin as usize] = e.duty;
                if e.cycle < fc {
                    continue;
                }
                let all_off = inputs.iter().all(|&p| duty[p as usize] == 0.0);
                match off_at {
                    None if all_off => off_at = Some(e.cycle),
                    Some(_) if !all_off => {
                        again_at = Some(e.cycle);
                        break;
                    }
                    _ => {}
                }
            }
        }
        let since_fault = |c: Option<u64>| Some((c? - fault_cycle?) as f64 / clock_hz as f64);
        let motors_off_after_s = since_fault(off_at);
        let driven_again_after_s = since_fault(again_at);
        let leg = run.legs.first();
        let replies = crate::firmware::link::replies(&run.bluetooth_out);
        let led_changes = run
            .leds
            .iter()
            .map(|e| (e.cycle as f64 / clock_hz as f64, e.colour().to_string()))
            .collect();
        Self {
            completed: run.completed,
            finding: run.finding.clone(),
            motors_off_after_s,
            fault_code: run.fault_code,
            legs: run.legs.len(),
            turns: run.turns.len(),
            end_x_cm: run.final_pose.x_mm / 10.0,
            end_y_cm: run.final_pose.y_mm / 10.0,
            end_distance_cm: run.final_pose.x_mm.hypot(run.final_pose.y_mm) / 10.0,
            robot_time_s: run.robot_time_s,
            first_leg_counts: leg.and_then(|l| {
                Some((l.firmware_count_left? + l.firmware_count_right?) as f64 / 2.0)
            }),
            first_leg_plant_mm: leg.map(|l| l.plant_distance_mm),
            first_leg_arc_mm: leg.map(|l| l.plant_arc_mm),
            first_leg_heading_deg: leg.map(|l| l.plant_heading_change_deg),
            first_leg_drive_s: leg
                .map(|l| (l.cutoff_cycle - l.start_cycle) as f64 / clock_hz as f64),
            first_leg_count_error: leg.and_then(|l| {
                Some((
                    l.firmware_count_left? as i64 - l.plant_edges_left,
                    l.firmware_count_right? as i64 - l.plant_edges_right,
                ))
            }),
            fault_at_s: fault_cycle.map(|c| c as f64 / clock_hz as f64),
            bluetooth_reply_bytes: run.bluetooth_out.len(),
            replies: replies.len(),
            error_replies: replies.iter().filter(|r| !r.ok).count(),
            hang: run.hang.clone(),
            led_changes,
            led_at_end: run.leds.last().map_or("off", |e| e.colour()).into(),
            brownouts: run.brownouts.clone(),
            warnings: run.warnings.clone(),
            faults_never_fired: run.faults_never_fired.iter().map(|i| i + 1).collect(),
            driven_again_after_s,
            uarts: run.uarts.clone(),
            setpoint_counts_per_s: (run.believed.setpoint_counts_per_s(0)
                + run.believed.setpoint_counts_per_s(1))
                / 2.0,
        }
    }

    /// One line for a person.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        parts.push(match (&self.hang, self.completed) {
            (Some(h), _) => format!("HUNG (no progress for {:.1} s) {h}", h.still_s),
            (None, true) => "completed".to_string(),
            (None, false) => "did not complete".to_string(),
        });
        match self.motors_off_after_s {
            Some(t) => parts.push(format!("motors off {:.0} ms after the fault", t * 1e3)),
            None => parts.push("motors never all off after the fault".into()),
        }
        if let Some(c) = self.fault_code.filter(|c| *c != 0) {
            parts.push(format!("fault code {c}"));
        }
        parts.push(format!("{} legs, {} turns", self.legs, self.turns));
        // The LED only when it changed after the fault (the first change is
        // the boot's).
        let fault_at = self.fault_at_s.unwrap_or(0.0);
        let changed = self.led_changes.iter().skip(1).last();
        if let Some((t, c)) = changed.filter(|(t, _)| *t > fault_at) {
            parts.push(format!("battery LED {c} from {t:.3} s"));
        }
        if let Some((l, r)) = self.first_leg_count_error.filter(|e| *e != (0, 0)) {
            parts.push(format!("first leg counts off by {l:+} left, {r:+} right"));
        }
        for (on, off) in &self.brownouts {
            parts.push(match off {
                Some(off) => format!("held in brown-out reset {on:.3}-{off:.3} s"),
                None => format!("held in brown-out reset from {on:.3} s"),
            });
        }
        if self.error_replies > 0 {
            parts.push(format!("{} error replies", self.error_replies));
        }
        parts.push(format!(
            "ended {:.0} cm from the start",
            self.end_distance_cm
        ));
        parts.join(", ")
    }
}

/// How much longer than at the set-points the first leg took (0.1: 10 %).
pub fn leg_overrun(o: &Observed) -> Option<f64> {
    let nominal = o.first_leg_counts? / o.setpoint_counts_per_s;
    Some(o.first_leg_drive_s? / nominal - 1.0)
}

/// One row of `hil faults`.
#[derive(Debug, Clone, Serialize)]
pub struct FaultRow {
    pub fault: String,
    pub what: String,
    /// The firmware under test by its name (a described firmware's
    /// `firmware.name`, else its ELF's): what `robust` and
    /// `robust_observed` are of, and the text report's label for them.
    pub firmware: String,
    /// The robust build's expected reaction, which the firmware under test
    /// is judged by.
    pub expected: String,
    /// What the firmware under test did.
    pub robust: String,
    pub thesis: String,
    /// The verdict is [`Verdict::Pass`].
    pub pass: bool,
    pub verdict: Verdict,
    pub why: String,
    pub robust_observed: Observed,
    pub thesis_observed: Option<Observed>,
}

fn run_case(
    fw: &Firmware,
    robot: &RobotConfig,
    case: &FaultCase,
    options: &FaultOptions,
) -> Result<Observed, BenchError> {
    let opts = TestOptions {
        leg_mm: case.leg_mm,
        bench: BenchOptions {
            seed: options.seed,
            board: options.board,
            ..Default::default()
        },
        limit_s: Some(case.limit_s),
        record: false,
        faults: case.faults.clone(),
        framed: case.framed,
        params: Vec::new(),
        hang_after_s: Some(options.hang_after_s),
        tell: Default::default(),
        description: options.description.clone(),
        start_delay_s: 0.0,
        tap: None,
    };
    let run = run_test(fw.clone(), robot, case.test, &opts)?;
    Ok(Observed::from_run(
        &run,
        opts.bench.clock.hz(),
        &options.board,
    ))
}

/// Run one fault against the robust build and, when given, the thesis build.
pub fn run_fault(
    case: &FaultCase,
    robust: &Firmware,
    thesis: Option<&Firmware>,
    robot: &RobotConfig,
    options: &FaultOptions,
) -> Result<FaultRow, BenchError> {
    let r = run_case(robust, robot, case, options)?;
    let (verdict, why) = judge(case, &r);
    // The thesis build may do anything: whatever the bench sees is a finding.
    let t = match thesis {
        Some(fw) => match run_case(fw, robot, case, options) {
            Ok(o) => Some(Ok(o)),
            Err(e) => Some(Err(e.to_string())),
        },
        None => None,
    };
    let firmware = match &options.description {
        Some(d) => d.firmware_name(robust),
        None => robust.name(),
    };
    Ok(FaultRow {
        fault: case.name.into(),
        what: case.what.into(),
        firmware,
        expected: case.expected.into(),
        robust: r.describe(),
        thesis: match &t {
            Some(Ok(o)) => o.describe(),
            Some(Err(e)) => format!("the bench stopped it: {e}"),
            None if options.description.is_some() => {
                "not run (compared with the robust build only, not with a described firmware)"
                    .into()
            }
            None => "not run (no thesis build)".into(),
        },
        pass: verdict == Verdict::Pass,
        verdict,
        why,
        robust_observed: r,
        thesis_observed: t.and_then(|t| t.ok()),
    })
}

/// The verdict on the robust build's run of `case`, and why. A fault that
/// never fired fails the case before its check is asked: the check would
/// judge a run without the fault (a reset that never came leaves the motors
/// as a fault-free run does).
fn judge(case: &FaultCase, o: &Observed) -> (Verdict, String) {
    if !o.faults_never_fired.is_empty() {
        let list: Vec<String> = o.faults_never_fired.iter().map(|i| i.to_string()).collect();
        return (
            Verdict::NotFired,
            format!(
                "fault {} never fired in {:.1} s of robot time: the run shows no reaction to it",
                list.join(", "),
                o.robot_time_s
            ),
        );
    }
    match case.check {
        None => (
            Verdict::NotJudged,
            "not judged: the scenario states no expectation".into(),
        ),
        Some(check) => match check(o) {
            Ok(why) => (Verdict::Pass, why),
            Err(why) => (Verdict::Fail, why),
        },
    }
}

/// The `hil faults` table.
pub fn render(rows: &[FaultRow]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for r in rows {
        let _ = writeln!(s, "{} [{}]", r.fault, r.verdict.tag());
        let _ = writeln!(s, "  fault     {}", r.what);
        let _ = writeln!(s, "  expected  {}", r.expected);
        let _ = writeln!(s, "  {:<9} {}", r.firmware, r.robust);
        let _ = writeln!(s, "  judged    {}", r.why);
        let _ = writeln!(s, "  thesis    {}", r.thesis);
        let thesis = r.thesis_observed.iter().flat_map(|o| &o.warnings);
        for w in r
            .robust_observed
            .warnings
            .iter()
            .map(|w| (r.firmware.as_str(), w))
            .chain(thesis.map(|w| ("thesis", w)))
        {
            let _ = writeln!(s, "  warning   {}: {}", w.0, w.1);
        }
    }
    let count = |v: Verdict| rows.iter().filter(|r| r.verdict == v).count();
    let _ = write!(
        s,
        "{} passed, {} failed",
        count(Verdict::Pass),
        count(Verdict::Fail)
    );
    for (v, what) in [
        (Verdict::NotFired, "with a fault that never fired (failed)"),
        (Verdict::NotJudged, "ran, not judged"),
    ] {
        if count(v) > 0 {
            let _ = write!(s, ", {} {what}", count(v));
        }
    }
    let _ = writeln!(s);
    s
}

/// A scenario file as a fault case: run against both builds and reported,
/// not judged (a scenario file states no expectation). The case's texts
/// live as long as the process: a CLI run loads one scenario. Err: the
/// scenario names a test of a firmware's own, which the fault cases' thesis
/// and robust builds do not have.
pub fn from_scenario(
    path: &std::path::Path,
    s: &crate::runs::scenario::Scenario,
) -> Result<FaultCase, String> {
    let test = match &s.test {
        None => Test::Line,
        Some(t) => t.thesis().ok_or_else(|| {
            format!(
                "the scenario {}: test = {t:?}: hil faults runs the thesis' tests \
                 (umbmark-cw, umbmark-ccw, line, triangle)",
                path.display()
            )
        })?,
    };
    let leak = |s: String| -> &'static str { Box::leak(s.into_boxed_str()) };
    let name = s.name.clone().unwrap_or_else(|| {
        path.file_stem()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scenario".into())
    });
    Ok(FaultCase {
        name: leak(name),
        what: leak(format!(
            "{} fault(s) from the scenario {}",
            s.faults.len(),
            path.display()
        )),
        expected: "not stated (a scenario file has no expectation)",
        test,
        leg_mm: s.leg_mm.unwrap_or(2000.0),
        faults: s.scheduled(),
        limit_s: s.limit_s.unwrap_or(60.0),
        framed: s.framed,
        check: None,
    })
}
