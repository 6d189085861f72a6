//! `hil ui`: the operator's web page on loopback, in place of the thesis'
//! MATLAB GUI. One static page (embedded in the binary), a small JSON API,
//! and server-sent events for the live telemetry.
//!
//! Every robot, emulated or real, is driven through the same [`Link`] over a
//! serial device: an emulated robot is an [`EmulatedRobot`] on a
//! pseudo-terminal, opened like any port. Only the emulated robot's pose on
//! the floor comes from the side (a real robot has no camera over it).

use std::convert::Infallible;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use axum::extract::{Json, State};
use axum::http::{header, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use henrytwo_protocol::param::Param;
use serde::{Deserialize, Serialize};
use serde_json::json;
use thiserror::Error;
use tokio::sync::{broadcast, Mutex};

use super::client::{Link, LinkError, LinkOptions};
use super::emulated::{EmulatedRobot, EmulatorError, ServeOptions};
use super::session::{self, Evaluation, Params, RoundEntry, Session, SessionError};
use crate::bench::BenchOptions;
use crate::firmware::description::Description;
use crate::firmware::elf::Firmware;
use crate::runs::experiment::Test;

const INDEX_HTML: &str = include_str!("ui/index.html");
const APP_JS: &str = include_str!("ui/app.js");
const CHARTS_JS: &str = include_str!("ui/charts.js");

mod described;
mod floor;
mod poll;

use floor::StartPose;

/// The firmware's control tick (timer 1, exactly 15 ms): its telemetry
/// counts them, the robot's own clock, emulated or real.
const TICK_S: f64 = 0.015;

#[derive(Debug, Error)]
pub enum UiError {
    #[error(transparent)]
    Link(#[from] LinkError),
    #[error(transparent)]
    Emulator(#[from] EmulatorError),
    #[error(transparent)]
    Session(#[from] SessionError),
    #[error("no robot connected: pick one and press Connect")]
    NotConnected,
    #[error("{0}")]
    Busy(String),
    #[error("{0}")]
    Input(String),
    #[error("cannot listen on 127.0.0.1:{port}: {source}; pick another port with --listen-port")]
    Listen { port: u16, source: std::io::Error },
}

impl IntoResponse for UiError {
    fn into_response(self) -> Response {
        let status = match &self {
            UiError::Input(_) | UiError::Session(SessionError::Csv(_)) => StatusCode::BAD_REQUEST,
            UiError::Session(
                SessionError::WhichExperiment { .. } | SessionError::LegChanged { .. },
            ) => StatusCode::BAD_REQUEST,
            UiError::NotConnected | UiError::Busy(_) => StatusCode::CONFLICT,
            UiError::Link(LinkError::Refused { .. } | LinkError::OutOfRange { .. }) => {
                StatusCode::CONFLICT
            }
            _ => StatusCode::BAD_GATEWAY,
        };
        (status, Json(json!({ "error": self.to_string() }))).into_response()
    }
}

/// Where `hil ui` finds things.
///
/// [`robot_configs`] lists a folder of configs for [`UiOptions::robots`].
#[derive(Debug, Clone)]
pub struct UiOptions {
    /// Session files, one per robot.
    pub sessions_dir: PathBuf,
    /// Robot configs offered as emulated robots: the name shown, the file.
    /// The first is offered first.
    pub robots: Vec<(String, PathBuf)>,
    /// The firmware the emulated robots run.
    pub firmware: Firmware,
    /// A serial port offered first (`--port`).
    pub port: Option<String>,
    pub baud: u32,
    /// The emulated robots' board (their wiring and links) and plant seed.
    pub bench: BenchOptions,
    /// How the firmware is run when it knows nothing of the bench (`--tests
    /// FILE`): the station runs the tests it describes, as `hil run` does.
    pub description: Option<Arc<Description>>,
}

impl UiOptions {
    /// How an emulated robot is served at `speed`: on the board and seed asked for.
    fn serve_options(&self, speed: f64) -> ServeOptions {
        ServeOptions {
            speed,
            bench: self.bench,
            ..Default::default()
        }
    }
}

/// The robot configs in `dir` (`*.toml`), by name, sorted; `first` (a
/// config given on the command line) leads the list, else the reference
/// robot ([`crate::paths::REFERENCE_ROBOT`]) when it is among them: the
/// page preselects the first.
pub fn robot_configs(dir: &std::path::Path, first: Option<PathBuf>) -> Vec<(String, PathBuf)> {
    let name = |p: &std::path::Path| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let mut all: Vec<(String, PathBuf)> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .map(|p| (name(&p), p))
                .collect()
        })
        .unwrap_or_default();
    all.sort();
    let reference = || {
        all.iter()
            .find(|(n, _)| n == crate::paths::REFERENCE_ROBOT)
            .map(|(_, p)| p.clone())
    };
    if let Some(f) = first.or_else(reference) {
        all.retain(|(n, _)| *n != name(&f));
        all.insert(0, (name(&f), f));
    }
    all
}

struct Connection {
    label: String,
    /// What the page asked for, shown again by a tab opened later.
    selection: ConnectRequest,
    /// The bench protocol's link; None for a described firmware (it speaks
    /// none).
    link: Option<Arc<Mutex<Link>>>,
    emulator: Option<Arc<EmulatedRobot>>,
    poller: Option<tokio::task::JoinHandle<()>>,
    /// The robot a described firmware's tests run on.
    described: Option<described::Target>,
}

impl Drop for Connection {
    fn drop(&mut self) {
        if let Some(p) = &self.poller {
            p.abort();
        }
    }
}

struct App {
    options: UiOptions,
    conn: Mutex<Option<Connection>>,
    /// The session of the connected robot and its file.
    session: Mutex<Option<(PathBuf, Session)>>,
    start: std::sync::Mutex<Option<StartPose>>,
    runs: std::sync::atomic::AtomicU64,
    events: broadcast::Sender<String>,
    /// The described test running, if any.
    live: std::sync::Mutex<Option<described::LiveRun>>,
}

type Shared = Arc<App>;

/// Serve the page on 127.0.0.1:`port` (0: any free port); `ready` gets the
/// address once listening.
pub async fn serve(
    options: UiOptions,
    port: u16,
    ready: impl FnOnce(SocketAddr),
) -> Result<(), UiError> {
    let listener = tokio::net::TcpListener::bind(("127.0.0.1", port))
        .await
        .map_err(|source| UiError::Listen { port, source })?;
    let addr = listener
        .local_addr()
        .map_err(|source| UiError::Listen { port, source })?;
    let (events, _) = broadcast::channel(256);
    let app = Arc::new(App {
        options,
        conn: Mutex::new(None),
        session: Mutex::new(None),
        start: std::sync::Mutex::new(None),
        runs: std::sync::atomic::AtomicU64::new(0),
        events,
        live: std::sync::Mutex::new(None),
    });
    let router = Router::new()
        .route("/", get(index))
        .route("/app.js", get(app_js))
        .route("/charts.js", get(charts_js))
        .route("/api/robots", get(robots))
        .route("/api/connect", post(connect))
        .route("/api/disconnect", post(disconnect))
        .route("/api/start", post(start))
        .route("/api/stop", post(stop))
        .route("/api/params", get(read_params))
        .route("/api/session", get(get_session).put(put_session))
        .route("/api/import", post(import))
        .route("/api/apply", post(apply))
        .route("/api/events", get(event_stream))
        .with_state(app);
    ready(addr);
    axum::serve(listener, router)
        .await
        .map_err(|source| UiError::Listen { port, source })
}

async fn index() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        INDEX_HTML,
    )
}

async fn app_js() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        APP_JS,
    )
}

async fn charts_js() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        CHARTS_JS,
    )
}

#[derive(Serialize)]
struct Robots {
    emulated: Vec<String>,
    ports: Vec<String>,
    default_port: Option<String>,
    baud: u32,
    connected: Option<String>,
    /// The robot connected as the page selects it: its config and speed,
    /// or its port and baud.
    selection: Option<ConnectRequest>,
    /// A described firmware's tests (`hil ui --tests FILE`), by name.
    #[serde(skip_serializing_if = "Option::is_none")]
    tests: Option<Vec<String>>,
}

async fn robots(State(app): State<Shared>) -> Json<Robots> {
    let emulated = app.options.robots.iter().map(|(n, _)| n.clone()).collect();
    let ports = tokio_serial::available_ports()
        .map(|v| v.into_iter().map(|p| p.port_name).collect())
        .unwrap_or_default();
    let (connected, selection) = app
        .conn
        .lock()
        .await
        .as_ref()
        .map(|c| (c.label.clone(), c.selection.clone()))
        .unzip();
    Json(Robots {
        emulated,
        ports,
        default_port: app.options.port.clone(),
        baud: app.options.baud,
        connected,
        selection,
        tests: app
            .options
            .description
            .as_deref()
            .map(described::test_names),
    })
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum ConnectRequest {
    Emulated { config: String, speed: f64 },
    Serial { port: String, baud: u32 },
}

/// The robot's odometry parameters, read over the protocol.
async fn robot_params(link: &mut Link) -> Result<Params, LinkError> {
    Ok(Params {
        c_left: link.get_param(Param::CorrLeft).await? as f64,
        c_right: link.get_param(Param::CorrRight).await? as f64,
        wheelbase_mm: link.get_param(Param::WheelbaseMm).await? as f64,
    })
}

async fn connect(
    State(app): State<Shared>,
    Json(req): Json<ConnectRequest>,
) -> Result<Json<serde_json::Value>, UiError> {
    // One robot at a time: the previous link and emulator go first.
    *app.conn.lock().await = None;
    if let Ok(mut live) = app.live.lock() {
        *live = None;
    }
    if let Some(d) = app.options.description.clone() {
        return described::connect(&app, &d, req).await;
    }
    let selection = req.clone();
    let (key, label, path, baud, emulator) = match req {
        ConnectRequest::Emulated { config, speed } => {
            let (_, robot) = offered_robot(&app, &config)?;
            let options = app.options.serve_options(speed);
            let baud = options.bench.board.command_uart.baud;
            let firmware = app.options.firmware.clone();
            let emu = tokio::task::spawn_blocking(move || {
                EmulatedRobot::spawn(firmware, &robot, options)
            })
            .await
            .map_err(|_| EmulatorError::Lost)??;
            let path = emu.path().to_string_lossy().into_owned();
            (
                format!("emulated-{config}"),
                format!("emulated {config} at {speed}x ({path})"),
                path,
                baud,
                Some(Arc::new(emu)),
            )
        }
        ConnectRequest::Serial { port, baud } => (
            format!("serial-{port}"),
            format!("{port} at {baud} baud"),
            port,
            baud,
            None,
        ),
    };
    let mut link = Link::open_serial(&path, baud, LinkOptions::default())?;
    let version = link.ping().await?;
    let params = robot_params(&mut link).await?;
    let setpoints = (
        link.get_param(Param::SetpointLeft).await?,
        link.get_param(Param::SetpointRight).await?,
    );
    let leg_mm = link.get_param(Param::LegLengthMm).await?;
    // The session of this robot, or a new one starting from its parameters.
    let file = app.options.sessions_dir.join(session::file_name(&key));
    let sess = match session::load(&file)? {
        // A file edited by hand may have lost its rounds: start one.
        Some(mut s) if s.rounds.is_empty() => {
            s.rounds.push(RoundEntry::new(params));
            s
        }
        Some(s) => s,
        None => {
            let s = Session::new(&key, params);
            session::save(&file, &s)?;
            s
        }
    };
    let evaluation = session::evaluate(&sess);
    let body = json!({
        "robot": label,
        "key": key,
        "protocol_version": version,
        "params": params,
        "setpoints": [setpoints.0, setpoints.1],
        "leg_mm": leg_mm,
        "emulated": emulator.is_some(),
        "session_file": file,
        "session": sess,
        "evaluation": evaluation,
    });
    *app.session.lock().await = Some((file, sess));
    let link = Arc::new(Mutex::new(link));
    // A device on a port is taken at real time (a robot's own clock).
    let pace = match selection {
        ConnectRequest::Emulated { speed, .. } => speed,
        ConnectRequest::Serial { .. } => 1.0,
    };
    let poller = tokio::spawn(poll::poll(
        app.clone(),
        link.clone(),
        emulator.clone(),
        setpoints,
        pace,
    ));
    *app.conn.lock().await = Some(Connection {
        label,
        selection,
        link: Some(link),
        emulator,
        poller: Some(poller),
        described: None,
    });
    Ok(Json(body))
}

/// The robot config offered as `config`, and the file it came from: only
/// those offered, the page names no files.
fn offered_robot(app: &App, config: &str) -> Result<(PathBuf, plant_model::RobotConfig), UiError> {
    let file = app
        .options
        .robots
        .iter()
        .find(|(n, _)| *n == config)
        .map(|(_, f)| f.clone())
        .ok_or_else(|| {
            UiError::Input(format!(
                "{config:?} is not one of the robot configs offered"
            ))
        })?;
    let robot = plant_model::RobotConfig::load(&file)
        .map_err(|e| UiError::Input(format!("robot config {}: {e}", file.display())))?;
    Ok((file, robot))
}

async fn disconnect(State(app): State<Shared>) -> Json<serde_json::Value> {
    *app.conn.lock().await = None;
    if let Ok(mut live) = app.live.lock() {
        *live = None;
    }
    Json(json!({ "ok": true }))
}

async fn link_of(app: &App) -> Result<(Arc<Mutex<Link>>, Option<Arc<EmulatedRobot>>), UiError> {
    let conn = app.conn.lock().await;
    let c = conn.as_ref().ok_or(UiError::NotConnected)?;
    let link = c.link.clone().ok_or_else(|| {
        UiError::Input(format!(
            "{}: the firmware speaks no bench protocol: it has no parameters to read or send",
            app.options
                .description
                .as_ref()
                .map_or("the test description", |d| d.path.as_str())
        ))
    })?;
    Ok((link, c.emulator.clone()))
}

#[derive(Deserialize)]
struct StartRequest {
    test: Test,
    leg_mm: Option<f64>,
}

async fn start(
    State(app): State<Shared>,
    Json(req): Json<serde_json::Value>,
) -> Result<Json<serde_json::Value>, UiError> {
    if let Some(d) = app.options.description.clone() {
        return described::start(&app, &d, req).await;
    }
    let req: StartRequest = serde_json::from_value(req).map_err(|e| {
        UiError::Input(format!(
            "{e}: give {{\"test\": one of umbmark-cw, umbmark-ccw, line, triangle, \"leg_mm\": a length}}"
        ))
    })?;
    let (link, emulator) = link_of(&app).await?;
    // The session before the link, as `apply` takes them.
    let mut guard = app.session.lock().await;
    let mut l = link.lock().await;
    let leg_mm = match req.leg_mm {
        Some(v) => l.set_param(Param::LegLengthMm, v as f32).await?,
        None => l.get_param(Param::LegLengthMm).await?,
    } as f64;
    // The leg the round's end points will come from, recorded before the
    // robot moves: a round whose points came from another leg refuses it.
    let recorded = match guard.as_mut() {
        Some((file, s)) => {
            let mut new = s.clone();
            if session::record_leg(&mut new, req.test, leg_mm)? {
                Some((file.clone(), new))
            } else {
                None
            }
        }
        None => None,
    };
    if let Some(v) = emulator.as_ref().map(|e| e.view()) {
        if let Ok(mut s) = app.start.lock() {
            *s = Some(StartPose {
                run: app.runs.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
                test: req.test,
                leg_mm,
                x_mm: v.x_mm,
                y_mm: v.y_mm,
                theta_rad: v.theta_rad,
            });
        }
    }
    l.start(req.test).await?;
    let mut body = json!({ "started": req.test.name(), "leg_mm": leg_mm });
    if let Some((file, new)) = recorded {
        session::save(&file, &new)?;
        body["session"] = json!(new);
        body["evaluation"] = json!(session::evaluate(&new));
        if let Some((_, s)) = guard.as_mut() {
            *s = new;
        }
    }
    Ok(Json(body))
}

/// Stop the robot; a test it was running gives no end point.
async fn stop(State(app): State<Shared>) -> Result<Json<serde_json::Value>, UiError> {
    if app.options.description.is_some() {
        return Ok(described::stop(&app));
    }
    let (link, _) = link_of(&app).await?;
    link.lock().await.stop().await?;
    if let Ok(mut s) = app.start.lock() {
        *s = None;
    }
    Ok(Json(json!({ "stopped": true })))
}

async fn read_params(State(app): State<Shared>) -> Result<Json<Params>, UiError> {
    let (link, _) = link_of(&app).await?;
    let p = robot_params(&mut *link.lock().await).await?;
    Ok(Json(p))
}

#[derive(Serialize)]
struct SessionReply {
    session: Session,
    evaluation: Evaluation,
    #[serde(skip_serializing_if = "Option::is_none")]
    session_file: Option<PathBuf>,
}

fn reply(s: &Session) -> Json<SessionReply> {
    Json(SessionReply {
        session: s.clone(),
        evaluation: session::evaluate(s),
        session_file: None,
    })
}

/// The connected robot's session, for a page opened (again) after Connect.
async fn get_session(State(app): State<Shared>) -> Result<Json<SessionReply>, UiError> {
    let guard = app.session.lock().await;
    let (file, s) = guard.as_ref().ok_or(UiError::NotConnected)?;
    let mut r = reply(s);
    r.session_file = Some(file.clone());
    Ok(r)
}

/// The page sends the whole session as typed; it is saved before the reply.
async fn put_session(
    State(app): State<Shared>,
    Json(mut new): Json<Session>,
) -> Result<Json<SessionReply>, UiError> {
    let mut guard = app.session.lock().await;
    let (file, s) = guard.as_mut().ok_or(UiError::NotConnected)?;
    // The page edits points and fields; rounds, their parameters and what
    // was applied are the server's.
    if new.rounds.len() != s.rounds.len() {
        return Err(UiError::Input(
            "the page is out of date (another tab applied a correction): reload it".into(),
        ));
    }
    for (n, old) in new.rounds.iter_mut().zip(&s.rounds) {
        n.params = old.params;
        n.applied = old.applied;
        n.leg_mm = old.leg_mm;
    }
    new.robot = s.robot.clone();
    session::save(file, &new)?;
    *s = new;
    Ok(reply(s))
}

#[derive(Deserialize)]
struct ImportRequest {
    text: String,
    experiment: Option<u32>,
}

async fn import(
    State(app): State<Shared>,
    Json(req): Json<ImportRequest>,
) -> Result<Json<SessionReply>, UiError> {
    let mut guard = app.session.lock().await;
    let (file, s) = guard.as_mut().ok_or(UiError::NotConnected)?;
    let mut new = s.clone();
    let round = new.rounds.len() - 1;
    session::import_csv(&mut new, round, &req.text, req.experiment)?;
    session::save(file, &new)?;
    *s = new;
    Ok(reply(s))
}

/// Send the last round's correction (SET_PARAM cL, cR, wheelbase), read the
/// parameters back (GET_PARAM), record them and open the next round.
async fn apply(State(app): State<Shared>) -> Result<Json<serde_json::Value>, UiError> {
    let (link, _) = link_of(&app).await?;
    let mut guard = app.session.lock().await;
    let (file, s) = guard.as_mut().ok_or(UiError::NotConnected)?;
    let ev = session::evaluate(s);
    let last = s.rounds.len() - 1;
    let send = ev.rounds[last].send.ok_or_else(|| {
        UiError::Input("the round is not complete: enter every end point first".into())
    })?;
    let readback = {
        let mut l = link.lock().await;
        l.set_param(Param::CorrLeft, send.c_left as f32).await?;
        l.set_param(Param::CorrRight, send.c_right as f32).await?;
        l.set_param(Param::WheelbaseMm, send.wheelbase_mm as f32)
            .await?;
        robot_params(&mut l).await?
    };
    let mut new = s.clone();
    new.rounds[last].applied = Some(readback);
    // The next round checks the correction with the same test.
    let mut next = RoundEntry::new(readback);
    next.method = new.rounds[last].method;
    new.rounds.push(next);
    session::save(file, &new)?;
    *s = new;
    Ok(Json(json!({
        "sent": send,
        "read_back": readback,
        "session": s,
        "evaluation": session::evaluate(s),
    })))
}

async fn event_stream(
    State(app): State<Shared>,
) -> Sse<impl futures_util::Stream<Item = Result<Event, Infallible>>> {
    let rx = app.events.subscribe();
    let stream = futures_util::stream::unfold(rx, |mut rx| async move {
        loop {
            match rx.recv().await {
                Ok(text) => return Some((Ok(Event::default().data(text)), rx)),
                // A slow tab skips telemetry rather than stalling the rest.
                Err(broadcast::error::RecvError::Lagged(_)) => continue,
                Err(broadcast::error::RecvError::Closed) => return None,
            }
        }
    });
    Sse::new(stream).keep_alive(KeepAlive::default())
}

#[cfg(test)]
mod tests;
