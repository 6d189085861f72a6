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
use crate::elf::Firmware;
use crate::experiment::{run_test, Test, TestOptions, TestRun};

mod encoder_dropout;
mod encoder_stuck_b;
mod encoder_swapped;
mod link_corruption;
mod missed_counts;
mod motor_disconnected;
mod motor_stall;
mod reset_mid_test;
mod turn_slip_burst;

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
    /// Judge the robust build's run: Ok(why) passes, Err(why) fails.
    pub check: fn(&Observed) -> Result<String, String>,
}

/// Every fault, in a fixed order.
pub fn library() -> Vec<FaultCase> {
    vec![
        encoder_dropout::case(),
        encoder_stuck_b::case(),
        encoder_swapped::case(),
        missed_counts::case(),
        motor_disconnected::case(),
        motor_stall::case(),
        turn_slip_burst::case(),
        link_corruption::case(),
        reset_mid_test::case(),
    ]
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
            "expected motors off within {:.0} ms and a fault code; saw {t:?} s and code {c:?}",
            max_s * 1e3
        )),
    }
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
    pub bluetooth_reply_bytes: usize,
}

impl Observed {
    pub fn from_run(run: &TestRun, clock_hz: u32) -> Self {
        let fault_cycle = run.applied.first().map(|a| a.0);
        let motors_off_after_s = fault_cycle.and_then(|fc| {
            // Replay the drive log to find the first all-off moment after
            // the fault.
            let mut duty = [0.0f64; 10];
            for e in &run.drive {
                duty[e.pin as usize] = e.duty;
                if e.cycle >= fc && duty[6..10].iter().all(|d| *d == 0.0) {
                    return Some((e.cycle - fc) as f64 / clock_hz as f64);
                }
            }
            None
        });
        let leg = run.legs.first();
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
            first_leg_counts: leg
                .map(|l| (l.firmware_count_left + l.firmware_count_right) as f64 / 2.0),
            first_leg_plant_mm: leg.map(|l| l.plant_distance_mm),
            first_leg_arc_mm: leg.map(|l| l.plant_arc_mm),
            bluetooth_reply_bytes: run.bluetooth_out.len(),
        }
    }

    /// One line for a person.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        parts.push(if self.completed {
            "completed".to_string()
        } else {
            "did not complete (hang or runaway)".to_string()
        });
        match self.motors_off_after_s {
            Some(t) => parts.push(format!("motors off {:.0} ms after the fault", t * 1e3)),
            None => parts.push("motors never all off after the fault".into()),
        }
        if let Some(c) = self.fault_code.filter(|c| *c != 0) {
            parts.push(format!("fault code {c}"));
        }
        parts.push(format!("{} legs, {} turns", self.legs, self.turns));
        parts.push(format!(
            "ended {:.0} cm from the start",
            self.end_distance_cm
        ));
        parts.join(", ")
    }
}

/// One row of `hil faults`.
#[derive(Debug, Clone, Serialize)]
pub struct FaultRow {
    pub fault: String,
    pub what: String,
    pub expected: String,
    pub robust: String,
    pub thesis: String,
    pub pass: bool,
    pub why: String,
    pub robust_observed: Observed,
    pub thesis_observed: Option<Observed>,
}

fn run_case(
    fw: &Firmware,
    robot: &RobotConfig,
    case: &FaultCase,
    seed: u64,
) -> Result<Observed, BenchError> {
    let opts = TestOptions {
        leg_mm: case.leg_mm,
        bench: BenchOptions {
            seed,
            ..Default::default()
        },
        limit_s: Some(case.limit_s),
        record: false,
        faults: case.faults.clone(),
        framed: case.framed,
        params: Vec::new(),
    };
    let run = run_test(fw.clone(), robot, case.test, &opts)?;
    Ok(Observed::from_run(&run, opts.bench.clock.hz()))
}

/// Run one fault against the robust build and, when given, the thesis build.
pub fn run_fault(
    case: &FaultCase,
    robust: &Firmware,
    thesis: Option<&Firmware>,
    robot: &RobotConfig,
    seed: u64,
) -> Result<FaultRow, BenchError> {
    let r = run_case(robust, robot, case, seed)?;
    let (pass, why) = match (case.check)(&r) {
        Ok(why) => (true, why),
        Err(why) => (false, why),
    };
    // The thesis build may do anything: whatever the bench sees is a finding.
    let t = match thesis {
        Some(fw) => match run_case(fw, robot, case, seed) {
            Ok(o) => Some(Ok(o)),
            Err(e) => Some(Err(e.to_string())),
        },
        None => None,
    };
    Ok(FaultRow {
        fault: case.name.into(),
        what: case.what.into(),
        expected: case.expected.into(),
        robust: r.describe(),
        thesis: match &t {
            Some(Ok(o)) => o.describe(),
            Some(Err(e)) => format!("the bench stopped it: {e}"),
            None => "not run (no thesis build)".into(),
        },
        pass,
        why,
        robust_observed: r,
        thesis_observed: t.and_then(|t| t.ok()),
    })
}

/// The `hil faults` table.
pub fn render(rows: &[FaultRow]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    for r in rows {
        let _ = writeln!(s, "{} [{}]", r.fault, if r.pass { "pass" } else { "FAIL" });
        let _ = writeln!(s, "  fault     {}", r.what);
        let _ = writeln!(s, "  expected  {}", r.expected);
        let _ = writeln!(s, "  robust    {}", r.robust);
        let _ = writeln!(s, "  judged    {}", r.why);
        let _ = writeln!(s, "  thesis    {}", r.thesis);
    }
    let passed = rows.iter().filter(|r| r.pass).count();
    let _ = writeln!(s, "{passed} passed, {} failed", rows.len() - passed);
    s
}
