//! A described firmware's tests on the station (`hil ui --tests FILE`).
//!
//! A firmware run from a test description speaks no bench protocol: there
//! is no link to poll and no START_TEST to send. So the station runs each of
//! its tests as `hil run TEST --tests FILE` does ([`run_test_observed`]: the
//! same reset, ready wait, start, end and analysis; same numbers), on its
//! own thread, paced to the wall clock by an observer that sends the page
//! the run's progress (robot time, pose, the legs and turns so far, each
//! USART's new text), then the run's report.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use axum::extract::Json;
use plant_model::RobotConfig;
use serde_json::json;
use tokio::sync::broadcast;

use super::poll::SAMPLE_S;
use super::{ConnectRequest, Connection, Shared, UiError};
use crate::bench::{Bench, Observer, Step};
use crate::clients::station::emulated::{check_speed, Pacer};
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::runs::experiment::{
    legs_and_turns_so_far, run_test_observed, uarts, TestName, TestOptions,
};

/// The leg of a description that fixes none (as `hil run`'s default).
const DEFAULT_LEG_MM: f64 = 2000.0;

/// A described firmware's robot, as connected: what each test runs on.
#[derive(Clone)]
pub(super) struct Target {
    robot: RobotConfig,
    speed: f64,
}

/// A described test running on its own thread. Stopped (or replaced), it
/// runs out unpaced and tells the page nothing more.
pub(super) struct LiveRun {
    stop: Arc<AtomicBool>,
    thread: std::thread::JoinHandle<()>,
}

impl LiveRun {
    fn running(&self) -> bool {
        !self.thread.is_finished() && !self.stop.load(Ordering::Relaxed)
    }
}

impl Drop for LiveRun {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// The description's tests, for the page's list.
pub(super) fn test_names(d: &Description) -> Vec<String> {
    d.tests.keys().map(|t| t.name().to_string()).collect()
}

/// Connect an emulated robot for `d`'s tests: nothing boots until a test
/// starts (each starts from reset, as `hil run` starts it).
pub(super) async fn connect(
    app: &Shared,
    d: &Description,
    req: ConnectRequest,
) -> Result<Json<serde_json::Value>, UiError> {
    let ConnectRequest::Emulated { config, speed } = req.clone() else {
        return Err(UiError::Input(format!(
            "{}: a described firmware's tests run on the emulated robot (the station starts \
             them on the bench, as hil run TEST --tests FILE does); pick an emulated robot",
            d.path
        )));
    };
    check_speed(speed).map_err(|e| UiError::Input(e.to_string()))?;
    let (_, robot) = super::offered_robot(app, &config)?;
    let label = format!("emulated {config} at {speed}x ({})", d.path);
    let body = json!({
        "robot": label,
        "key": format!("emulated-{config}"),
        "emulated": true,
        "described": {
            "file": d.path,
            "firmware": d.firmware_name(&app.options.firmware),
            "tests": test_names(d),
        },
    });
    *app.conn.lock().await = Some(Connection {
        label,
        selection: req,
        link: None,
        emulator: None,
        poller: None,
        described: Some(Target { robot, speed }),
    });
    Ok(Json(body))
}

/// Start `test` of `d` on the connected emulated robot.
pub(super) async fn start(
    app: &Shared,
    d: &Arc<Description>,
    req: serde_json::Value,
) -> Result<Json<serde_json::Value>, UiError> {
    let name = req.get("test").and_then(|t| t.as_str()).ok_or_else(|| {
        UiError::Input(format!(
            "give the test to start as {{\"test\": NAME}}, NAME one of {}",
            test_names(d).join(", ")
        ))
    })?;
    let test: TestName = name.parse().map_err(UiError::Input)?;
    d.test(test.clone())
        .map_err(|e| UiError::Input(e.to_string()))?;
    let target = app
        .conn
        .lock()
        .await
        .as_ref()
        .ok_or(UiError::NotConnected)?
        .described
        .clone()
        .ok_or(UiError::NotConnected)?;
    let mut live = app.live.lock().map_err(|_| UiError::NotConnected)?;
    if live.as_ref().is_some_and(LiveRun::running) {
        return Err(UiError::Busy(
            "a test is running: stop it first, or wait for its end".into(),
        ));
    }
    let opts = TestOptions {
        leg_mm: d
            .leg_mm(None, DEFAULT_LEG_MM)
            .map_err(|e| UiError::Input(e.to_string()))?,
        bench: app.options.bench,
        description: Some(d.clone()),
        ..Default::default()
    };
    let leg_mm = opts.leg_mm;
    *live = Some(spawn(
        app.options.firmware.clone(),
        target,
        test,
        opts,
        app.events.clone(),
    ));
    Ok(Json(json!({ "started": name, "leg_mm": leg_mm })))
}

/// Stop the running test: the page hears no more of it.
pub(super) fn stop(app: &Shared) -> Json<serde_json::Value> {
    if let Ok(mut live) = app.live.lock() {
        *live = None;
    }
    Json(json!({ "stopped": true }))
}

fn spawn(
    firmware: Firmware,
    target: Target,
    test: TestName,
    opts: TestOptions,
    events: broadcast::Sender<String>,
) -> LiveRun {
    let stop = Arc::new(AtomicBool::new(false));
    let thread = {
        let stop = stop.clone();
        std::thread::spawn(move || {
            let observer = Live {
                events: events.clone(),
                stop: stop.clone(),
                test: test.clone(),
                opts: opts.clone(),
                speed: target.speed,
                begun: None,
                next_s: 0.0,
                sent: Vec::new(),
            };
            let result = run_test_observed(
                firmware,
                &target.robot,
                test.clone(),
                &opts,
                Some(Box::new(observer)),
            );
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let event = match result {
                Ok((run, _)) => json!({ "kind": "described_end", "test": test.name(), "run": run }),
                Err(e) => json!({ "kind": "error", "message": format!("test {test}: {e}") }),
            };
            let _ = events.send(event.to_string());
        })
    };
    LiveRun { stop, thread }
}

/// Watches a described test from its start: every [`SAMPLE_S`] of robot
/// time, its progress to the page, then a wait until the wall clock is
/// due (the one reader of the host clock, outside the simulation: the run's
/// cycles are the same watched or not).
struct Live {
    events: broadcast::Sender<String>,
    stop: Arc<AtomicBool>,
    test: TestName,
    opts: TestOptions,
    speed: f64,
    /// Robot time and cycle of the first check (the test's start), and
    /// the pacer started then.
    begun: Option<(f64, u64, Pacer)>,
    next_s: f64,
    /// Bytes of each USART already sent to the page.
    sent: Vec<(u8, usize)>,
}

impl Live {
    fn progress(&mut self, b: &Bench, t0: f64, since: u64) -> serde_json::Value {
        let (legs, turns) = legs_and_turns_so_far(b, &self.test, &self.opts, since);
        let pose = b.core().robot().pose();
        let mut texts = Vec::new();
        for u in uarts::outputs(b) {
            let sent = match self.sent.iter_mut().find(|(n, _)| *n == u.usart) {
                Some((_, s)) => s,
                None => {
                    self.sent.push((u.usart, 0));
                    &mut self.sent.last_mut().expect("just pushed").1
                }
            };
            if u.bytes.len() > *sent {
                texts.push(json!({
                    "name": u.name,
                    "usart": u.usart,
                    "text": String::from_utf8_lossy(&u.bytes[*sent..]),
                }));
                *sent = u.bytes.len();
            }
        }
        json!({
            "kind": "described",
            "test": self.test.name(),
            "time_s": b.robot_time_s() - t0,
            "pose": {
                "x_mm": pose.x().0,
                "y_mm": pose.y().0,
                "theta_deg": pose.theta().0.to_degrees(),
            },
            "legs": legs,
            "turns": turns,
            "uarts": texts,
        })
    }
}

impl Observer for Live {
    fn step(&mut self, _: &Step) {}

    fn wants_steps(&self) -> bool {
        false
    }

    fn check(&mut self, b: &Bench) {
        if self.stop.load(Ordering::Relaxed) {
            return;
        }
        let t = b.robot_time_s();
        if self.begun.is_none() {
            // The text before the start (a greeting, the ready line) is
            // the page's too: sent with the first sample.
            self.begun = Some((t, b.cycle(), Pacer::new(self.speed)));
            self.next_s = t;
        }
        if t < self.next_s {
            return;
        }
        self.next_s = t + SAMPLE_S;
        let (t0, since) = self
            .begun
            .as_ref()
            .map(|(t0, c, _)| (*t0, *c))
            .expect("begun above");
        let event = self.progress(b, t0, since);
        let _ = self.events.send(event.to_string());
        if let Some((_, _, pacer)) = &self.begun {
            pacer.wait(t - t0);
        }
    }

    fn into_any(self: Box<Self>) -> Box<dyn std::any::Any> {
        self
    }
}
