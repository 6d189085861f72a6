//! The telemetry the page draws: the robot polled at a fixed interval of
//! its own time, whatever the pace it is served at, and the samples sent
//! to the page in batches.
//!
//! At 20x a poll every 250 ms of wall time would be one sample per 5 s of
//! robot time, and a turn (about a second) would never show on the speed
//! chart. Polling every [`SAMPLE_S`] of robot time instead keeps the chart's
//! resolution the same at every speed; the page gets one event per about
//! [`SAMPLE_S`] of wall time with every sample taken since the last one,
//! so a fast robot does not flood it with events.

use std::sync::Arc;
use std::time::Duration;

use serde_json::json;
use tokio::sync::Mutex;

use super::floor::{end_error, in_start_frame, run_pose};
use super::{Shared, TICK_S};
use crate::clients::station::client::{Link, LinkError, Notice};
use crate::clients::station::emulated::EmulatedRobot;

/// Robot time between two telemetry samples: a GET_TELEMETRY and a
/// GET_STATE take ~60 ms on the wire at 9600 baud (in robot time, whatever
/// the pace), so 4 samples per robot second leave room for commands.
pub(super) const SAMPLE_S: f64 = 0.25;

/// Samples per event to the page at `pace` robot seconds per wall second:
/// about one event per [`SAMPLE_S`] of wall time.
fn per_event(pace: f64) -> usize {
    pace.ceil().clamp(1.0, 1000.0) as usize
}

/// Telemetry to the page until the link fails; `pace`: robot seconds per
/// wall second (an emulated robot's speed; 1 for a device on a port).
pub(super) async fn poll(
    app: Shared,
    link: Arc<Mutex<Link>>,
    emulator: Option<Arc<EmulatedRobot>>,
    setpoints: (f32, f32),
    pace: f64,
) {
    let mut every = tokio::time::interval(Duration::from_secs_f64(SAMPLE_S / pace));
    // A late poll (a busy host, a command holding the link) shifts the
    // next ones rather than bursting to catch up.
    every.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut samples = Vec::new();
    let send = |event: serde_json::Value| {
        let _ = app.events.send(event.to_string());
    };
    loop {
        every.tick().await;
        let got = {
            let mut l = link.lock().await;
            match (l.telemetry().await, l.state().await) {
                (Ok(t), Ok(s)) => Ok((t, s, l.take_notices())),
                (Err(e), _) | (_, Err(e)) => Err(e),
            }
        };
        let (t, s, notices) = match got {
            Ok(v) => v,
            Err(e) => {
                send(json!({ "kind": "error", "message": e.to_string() }));
                if matches!(e, LinkError::PortGone { .. }) {
                    return;
                }
                continue;
            }
        };
        let view = emulator.as_ref().map(|e| e.view());
        let started = app.start.lock().ok().and_then(|s| *s);
        let run = started
            .zip(view.as_ref())
            .map(|(s, v)| run_pose(&s, v.x_mm, v.y_mm, v.theta_rad));
        samples.push(json!({
            "time_s": f64::from(t.ticks) * TICK_S,
            "speed_left": t.speed_left,
            "speed_right": t.speed_right,
            "setpoint_left": setpoints.0,
            "setpoint_right": setpoints.1,
            "state": s.state,
            "phase": s.phase,
            "segment": s.segment,
            "run": run,
        }));
        // The samples go out before a notice, so the page has a run's
        // telemetry before its end.
        if samples.len() >= per_event(pace) || !notices.is_empty() {
            send(json!({
                "kind": "telemetry",
                "duty_left": t.duty_left,
                "duty_right": t.duty_right,
                "count_left": t.left_count,
                "count_right": t.right_count,
                "state": s.state,
                "phase": s.phase,
                "test": s.test,
                "segment": s.segment,
                "fault": s.fault,
                "tests_done": s.tests_done,
                "speed_left": t.speed_left,
                "speed_right": t.speed_right,
                "time_s": f64::from(t.ticks) * TICK_S,
                "pose": view,
                "samples": std::mem::take(&mut samples),
            }));
        }
        for n in notices {
            let start = match (n, &view) {
                (Notice::TestDone { .. }, Some(_)) => {
                    app.start.lock().ok().and_then(|mut s| s.take())
                }
                _ => None,
            };
            let end = start
                .zip(view.as_ref())
                .map(|(s, v)| end_error(&s, v.x_mm, v.y_mm));
            let run_end = start.zip(view.as_ref()).map(|(s, v)| {
                let (x, y) = in_start_frame(&s, v.x_mm, v.y_mm);
                json!({ "id": s.run, "x_cm": x / 10.0, "y_cm": y / 10.0 })
            });
            send(json!({
                "kind": "notice",
                "notice": n,
                "end_error_cm": end,
                "run_end": run_end,
                "leg_mm": start.map(|s| s.leg_mm),
            }));
        }
        if let Some(e) = view.and_then(|v| v.error) {
            send(json!({ "kind": "error", "message": format!("the emulated robot stopped: {e}") }));
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fast_robot_sends_about_one_event_per_sample_interval_of_wall_time() {
        assert_eq!(per_event(1.0), 1);
        assert_eq!(per_event(0.5), 1);
        assert_eq!(per_event(20.0), 20);
        assert_eq!(per_event(2.5), 3);
    }
}
