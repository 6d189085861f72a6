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

use super::expect::{Anchor, Condition, Direction, Expectation, Level, MotorState, VarType};
use super::Scenario;
use crate::bench::{Bench, Observer, Step};
use crate::board::Board;
use crate::elf::Firmware;
use crate::experiment::TestRun;
use crate::time::Clock;

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
                    let p = crate::board::pin_named(pin).ok_or_else(|| {
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

/// The first cycle in `[open, close]` at which `pattern` has arrived whole
/// on USART `n` (all its bytes at or after `open`); else what came.
pub(crate) fn find_pattern(
    log: &[(u64, u8, u8)],
    n: u8,
    pattern: &[u8],
    open: u64,
    close: u64,
) -> Result<u64, String> {
    let bytes: Vec<(u64, u8)> = log
        .iter()
        .filter(|(c, u, _)| *u == n && *c >= open)
        .map(|(c, _, b)| (*c, *b))
        .collect();
    let found = bytes
        .windows(pattern.len())
        .find(|w| w.iter().map(|(_, b)| *b).eq(pattern.iter().copied()))
        .map(|w| w[w.len() - 1].0)
        .filter(|c| *c <= close);
    found.ok_or_else(|| {
        let seen: Vec<u8> = bytes
            .iter()
            .filter(|(c, _)| *c <= close)
            .map(|(_, b)| *b)
            .collect();
        format!(
            "{} byte(s) on USART{n} in the window: {}",
            seen.len(),
            shown(&seen)
        )
    })
}

/// Bytes for a message: as text when printable, else hex; the first 48.
fn shown(b: &[u8]) -> String {
    let head = &b[..b.len().min(48)];
    let more = if b.len() > 48 { " ..." } else { "" };
    if head.iter().all(|c| c.is_ascii_graphic() || *c == b' ') {
        format!("{:?}{more}", String::from_utf8_lossy(head))
    } else {
        let hex: Vec<String> = head.iter().map(|c| format!("{c:02x}")).collect();
        format!("[{}]{more}", hex.join(" "))
    }
}

/// The first frame the firmware sent on USART `n` in `[open, close]` with
/// that id (and status, and data prefix); else the ids it did send.
#[allow(clippy::too_many_arguments)]
pub(crate) fn find_frame(
    log: &[(u64, u8, u8)],
    n: u8,
    id: u8,
    status: Option<u8>,
    data: Option<&[u8]>,
    open: u64,
    close: u64,
    clock: Clock,
) -> Result<u64, String> {
    // A generous inter-byte timeout: the bench's bytes come back to back.
    let ms = clock.cycles_per_ms().max(1);
    let mut parser = henrytwo_protocol::frame::Parser::new(100);
    let mut ids = Vec::new();
    for (c, _, b) in log
        .iter()
        .filter(|(c, u, _)| *u == n && *c >= open && *c <= close)
    {
        let now = (c / ms) as u32;
        parser.poll(now);
        if let Some(henrytwo_protocol::frame::Event::Frame(p)) = parser.push(*b, now) {
            let fits = p.first() == Some(&id)
                && status.is_none_or(|s| p.get(1) == Some(&s))
                && data.is_none_or(|d| p.get(2..).is_some_and(|rest| rest.starts_with(d)));
            if fits {
                return Ok(*c);
            }
            ids.push(format!("0x{:02x}", p[0]));
        }
    }
    Err(if ids.is_empty() {
        "no frame".into()
    } else {
        format!("frames with id {}", ids.join(", "))
    })
}

/// A condition in a message's words.
pub(crate) fn describe(c: &Condition) -> String {
    match c {
        Condition::Uart {
            text,
            bytes,
            dir,
            usart,
        } => {
            let p = text.as_ref().map_or_else(
                || shown(bytes.as_deref().unwrap_or_default()),
                |t| format!("{t:?}"),
            );
            let on = usart.map_or_else(|| "the command link".to_owned(), |n| format!("USART{n}"));
            match dir {
                Direction::Tx => format!("the firmware sent {p} on {on}"),
                Direction::Rx => format!("{p} arrived on {on}"),
            }
        }
        Condition::Frame { id, status, .. } => match status {
            Some(s) => format!("a frame with id 0x{id:02x} and status {s}"),
            None => format!("a frame with id 0x{id:02x}"),
        },
        Condition::Motor {
            side,
            state,
            duty_min,
            duty_max,
        } => {
            let mut s = format!("{side:?} motor(s) {state:?}").to_lowercase();
            if let Some(v) = duty_min {
                s += &format!(", duty >= {v}");
            }
            if let Some(v) = duty_max {
                s += &format!(", duty <= {v}");
            }
            s
        }
        Condition::Pin { pin, level } => format!("{pin} {level:?}")
            .to_lowercase()
            .replace(&pin.to_lowercase(), pin),
        Condition::Var {
            symbol,
            eq,
            ne,
            min,
            max,
            ..
        } => {
            let mut parts = Vec::new();
            for (op, v) in [("==", eq), ("!=", ne), (">=", min), ("<=", max)] {
                if let Some(v) = v {
                    parts.push(format!("{symbol} {op} {v}"));
                }
            }
            parts.join(" and ")
        }
        Condition::Pose {
            x_mm,
            y_mm,
            distance_mm,
            heading_deg,
            tol_mm,
            tol_pct,
            tol_deg,
        } => {
            let tol = |v: f64| tol_mm.unwrap_or_else(|| v.abs() * tol_pct.unwrap_or(0.0) / 100.0);
            let mut parts = Vec::new();
            for (what, v) in [("x", x_mm), ("y", y_mm), ("distance", distance_mm)] {
                if let Some(v) = v {
                    parts.push(format!("{what} {v} ± {:.1} mm", tol(*v)));
                }
            }
            if let (Some(h), Some(t)) = (heading_deg, tol_deg) {
                parts.push(format!("heading {h} ± {t}°"));
            }
            format!("pose {}", parts.join(", "))
        }
    }
}

/// A motor's state and drive duty from its inputs (DRV8833 terms).
/// One motor against a `motor` condition's state and duty bounds, from
/// its bridge inputs: whether it holds, and what was seen.
pub(crate) fn motor_holds(
    want: MotorState,
    duty_min: Option<f64>,
    duty_max: Option<f64>,
    side: Side,
    inputs: (f64, f64),
) -> (bool, String) {
    let (got, duty) = motor_state(inputs);
    let holds = state_is(want, got)
        && duty_min.is_none_or(|m| duty >= m)
        && duty_max.is_none_or(|m| duty <= m);
    (
        holds,
        format!("{side:?} {got:?} duty {duty:.3}").to_lowercase(),
    )
}

/// A `var` condition's comparisons of the value `v` (false for any other
/// condition).
pub(crate) fn var_holds(c: &Condition, v: f64) -> bool {
    let Condition::Var {
        eq, ne, min, max, ..
    } = c
    else {
        return false;
    };
    eq.is_none_or(|e| v == e)
        && ne.is_none_or(|e| v != e)
        && min.is_none_or(|m| v >= m)
        && max.is_none_or(|m| v <= m)
}

/// A `pose` condition on the pose `x`, `y` (mm), `theta` (radians): whether
/// it holds (false for any other condition), and what was seen.
pub(crate) fn pose_holds(c: &Condition, x: f64, y: f64, theta: f64) -> (bool, String) {
    let d = x.hypot(y);
    let heading = theta.to_degrees();
    let seen = format!("x {x:.1} mm, y {y:.1} mm, distance {d:.1} mm, heading {heading:.2}°");
    let Condition::Pose {
        x_mm,
        y_mm,
        distance_mm,
        heading_deg,
        tol_mm,
        tol_pct,
        tol_deg,
    } = c
    else {
        return (false, seen);
    };
    let near = |want: f64, got: f64| {
        let tol = tol_mm.unwrap_or_else(|| want.abs() * tol_pct.unwrap_or(0.0) / 100.0);
        (got - want).abs() <= tol
    };
    let holds = x_mm.is_none_or(|v| near(v, x))
        && y_mm.is_none_or(|v| near(v, y))
        && distance_mm.is_none_or(|v| near(v, d))
        && heading_deg.zip(*tol_deg).is_none_or(|(h, t)| {
            // The nearest turn of the heading to the one asked for.
            ((heading - h + 180.0).rem_euclid(360.0) - 180.0).abs() <= t
        });
    (holds, seen)
}

pub(crate) fn motor_state((in1, in2): (f64, f64)) -> (MotorState, f64) {
    let drive = in1 - in2;
    let state = if drive > 0.0 {
        MotorState::Forward
    } else if drive < 0.0 {
        MotorState::Reverse
    } else if in1 > 0.0 {
        MotorState::Brake
    } else {
        MotorState::Coast
    };
    (state, drive.abs())
}

pub(crate) fn state_is(want: MotorState, got: MotorState) -> bool {
    want == got || (want == MotorState::Off && matches!(got, MotorState::Coast | MotorState::Brake))
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
