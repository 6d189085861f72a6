// The station page's three charts, drawn as SVG: every tick, axis label and
// legend entry is an element of the page, so what the operator reads is what
// the tests read. Each chart's <svg> carries its ranges as data attributes
// (data-x-min, data-x-max, data-y-min, data-y-max, data-px-per-x,
// data-px-per-y, data-x-label, data-y-label). No number is computed here
// beyond placing what the server sent.
"use strict";

const SVG_NS = "http://www.w3.org/2000/svg";
// Room for the tick labels and axis labels around the plotting area (px).
const MARGIN = { left: 58, right: 12, top: 10, bottom: 40 };

function svgEl(name, attrs, parent, text) {
  const e = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

// A tick step of 1, 2 or 5 times a power of ten, giving about `n` ticks over `span`.
function tickStep(span, n) {
  const raw = span / Math.max(n, 1);
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

// The multiples of `step` in [lo, hi], counted in whole steps so that no
// rounding noise accumulates.
function ticksIn(lo, hi, step) {
  const out = [];
  for (let i = Math.ceil(lo / step - 1e-9); i * step <= hi + step * 1e-9; i++) out.push(i * step);
  return out;
}

const decimalsOf = (step) => Math.max(0, -Math.floor(Math.log10(step) + 1e-9));

// Empties `svg` and draws a frame, grid, ticks with their numbers and the two
// axis labels for the data ranges `x` and `y` ([lo, hi]). With `equal`, one
// unit is as many pixels along x as along y: the narrower range is widened
// about its middle to fill the frame. Returns the data-to-pixel maps and the
// group to draw the data into (clipped to the frame).
function axes(svg, { x, y, xLabel, yLabel, equal }) {
  svg.replaceChildren();
  const W = Number(svg.getAttribute("width")), H = Number(svg.getAttribute("height"));
  const w = W - MARGIN.left - MARGIN.right, h = H - MARGIN.top - MARGIN.bottom;
  let [x0, x1] = x, [y0, y1] = y;
  if (!(x1 > x0)) [x0, x1] = [x0 - 1, x0 + 1];
  if (!(y1 > y0)) [y0, y1] = [y0 - 1, y0 + 1];
  let sx = w / (x1 - x0), sy = h / (y1 - y0);
  if (equal) {
    const s = Math.min(sx, sy);
    const widen = (lo, hi, px) => {
      const mid = (lo + hi) / 2, half = px / s / 2;
      return [mid - half, mid + half];
    };
    [x0, x1] = widen(x0, x1, w);
    [y0, y1] = widen(y0, y1, h);
    sx = sy = s;
  }
  const X = (v) => MARGIN.left + (v - x0) * sx, Y = (v) => MARGIN.top + h - (v - y0) * sy;
  Object.assign(svg.dataset, {
    xMin: x0, xMax: x1, yMin: y0, yMax: y1, pxPerX: sx, pxPerY: sy, xLabel, yLabel,
  });
  const clipId = svg.id + "-clip";
  const clip = svgEl("clipPath", { id: clipId }, svgEl("defs", {}, svg));
  svgEl("rect", { x: MARGIN.left, y: MARGIN.top, width: w, height: h }, clip);
  const grid = svgEl("g", { class: "grid", stroke: "#eee" }, svg);
  const frame = svgEl("g", { class: "axes", stroke: "#888", fill: "#555", "font-size": 11 }, svg);
  // About one tick per 80 px across and per 45 px up; equal scales get one step.
  let stepX = tickStep(x1 - x0, w / 80), stepY = tickStep(y1 - y0, h / 45);
  if (equal) stepX = stepY = Math.max(stepX, stepY);
  for (const v of ticksIn(x0, x1, stepX)) {
    svgEl("line", { x1: X(v), x2: X(v), y1: MARGIN.top, y2: MARGIN.top + h }, grid);
    svgEl("line", { x1: X(v), x2: X(v), y1: MARGIN.top + h, y2: MARGIN.top + h + 4 }, frame);
    svgEl("text", { class: "tick x", "data-value": v, x: X(v), y: MARGIN.top + h + 16, "text-anchor": "middle", stroke: "none" },
      frame, v.toFixed(decimalsOf(stepX)));
  }
  for (const v of ticksIn(y0, y1, stepY)) {
    svgEl("line", { y1: Y(v), y2: Y(v), x1: MARGIN.left, x2: MARGIN.left + w }, grid);
    svgEl("line", { y1: Y(v), y2: Y(v), x1: MARGIN.left - 4, x2: MARGIN.left }, frame);
    svgEl("text", { class: "tick y", "data-value": v, x: MARGIN.left - 6, y: Y(v) + 4, "text-anchor": "end", stroke: "none" },
      frame, v.toFixed(decimalsOf(stepY)));
  }
  svgEl("rect", { x: MARGIN.left, y: MARGIN.top, width: w, height: h, fill: "none" }, frame);
  svgEl("text", { class: "axis-label x", x: MARGIN.left + w / 2, y: H - 6, "text-anchor": "middle", stroke: "none" }, frame, xLabel);
  svgEl("text", {
    class: "axis-label y", x: 12, y: MARGIN.top + h / 2, "text-anchor": "middle", stroke: "none",
    transform: `rotate(-90 12 ${MARGIN.top + h / 2})`,
  }, frame, yLabel);
  const plot = svgEl("g", { "clip-path": `url(#${clipId})`, fill: "none" }, svg);
  return { X, Y, plot, frame: { left: MARGIN.left, top: MARGIN.top, w, h } };
}

// A legend in the frame's top right corner: each item a short line (dashed
// with `dash`) or a `marker` ("circle", "cross", "dot"), then its label. The
// box is as wide as the widest label measured in the font it is drawn in
// (a count of characters misjudges "UMBmark CCW" against "ideal path").
function legend(svg, frame, items) {
  const g = svgEl("g", { class: "legend", "font-size": 11 }, svg);
  const box = svgEl("rect", { fill: "#fff", "fill-opacity": 0.85, stroke: "#ccc" }, g);
  const texts = items.map((item, i) =>
    svgEl("text", { class: "legend-item", y: frame.top + 16 + 16 * i, fill: "#333" }, g, item.label));
  const width = 24 + Math.ceil(Math.max(...texts.map((t) => t.getComputedTextLength())));
  const x = frame.left + frame.w - width - 6;
  Object.entries({ x: x - 4, y: frame.top + 4, width: width + 8, height: 16 * items.length + 6 })
    .forEach(([k, v]) => box.setAttribute(k, v));
  items.forEach((item, i) => {
    const cy = frame.top + 16 + 16 * i;
    if (item.marker) marker(g, item.marker, x + 9, cy - 4, item.color);
    else svgEl("line", { x1: x, x2: x + 18, y1: cy - 4, y2: cy - 4, stroke: item.color, "stroke-width": 2, "stroke-dasharray": item.dash || "none" }, g);
    texts[i].setAttribute("x", x + 24);
  });
}

function marker(parent, kind, x, y, color, attrs = {}) {
  if (kind === "cross") {
    return svgEl("path", { d: `M${x - 5},${y - 5}L${x + 5},${y + 5}M${x + 5},${y - 5}L${x - 5},${y + 5}`, stroke: color, "stroke-width": 2, fill: "none", ...attrs }, parent);
  }
  return svgEl("circle", {
    cx: x, cy: y, r: kind === "dot" ? 4 : 5, stroke: color, "stroke-width": 2, fill: kind === "circle" ? "none" : color, ...attrs,
  }, parent);
}

// A polyline through `points` ([x, y], or null for a gap).
function pathD(points, X, Y) {
  let d = "", up = true;
  for (const p of points) {
    if (!p) { up = true; continue; }
    d += `${up ? "M" : "L"}${X(p[0]).toFixed(1)},${Y(p[1]).toFixed(1)}`;
    up = false;
  }
  return d;
}

// The span of `values` and `always`, widened by `pad` of itself on each side.
function rangeOf(values, always, pad) {
  const all = [...values, ...always].filter((v) => isFinite(v));
  const lo = Math.min(...all), hi = Math.max(...all), m = (hi - lo) * pad;
  return [lo - m, hi + m];
}

const LEFT = "#1f6feb", RIGHT = "#d9480f";

// Wheel speeds and set-points against robot time. `samples`: {time_s,
// speed_left, speed_right, setpoint_left, setpoint_right, phase, segment}, or null where the
// robot stood still (a gap in the lines).
function drawSpeeds(svg, samples, unit) {
  const live = samples.filter((s) => s);
  const ts = live.map((s) => s.time_s);
  const vs = live.flatMap((s) => [s.speed_left, s.speed_right, s.setpoint_left, s.setpoint_right]);
  const a = axes(svg, {
    x: ts.length ? [Math.min(...ts), Math.max(...ts)] : [0, 10],
    // Headroom above the lines for the legend.
    y: ((lo, hi) => [lo, hi + (hi - lo) * 0.35])(...rangeOf(vs, [0, 5], 0.05)),
    xLabel: "robot time (s)",
    yLabel: `speed (${unit})`,
  });
  const line = (key, color, dash) => svgEl("path", {
    class: `series ${key}`, d: pathD(samples.map((s) => (s ? [s.time_s, s[key]] : null)), a.X, a.Y),
    stroke: color, "stroke-width": 1.5, "stroke-dasharray": dash,
  }, a.plot);
  // Which moment of a run each drawn sample is: [robot time (s), phase, segment].
  svg.dataset.samples = JSON.stringify(live.map((s) => [s.time_s, s.phase, s.segment]));
  line("setpoint_left", LEFT, "5 4");
  line("setpoint_right", RIGHT, "5 4");
  line("speed_left", LEFT, "none");
  line("speed_right", RIGHT, "none");
  legend(svg, a.frame, [
    { label: "left", color: LEFT }, { label: "right", color: RIGHT },
    { label: "set-point", color: "#555", dash: "5 4" },
  ]);
}

const RUN_COLORS = { "umbmark-cw": "#c81e1e", "umbmark-ccw": "#000", line: LEFT, triangle: "#2b8a3e" };
const RUN_NAMES = { "umbmark-cw": "UMBmark CW", "umbmark-ccw": "UMBmark CCW", line: "line", triangle: "triangle" };

// The emulated robot's runs, each in its own start frame (cm, x along the
// first leg, y to the left) so that all start at the origin: `runs` are
// {id, test, leg_mm, ideal_cm, points_cm, end_cm (null until done)}; the
// robot is drawn at the last run's last pose, `heading` radians in its frame.
function drawFloor(svg, runs, heading) {
  const pts = runs.flatMap((r) => [...r.points_cm, ...r.ideal_cm]);
  const a = axes(svg, {
    x: rangeOf(pts.map((p) => p[0]), [-10, 10], 0.08),
    y: rangeOf(pts.map((p) => p[1]), [-10, 10], 0.08),
    xLabel: "x (cm), along the first leg",
    yLabel: "y (cm), to the left",
    equal: true,
  });
  const ideals = new Map();
  for (const r of runs) ideals.set(`${r.test}/${r.leg_mm}`, r);
  for (const r of ideals.values()) {
    svgEl("path", {
      class: "ideal", "data-test": r.test, "data-leg-mm": r.leg_mm, "data-points-cm": JSON.stringify(r.ideal_cm),
      d: pathD(r.ideal_cm, a.X, a.Y), stroke: RUN_COLORS[r.test], "stroke-opacity": 0.45, "stroke-width": 1.5, "stroke-dasharray": "6 4",
    }, a.plot);
  }
  const last = runs[runs.length - 1];
  if (last && last.points_cm.length) {
    // The robot, about its wheelbase (13 cm) across, on the floor's scale.
    const [x, y] = last.points_cm[last.points_cm.length - 1];
    const r = 6.5, at = (d, k) => `${a.X(x + Math.cos(heading + d) * r * k)},${a.Y(y + Math.sin(heading + d) * r * k)}`;
    svgEl("polygon", { class: "robot", points: `${at(0, 1)} ${at(2.5, 0.7)} ${at(-2.5, 0.7)}`, fill: "#283845", "fill-opacity": 0.3 }, a.plot);
  }
  for (const r of runs) {
    svgEl("path", {
      class: "run", "data-run": r.id, "data-test": r.test, "data-points-cm": JSON.stringify(r.points_cm),
      d: pathD(r.points_cm, a.X, a.Y), stroke: RUN_COLORS[r.test], "stroke-width": 1.5,
    }, a.plot);
    if (r.end_cm) {
      marker(a.plot, "circle", a.X(r.end_cm[0]), a.Y(r.end_cm[1]), RUN_COLORS[r.test],
        { class: "end", "data-run": r.id, "data-x-cm": r.end_cm[0], "data-y-cm": r.end_cm[1] });
    }
  }
  const tests = [...new Set(runs.map((r) => r.test))];
  if (tests.length) {
    legend(svg, a.frame, [
      ...tests.map((t) => ({ label: RUN_NAMES[t] || t, color: RUN_COLORS[t] })),
      { label: "ideal path", color: "#999", dash: "6 4" },
      { label: "end point", color: "#555", marker: "circle" },
    ]);
  }
}

// The end points of the round's two groups (cm) with their centroids and
// the vectors from the start to them: `groups` are [{label, points}], the
// first drawn as red circles, the second as black crosses; `centroids`
// [x, y] or null each.
function drawScatter(svg, groups, centroids) {
  const COLORS = ["#c81e1e", "#000"], MARKS = ["circle", "cross"];
  const all = [...groups.flatMap((g) => g.points), ...centroids.filter((c) => c)];
  let span = 5;
  for (const [x, y] of all) span = Math.max(span, Math.abs(x), Math.abs(y));
  span *= 1.15;
  const a = axes(svg, { x: [-span, span], y: [-span, span], xLabel: "x (cm), along the first leg", yLabel: "y (cm), to the left", equal: true });
  svgEl("path", { d: `M${a.X(-span * 2)},${a.Y(0)}H${a.X(span * 2)}M${a.X(0)},${a.Y(-span * 2)}V${a.Y(span * 2)}`, stroke: "#bbb" }, a.plot);
  groups.forEach((g, i) => {
    for (const [x, y] of g.points) {
      marker(a.plot, MARKS[i], a.X(x), a.Y(y), COLORS[i], { class: "point", "data-group": g.label, "data-x-cm": x, "data-y-cm": y });
    }
  });
  // Centroids and the vectors from the start to them, as the thesis GUI drew them.
  centroids.forEach((c, i) => {
    if (!c) return;
    const [x, y] = c;
    svgEl("line", { x1: a.X(0), y1: a.Y(0), x2: a.X(x), y2: a.Y(y), stroke: COLORS[i], "stroke-width": 2, "stroke-dasharray": "6 4" }, a.plot);
    marker(a.plot, "dot", a.X(x), a.Y(y), COLORS[i], { class: "centroid", "data-group": groups[i].label, "data-x-cm": x, "data-y-cm": y });
    svgEl("text", { x: a.X(x) + 7, y: a.Y(y) - 7, fill: COLORS[i], "font-size": 11 }, a.plot, groups[i].label + " centroid");
  });
  legend(svg, a.frame, [
    ...groups.map((g, i) => ({ label: g.label, color: COLORS[i], marker: MARKS[i] })),
    { label: "centroid", color: "#555", marker: "dot" },
  ]);
}
