// The station page: picks a robot, starts tests, shows telemetry, keeps the
// typed end points in the server's session file, and shows what the calib
// crate computes from them. No number is computed here: the page only draws.
"use strict";

const $ = (id) => document.getElementById(id);
let session = null;      // the session as the server saved it (plus local edits)
let evaluation = null;   // the server's evaluation of it
let saving = false, dirty = false;
const speeds = [];       // recent telemetry samples for the chart; null: the robot stood still
// The chart's samples: 60 s of robot time at the server's 4 samples per robot second.
const SPEED_SAMPLES = 240;
const runs = [];         // the emulated robot's recent runs, each in its start frame (cm)
let heading = 0;         // the emulated robot's heading in its last run's frame (rad)

async function api(method, path, body) {
  const r = await fetch(path, {
    method,
    headers: body === undefined ? {} : { "content-type": "application/json" },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const data = await r.json().catch(() => ({ error: r.statusText }));
  if (!r.ok) throw new Error(data.error || r.statusText);
  return data;
}

function status(text, error) {
  $("status").textContent = text;
  $("status").className = error ? "error" : "";
}

// Headings accumulate over turns; people read them within ±180°.
const wrapDeg = (d) => ((((d + 180) % 360) + 360) % 360) - 180;
const fmt = (v, d) => (v === null || v === undefined || !isFinite(v) ? "-" : v.toFixed(d));

function setVal(id, v, d) {
  const el = $(id);
  el.textContent = fmt(v, d);
  // The exact value, for checks that compare with the library.
  if (v === null || v === undefined) el.removeAttribute("data-value");
  else el.setAttribute("data-value", String(v));
}

async function loadRobots() {
  const r = await api("GET", "/api/robots");
  const sel = $("robot-select");
  sel.innerHTML = "";
  for (const name of r.emulated) {
    sel.add(new Option("emulated: " + name, "emulated:" + name));
  }
  const ports = r.default_port ? [r.default_port, ...r.ports.filter((p) => p !== r.default_port)] : r.ports;
  for (const p of ports) sel.add(new Option("serial: " + p, "serial:" + p));
  sel.add(new Option("serial: the port typed on the right", "serial:"));
  // A port given on the command line first, else the first config (the
  // one given with --robot, if any).
  if (r.default_port) sel.value = "serial:" + r.default_port;
  else if (r.emulated.length) sel.value = "emulated:" + r.emulated[0];
  $("baud").value = r.baud;
  // A tab opened while a robot is connected shows that robot as selected.
  const c = r.selection;
  if (c && c.kind === "emulated") {
    sel.value = "emulated:" + c.config;
    $("speed").value = c.speed;
  } else if (c && c.kind === "serial") {
    const known = [...sel.options].some((o) => o.value === "serial:" + c.port);
    sel.value = known ? "serial:" + c.port : "serial:";
    if (!known) $("port-input").value = c.port;
    $("baud").value = c.baud;
  }
  if (r.connected) status("connected: " + r.connected);
}

async function connect() {
  const choice = $("robot-select").value;
  let req;
  if (choice.startsWith("emulated:")) {
    const sp = $("speed");
    if (!sp.value || !sp.checkValidity()) {
      return status(`speed ${sp.value || "(empty)"}: give a factor from ${sp.min} to ${sp.max}`, true);
    }
    req = { kind: "emulated", config: choice.slice(9), speed: Number($("speed").value) };
  } else {
    const port = choice.slice(7) || $("port-input").value.trim();
    if (!port) return status("type the serial port's path first", true);
    req = { kind: "serial", port, baud: Number($("baud").value) };
  }
  status("connecting…");
  $("connect").disabled = true;
  try {
    const r = await api("POST", "/api/connect", req);
    if (r.described) return showDescribed(r);
    status("connected: " + r.robot + ", protocol " + r.protocol_version);
    $("session-file").textContent = r.session_file;
    $("leg-mm").value = r.leg_mm;
    showRobotParams(r.params);
    runs.length = 0;
    speeds.length = 0;
    showSpeeds();
    showFloor();
    robotTime = null;
    if (r.emulated) showPose();
    else $("pose").textContent = NO_POSE;
    setSession(r.session, r.evaluation);
  } catch (e) {
    status(e.message, true);
  } finally {
    $("connect").disabled = false;
  }
}

function showRobotParams(p) {
  setVal("robot-cl", p.c_left, 6);
  setVal("robot-cr", p.c_right, 6);
  setVal("robot-wheelbase", p.wheelbase_mm, 2);
}

// --- the end points ---------------------------------------------------------

const lastRound = () => session.rounds.length - 1;

// The two groups of runs of a method, as the session names them, and how
// the page labels them.
const GROUPS = {
  umbmark: [["cw", "CW"], ["ccw", "CCW"]],
  triangle: [["line", "line"], ["triangle", "triangle"]],
};
const CSV_LAYOUT = { umbmark: "experiment,direction,run,x_cm,y_cm", triangle: "experiment,test,run,x_cm,y_cm" };
const groupsOf = (round) => GROUPS[round.method || "umbmark"];

function setSession(s, ev) {
  session = s;
  const k = lastRound();
  const round = s.rounds[k];
  $("round-no").textContent = k;
  $("round-cl").textContent = fmt(round.params.c_left, 6);
  $("round-cr").textContent = fmt(round.params.c_right, 6);
  $("round-b").textContent = fmt(round.params.wheelbase_mm, 2);
  $("side_cm").value = s.side_cm;
  $("line_commanded_cm").value = round.line_commanded_cm;
  $("line_measured_cm").value = round.line_measured_cm;
  $("method").value = round.method || "umbmark";
  $("exact-solution").checked = s.solution === "exact";
  showPoints();
  showEvaluation(ev);
}

// The rows of the round's method; the other method's rows stay in the
// session as typed.
function showPoints() {
  const k = lastRound();
  const round = session.rounds[k];
  const groups = groupsOf(round);
  groups.forEach(([, label], g) => {
    $(`head-${g}-x`).textContent = label + " x";
    $(`head-${g}-y`).textContent = label + " y";
  });
  $("csv-layout").textContent = CSV_LAYOUT[round.method || "umbmark"];
  const body = $("points").tBodies[0];
  body.innerHTML = "";
  const n = Math.max(...groups.map(([dir]) => round[dir].length));
  for (let i = 0; i < n; i++) {
    const tr = body.insertRow();
    tr.insertCell().textContent = i + 1;
    for (const [dir] of groups) {
      for (const axis of ["x", "y"]) {
        const td = tr.insertCell();
        if (i >= round[dir].length) continue;
        const input = document.createElement("input");
        input.className = "num";
        input.id = `r${k}-${dir}-${i + 1}-${axis}`;
        input.value = round[dir][i][axis];
        input.addEventListener("input", () => {
          session.rounds[lastRound()][dir][i][axis] = input.value;
          save();
        });
        td.appendChild(input);
      }
    }
  }
}

function edited(field) {
  return () => {
    const round = session.rounds[lastRound()];
    if (field === "side_cm") session.side_cm = $("side_cm").value;
    else round[field] = $(field).value;
    save();
  };
}

// Every change is sent at once; while a save is under way the next one waits
// and then sends the latest state, so nothing typed is lost or reordered.
async function save() {
  if (!session) return;
  dirty = true;
  if (saving) return;
  saving = true;
  try {
    while (dirty) {
      dirty = false;
      $("save-state").textContent = "saving…";
      const r = await api("PUT", "/api/session", session);
      evaluation = r.evaluation;
      if (!dirty) showEvaluation(r.evaluation);
      $("save-state").textContent = "saved";
      $("save-state").className = "ok";
    }
  } catch (e) {
    $("save-state").textContent = "NOT saved: " + e.message;
    $("save-state").className = "msg";
  } finally {
    saving = false;
  }
}

function fieldId(serverId) {
  const k = lastRound();
  if (serverId === `r${k}-line_commanded_cm`) return "line_commanded_cm";
  if (serverId === `r${k}-line_measured_cm`) return "line_measured_cm";
  return serverId;
}

function showEvaluation(ev) {
  evaluation = ev;
  for (const el of document.querySelectorAll("input.invalid")) {
    el.classList.remove("invalid");
    el.title = "";
  }
  const msgs = [];
  for (const [id, msg] of Object.entries(ev.errors)) {
    const el = $(fieldId(id));
    if (el) {
      el.classList.add("invalid");
      el.title = msg;
    }
    if (id === "side_cm" || id.startsWith(`r${lastRound()}-`)) msgs.push(`${id}: ${msg}`);
  }
  $("field-errors").textContent = msgs.join("; ");
  const cur = ev.rounds[lastRound()];
  const tri = cur.method === "triangle";
  const r = tri ? cur.triangle : cur.result;
  $("correction-title").textContent = `Correction (calib, ${tri ? "Triangular Path" : "Borenstein"}, ` +
    `${session.solution === "exact" ? "exact solution" : "first order"})`;
  $("ed-eb-label").textContent = tri ? "Ed (line), Eb (triangle)" : "Ed, Eb";
  // Constant markup only (the subscript), never anything typed.
  $("emax-label").innerHTML = tri ? "triangle centroid r (cm)" : "E<sub>max,syst</sub> (cm)";
  setVal("ed", r ? r.ed : null, 6);
  setVal("eb", r ? r.eb : null, 6);
  setVal("cl", r ? r.cl : null, 6);
  setVal("cr", r ? r.cr : null, 6);
  setVal("wheelbase", r ? r.wheelbase_mm : null, 2);
  setVal("es", r ? r.es : null, 6);
  $("emax").textContent = r ? fmt(tri ? r.triangle_r_cm : r.e_max_cm, 2) : "-";
  const s = cur.send;
  setVal("send-cl", s ? s.c_left : null, 6);
  setVal("send-cr", s ? s.c_right : null, 6);
  setVal("send-wheelbase", s ? s.wheelbase_mm : null, 2);
  $("apply").disabled = !s;
  $("warnings").textContent = r ? r.warnings.join(" ") : tri
    ? `${cur.complete_line} of the line and ${cur.complete_triangle} of the triangle runs complete`
    : `${cur.complete_cw} of CW and ${cur.complete_ccw} of CCW runs complete`;
  showScatter();
  showRounds();
}

function showRounds() {
  const body = $("rounds").tBodies[0];
  body.innerHTML = "";
  session.rounds.forEach((round, k) => {
    const ev = evaluation.rounds[k];
    const r = ev.result, t = ev.triangle;
    const errs = r ? [fmt(r.r_cg_cw_cm, 2), fmt(r.r_cg_ccw_cm, 2), fmt(r.e_max_cm, 2)]
      : t ? [fmt(Math.hypot(t.line_centroid.x_cm, t.line_centroid.y_cm), 2), fmt(t.triangle_r_cm, 2), "-"]
      : ["-", "-", "-"];
    const tr = body.insertRow();
    for (const v of [k, fmt(round.params.c_left, 6), fmt(round.params.c_right, 6), fmt(round.params.wheelbase_mm, 2), ...errs]) {
      tr.insertCell().textContent = v;
    }
  });
  const t10 = $("table10").tBodies[0];
  t10.innerHTML = "";
  for (const row of evaluation.table) {
    const tr = t10.insertRow();
    for (const v of [row.round, fmt(row.wheelbase_before_mm, 2), fmt(row.wheelbase_after_mm, 2), fmt(row.wheelbase_correction_pct, 2),
      fmt(row.error_before_cm, 2), fmt(row.error_after_cm, 2), fmt(row.position_correction_pct, 2)]) {
      tr.insertCell().textContent = v;
    }
  }
}

async function importCsv() {
  const file = $("csv-file").files[0];
  if (!file) return ($("field-errors").textContent = "choose a CSV file first");
  const exp = $("csv-experiment").value.trim();
  try {
    const r = await api("POST", "/api/import", { text: await file.text(), experiment: exp ? Number(exp) : null });
    setSession(r.session, r.evaluation);
  } catch (e) {
    $("field-errors").textContent = e.message;
  }
}

async function apply() {
  $("apply").disabled = true;
  $("apply-result").textContent = "sending…";
  try {
    const r = await api("POST", "/api/apply");
    showRobotParams(r.read_back);
    $("apply-result").textContent = "sent; read back: cL " + fmt(r.read_back.c_left, 6) + ", cR " +
      fmt(r.read_back.c_right, 6) + ", b " + fmt(r.read_back.wheelbase_mm, 2) + " mm";
    $("apply-result").className = "ok";
    setSession(r.session, r.evaluation);
  } catch (e) {
    $("apply-result").textContent = e.message;
    $("apply-result").className = "msg";
    $("apply").disabled = false;
  }
}

// --- drawing (charts.js draws) -----------------------------------------------

// The unit of the firmware's speeds (the protocol's telemetry).
const SPEED_UNIT = "thesis RPM = wheel RPM / 6";

function showScatter() {
  if (!session) return;
  const k = lastRound();
  const round = session.rounds[k];
  const groups = groupsOf(round);
  const pts = (dir) => round[dir].map((p) => [parseFloat(String(p.x).replace(",", ".")), parseFloat(String(p.y).replace(",", "."))])
    .filter(([x, y]) => isFinite(x) && isFinite(y));
  const ev = evaluation && evaluation.rounds[k];
  const r = ev && ev.result, t = ev && ev.triangle;
  // A triangle centroid without y (not measured) is not drawn.
  const cents = r ? [r.centroid_cw, r.centroid_ccw] : t ? [t.line_centroid, t.triangle_centroid] : [null, null];
  drawScatter($("scatter"), groups.map(([dir, label]) => ({ label, points: pts(dir) })),
    cents.map((c) => (c && c.y_cm !== null && c.y_cm !== undefined ? [c.x_cm, c.y_cm] : null)));
}

const showSpeeds = () => drawSpeeds($("speeds"), speeds, SPEED_UNIT);
const showFloor = () => drawFloor($("floor"), runs, heading);

// --- live telemetry -----------------------------------------------------------

const STATES = ["booting", "idle", "driving", "braking"];
const IDLE = 1;
const PHASES = ["idle", "leg", "turn", "braking", "fault"];
const TESTS = { 2: "umbmark-cw", 3: "umbmark-ccw", 4: "line", 5: "triangle" };

// The live values of a robot at rest: its firmware keeps the last duty and
// speed it computed, which are not what the motors do now.
function clearLive() {
  for (const id of ["pwm-left", "pwm-right", "speed-left", "speed-right"]) $(id).textContent = "-";
}

function onEvent(ev) {
  if (ev.kind === "telemetry") {
    $("state").textContent = `${STATES[ev.state] || ev.state} / ${PHASES[ev.phase] || ev.phase}` +
      (ev.test ? `, ${TESTS[ev.test] || ev.test} segment ${ev.segment}` : "") + (ev.fault ? `, FAULT ${ev.fault}` : "");
    $("tests-done").textContent = ev.tests_done;
    // The samples of robot time since the last event. The chart changes
    // only while the robot moves: at rest it ends its lines once (a gap
    // before the next run) and stays as it is.
    let drawn = false;
    for (const sample of ev.samples) {
      if (sample.state === IDLE) {
        if (speeds.length && speeds[speeds.length - 1]) {
          speeds.push(null);
          drawn = true;
        }
      } else {
        speeds.push(sample);
        drawn = true;
      }
      if (sample.run) onRunPose(sample.run);
    }
    while (speeds.length > SPEED_SAMPLES || (speeds.length && !speeds[0])) speeds.shift();
    if (drawn) showSpeeds();
    if (ev.samples.some((x) => x.run)) showFloor();
    if (ev.state === IDLE) clearLive();
    else {
      $("pwm-left").textContent = ev.duty_left;
      $("pwm-right").textContent = ev.duty_right;
      $("speed-left").textContent = fmt(ev.speed_left, 2);
      $("speed-right").textContent = fmt(ev.speed_right, 2);
    }
    if (ev.pose) showPose(ev.pose.robot_time_s);
  } else if (ev.kind === "notice") {
    const n = ev.notice;
    if (n.kind === "test_done") {
      if (ev.run_end) onRunEnd(ev.run_end);
      let text = `${TESTS[n.test] || n.test} done`;
      if (ev.end_error_cm && session) {
        const [x, y] = ev.end_error_cm;
        text += `; the emulator's floor says x ${x.toFixed(2)} cm, y ${y.toFixed(2)} cm`;
        fillEndPoint(TESTS[n.test], x, y, ev.leg_mm);
      }
      $("notice").textContent = text;
    } else {
      $("notice").textContent = `FAULT ${n.fault} in test ${n.test}, segment ${n.segment}`;
    }
  } else if (ev.kind === "described" || ev.kind === "described_end") {
    onDescribed(ev);
  } else if (ev.kind === "error") {
    status(ev.message, true);
  }
}

// --- a described firmware (hil ui --tests FILE) ---------------------------------
// Its tests are the description's, run by the server as hil run runs them;
// the page shows their progress and report.

function showDescribed(r) {
  status(`connected: ${r.robot}, firmware ${r.described.firmware}, tests of ${r.described.file}`);
  const box = $("test-buttons");
  box.innerHTML = "";
  for (const name of r.described.tests) {
    const b = document.createElement("button");
    b.dataset.test = name;
    b.textContent = name;
    b.onclick = () => startTest(name);
    box.append(b, " ");
  }
  $("leg-mm").disabled = true;
  $("described").hidden = false;
  $("pose").textContent = "";
}

const legsText = (legs) => `${legs.length}` + (legs.length ? ` (${legs.map((l) => fmt(l.plant_distance_mm, 0)).join(", ")} mm)` : "");
const turnsText = (turns) => `${turns.length}` + (turns.length ? ` (${turns.map((t) => fmt(t.plant_angle_deg, 1)).join(", ")}°)` : "");

function onDescribed(ev) {
  if (ev.kind === "described") {
    $("state").textContent = `${ev.test} running, ${fmt(ev.time_s, 2)} s`;
    $("described-legs").textContent = legsText(ev.legs);
    $("described-turns").textContent = turnsText(ev.turns);
    $("described-pose").textContent = `x ${fmt(ev.pose.x_mm, 1)} mm, y ${fmt(ev.pose.y_mm, 1)} mm, θ ${fmt(wrapDeg(ev.pose.theta_deg), 1)}°`;
    for (const u of ev.uarts) $("uart-text").textContent += u.text;
    return;
  }
  const run = ev.run;
  $("state").textContent = `${ev.test} ${run.completed ? "completed" : "did not complete"}, ${fmt(run.robot_time_s, 2)} s`;
  $("notice").textContent = run.finding || "";
  $("described-legs").textContent = legsText(run.legs);
  $("described-turns").textContent = turnsText(run.turns);
  const p = run.final_pose;
  $("described-pose").textContent = `x ${fmt(p.x_mm, 1)} mm, y ${fmt(p.y_mm, 1)} mm, θ ${fmt(wrapDeg(p.theta_deg), 1)}°`;
}

// A run is drawn from the origin of its start frame, where the server's
// poses of it are given; the last ten runs stay on the floor.
function onRunPose(p) {
  let run = runs.find((r) => r.id === p.id);
  if (!run) {
    run = { id: p.id, test: p.test, leg_mm: p.leg_mm, ideal_cm: p.ideal_cm, points_cm: [[0, 0]], at_cm: [0, 0], end_cm: null };
    runs.push(run);
    if (runs.length > 10) runs.shift();
  }
  const last = run.points_cm[run.points_cm.length - 1];
  if (Math.hypot(last[0] - p.x_cm, last[1] - p.y_cm) > 0.2) run.points_cm.push([p.x_cm, p.y_cm]);
  if (run.points_cm.length > 5000) run.points_cm.splice(1, 1);
  run.at_cm = [p.x_cm, p.y_cm];
  heading = p.theta_rad;
}

// The emulated robot's pose in the frame the floor draws: the last run's
// start frame (x along its first leg, y to the left), not the pose since
// Connect, so the numbers read are the ones plotted.
let robotTime = null;
const NO_POSE = "a real robot has no pose here: measure its end point on the floor";
function showPose(t) {
  if (t !== undefined) robotTime = t;
  const el = $("pose");
  const time = robotTime === null ? "" : `; robot time ${fmt(robotTime, 1)} s`;
  const run = runs[runs.length - 1];
  if (!run) {
    el.textContent = `no run yet (the floor draws each run from where it started)${time}`;
    return;
  }
  const [x, y] = run.end_cm || run.at_cm;
  // Constant markup and numbers only.
  el.innerHTML = `${run.end_cm ? "last run ended at" : "this run, now at"} ` +
    `x <span id="pose-x" class="val"></span> cm, y <span id="pose-y" class="val"></span> cm, ` +
    `heading <span id="pose-heading" class="val"></span>° in its start frame (as on the floor)${time}`;
  setVal("pose-x", x, 1);
  setVal("pose-y", y, 1);
  setVal("pose-heading", wrapDeg(heading * 180 / Math.PI), 1);
}

function onRunEnd(e) {
  const run = runs.find((r) => r.id === e.id);
  if (!run) return;
  run.end_cm = [e.x_cm, e.y_cm];
  const last = run.points_cm[run.points_cm.length - 1];
  if (last[0] !== e.x_cm || last[1] !== e.y_cm) run.points_cm.push(run.end_cm);
  showFloor();
  showPose();
}

// The emulated robot's end point goes into the next empty row of its
// direction, as the operator with the tape measure would type it; a line's
// gives the commanded and measured lengths for Es, when not typed yet.
function fillEndPoint(test, x, y, legMm) {
  const k = lastRound();
  const tri = session.rounds[k].method === "triangle";
  if (test === "line" && legMm && !tri) {
    const round = session.rounds[k];
    if (String(round.line_commanded_cm).trim() || String(round.line_measured_cm).trim()) return;
    round.line_commanded_cm = (legMm / 10).toFixed(2);
    round.line_measured_cm = (legMm / 10 + x).toFixed(2);
    $("line_commanded_cm").value = round.line_commanded_cm;
    $("line_measured_cm").value = round.line_measured_cm;
    return save();
  }
  // In a Triangular Path round the line and the triangle are its runs.
  const dir = tri ? (test === "line" || test === "triangle" ? test : null)
    : test === "umbmark-cw" ? "cw" : test === "umbmark-ccw" ? "ccw" : null;
  if (!dir) return;
  const rows = session.rounds[k][dir];
  const i = rows.findIndex((p) => !String(p.x).trim() && !String(p.y).trim());
  if (i < 0) return;
  rows[i] = { x: x.toFixed(2), y: y.toFixed(2) };
  $(`r${k}-${dir}-${i + 1}-x`).value = rows[i].x;
  $(`r${k}-${dir}-${i + 1}-y`).value = rows[i].y;
  save();
}

function listen() {
  const es = new EventSource("/api/events");
  es.onmessage = (m) => onEvent(JSON.parse(m.data));
}

async function startTest(test) {
  try {
    const leg = Number($("leg-mm").value);
    $("uart-text").textContent = "";
    const r = await api("POST", "/api/start", { test, leg_mm: leg });
    $("notice").textContent = `${r.started} started, ${r.leg_mm} mm legs`;
    // The round recorded the leg, and the side follows it.
    if (r.session) setSession(r.session, r.evaluation);
  } catch (e) {
    $("notice").textContent = e.message;
  }
}

async function stop() {
  try {
    await api("POST", "/api/stop");
    $("notice").textContent = "stopped";
    clearLive();
  } catch (e) {
    $("notice").textContent = e.message;
  }
}

window.addEventListener("load", () => {
  showSpeeds();
  showFloor();
  $("connect").onclick = connect;
  for (const b of document.querySelectorAll("button[data-test]")) b.onclick = () => startTest(b.dataset.test);
  $("stop").onclick = stop;
  $("side_cm").addEventListener("input", edited("side_cm"));
  $("line_commanded_cm").addEventListener("input", edited("line_commanded_cm"));
  $("line_measured_cm").addEventListener("input", edited("line_measured_cm"));
  $("method").addEventListener("change", () => {
    session.rounds[lastRound()].method = $("method").value;
    showPoints();
    save();
  });
  $("exact-solution").addEventListener("change", () => {
    session.solution = $("exact-solution").checked ? "exact" : "first-order";
    save();
  });
  $("import").onclick = importCsv;
  $("apply").onclick = apply;
  $("read-params").onclick = () => api("GET", "/api/params").then(showRobotParams).catch((e) => ($("apply-result").textContent = e.message));
  listen();
  loadRobots().catch((e) => status(e.message, true));
  // A reopened tab picks up the session of the robot still connected.
  api("GET", "/api/session")
    .then((r) => {
      $("session-file").textContent = r.session_file;
      setSession(r.session, r.evaluation);
      return api("GET", "/api/params").then(showRobotParams);
    })
    .catch(() => {});
});
