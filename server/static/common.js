// Shared helpers of the dashboard pages: DOM building, number formats, the live stream,
// and small SVG charts. Plain JavaScript, no framework; text always goes in through
// textContent, never as HTML, so names and details from the network cannot inject markup.
"use strict";

const EDNC = (() => {
  const SVG_NS = "http://www.w3.org/2000/svg";

  /** An element with attributes (class, data-*, ...) and children (nodes or text). */
  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    setAttrs(node, attrs);
    append(node, children);
    return node;
  }

  function svg(tag, attrs, ...children) {
    const node = document.createElementNS(SVG_NS, tag);
    setAttrs(node, attrs);
    append(node, children);
    return node;
  }

  function setAttrs(node, attrs) {
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v === null || v === undefined || v === false) continue;
      node.setAttribute(k, v === true ? "" : String(v));
    }
  }

  function append(node, children) {
    for (const c of children.flat()) {
      if (c === null || c === undefined || c === false) continue;
      node.append(c instanceof Node ? c : document.createTextNode(String(c)));
    }
  }

  /** Replace a node's children (null, undefined and false children are left out). */
  function fill(node, ...children) {
    node.replaceChildren();
    append(node, children);
    return node;
  }

  // What the keys of a diagnosis estimate (formats.md §3) mean, for a person: a label and
  // the unit; a key "<k>_std" is the standard uncertainty of "<k>" and is shown beside it.
  const ESTIMATE_LABELS = {
    reversal_um: ["reversal", "µm"], um_per_K: ["sensitivity", "µm/K"],
    um_per_m_K: ["expansion", "µm/(m·K)"], um_per_h: ["drift", "µm/h"],
    radial_um: ["radial amplitude", "µm"], order: ["per revolution, order", ""],
    period_mm: ["period", "mm"], phase_rad: ["phase", "rad"], tau_s: ["time constant", "s"],
    amplitude_um: ["amplitude", "µm"], max_abs_um: ["largest residual", "µm"],
    structure_um: ["structure", "µm"], steady_um_per_K: ["steady sensitivity", "µm/K"],
    offset_um: ["offset", "µm"], rms_um: ["RMS", "µm"], rms_rigid_um: ["RMS (rigid model)", "µm"],
    n_readings: ["readings", ""], rms_before_um: ["RMS before", "µm"],
    rms_after_um: ["RMS after", "µm"], r2: ["R²", ""],
  };
  const SUFFIX_UNITS = [["_um_per_m_K", "µm/(m·K)"], ["_um_per_K", "µm/K"], ["_um_per_h", "µm/h"],
    ["_um", "µm"], ["_mm", "mm"], ["_urad", "µrad"], ["_rad", "rad"], ["_s", "s"],
    ["_C", "°C"], ["_K", "K"]];

  /** One estimate entry as "reversal 9.80 ± 0.12 µm" (std from the "<key>_std" entry of
   *  `all` when given); labels, not keys. */
  function estimate(key, value, all = {}) {
    let [label, unit] = ESTIMATE_LABELS[key] || [null, null];
    if (label === null) {
      const found = SUFFIX_UNITS.find(([suffix]) => key.endsWith(suffix));
      unit = found ? found[1] : "";
      label = (found ? key.slice(0, -found[0].length) : key).replace(/_/g, " ");
    }
    const digits = Number.isInteger(value) ? 0 : Math.abs(value) < 0.1 ? 3 : 2;
    const std = all[`${key}_std`];
    const spread = typeof std === "number" ? ` ± ${num(std, digits)}` : "";
    return `${label} ${num(value, digits)}${spread}${unit ? " " + unit : ""}`;
  }

  /** Every entry of an estimate, its "_std" entries beside their values. */
  function estimates(all) {
    return Object.entries(all || {})
      .filter(([k]) => !(k.endsWith("_std") && k.slice(0, -4) in all))
      .map(([k, v]) => estimate(k, v, all)).join(", ");
  }

  /** What a diagnosis says, in words: effect "none" means the readings show no effect
   *  beyond the model (a diagnosis was made), not that none was made. */
  function effectText(d) {
    if (d.effect === "none") return "no effect beyond the model found";
    const words = { backlash: "backlash", thermal_drift: "thermal drift",
      thermal_expansion: "thermal expansion", time_drift: "drift with time",
      periodic: "periodic error", rotary_periodic: "rotary periodic error",
      unexplained: "unexplained error" };
    return [words[d.effect] || d.effect.replace(/_/g, " "), d.axis ? `on ${d.axis}` : null,
      d.sensor ? `(sensor ${d.sensor})` : null].filter(Boolean).join(" ");
  }

  /** A model's info entry (fit statistics) as a label with its unit. */
  function infoText(key, value) {
    return typeof value === "number" ? estimate(key, value) : `${key.replace(/_/g, " ")}: ${value}`;
  }

  /** A number with fixed decimals, or an em dash when there is none. */
  function num(value, digits = 1) {
    if (value === null || value === undefined || !Number.isFinite(value)) return "—";
    const text = value.toFixed(digits);
    return text === "-" + (0).toFixed(digits) ? (0).toFixed(digits) : text;
  }

  /** A number with its unit, "12.3 µm"; an em dash without a value. */
  function qty(value, unit, digits = 1) {
    const text = num(value, digits);
    return text === "—" ? text : `${text} ${unit}`;
  }

  function signed(value, unit, digits = 1) {
    const text = qty(value, unit, digits);
    return value > 0 && text !== "—" ? "+" + text : text;
  }

  /** "12 s ago", "3 min ago" from an age in seconds. */
  function age(seconds) {
    if (seconds === null || seconds === undefined) return "never";
    if (seconds < 60) return `${seconds.toFixed(0)} s ago`;
    if (seconds < 3600) return `${(seconds / 60).toFixed(0)} min ago`;
    if (seconds < 86400) return `${(seconds / 3600).toFixed(1)} h ago`;
    return `${(seconds / 86400).toFixed(1)} d ago`;
  }

  /** An ISO time as local "YYYY-MM-DD HH:MM:SS". */
  function time(iso) {
    if (!iso) return "—";
    const d = new Date(iso);
    const p = (n) => String(n).padStart(2, "0");
    return `${d.getFullYear()}-${p(d.getMonth() + 1)}-${p(d.getDate())} ` +
      `${p(d.getHours())}:${p(d.getMinutes())}:${p(d.getSeconds())}`;
  }

  /** A rotary axis's position is in degrees, a linear one's in mm. */
  function posUnit(axis) { return axis.rotary ? "°" : "mm"; }
  function compUnit(axis) { return axis.rotary ? "µrad" : "µm"; }

  async function getJSON(url) {
    const r = await fetch(url, { headers: { Accept: "application/json" } });
    let body = null;
    try { body = await r.json(); } catch (_) { body = null; }
    if (!r.ok) {
      const detail = body && body.detail;
      const text = typeof detail === "string" ? detail
        : Array.isArray(detail) ? detail.map((d) => d.msg).join("; ") : r.statusText;
      const err = new Error(text || `HTTP ${r.status}`);
      err.status = r.status;
      throw err;
    }
    return body;
  }

  /**
   * Follow /api/live: onSnapshot(snapshot) for every snapshot, onState("live" | "down")
   * when the stream opens or breaks. EventSource reconnects by itself (the server ends each
   * stream after a while, see server/dashboard/live.py).
   */
  function follow(onSnapshot, onState) {
    // The server ends every stream after a while and the browser reconnects within a
    // second: only a link that stays down for a few seconds is shown as down. A reply that
    // is not a stream (a 5xx) makes EventSource give up: start a new one after a pause.
    let pending = null;
    const up = () => {
      clearTimeout(pending);
      pending = null;
      onState("live");
    };
    const open = () => {
      const source = new EventSource("/api/live");
      source.addEventListener("open", up);
      source.addEventListener("error", () => {
        if (pending === null) pending = setTimeout(() => onState("down"), 3000);
        if (source.readyState === EventSource.CLOSED) setTimeout(open, 5000);
      });
      source.addEventListener("snapshot", (e) => {
        up();
        onSnapshot(JSON.parse(e.data));
      });
    };
    open();
  }

  /** The live indicator in the page header. */
  function showLinkState(node, state) {
    node.className = "live-indicator " + state;
    node.textContent = state === "live" ? "● live" : "● reconnecting…";
  }

  const HEALTH_TEXT = { ok: "OK", unknown: "UNKNOWN", warn: "ATTENTION", offline: "OFFLINE",
    alarm: "ALARM", out_of_tolerance: "OUT OF TOLERANCE" };
  const SEVERITY = ["ok", "unknown", "warn", "offline", "alarm", "out_of_tolerance"];

  function healthPill(card) {
    return el("span", { class: `pill ${card.health}`, "data-field": "health",
      title: card.health_reason }, HEALTH_TEXT[card.health] || card.health);
  }

  /** The reasons behind a machine's accuracy state, worst first, as a list. */
  function reasonList(card) {
    const reasons = card.accuracy ? card.accuracy.reasons
      : [{ state: card.health, code: "", text: card.health_reason }];
    return el("ul", { class: "reasons", "data-field": "reasons" }, reasons.map((r) =>
      el("li", { class: `reason ${r.state}`, "data-code": r.code }, r.text)));
  }

  /** "3.3 kB" from bytes. */
  function bytes(n) {
    if (n === null || n === undefined) return "—";
    return n < 1000 ? `${n} B` : n < 1e6 ? `${(n / 1000).toFixed(1)} kB`
      : `${(n / 1e6).toFixed(2)} MB`;
  }

  const KIND_TEXT = { grid: "grid map", tables: "component tables",
    factored: "factored map (one-axis tables the controller combines)" };

  /** The temperatures a map was built at: "spindle 21.5 °C, column 20.1 °C". */
  function builtAt(temps) {
    return Object.entries(temps || {}).map(([k, v]) =>
      `${k.replace(/^T_/, "").replace(/_C$/, "")} ${num(v, 1)} °C`).join(", ");
  }

  /** What the machine's newest map is: kind, size, age, error as sent (when checked). */
  function mapFacts(m) {
    if (m.latest === null || m.latest === undefined) return "no map built";
    const parts = [`v${m.latest}`, KIND_TEXT[m.kind] || "map", bytes(m.bytes)];
    if (m.age_s !== null && m.age_s !== undefined) parts.push(`applied ${age(m.age_s)}`);
    if (m.error_um !== null && m.error_um !== undefined) {
      parts.push(`error as sent ${num(m.error_um, 2)} µm` +
        (m.tolerance_um ? ` (built for ${num(m.tolerance_um, 2)} µm)` : ""));
    }
    return parts.join(" · ");
  }

  // ---- trend charts (uPlot, served from /static/vendor/uplot) ------------------------
  const COLORS = ["#7cc0ff", "#ef6f6c", "#52c77a", "#e8b13c", "#c792ea", "#5fd7d7", "#f78c6c"];
  const WINDOWS = [["1 h", 3600], ["8 h", 8 * 3600], ["24 h", 86400], ["7 d", 7 * 86400],
    ["30 d", 30 * 86400]];

  /** The window chosen in the page's address (?window=<s>), default 24 h. */
  function windowS() {
    const w = Number(new URLSearchParams(location.search).get("window"));
    return WINDOWS.some(([, s]) => s === w) ? w : 86400;
  }

  /** A select of the windows; choosing one keeps it in the address and calls onChange. */
  function windowSelect(onChange) {
    const s = el("select", { "aria-label": "history window", id: "window" },
      WINDOWS.map(([label, secs]) => el("option", { value: secs, selected: secs === windowS() },
        label)));
    s.addEventListener("change", () => {
      const params = new URLSearchParams(location.search);
      params.set("window", s.value);
      history.replaceState(null, "", `${location.pathname}?${params}`);
      onChange(Number(s.value));
    });
    return s;
  }

  /**
   * A time chart with axes (time, and the unit) of series [{name, t: [s], mean: []}]
   * drawn by uPlot into a new <div class="trend-chart">; the series need not share times
   * (a missing bucket is a gap). `data-points` says how many points were drawn.
   */
  function timeChart(series, { unit, title = "", width = 300, height = 140, points = false,
    since = null, until = null } = {}) {
    const box = el("div", { class: "trend-chart", "data-unit": unit });
    const times = [...new Set(series.flatMap((s) => s.t))].sort((a, b) => a - b);
    const index = new Map(times.map((t, i) => [t, i]));
    const columns = series.map((s) => {
      const col = new Array(times.length).fill(null);
      s.t.forEach((t, i) => { col[index.get(t)] = s.mean[i]; });
      return col;
    });
    box.setAttribute("data-points", String(series.reduce((n, s) => n + s.t.length, 0)));
    box.setAttribute("data-series", series.map((s) => s.name).join(","));
    if (!times.length) {
      box.append(el("p", { class: "sub nodata" }, `${title ? title + ": " : ""}no data in ` +
        "this window"));
      return box;
    }
    const dim = "#93a1b0", line = "#2c3845";
    const axis = { stroke: dim, grid: { stroke: line, width: 1 }, ticks: { stroke: line },
      font: "11px DejaVu Sans, sans-serif" };
    const opts = {
      width, height, title,
      scales: { x: { time: true, range: since !== null ? [since, until] : undefined },
        // a little room around the data: a flat series is a line in the middle, not at 0
        y: { range: (u, lo, hi) => {
          if (lo === null || hi === null) return [0, 1];
          const pad = hi > lo ? (hi - lo) * 0.1 : Math.max(Math.abs(hi) * 0.02, 0.5);
          return [lo - pad, hi + pad];
        } } },
      axes: [axis, { ...axis, label: unit, labelFont: "11px DejaVu Sans, sans-serif",
        size: 50, labelSize: 14 }],
      series: [{ label: "time" }, ...series.map((s, i) => ({
        label: s.name, stroke: COLORS[i % COLORS.length], width: 1.5,
        points: { show: points || s.t.length < 3 },
        value: (u, v) => (v === null || v === undefined ? "—" : `${v.toFixed(2)} ${unit}`),
      }))],
      legend: { show: true, live: true },
      cursor: { drag: { x: false, y: false } },
    };
    // eslint-disable-next-line no-undef
    box.chart = new uPlot(opts, [times, ...columns], box);
    return box;
  }


  /** Diverging blue–white–red colour of t in [-1, 1]. */
  function diverging(t) {
    const x = Math.max(-1, Math.min(1, Number.isFinite(t) ? t : 0));
    const lerp = (a, b, s) => Math.round(a + (b - a) * s);
    const white = [247, 247, 247];
    const end = x < 0 ? [33, 102, 172] : [178, 24, 43];
    const s = Math.abs(x);
    return `rgb(${lerp(white[0], end[0], s)},${lerp(white[1], end[1], s)},` +
      `${lerp(white[2], end[2], s)})`;
  }

  /** "Nice" tick values covering [lo, hi]. */
  function ticks(lo, hi, count = 5) {
    if (!(hi > lo)) return [lo];
    const raw = (hi - lo) / count;
    const mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
      out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    }
    return out;
  }

  /**
   * A line chart: series = [{name, cls, x: [], y: []}], axes labelled with units.
   * Returns an <svg> element.
   */
  function lineChart(series, { width = 420, height = 220, xLabel = "", yLabel = "",
    title = "" } = {}) {
    const m = { l: 56, r: 12, t: title ? 24 : 10, b: 40 };
    const xs = series.flatMap((s) => s.x);
    const ys = series.flatMap((s) => s.y).concat([0]);
    let [x0, x1] = [Math.min(...xs), Math.max(...xs)];
    let [y0, y1] = [Math.min(...ys), Math.max(...ys)];
    if (!(x1 > x0)) { x0 -= 1; x1 += 1; }
    if (!(y1 > y0)) { y0 -= 1; y1 += 1; }
    const pad = (y1 - y0) * 0.08;
    y0 -= pad; y1 += pad;
    const X = (v) => m.l + (v - x0) / (x1 - x0) * (width - m.l - m.r);
    const Y = (v) => height - m.b - (v - y0) / (y1 - y0) * (height - m.t - m.b);
    const root = svg("svg", { viewBox: `0 0 ${width} ${height}`, class: "chart",
      role: "img", "aria-label": title || yLabel });
    if (title) root.append(svg("text", { x: m.l, y: 16, class: "chart-title" }, title));
    for (const t of ticks(y0, y1, 4)) {
      root.append(svg("line", { x1: m.l, x2: width - m.r, y1: Y(t), y2: Y(t),
        class: t === 0 ? "zero" : "grid" }));
      root.append(svg("text", { x: m.l - 6, y: Y(t) + 4, class: "tick", "text-anchor": "end" },
        num(t, Math.abs(y1 - y0) < 5 ? 1 : 0)));
    }
    for (const t of ticks(x0, x1, 5)) {
      root.append(svg("text", { x: X(t), y: height - m.b + 16, class: "tick",
        "text-anchor": "middle" }, num(t, 0)));
    }
    root.append(svg("text", { x: (m.l + width - m.r) / 2, y: height - 6, class: "axis-label",
      "text-anchor": "middle" }, xLabel));
    root.append(svg("text", { x: 12, y: (m.t + height - m.b) / 2, class: "axis-label",
      "text-anchor": "middle", transform: `rotate(-90 12 ${(m.t + height - m.b) / 2})` },
    yLabel));
    for (const s of series) {
      const d = s.x.map((x, i) => `${i ? "L" : "M"}${X(x).toFixed(1)},${Y(s.y[i]).toFixed(1)}`)
        .join("");
      root.append(svg("path", { d, class: `series ${s.cls}` }));
      s.x.forEach((x, i) => root.append(svg("circle", { cx: X(x), cy: Y(s.y[i]), r: 2.5,
        class: `dot ${s.cls}` })));
    }
    return root;
  }

  /** Destroy the uPlot charts under a node before it is refilled: each one listens on the
   *  window (resize, scroll) until destroyed, and the pages redraw every 30 s. */
  function dropCharts(node) {
    node.querySelectorAll(".trend-chart").forEach((c) => {
      if (c.chart) c.chart.destroy();
      c.chart = null;
    });
  }

  return { el, svg, fill, dropCharts, estimate, estimates, effectText, infoText, num, qty, signed, age,
    time, posUnit, compUnit, getJSON, follow, showLinkState, healthPill, reasonList, bytes,
    builtAt, mapFacts, KIND_TEXT, HEALTH_TEXT, SEVERITY, diverging, ticks, lineChart,
    timeChart, windowS, windowSelect };
})();
