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

  /** An estimate such as reversal_um = 9.8 as "reversal 9.80 µm" (unit from the key). */
  function estimate(key, value) {
    const units = [["_um_per_m_K", "µm/(m·K)"], ["_um_per_K", "µm/K"], ["_um", "µm"],
      ["_mm", "mm"], ["_urad", "µrad"], ["_s", "s"], ["_C", "°C"]];
    const found = units.find(([suffix]) => key.endsWith(suffix));
    const name = (found ? key.slice(0, -found[0].length) : key).replace(/_/g, " ");
    return found ? `${name} ${num(value, 2)} ${found[1]}` : `${name} ${num(value, 3)}`;
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

  const HEALTH_TEXT = { ok: "OK", warn: "ATTENTION", alarm: "ALARM", offline: "OFFLINE" };

  function healthPill(card) {
    return el("span", { class: `pill ${card.health}`, "data-field": "health",
      title: card.health_reason }, HEALTH_TEXT[card.health] || card.health);
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

  return { el, svg, fill, estimate, num, qty, signed, age, time, posUnit, compUnit, getJSON, follow,
    showLinkState, healthPill, diverging, ticks, lineChart };
})();
