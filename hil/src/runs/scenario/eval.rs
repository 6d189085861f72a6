//! Judging a run against a scenario's expectations.
//!
//! A [`Watch`] rides along the run as the bench's [`Observer`] of the run
//! loop's checks only (it never asks for every step, so the run keeps its
//! speed and its cycles): at each check it logs what changed of the state
//! the expectations read (bridge inputs, named pins, firmware variables,
//! the plant's pose at its own steps) and keeps the latest state for
//! triage. UART bytes, fault actions, legs and turns come from the run's
//! own records, at the cycles they happened. [`judge`] then walks each
//! expectation's window over those logs: nothing here reads a host clock.

use plant_model::Side;
use serde::Serialize;

use super::expect::{Anchor, Condition, Direction, Expectation, Level, VarType};
use super::Scenario;
use crate::bench::{Bench, Observer, Step};
use crate::board::Board;
use crate::firmware::elf::Firmware;
use crate::mcu::clock::Clock;
use crate::runs::experiment::TestRun;

use super::judge::{describe, find_frame, find_pattern, motor_holds, pose_holds, var_holds};

/// The firmware's bench variables kept in the last state, when it has them.
const STATE_VARS: [(&str, VarType); 10] = [
    ("HT_STATE", VarType::U8),
    ("HT_PHASE", VarType::U8),
    ("HT_SEGMENT", VarType::U8),
    ("HT_FAULT", VarType::U8),
    ("HT_LEFT_COUNT", VarType::I32),
    ("HT_RIGHT_COUNT", VarType::I32),
    ("HT_DUTY_LEFT", VarType::U8),
    ("HT_DUTY_RIGHT", VarType::U8),
    ("HT_SPEED_LEFT", VarType::F32),
    ("HT_SPEED_RIGHT", VarType::F32),
];

/// A value logged when it changes: (cycle, value).
type Changes<T> = Vec<(u64, T)>;

fn log_change<T: PartialEq>(log: &mut Changes<T>, cycle: u64, value: T) {
    if log.last().is_none_or(|(_, v)| *v != value) {
        log.push((cycle, value));
    }
}

/// A firmware variable the expectations read.
#[derive(Debug, Clone)]
struct Var {
    symbol: String,
    addr: u16,
    ty: VarType,
}

/// The state of the run at its last check, saved for triage on a failure.
#[derive(Debug, Clone, Default, Serialize)]
pub struct LastState {
    pub cycle: u64,
    pub robot_time_s: f64,
    pub x_mm: f64,
    pub y_mm: f64,
    pub heading_deg: f64,
    /// Wheel speeds, rad/s (left, right).
    pub wheel_speed_rad_s: [f64; 2],
    /// Each motor's bridge inputs as the DRV8833's (in1, in2) duties (left, right).
    pub pwm: [(f64, f64); 2],
    /// The firmware's bench variables it has, by symbol.
    pub firmware: std::collections::BTreeMap<String, f64>,
}

/// What a run logged for its expectations (see the module docs).
pub struct Watch {
    clock: Clock,
    pins: Vec<(String, crate::board::Pin)>,
    pin_log: Vec<Changes<bool>>,
    vars: Vec<Var>,
    var_log: Vec<Changes<f64>>,
    /// Bridge inputs (in1, in2) by side.
    motor_log: [Changes<(f64, f64)>; 2],
    /// The plant's pose at its own steps: (x mm, y mm, heading rad), when
    /// an expectation reads it.
    pose_log: Option<Changes<(f64, f64, f64)>>,
    state_vars: Vec<Var>,
    first: Option<u64>,
    last: LastState,
}

impl Watch {
    /// A watch for `scenario`'s expectations on `firmware`: an error line
    /// for a `var` whose symbol the ELF lacks, or whose size is not its type's.
    pub fn new(scenario: &Scenario, firmware: &Firmware, clock: Clock) -> Result<Self, String> {
        let mut pins = Vec::new();
        let mut vars = Vec::new();
        let mut pose = false;
        for (i, e) in scenario.expect.iter().enumerate() {
            match &e.that {
                Condition::Pin { pin, .. } => {
                    // Scenarios run the robust firmware, a build for the Mega.
                    let mega = crate::board::Mcu::Atmega2560;
                    let p = crate::board::pin_named(mega, pin).ok_or_else(|| {
                        format!("expect {}: pin {pin:?} is not a Mega pin", i + 1)
                    })?;
                    if !pins.iter().any(|(n, _)| n == pin) {
                        pins.push((pin.clone(), p));
                    }
                }
                Condition::Var { symbol, ty, .. } => {
                    let addr = firmware.variable(symbol, ty.size()).map_err(|err| {
                        format!(
                            "expect {} ({}): {err} (var type = {:?} reads {} byte(s))",
                            i + 1,
                            e.label(i),
                            ty,
                            ty.size()
                        )
                    })?;
                    if !vars.iter().any(|v: &Var| v.symbol == *symbol) {
                        vars.push(Var {
                            symbol: symbol.clone(),
                            addr,
                            ty: *ty,
                        });
                    }
                }
                Condition::Pose { .. } => pose = true,
                _ => {}
            }
        }
        let state_vars = STATE_VARS
            .iter()
            .filter_map(|(s, ty)| {
                firmware.variable(s, ty.size()).ok().map(|addr| Var {
                    symbol: (*s).into(),
                    addr,
                    ty: *ty,
                })
            })
            .collect();
        Ok(Self {
            clock,
            pin_log: vec![Vec::new(); pins.len()],
            pins,
            var_log: vec![Vec::new(); vars.len()],
            vars,
            motor_log: [Vec::new(), Vec::new()],
            pose_log: pose.then(Vec::new),
            state_vars,
            first: None,
            last: LastState::default(),
        })
    }

    /// The state at the run's last check.
    pub fn last_state(&self) -> &LastState {
        &self.last
    }

    fn read(bench: &Bench, v: &Var) -> f64 {
        let mut b = [0u8; 4];
        for (k, byte) in b.iter_mut().enumerate().take(v.ty.size() as usize) {
            *byte = bench.read_u8(v.addr + k as u16);
        }
        v.ty.value(b)
    }
}

impl Observer for Watch {
    fn step(&mut self, _step: &Step) {}

    fn wants_steps(&self) -> bool {
        false
    }

    fn check(&mut self, bench: &Bench) {
        let cycle = bench.cycle();
        self.first.get_or_insert(cycle);
        let robot = bench.core().robot();
        for (k, side) in [Side::Left, Side::Right].into_iter().enumerate() {
            let (a, b) = robot.bridge_inputs(side);
            log_change(&mut self.motor_log[k], cycle, (a.get(), b.get()));
            self.last.pwm[k] = (a.get(), b.get());
            self.last.wheel_speed_rad_s[k] = robot.wheel_speed(side).0;
        }
        for (k, (_, pin)) in self.pins.iter().enumerate() {
            let high = bench.read_u8(pin.pin_register()) & (1 << pin.bit) != 0;
            log_change(&mut self.pin_log[k], cycle, high);
        }
        for (k, v) in self.vars.iter().enumerate() {
            log_change(&mut self.var_log[k], cycle, Self::read(bench, v));
        }
        let pose = robot.pose();
        let (x, y, theta) = (pose.x().0, pose.y().0, pose.theta().0);
        if let Some(log) = &mut self.pose_log {
            // At the plant's own time: the cycle its pose is of.
            let at = self.clock.cycle_at_or_after(robot.now()).min(cycle);
            log_change(log, at, (x, y, theta));
        }
        self.last.cycle = cycle;
        self.last.robot_time_s = self.clock.seconds(cycle).0;
        self.last.x_mm = x;
        self.last.y_mm = y;
        self.last.heading_deg = theta.to_degrees();
        for v in &self.state_vars {
            self.last
                .firmware
                .insert(v.symbol.clone(), Self::read(bench, v));
        }
    }

    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any> {
        self
    }
}

/// The verdict on one expectation.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    pub name: String,
    pub pass: bool,
    /// Which expectation, when, what was seen.
    pub message: String,
    /// Robot time the verdict was reached at (s): the cycle the condition
    /// held at, or the one at which the window ended without it.
    pub at_s: Option<f64>,
}

/// A condition's value over the run: (cycle, holds, what was seen), one
/// entry per change, in cycle order.
type Timeline = Vec<(u64, bool, String)>;

/// What the evaluation reads of the run beside the watch.
pub struct Context<'a> {
    pub run: &'a TestRun,
    pub board: &'a Board,
    pub clock: Clock,
}

/// Judge each of `scenario`'s expectations on the run (in file order).
pub fn judge(scenario: &Scenario, watch: &Watch, cx: &Context) -> Vec<Outcome> {
    scenario
        .expect
        .iter()
        .enumerate()
        .map(|(i, e)| judge_one(scenario, i, e, watch, cx))
        .collect()
}

fn judge_one(
    scenario: &Scenario,
    index: usize,
    e: &Expectation,
    watch: &Watch,
    cx: &Context,
) -> Outcome {
    let name = e.label(index);
    let s = |c: u64| cx.clock.seconds(c).0;
    let end = watch.last.cycle.max(watch.first.unwrap_or(0));
    let fail = |message: String, at: Option<u64>| Outcome {
        name: name.clone(),
        pass: false,
        message,
        at_s: at.map(s),
    };
    let Some(open) = anchor_cycle(scenario, e.after, watch, cx) else {
        return fail(
            format!(
                "{name}: after {}: that never happened in {:.3} s of robot time",
                e.after.describe(),
                s(end)
            ),
            None,
        );
    };
    let close = match e.within_ms {
        Some(ms) => open.saturating_add(cx.clock.cycles_in(plant_model::Seconds(ms / 1000.0))),
        None => end,
    };
    let window = match e.within_ms {
        Some(ms) => format!(
            "within {ms} ms of {} (at {:.3} s)",
            e.after.describe(),
            s(open)
        ),
        None => format!(
            "from {} (at {:.3} s) to the end",
            e.after.describe(),
            s(open)
        ),
    };
    let what = describe(&e.that);
    // An event (bytes, a frame) happens once; a state holds over time.
    let found = match &e.that {
        Condition::Uart {
            usart,
            text,
            bytes,
            dir,
        } => {
            let pattern = text.as_ref().map_or_else(
                || bytes.clone().unwrap_or_default(),
                |t| t.as_bytes().to_vec(),
            );
            let n = usart.unwrap_or(cx.board.command_uart.usart);
            let log = match dir {
                Direction::Tx => &cx.run.uart,
                Direction::Rx => &cx.run.uart_rx,
            };
            Some(find_pattern(log, n, &pattern, open, close))
        }
        Condition::Frame {
            usart,
            id,
            status,
            data,
        } => {
            let n = usart.unwrap_or(cx.board.command_uart.usart);
            Some(find_frame(
                &cx.run.uart,
                n,
                *id,
                *status,
                data.as_deref(),
                open,
                close,
                cx.clock,
            ))
        }
        _ => None,
    };
    if let Some(found) = found {
        return match found {
            Ok(at) => Outcome {
                name: name.clone(),
                pass: true,
                message: format!("{name}: {what} at {:.3} s, {window}", s(at)),
                at_s: Some(s(at)),
            },
            Err(seen) => fail(
                format!(
                    "{name}: expected {what} {window}; not seen by {:.3} s ({seen})",
                    s(close.min(end))
                ),
                Some(close.min(end)),
            ),
        };
    }
    let timeline = timeline(&e.that, watch);
    let verdict = if e.throughout {
        throughout(&timeline, open, close)
    } else {
        reaches(&timeline, open, close)
    };
    match verdict {
        Ok(at) => Outcome {
            name: name.clone(),
            pass: true,
            message: format!(
                "{name}: {what} {} {window}",
                if e.throughout {
                    "throughout".to_owned()
                } else {
                    format!("at {:.3} s,", s(at))
                }
            ),
            at_s: Some(s(at)),
        },
        Err((at, seen)) => {
            let how = if e.throughout {
                "throughout"
            } else {
                "at some point"
            };
            let at = at.min(end);
            fail(
                format!(
                    "{name}: expected {what} {how} {window}; at {:.3} s: {seen}",
                    s(at)
                ),
                Some(at),
            )
        }
    }
}

/// The cycle an anchor's event happened at, None when it never did.
fn anchor_cycle(scenario: &Scenario, a: Anchor, watch: &Watch, cx: &Context) -> Option<u64> {
    let run = cx.run;
    match a {
        Anchor::Start => watch.first,
        Anchor::End => Some(watch.last.cycle),
        Anchor::Time { s } => Some(cx.clock.cycles_in(plant_model::Seconds(s))),
        Anchor::LegStart { n } => run.legs.get(n - 1).map(|l| l.start_cycle),
        Anchor::TurnStart { n } => run.turns.get(n - 1).map(|t| t.start_cycle),
        Anchor::Fault { n } => {
            // The k-th application of that action, k counting the file's
            // earlier faults with the same action (their undo is another).
            let action = &scenario.faults.get(n - 1)?.action;
            let k = scenario.faults[..n - 1]
                .iter()
                .filter(|f| f.action == *action)
                .count();
            run.applied
                .iter()
                .filter(|(_, a)| a == action)
                .nth(k)
                .map(|(c, _)| *c)
        }
    }
}

/// Ok(cycle) at which the timeline holds first in `[open, close]`, else
/// Err(cycle, seen) of the window's last state.
fn reaches(t: &Timeline, open: u64, close: u64) -> Result<u64, (u64, String)> {
    let at_open = t.iter().rev().find(|(c, ..)| *c <= open);
    if let Some((_, true, _)) = at_open {
        return Ok(open);
    }
    if let Some((c, ..)) = t.iter().find(|(c, h, _)| *h && *c > open && *c <= close) {
        return Ok(*c);
    }
    let last = t.iter().rev().find(|(c, ..)| *c <= close);
    Err((
        close,
        last.map_or_else(|| "nothing recorded".into(), |l| l.2.clone()),
    ))
}

/// Ok(open) when the timeline holds over all of `[open, close]`, else
/// Err(cycle, seen) of the first state that does not.
fn throughout(t: &Timeline, open: u64, close: u64) -> Result<u64, (u64, String)> {
    match t.iter().rev().find(|(c, ..)| *c <= open) {
        None => return Err((open, "nothing recorded yet".into())),
        Some((_, false, seen)) => return Err((open, seen.clone())),
        _ => {}
    }
    match t.iter().find(|(c, h, _)| !*h && *c > open && *c <= close) {
        Some((c, _, seen)) => Err((*c, seen.clone())),
        None => Ok(open),
    }
}

/// The condition's timeline from the watch's logs.
fn timeline(cond: &Condition, w: &Watch) -> Timeline {
    match cond {
        Condition::Motor {
            side,
            state,
            duty_min,
            duty_max,
        } => {
            let sides = side.sides();
            let idx = |s: &Side| if *s == Side::Left { 0 } else { 1 };
            let mut cycles: Vec<u64> = sides
                .iter()
                .flat_map(|s| w.motor_log[idx(s)].iter().map(|(c, _)| *c))
                .collect();
            cycles.sort_unstable();
            cycles.dedup();
            cycles
                .into_iter()
                .map(|c| {
                    let mut holds = true;
                    let mut seen = Vec::new();
                    for s in sides {
                        let log = &w.motor_log[idx(s)];
                        let Some((_, inputs)) = log.iter().rev().find(|(at, _)| *at <= c) else {
                            holds = false;
                            continue;
                        };
                        let (h, what) = motor_holds(*state, *duty_min, *duty_max, *s, *inputs);
                        holds &= h;
                        seen.push(what);
                    }
                    (c, holds, seen.join(", "))
                })
                .collect()
        }
        Condition::Pin { pin, level } => {
            let k = w
                .pins
                .iter()
                .position(|(n, _)| n == pin)
                .expect("the watch has every pin");
            w.pin_log[k]
                .iter()
                .map(|(c, high)| {
                    let holds = *high == (*level == Level::High);
                    (
                        *c,
                        holds,
                        format!("{pin} {}", if *high { "high" } else { "low" }),
                    )
                })
                .collect()
        }
        Condition::Var { symbol, .. } => {
            let k = w
                .vars
                .iter()
                .position(|v| v.symbol == *symbol)
                .expect("the watch has every var");
            w.var_log[k]
                .iter()
                .map(|(c, v)| (*c, var_holds(cond, *v), format!("{symbol} = {v}")))
                .collect()
        }
        Condition::Pose { .. } => w
            .pose_log
            .iter()
            .flatten()
            .map(|(c, (x, y, theta))| {
                let (holds, seen) = pose_holds(cond, *x, *y, *theta);
                (*c, holds, seen)
            })
            .collect(),
        Condition::Uart { .. } | Condition::Frame { .. } => Vec::new(),
    }
}
