// pipescope inspection report: builds the page from the JSON in <script id="pipescope-data">.
// Charts use uPlot, the 3D view uses three.js; both are embedded in the HTML file (nothing is fetched).
// Schema: "pipescope-report/1" (see spec/report_data.md).
"use strict";

(function () {
  const root = document.documentElement;
  const main = document.getElementById("report");
  performance.mark("pipescope:script");
  const data = JSON.parse(document.getElementById("pipescope-data").textContent);
  performance.mark("pipescope:parsed");

  // Everything the page waits for before it reports "ready" (charts drawn, strips laid out, viewer frame).
  const pending = [];

  // Colours shared by charts, strips and the 3D view.
  const COLORS = {
    estimate: "#1f5fa8",
    truth: "#5f6b7a",
    flagged: "#d9730d",
    positionError: "#b42318",
    distanceError: "#1f5fa8",
    speed: "#2f7d4f",
    trajectory3d: 0xd9480f,
    junction3d: 0x7048e8,
  };
  const STATE_SHADES = {
    predicted: "rgba(217, 115, 13, 0.16)",
    bridged: "rgba(112, 72, 232, 0.14)",
    not_localised: "rgba(180, 35, 24, 0.16)",
  };
  const STATE_LABELS = { predicted: "predicted", bridged: "bridged", not_localised: "not localised" };
  const SECTION_PALETTE = [
    [31, 95, 168], [217, 115, 13], [47, 125, 79], [180, 35, 24], [112, 72, 232],
    [140, 86, 75], [214, 51, 132], [95, 107, 122], [163, 147, 0], [12, 133, 153],
  ];

  // ---------------------------------------------------------------- small helpers

  // el("div", {class: "x"}, child, "text", ...): builds DOM nodes; strings become text (never HTML).
  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [key, value] of Object.entries(attrs || {})) {
      if (value == null || value === false) continue;
      if (key === "class") node.className = value;
      else if (key === "text") node.textContent = value;
      else if (key.startsWith("on")) node.addEventListener(key.slice(2), value);
      else node.setAttribute(key, value === true ? "" : value);
    }
    for (const child of children.flat()) {
      if (child == null || child === false) continue;
      node.append(child instanceof Node ? child : String(child));
    }
    return node;
  }

  const isNum = (v) => typeof v === "number" && Number.isFinite(v);

  // Formats a number with fixed digits and an optional unit; "—" for missing values.
  function fmt(value, digits = 3, unit = "") {
    if (!isNum(value)) return value == null || value === "" ? "—" : String(value);
    const text = value.toFixed(digits).replace(/^-(0\.?0*)$/, "$1");
    return unit ? text + "\u2009" + unit : text;
  }

  // Formats a free value (metrics, section fields): numbers get sensible digits.
  function fmtAny(value) {
    if (value == null) return "—";
    if (typeof value === "number") {
      if (Number.isInteger(value)) return String(value);
      const magnitude = Math.abs(value);
      return value.toPrecision(magnitude >= 1000 ? 7 : magnitude >= 1 ? 5 : 4).replace(/(\.\d*?)0+$/, "$1").replace(/\.$/, "");
    }
    if (typeof value === "boolean") return value ? "yes" : "no";
    if (Array.isArray(value)) return value.map(fmtAny).join(", ");
    if (typeof value === "object") return JSON.stringify(value);
    return String(value);
  }

  // A table from column specs {label, value(row), num (right-align)} and rows.
  function table(columns, rows, attrs) {
    const head = el("tr", null, columns.map((c) => el("th", { class: c.num ? "num" : null, title: c.title }, c.label)));
    const body = rows.map((row) =>
      el("tr", row.__attrs || null, columns.map((c) => {
        const value = c.value(row);
        return el("td", { class: c.num ? "num" : null }, value instanceof Node ? value : value == null ? "—" : String(value));
      })));
    return el("div", { class: "table-wrap" }, el("table", attrs || null, el("thead", null, head), el("tbody", null, body)));
  }

  // Table of the keys of flat objects (union of keys in first-seen order).
  function objectTable(objects) {
    const keys = [];
    for (const object of objects) for (const key of Object.keys(object)) if (!keys.includes(key)) keys.push(key);
    return table(keys.map((key) => ({
      label: key.replace(/_/g, " "),
      num: objects.some((o) => typeof o[key] === "number"),
      value: (o) => fmtAny(o[key]),
    })), objects);
  }

  // "a – b", or "—" when neither end is known.
  function range(a, b, digits) {
    return !isNum(a) && !isNum(b) ? "—" : `${fmt(a, digits)} – ${fmt(b, digits)}`;
  }

  // Key/value list for the summary.
  function facts(pairs) {
    return el("dl", { class: "facts" }, pairs.filter(Boolean).map(([key, value]) =>
      el("div", null, el("dt", null, key), el("dd", null, value))));
  }

  const sections = [];  // {id, title} for the navigation bar

  function section(id, title, ...children) {
    sections.push({ id, title });
    const node = el("section", { id, class: "report-section" }, el("h2", null, title), ...children);
    main.append(node);
    return node;
  }

  function note(text, cls) {
    return el("p", { class: "note" + (cls ? " " + cls : "") }, text);
  }

  // Base64 to bytes (native decoder where the browser has one).
  function base64Bytes(text) {
    if (typeof Uint8Array.fromBase64 === "function") return Uint8Array.fromBase64(text);
    const binary = atob(text);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return bytes;
  }

  const littleEndianHost = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1;

  // Little-endian float32 / uint16 arrays from base64 (copied through DataView on big-endian hosts).
  function base64Float32(text) {
    const bytes = base64Bytes(text);
    if (littleEndianHost) return new Float32Array(bytes.buffer, bytes.byteOffset, bytes.byteLength >> 2);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    return Float32Array.from({ length: bytes.byteLength >> 2 }, (_, i) => view.getFloat32(i * 4, true));
  }

  function base64Uint16(text) {
    const bytes = base64Bytes(text);
    if (littleEndianHost) return new Uint16Array(bytes.buffer, bytes.byteOffset, bytes.byteLength >> 1);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    return Uint16Array.from({ length: bytes.byteLength >> 1 }, (_, i) => view.getUint16(i * 2, true));
  }

  // Waits for an <img> to load and decode; a broken image is a page error.
  function imageReady(img, what) {
    return img.decode().catch(() => {
      throw new Error("could not decode image: " + what);
    });
  }

  // Calls fn(width) when the element's width changes (after the first layout), debounced.
  function onWidthChange(element, fn) {
    let lastWidth = element.clientWidth;
    let timer = 0;
    new ResizeObserver(() => {
      const width = element.clientWidth;
      if (Math.abs(width - lastWidth) < 2) return;
      lastWidth = width;
      clearTimeout(timer);
      timer = setTimeout(() => fn(width), 120);
    }).observe(element);
  }

  // ---------------------------------------------------------------- header and summary

  const run = data.run || {};
  const quality = data.quality || {};
  const stations = data.stations || { t: [] };
  const truth = data.ground_truth;
  const convention = data.convention || {};

  document.title = (data.title || "pipescope report") + " — pipescope";

  function buildTitle() {
    const generated = data.generated || {};
    main.append(el("div", { class: "title-block" },
      el("h1", null, data.title || "Inspection report"),
      el("p", { class: "subtitle" },
        [run.command && `${run.command} run`, run.method && `method ${run.method}`,
          generated.by && `written by ${generated.by}`, generated.utc && generated.utc.replace("T", " ").replace("Z", " UTC")]
          .filter(Boolean).join(" · ")),
      el("p", { class: "paths" },
        el("span", null, "Run: ", el("code", null, run.directory || "—")),
        run.dataset ? el("span", null, "Dataset: ", el("code", null, run.dataset)) : null)));
  }

  function verdictBadge() {
    const verdict = quality.verdict;
    const cls = verdict === "reliable" ? "ok" : verdict === "unreliable" ? "bad" : "unknown";
    return el("span", { class: "badge badge-" + cls, id: "quality-verdict" }, verdict || "not assessed");
  }

  function buildSummary() {
    const frames = isNum(run.frames) ? `${run.frames_localised ?? "—"} localised of ${run.frames}` : "—";
    const counts = ["measured", "bridged", "predicted", "not_localised"]
      .filter((k) => isNum(quality["frames_" + k]))
      .map((k) => `${quality["frames_" + k]} ${k.replace("_", " ")}`).join(", ");
    const left = facts([
      ["Method", run.method || "—"],
      ["Frames", frames],
      counts && ["Frame states", counts],
      ["Distance travelled", fmt(run.distance_travelled_m, 3, "m")],
      ["Distance along pipe", isNum(run.distance_min_m) ? `${fmt(run.distance_min_m, 3)} to ${fmt(run.distance_max_m, 3, "m")}` : "—"],
      ["Duration", fmt(run.duration_s, 2, "s")],
      ["Pipe radius", fmt(run.radius_m, 3, "m")],
      isNum(quality.longest_predicted_stretch) && ["Longest predicted stretch", `${quality.longest_predicted_stretch} frames`],
    ]);

    const reasons = (quality.reasons || []).length
      ? el("ul", { class: "reasons" }, quality.reasons.map((r) => el("li", null, r)))
      : null;
    const verdictBox = el("div", { class: "verdict verdict-" + (quality.verdict || "unknown") },
      el("div", { class: "verdict-head" }, el("span", { class: "verdict-label" }, "Quality"), verdictBadge()),
      reasons || note(quality.verdict === "reliable" ? "No quality check failed." : "No reasons given."),
      // A map run whose positions past a turn are unconfirmed keeps its distances along the pipe.
      quality.along_pipe_verdict && quality.along_pipe_verdict !== quality.verdict
        ? note("Distances along the pipe: " + quality.along_pipe_verdict + ".")
        : null);

    const body = [el("div", { class: "summary-grid" }, left, verdictBox)];

    const stretches = quality.stretches || [];
    body.push(el("h3", null, "Stretches not measured"));
    if (stretches.length) {
      body.push(table([
        { label: "State", value: (s) => el("span", { class: "state state-" + s.state }, STATE_LABELS[s.state] || s.state) },
        { label: "Frames", num: true, value: (s) => `${s.first_frame}–${s.last_frame}` },
        { label: "Count", num: true, value: (s) => s.last_frame - s.first_frame + 1 },
        { label: "Time (s)", num: true, value: (s) => range(s.t_from, s.t_to, 2) },
        { label: "Distance (m)", num: true, value: (s) => range(s.distance_from_m, s.distance_to_m, 3) },
      ], stretches, { class: "stretches" }));
    } else {
      body.push(note("Every localised frame was measured: nothing was predicted or bridged."));
    }

    const warnings = data.warnings || [];
    body.push(el("h3", null, "Warnings"));
    body.push(warnings.length
      ? el("ul", { class: "warnings" }, warnings.map((w) => el("li", null, w)))
      : note("None."));

    body.push(el("h3", null, "Inspection coordinates"));
    body.push(facts([
      ["Distance", convention.distance || "—"],
      ["Clock", convention.clock || "—"],
      ["Up", (convention.up_source || "—") + (Array.isArray(convention.up) ? ` (up = [${convention.up.join(", ")}] in the run frame)` : "")],
    ]));

    section("summary", "Summary", ...body);
  }

  // ---------------------------------------------------------------- charts (uPlot)

  const charts = [];  // {plot, holder, height}
  const AXIS_FONT = "12px system-ui, -apple-system, 'Segoe UI', Roboto, sans-serif";

  function axis(label, extra) {
    return Object.assign({
      label, font: AXIS_FONT, labelFont: "600 12px system-ui, -apple-system, 'Segoe UI', Roboto, sans-serif",
      stroke: "#3d4652", grid: { stroke: "#e6e9ee", width: 1 }, ticks: { stroke: "#c8ced6", width: 1 },
      // Tick labels with as many decimals as the tick step needs.
      values: (u, splits, axisIdx, space, step) => splits.map((v) => v == null ? "" : fmt(v, distanceDecimals(step))),
    }, extra);
  }

  // Shades the predicted / bridged / not-localised stretches behind the series (x scale in seconds or metres).
  function stretchShading(key) {
    const stretches = quality.stretches || [];
    return (u) => {
      const ctx = u.ctx;
      const { top, height } = u.bbox;
      ctx.save();
      for (const s of stretches) {
        const a = key === "t" ? s.t_from : s.distance_from_m;
        const b = key === "t" ? s.t_to : s.distance_to_m;
        if (!isNum(a) || !isNum(b)) continue;
        let x0 = u.valToPos(Math.min(a, b), "x", true);
        let x1 = u.valToPos(Math.max(a, b), "x", true);
        if (x1 - x0 < 2) { x0 -= 1; x1 += 1; }  // a one-frame stretch stays visible
        ctx.fillStyle = STATE_SHADES[s.state] || STATE_SHADES.predicted;
        ctx.fillRect(x0, top, x1 - x0, height);
      }
      ctx.restore();
    };
  }

  // Creates a chart in its own figure; resolves the pending promise at its first draw.
  function chart(parent, title, caption, makeOptions, chartData) {
    const holder = el("div", { class: "chart-plot" });
    const figure = el("figure", { class: "chart" }, el("figcaption", null, el("strong", null, title), caption ? " " + caption : ""), holder);
    parent.append(figure);
    let drawn;
    pending.push(new Promise((resolve) => { drawn = resolve; }));
    const height = 260;
    const options = makeOptions(Math.max(holder.clientWidth, 200), height);
    options.hooks = options.hooks || {};
    let first = true;
    options.hooks.draw = (options.hooks.draw || []).concat([() => {
      if (first) performance.mark("pipescope:chart-" + title);
      first = false;
      drawn();
    }]);
    const plot = new uPlot(options, chartData, holder);
    charts.push({ plot, holder, height });
    onWidthChange(holder, (width) => plot.setSize({ width: Math.max(width, 200), height }));
    return plot;
  }

  // Path builder for x/y (mode 2) series: joins the points in data order (x need not be sorted).
  function orderedLine(u, seriesIdx, idx0, idx1) {
    const [xs, ys] = u.data[seriesIdx];
    const path = new Path2D();
    let penDown = false, lastX = 0, lastY = 0;
    for (let i = idx0; i <= idx1; i++) {
      if (xs[i] == null || ys[i] == null) { penDown = false; continue; }
      const px = u.valToPos(xs[i], "x", true);
      const py = u.valToPos(ys[i], "y", true);
      if (!penDown) { path.moveTo(px, py); penDown = true; }
      else if (Math.abs(px - lastX) + Math.abs(py - lastY) < 0.5) continue;  // skip sub-pixel steps
      else path.lineTo(px, py);
      lastX = px; lastY = py;
    }
    return { stroke: path, fill: null, clip: null, band: null, gaps: null, flags: 0 };
  }

  // Path builder for x/y (mode 2) markers: a small square at each point.
  function squareMarkers(size) {
    return (u, seriesIdx, idx0, idx1) => {
      const [xs, ys] = u.data[seriesIdx];
      const path = new Path2D();
      const half = size * devicePixelRatio / 2;
      for (let i = idx0; i <= idx1; i++) {
        if (xs[i] == null || ys[i] == null) continue;
        path.rect(u.valToPos(xs[i], "x", true) - half, u.valToPos(ys[i], "y", true) - half, 2 * half, 2 * half);
      }
      return { stroke: path, fill: path, clip: null, band: null, gaps: null, flags: 0 };
    };
  }

  // Hover for x/y charts: the point of each series nearest to the cursor (in pixels).
  function nearestPoint(u, seriesIdx) {
    const { left, top } = u.cursor;
    if (left == null || left < 0 || seriesIdx === 0) return null;
    const [xs, ys] = u.data[seriesIdx];
    let best = null, bestDistance = Infinity;
    for (let i = 0; i < xs.length; i++) {
      if (xs[i] == null || ys[i] == null) continue;
      const dx = u.valToPos(xs[i], "x") - left;
      const dy = u.valToPos(ys[i], "y") - top;
      const d = dx * dx + dy * dy;
      if (d < bestDistance) { bestDistance = d; best = i; }
    }
    return bestDistance <= 30 * 30 ? best : null;
  }

  // An x/y chart (top or side view): estimate, ground truth and the not-measured stations.
  function xyChart(parent, title, caption, xKey, yKey, yLabel, yDirection) {
    const series = [{}];
    const seriesData = [null];
    // Legend text of the hovered point (uPlot passes the point's index in x/y mode).
    const hovered = (times) => (u, v, seriesIdx, idx) => idx == null ? "—"
      : `t ${fmt(times[idx], 2)} s: ${xKey} ${fmt(u.data[seriesIdx][0][idx], 3)}, ${yKey} ${fmt(u.data[seriesIdx][1][idx], 3)}`;
    series.push({ label: "estimate", stroke: COLORS.estimate, width: 1.5, paths: orderedLine,
      points: { show: false, size: 7, stroke: COLORS.estimate, fill: "#fff" }, facets: xyFacets(), value: hovered(stations.t) });
    seriesData.push([stations[xKey], stations[yKey]]);
    if (truth) {
      series.push({ label: "ground truth", stroke: COLORS.truth, width: 1.5, dash: [6, 4], paths: orderedLine,
        points: { show: false, size: 7, stroke: COLORS.truth, fill: "#fff" }, facets: xyFacets(), value: hovered(truth.t) });
      seriesData.push([truth[xKey], truth[yKey]]);
    }
    const flagged = flaggedStations();
    if (flagged.length) {
      series.push({ label: "predicted / bridged", stroke: COLORS.flagged, fill: COLORS.flagged, width: 1, paths: squareMarkers(4),
        points: { show: false, size: 8, stroke: COLORS.flagged, fill: "#fff" }, facets: xyFacets(),
        value: hovered(flagged.map((i) => stations.t[i])) });
      seriesData.push([flagged.map((i) => stations[xKey][i]), flagged.map((i) => stations[yKey][i])]);
    }
    return chart(parent, title, caption, (width, height) => ({
      mode: 2, width, height,
      scales: { x: { time: false }, y: { dir: yDirection } },
      cursor: { drag: { x: true, y: true, uni: 20 }, dataIdx: nearestPoint, points: { one: false } },
      legend: { live: true },
      axes: [axis(xKey + " (m)"), axis(yLabel)],
      series,
    }), seriesData);
  }

  function xyFacets() {
    return [{ scale: "x", auto: true, sorted: 0 }, { scale: "y", auto: true, sorted: 0 }];
  }

  let flaggedCache = null;
  function flaggedStations() {
    if (!flaggedCache) {
      flaggedCache = [];
      (stations.state || []).forEach((state, i) => { if (state && state !== "measured") flaggedCache.push(i); });
    }
    return flaggedCache;
  }

  // A chart over time (mode 1, sorted x).
  function timeChart(parent, title, caption, series, columns, yLabel, digits) {
    return chart(parent, title, caption, (width, height) => ({
      width, height,
      scales: { x: { time: false } },
      cursor: { drag: { x: true, y: false } },
      axes: [axis("time (s)"), axis(yLabel)],
      series: [{ label: "t (s)", value: (u, v) => fmt(v, 2) }].concat(series.map((s) => Object.assign({
        width: 1.5, points: { show: false }, spanGaps: true, value: (u, v) => fmt(v, digits),
      }, s))),
      hooks: { drawClear: [stretchShading("t")] },
    }), columns);
  }

  // Joins ground truth (matched by timestamp) onto the station times.
  function truthOnStationTimes(key) {
    const joined = uPlot.join([[stations.t, stations[key]], [truth.t, truth[key]]]);
    return joined;
  }

  function shadingKey() {
    const present = new Set((quality.stretches || []).map((s) => s.state));
    if (!present.size) return null;
    return el("p", { class: "shade-key" }, "Shaded: ",
      [...present].map((state) => el("span", { class: "swatch-item" },
        el("span", { class: "swatch", style: `background:${STATE_SHADES[state]}` }), STATE_LABELS[state] || state)));
  }

  function buildTrajectory() {
    if (!stations.t || !stations.t.length) {
      section("trajectory", "Trajectory", note("No localised frames: nothing to plot."));
      return;
    }
    const grid = el("div", { class: "chart-grid" });
    const upY = Array.isArray(convention.up) ? convention.up[1] : 0;
    const node = section("trajectory", "Trajectory",
      note("Drag to zoom (both axes on the views, time on the others); double-click to reset. Hover shows values.", "screen-only"),
      shadingKey(), grid);
    xyChart(grid, "Top view", "x against z", "z", "x", "x (m)", 1);
    xyChart(grid, "Side view", upY < 0 ? "y against z (y axis drawn downwards: the pipe's up is up)" : "y against z",
      "z", "y", "y (m)", upY < 0 ? -1 : 1);

    let distanceColumns = [stations.t, stations.distance_m];
    const distanceSeries = [{ label: "distance", stroke: COLORS.estimate }];
    if (truth) {
      distanceColumns = truthOnStationTimes("distance_m");
      distanceSeries.push({ label: "ground truth", stroke: COLORS.truth, dash: [6, 4] });
    }
    timeChart(grid, "Distance along the pipe", "against time", distanceSeries, distanceColumns, "distance (m)", 3);
    timeChart(grid, "Speed", "against time", [{ label: "speed (m/s)", stroke: COLORS.speed }],
      [stations.t, stations.speed_m_s], "speed (m/s)", 3);
    return node;
  }

  function buildAccuracy() {
    if (!truth && !data.metrics) return;
    const body = [];
    if (truth && truth.t && truth.t.length) {
      // Sort by true distance so the x axis runs forwards.
      const order = truth.distance_m.map((_, i) => i).filter((i) => isNum(truth.distance_m[i]))
        .sort((a, b) => truth.distance_m[a] - truth.distance_m[b]);
      const xs = order.map((i) => truth.distance_m[i]);
      const grid = el("div", { class: "chart-grid" });
      body.push(note("Against the true distance along the pipe. Stations matched to the ground truth by timestamp."), grid);
      section("accuracy", "Accuracy against ground truth", ...body);
      const errorChart = (title, caption, key, label, color) => chart(grid, title, caption, (width, height) => ({
        width, height,
        scales: { x: { time: false } },
        cursor: { drag: { x: true, y: false } },
        axes: [axis("true distance along the pipe (m)"), axis(label)],
        series: [{ label: "distance (m)", value: (u, v) => fmt(v, 3) },
          { label, stroke: color, width: 1.5, points: { show: false }, spanGaps: true, value: (u, v) => fmt(v, 4) }],
        hooks: { drawClear: [stretchShading("distance")] },
      }), [xs, order.map((i) => truth[key][i])]);
      errorChart("Position error", "|estimate − truth|", "position_error_m", "position error (m)", COLORS.positionError);
      errorChart("Distance error", "estimated − true distance", "distance_error_m", "distance error (m)", COLORS.distanceError);
    } else {
      section("accuracy", "Accuracy against ground truth");
    }
    const node = document.getElementById("accuracy");
    if (data.metrics) {
      node.append(el("h3", null, "Metrics"));
      const entries = Object.entries(data.metrics).map(([key, value]) => ({ key, value }));
      node.append(table([
        { label: "Metric", value: (r) => el("code", null, r.key) },
        { label: "Value", num: true, value: (r) => fmtAny(r.value) },
      ], entries, { class: "metrics" }));
    }
  }

  // ---------------------------------------------------------------- unrolled wall strips

  const CLOCK_MARKS = [[0, "12"], [90, "3"], [180, "6"], [270, "9"]];
  const MAX_STRIP_COLS = 1200;
  const MAX_SCALE = 2;          // CSS px per mosaic column at most (small mosaics are not blown up further)
  const MAX_STRIP_HEIGHT = 200; // CSS px

  // Metres per strip: 1 m, or 2 / 5 / 10 m for long runs so that the page stays readable.
  function metresPerStrip(lengthM) {
    return lengthM <= 15 ? 1 : lengthM <= 40 ? 2 : lengthM <= 100 ? 5 : 10;
  }

  // A "nice" step (1, 2, 5 x 10^k) no smaller than minStep, and its minor subdivision.
  function niceStep(minStep) {
    const power = Math.pow(10, Math.floor(Math.log10(minStep)));
    for (const [mantissa, minor] of [[1, 5], [2, 4], [5, 5], [10, 5]]) {
      if (mantissa * power >= minStep * (1 - 1e-9)) return { major: mantissa * power, minor: mantissa * power / minor };
    }
    return { major: 10 * power, minor: 2 * power };
  }

  // Rows (fractional, row centres) where the clock angle equals `angle` modulo 360, within [-0.5, rows-0.5].
  function rowsAtClock(mosaic, angle, rows) {
    const a0 = mosaic.clock_deg_at_row0, per = mosaic.clock_deg_per_row;
    if (!isNum(a0) || !isNum(per) || per === 0) return [];
    const found = [];
    const span = Math.abs(per) * rows;
    const kMin = Math.floor((Math.min(a0, a0 + per * rows) - angle) / 360) - 1;
    const kMax = kMin + Math.ceil(span / 360) + 2;
    for (let k = kMin; k <= kMax; k++) {
      const r = (angle + 360 * k - a0) / per;
      if (r >= -0.5 && r <= rows - 0.5) found.push(r);
    }
    return found;
  }

  // Decimals needed to write multiples of `step` exactly (0.1 -> 1, 0.25 -> 2, 0.0025 -> 4).
  function distanceDecimals(step) {
    for (let d = 0; d < 8; d++) {
      const scaled = Math.abs(step) * Math.pow(10, d);
      if (Math.abs(scaled - Math.round(scaled)) < 1e-6 * Math.max(1, scaled)) return d;
    }
    return 8;
  }

  // Builds the strips of one mosaic into `holder` for the available width (CSS px).
  function layoutMosaic(holder, mosaic, mosaicIndex, image, available) {
    holder.textContent = "";
    const cols = mosaic.width_px, rows = mosaic.height_px;
    const perCol = mosaic.distance_m_per_col, d0 = mosaic.distance_m_at_col0;
    const metric = mosaic.metric && isNum(perCol) && perCol !== 0 && isNum(d0);
    const hasClock = isNum(mosaic.clock_deg_at_row0) && isNum(mosaic.clock_deg_per_row) && mosaic.clock_deg_per_row !== 0;

    let stripCols = Math.min(cols, MAX_STRIP_COLS);
    if (metric) {
      const metres = metresPerStrip(cols * Math.abs(perCol));
      stripCols = Math.min(cols, Math.max(1, Math.floor(metres / Math.abs(perCol))));
      if (metres === 1) stripCols = Math.min(stripCols, MAX_STRIP_COLS);
    }
    const scale = Math.min(MAX_SCALE, MAX_STRIP_HEIGHT / rows, available / stripCols);
    const heightCss = rows * scale;

    const observations = metric && hasClock ? (data.observations || []).filter((o) => isNum(o.distance_m) && isNum(o.clock_angle_deg)) : [];
    const strips = [];

    for (let col0 = 0, index = 0; col0 < cols; col0 += stripCols, index++) {
      const n = Math.min(stripCols, cols - col0);
      const widthCss = n * scale;
      const stripId = `m${mosaicIndex}-s${index}`;
      const dpr = Math.min(window.devicePixelRatio || 1, 2);

      const canvas = el("canvas", {
        class: "wall-strip-image", "data-strip": stripId, "data-mosaic": mosaicIndex,
        "data-col0": col0, "data-cols": n, "data-row0": 0, "data-rows": rows,
        width: Math.max(1, Math.round(widthCss * dpr)), height: Math.max(1, Math.round(heightCss * dpr)),
        role: "img", "aria-label": `${mosaic.title || "mosaic"}, columns ${col0} to ${col0 + n - 1}`,
      });
      const ctx = canvas.getContext("2d", { willReadFrequently: true });  // a software canvas: static image, no GPU upload
      ctx.imageSmoothingQuality = "high";
      ctx.drawImage(image, col0, 0, n, rows, 0, 0, canvas.width, canvas.height);

      const frame = el("div", { class: "wall-strip-frame", style: `width:${widthCss}px` }, canvas);
      const pct = (x, total) => `${(100 * x / total).toFixed(4)}%`;

      // Clock labels beside the strip at 12, 3, 6 and 9 o'clock.
      if (hasClock) {
        for (const [angle, text] of CLOCK_MARKS) {
          for (const r of rowsAtClock(mosaic, angle, rows)) {
            const top = pct((r + 0.5) * scale, heightCss);
            frame.append(el("span", { class: "clock-label", "data-strip": stripId, "data-clock-deg": angle, style: `top:${top}` }, text));
            frame.append(el("span", { class: "clock-guide", style: `top:${top}` }));
          }
        }
      }

      // Observation markers.
      for (const o of observations) {
        const c = (o.distance_m - d0) / perCol;
        if (c < col0 - 0.5 || c >= col0 + n - 0.5) continue;
        const r = rowsAtClock(mosaic, o.clock_angle_deg, rows)[0];
        if (r === undefined) continue;
        frame.append(el("a", {
          class: "wall-marker", href: `#observation-${o.id}`,
          style: `left:${pct((c - col0 + 0.5) * scale, widthCss)};top:${pct((r + 0.5) * scale, heightCss)}`,
          title: `#${o.id} ${o.code || ""} ${o.remark || ""} — ${fmt(o.distance_m, 3, "m")}, ${o.clock || ""}`.trim(),
        }, el("span", null, String(o.id))));
      }

      const strip = el("div", { class: "wall-strip" });
      if (metric) strip.append(ruler(stripId, col0, n, widthCss, scale, d0, perCol));
      strip.append(frame);
      holder.append(strip);
      strips.push(canvas);
    }
    measureStrips(holder);
  }

  // The distance ruler above one strip (labels and ticks positioned in % of the strip width).
  function ruler(stripId, col0, n, widthCss, scale, d0, perCol) {
    const pxPerMetre = scale / Math.abs(perCol);
    const { major, minor } = niceStep(90 / pxPerMetre);
    const decimals = distanceDecimals(major);
    // Distance at the strip's edges (outer edges of the first and last columns).
    const dA = d0 + perCol * (col0 - 0.5), dB = d0 + perCol * (col0 + n - 0.5);
    const lo = Math.min(dA, dB), hi = Math.max(dA, dB);
    const xOf = (d) => ((d - d0) / perCol - col0 + 0.5) * scale;
    const node = el("div", { class: "ruler", style: `width:${widthCss}px` });
    const left = (d) => `${(100 * xOf(d) / widthCss).toFixed(4)}%`;
    const minorCount = Math.round(major / minor);
    for (let k = Math.ceil(lo / minor - 1e-9); k * minor <= hi + 1e-12; k++) {
      const d = k * minor;
      const isMajor = k % minorCount === 0;
      node.append(el("span", { class: isMajor ? "tick tick-major" : "tick", style: `left:${left(d)}` }));
      if (isMajor) {
        const value = Number(d.toFixed(decimals + 2));
        node.append(el("span", { class: "ruler-label", "data-strip": stripId, "data-distance-m": value, style: `left:${left(d)}` },
          fmt(value, decimals)));
      }
    }
    return node;
  }

  // Records where labels ended up (CSS px relative to their strip image) for the browser check.
  function measureStrips(holder) {
    const images = new Map();
    for (const canvas of holder.querySelectorAll(".wall-strip-image")) {
      const rect = canvas.getBoundingClientRect();
      canvas.dataset.widthCss = rect.width.toFixed(3);
      canvas.dataset.heightCss = rect.height.toFixed(3);
      images.set(canvas.dataset.strip, rect);
    }
    for (const label of holder.querySelectorAll(".ruler-label")) {
      const rect = label.getBoundingClientRect(), image = images.get(label.dataset.strip);
      label.dataset.xCss = ((rect.left + rect.right) / 2 - image.left).toFixed(3);
    }
    for (const label of holder.querySelectorAll(".clock-label")) {
      const rect = label.getBoundingClientRect(), image = images.get(label.dataset.strip);
      label.dataset.yCss = ((rect.top + rect.bottom) / 2 - image.top).toFixed(3);
    }
  }

  function buildWall() {
    const mosaics = data.mosaics || [];
    if (!mosaics.length) return;
    const node = section("wall", "Unrolled wall");
    mosaics.forEach((mosaic, index) => {
      const metric = !!mosaic.metric;
      const holder = el("div", { class: "wall-strips" });
      const figure = el("div", { class: "mosaic" },
        el("h3", null, mosaic.title || `Mosaic ${index + 1}`),
        mosaic.note ? note(mosaic.note) : null,
        metric
          ? note(`Ruler: distance along the pipe in metres. Columns ${mosaic.distance_m_per_col < 0 ? "run against the survey direction (distance falls to the right)" : "run with the survey direction"}; ${fmt(Math.abs(mosaic.distance_m_per_col) * 1000, 2)} mm per column. Labels at the left: clock positions.`)
          : note("This mosaic is in image space: it has no distance scale, so no ruler or markers are drawn.", "warn"),
        holder);
      node.append(figure);
      const image = new Image();
      image.src = mosaic.image;
      pending.push(imageReady(image, mosaic.title || `mosaic ${index}`).then(() => {
        const available = () => holder.clientWidth - 36;  // room for the clock labels
        layoutMosaic(holder, mosaic, index, image, available());
        performance.mark(`pipescope:mosaic-${index}`);
        onWidthChange(holder, () => layoutMosaic(holder, mosaic, index, image, available()));
      }));
    });
  }

  // ---------------------------------------------------------------- map: classification, sections, junctions

  function buildMap() {
    const cls = data.classification;
    const sectionsList = data.sections || [];
    const junctions = data.junctions || [];
    const tToT = data.t_to_t || [];
    if (!cls && !sectionsList.length && !junctions.length && !tToT.length) return;
    const node = section("map", "Map");

    if (cls) {
      node.append(el("h3", null, "Classification"));
      if (cls.image) {
        const img = el("img", { class: "classification-strip", src: cls.image, alt: "classification along the run" });
        pending.push(imageReady(img, "classification strip"));
        node.append(el("figure", { class: "classification" }, img));
      }
      const keyframes = cls.keyframes || [];
      if (keyframes.length) {
        const counts = {};
        for (const k of keyframes) counts[k.class] = (counts[k.class] || 0) + 1;
        node.append(el("p", { class: "note" }, "Key frames by class: ",
          Object.entries(counts).map(([k, n]) => `${k} ${n}`).join(", "), "."));
        node.append(el("details", { class: "collapsible" },
          el("summary", null, `Key-frame classes (${keyframes.length})`),
          table([
            { label: "Frame", num: true, value: (k) => k.frame },
            { label: "Time (s)", num: true, value: (k) => fmt(k.t, 2) },
            { label: "Distance (m)", num: true, value: (k) => fmt(k.distance_m, 3) },
            { label: "Class", value: (k) => k.class },
            { label: "Section", num: true, value: (k) => k.section ?? "—" },
          ], keyframes)));
      }
    }
    if (sectionsList.length) {
      node.append(el("h3", null, "Sections"), objectTable(sectionsList));
    }
    if (junctions.length) {
      node.append(el("h3", null, "Junctions"), table([
        { label: "Name", value: (j) => j.name },
        { label: "Time (s)", num: true, value: (j) => fmt(j.t, 2) },
        { label: "Distance (m)", num: true, value: (j) => fmt(j.distance_m, 3) },
        { label: "Centre x, y, z (m)", num: true, value: (j) => Array.isArray(j.center) ? j.center.map((v) => fmt(v, 3)).join(", ") : "—" },
      ], junctions));
    }
    if (tToT.length) {
      const errorCell = (r) => isNum(r.error_pct)
        ? el("span", { class: Math.abs(r.error_pct) > 2 ? "bad-text" : null }, fmt(r.error_pct, 2, "%")) : "—";
      node.append(el("h3", null, "Distance between junctions"), table([
        { label: "From", value: (r) => r.from },
        { label: "To", value: (r) => r.to },
        { label: "Distance (m)", num: true, value: (r) => fmt(r.distance_m, 3) },
        { label: "True (m)", num: true, value: (r) => fmt(r.true_m, 3) },
        { label: "Error", num: true, value: errorCell },
      ], tToT));
    }
  }

  // ---------------------------------------------------------------- observations

  function buildObservations() {
    const observations = data.observations || [];
    if (!observations.length) return;
    const crop = (src, what) => {
      if (!src) return el("span", { class: "muted" }, "—");
      const img = el("img", { class: "crop", src, alt: what, loading: "eager" });
      pending.push(imageReady(img, what));
      return img;
    };
    const rows = observations.map((o) => Object.assign({ __attrs: { id: `observation-${o.id}` } }, o));
    section("observations", "Observations", table([
      { label: "#", num: true, value: (o) => o.id },
      { label: "Code", value: (o) => el("strong", null, o.code || "—") },
      { label: "Remark", value: (o) => o.remark || "—" },
      { label: "Frame", num: true, value: (o) => `${o.frame} (${fmt(o.u, 0)}, ${fmt(o.v, 0)})` },
      { label: "Distance (m)", num: true, value: (o) => fmt(o.distance_m, 3) },
      { label: "Clock", value: (o) => `${o.clock || "—"}` + (o.clock_from && o.clock_to ? ` (${o.clock_from}–${o.clock_to})` : "") },
      { label: "Section", num: true, value: (o) => o.section ?? "—" },
      { label: "Frame crop", value: (o) => crop(o.crop_frame, `observation ${o.id}, camera frame`) },
      { label: "Wall crop", value: (o) => crop(o.crop_wall, `observation ${o.id}, unrolled wall`) },
    ], rows, { class: "observations" }));
  }

  // ---------------------------------------------------------------- 3D viewer (three.js)

  // A WebGL 2 context for the viewer, or null. The renderer reuses it (creating contexts is slow in software GL).
  function webgl2Context() {
    try {
      const canvas = document.createElement("canvas");
      const context = canvas.getContext("webgl2", { antialias: false, alpha: false });
      return context ? { canvas, context } : null;
    } catch (e) {
      return null;
    }
  }

  // three.js and OrbitControls are embedded as text; they become blob: modules, with an import map so that
  // OrbitControls' `import ... from 'three'` resolves. Must run before any other module is loaded.
  function loadThree() {
    const moduleUrl = (id) => URL.createObjectURL(new Blob([document.getElementById(id).textContent], { type: "text/javascript" }));
    const threeUrl = moduleUrl("lib-three");
    const controlsUrl = moduleUrl("lib-orbit-controls");
    const importMap = el("script", { type: "importmap" });
    importMap.textContent = JSON.stringify({ imports: { three: threeUrl } });
    document.head.append(importMap);
    return Promise.all([import(threeUrl), import(controlsUrl)]).finally(() => performance.mark("pipescope:three-imported"));
  }

  function buildViewer() {
    const cloud = data.cloud;
    if (!cloud || !cloud.count) {
      root.dataset.viewer = "none";
      return;
    }
    const node = section("viewer", "3D view");
    const gl = webgl2Context();
    if (!gl) {
      root.dataset.viewer = "unavailable";
      node.append(note("The 3D view needs WebGL 2, which this browser does not provide here. The rest of the report is complete.", "warn"));
      return;
    }
    const stage = el("div", { class: "viewer-stage" });
    const overlay = el("div", { class: "viewer-labels" });
    const printImage = el("img", { class: "viewer-print", alt: "3D view" });
    const colorSelect = el("select", { id: "viewer-color" });
    const sizeInput = el("input", { id: "viewer-point-size", type: "range", min: "1", max: "8", step: "0.5", value: "2" });
    const sizeValue = el("output", null, "2 px");
    const legend = el("div", { class: "viewer-legend" });
    node.append(
      el("div", { class: "viewer-controls" },
        el("label", null, "Colour ", colorSelect),
        el("label", null, "Point size ", sizeInput, sizeValue),
        el("span", { class: "muted" }, `${cloud.count.toLocaleString("en")} points · drag to orbit, wheel to zoom, right-drag to pan`)),
      el("div", { class: "viewer" }, stage, overlay), printImage, legend);
    pending.push(loadThree().then(([THREE, controlsModule]) =>
      startViewer(THREE, controlsModule.OrbitControls, cloud, gl, { stage, overlay, printImage, colorSelect, sizeInput, sizeValue, legend })));
  }

  function startViewer(THREE, OrbitControls, cloud, gl, ui) {
    performance.mark("pipescope:three-loaded");
    const count = cloud.count;
    const positions = base64Float32(cloud.positions_f32);
    if (positions.length < count * 3) throw new Error(`cloud: positions hold ${positions.length / 3} points, count says ${count}`);
    const grey = cloud.grey_u8 ? base64Bytes(cloud.grey_u8) : null;
    const sectionIds = cloud.section_u16 ? base64Uint16(cloud.section_u16) : null;

    // Colour buffers (RGB bytes), built when first chosen.
    const colorBuilders = {};
    if (grey) colorBuilders.grey = () => {
      const rgb = new Uint8Array(count * 3);
      for (let i = 0, j = 0; i < count; i++, j += 3) rgb[j] = rgb[j + 1] = rgb[j + 2] = grey[i];
      return rgb;
    };
    const sectionsPresent = new Set();
    if (sectionIds) {
      for (let i = 0; i < count; i++) sectionsPresent.add(sectionIds[i]);
      colorBuilders.section = () => {
        const rgb = new Uint8Array(count * 3);
        for (let i = 0, j = 0; i < count; i++, j += 3) {
          const s = sectionIds[i];
          const c = s === 0xffff ? [170, 170, 170] : SECTION_PALETTE[s % SECTION_PALETTE.length];
          rgb[j] = c[0]; rgb[j + 1] = c[1]; rgb[j + 2] = c[2];
        }
        return rgb;
      };
    }
    const modes = Object.keys(colorBuilders);
    for (const mode of modes.concat(["plain"])) {
      ui.colorSelect.append(el("option", { value: mode }, { grey: "grey value", section: "section", plain: "single colour" }[mode]));
    }
    const colorCache = {};

    // Colours are used exactly as given (sRGB bytes in, the same bytes on screen): no colour management.
    THREE.ColorManagement.enabled = false;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(positions.subarray(0, count * 3), 3));
    geometry.computeBoundingSphere();
    const material = new THREE.PointsMaterial({ size: 2, sizeAttenuation: false, color: 0xffffff, vertexColors: true });
    const points = new THREE.Points(geometry, material);

    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f6f8);
    scene.add(points);

    const sphere = geometry.boundingSphere;
    const center = sphere.center.clone();
    const radius = Math.max(sphere.radius, 1e-3);

    if (cloud.trajectory_f32) {
      const path = base64Float32(cloud.trajectory_f32);
      const line = new THREE.BufferGeometry();
      line.setAttribute("position", new THREE.BufferAttribute(path, 3));
      scene.add(new THREE.Line(line, new THREE.LineBasicMaterial({ color: COLORS.trajectory3d })));
    }

    const junctions = (cloud.junctions || []).filter((j) => Array.isArray(j.center));
    const markerGeometry = new THREE.SphereGeometry(radius * 0.012, 16, 12);
    const markerMaterial = new THREE.MeshBasicMaterial({ color: COLORS.junction3d });
    const labels = junctions.map((j) => {
      const mesh = new THREE.Mesh(markerGeometry, markerMaterial);
      mesh.position.set(j.center[0], j.center[1], j.center[2]);
      scene.add(mesh);
      const label = el("span", { class: "junction-label" }, j.name);
      ui.overlay.append(label);
      return { position: mesh.position, label };
    });

    // Camera: the pipe's "up" is up on screen; look from the side of the longest extent.
    const up = new THREE.Vector3().fromArray(Array.isArray(convention.up) ? convention.up : [0, 1, 0]).normalize();
    if (!isFinite(up.x) || up.lengthSq() === 0) up.set(0, 1, 0);
    geometry.computeBoundingBox();
    const size = geometry.boundingBox.getSize(new THREE.Vector3());
    const along = size.x >= size.y && size.x >= size.z ? new THREE.Vector3(1, 0, 0)
      : size.y >= size.z ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(0, 0, 1);
    let side = new THREE.Vector3().crossVectors(up, along);
    if (side.lengthSq() < 1e-6) side = new THREE.Vector3().crossVectors(up, new THREE.Vector3(1, 0, 0));
    if (side.lengthSq() < 1e-6) side.set(0, 0, 1);
    side.normalize();

    const camera = new THREE.PerspectiveCamera(45, 1, radius / 1000, radius * 100);
    camera.up.copy(up);
    camera.position.copy(center).addScaledVector(side, radius * 1.9).addScaledVector(up, radius * 0.7);
    camera.lookAt(center);

    const renderer = new THREE.WebGLRenderer({ canvas: gl.canvas, context: gl.context, antialias: false });
    renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
    renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    ui.stage.append(renderer.domElement);

    const controls = new OrbitControls(camera, renderer.domElement);
    controls.target.copy(center);
    controls.screenSpacePanning = true;
    controls.update();

    const projected = new THREE.Vector3();
    function render() {
      renderer.render(scene, camera);
      const w = ui.stage.clientWidth, h = ui.stage.clientHeight;
      for (const { position, label } of labels) {
        projected.copy(position).project(camera);
        const visible = projected.z > -1 && projected.z < 1;
        label.style.display = visible ? "" : "none";
        label.style.transform = `translate(${((projected.x + 1) / 2 * w).toFixed(1)}px, ${((1 - projected.y) / 2 * h).toFixed(1)}px)`;
      }
    }
    let frameRequested = false;
    function requestRender() {
      if (frameRequested) return;
      frameRequested = true;
      requestAnimationFrame(() => { frameRequested = false; render(); });
    }
    controls.addEventListener("change", requestRender);

    function resize() {
      const w = Math.max(ui.stage.clientWidth, 100), h = Math.max(ui.stage.clientHeight, 100);
      renderer.setSize(w, h);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
    }
    new ResizeObserver(() => { resize(); requestRender(); }).observe(ui.stage);

    function setColorMode(mode) {
      if (mode === "plain" || !colorBuilders[mode]) {
        material.vertexColors = false;
        material.color.set(0x3d5a80);
        geometry.deleteAttribute("color");
      } else {
        colorCache[mode] = colorCache[mode] || colorBuilders[mode]();
        geometry.setAttribute("color", new THREE.BufferAttribute(colorCache[mode], 3, true));
        material.vertexColors = true;
        material.color.set(0xffffff);
      }
      material.needsUpdate = true;
      ui.legend.textContent = "";
      if (mode === "section") {
        const ids = [...sectionsPresent].sort((a, b) => a - b);
        ui.legend.append("Sections: ", ...ids.slice(0, 24).map((s) => el("span", { class: "swatch-item" },
          el("span", { class: "swatch", style: `background:rgb(${(s === 0xffff ? [170, 170, 170] : SECTION_PALETTE[s % SECTION_PALETTE.length]).join(",")})` }),
          s === 0xffff ? "none" : String(s))), ids.length > 24 ? ` … ${ids.length} in all` : "");
      }
      requestRender();
    }
    ui.colorSelect.addEventListener("change", () => setColorMode(ui.colorSelect.value));
    ui.sizeInput.addEventListener("input", () => {
      material.size = Number(ui.sizeInput.value);
      ui.sizeValue.textContent = `${ui.sizeInput.value} px`;
      requestRender();
    });

    // Printing: a still image of the current view replaces the canvas.
    window.addEventListener("beforeprint", () => {
      render();
      ui.printImage.src = renderer.domElement.toDataURL("image/png");
    });

    setColorMode(modes[0] || "plain");
    resize();
    performance.mark("pipescope:viewer-built");
    render();
    performance.mark("pipescope:viewer-rendered");
    // The first frame has been submitted; mark the viewer drawn after the browser has presented it.
    return new Promise((resolve) => requestAnimationFrame(() => {
      root.dataset.viewer = "drawn";
      resolve();
    }));
  }

  // ---------------------------------------------------------------- navigation, footer, print, ready

  function buildNav() {
    const nav = document.getElementById("nav");
    for (const { id, title } of sections) nav.append(el("a", { href: "#" + id }, title));
  }

  function buildFooter() {
    const generated = data.generated || {};
    const timings = (run.timings_s && typeof run.timings_s === "object") ? run.timings_s : {};
    const footer = document.getElementById("footer");
    footer.append(
      el("p", null, `Written by ${generated.by || "pipescope"}${generated.utc ? " at " + generated.utc : ""} · schema ${data.schema || "?"}`),
      Object.keys(timings).length
        ? el("p", null, "Timings: " + Object.entries(timings).map(([k, v]) => `${k} ${fmt(v, 2, "s")}`).join(" · ")) : null,
      el("p", { class: "muted" }, "Charts drawn with uPlot, 3D view with three.js (both MIT licensed, embedded in this file)."));
  }

  // Charts are redrawn at print width before printing and restored afterwards.
  function setupPrint() {
    const PRINT_WIDTH = 680;
    window.addEventListener("beforeprint", () => {
      for (const c of charts) c.plot.setSize({ width: PRINT_WIDTH, height: 220 });
    });
    window.addEventListener("afterprint", () => {
      for (const c of charts) c.plot.setSize({ width: Math.max(c.holder.clientWidth, 200), height: c.height });
    });
  }

  function setReady() {
    performance.mark("pipescope:ready");
    if (!root.dataset.viewer) root.dataset.viewer = data.cloud && data.cloud.count ? "pending" : "none";
    root.dataset.readyMs = performance.now().toFixed(0);
    root.dataset.pipescopeStatus = window.pipescopeErrors.messages.length ? "error" : "ready";
  }

  function build() {
    const steps = { buildTitle, buildSummary, buildTrajectory, buildAccuracy, buildWall, buildMap, buildObservations,
      buildViewer, buildNav, buildFooter, setupPrint };
    for (const [name, step] of Object.entries(steps)) {
      step();
      performance.mark("pipescope:" + name);  // timings for profiling (performance.getEntriesByType("mark"))
    }
  }

  try {
    if (data.schema !== "pipescope-report/1") console.error(`unexpected report schema: ${data.schema}`);
    build();
  } catch (error) {
    window.pipescopeErrors.record("Error while building the page: " + (error.stack || error));
  }
  Promise.all(pending).then(setReady, (error) => {
    window.pipescopeErrors.record("Error: " + (error && error.stack || error));
    setReady();
  });
})();
