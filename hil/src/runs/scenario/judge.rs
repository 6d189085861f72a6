//! What a condition means on what was observed: the UART pattern or frame
//! found in a byte log, a motor, variable or pose judged on one reading,
//! and a condition in words. Shared by the expectations judged over a
//! finished run (`eval.rs`) and the harness's live waits
//! (`crate::clients::harness`).

use plant_model::Side;

use super::expect::{Condition, Direction, MotorState};
use crate::mcu::clock::Clock;

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
            Some(s) => format!(
                "a frame {} with status {s}",
                crate::firmware::link::FrameId::from_byte(*id)
            ),
            None => format!("a frame {}", crate::firmware::link::FrameId::from_byte(*id)),
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

/// A motor's state and drive duty from its inputs (DRV8833 terms).
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
