// One machine's page: live values from /api/live, and from the JSON endpoints its
// description and model (/api/machines/{name}/dashboard), its newest error map as one heat
// map per output axis (.../maps/latest/grid) and the diagonal profiles of its newest
// verification (.../verifications/latest/diagonals). Map and plots reload when the live
// row shows a newer map version or verification.
"use strict";

(() => {
  const { el, svg, num, qty, signed, age, time, posUnit, compUnit, getJSON } = EDNC;
  const NAME = decodeURIComponent(location.pathname.split("/")[2] || "");
  const API = `/api/machines/${encodeURIComponent(NAME)}`;
  // What is on screen: the map version the live row showed when the map was last loaded,
  // and the verification report shown, so that only news triggers a reload.
  const shown = { mapLatest: undefined, verification: undefined, u: null, v: null };

  document.getElementById("name").textContent = NAME;
  document.title = `EDNC — ${NAME}`;

  function kv(rows) {
    return el("table", { class: "kv" }, rows.filter(Boolean).map(([k, v, attrs]) =>
      el("tr", {}, el("th", {}, k), el("td", attrs || {}, v))));
  }

  // ---- accuracy ------------------------------------------------------------------------
  function renderAccuracy(card) {
    const a = card.accuracy;
    const m = card.maps;
    EDNC.fill(document.getElementById("accuracy"),
      el("p", {}, EDNC.healthPill(card)),
      EDNC.reasonList(card),
      a ? kv([
        ["Tolerance", `${qty(a.tolerance_um, "µm", 1)} largest compensated diagonal range ` +
          "(accuracy_tolerance_um in the description, 10 µm by default)"],
        ["Last verification", a.residual_um === null ? "never verified"
          : `${qty(a.residual_um, "µm", 2)} ${a.residual_compensated ? "with" : "without"} ` +
            `compensation, ${time(a.verified_at)}`, { "data-field": "residual" }],
        ["Model", a.model_version === null ? "none uploaded"
          : `v${a.model_version}, ${age(a.model_age_s)}`],
        ["Error map", EDNC.mapFacts(m), { "data-field": "map-facts" }],
        EDNC.builtAt(m.built_at_C) ? ["Map built at", EDNC.builtAt(m.built_at_C)] : null,
      ]) : null);
  }

  // ---- live values -------------------------------------------------------------------
  function renderLive(card) {
    const status = document.getElementById("status");
    // the link's own state when it says more than "connected" (busy, PLC stopped, refused)
    const linkSays = card.link_state && card.link_state !== "offline" &&
      (card.link_state !== "connected" || card.link_reason);
    EDNC.fill(status, EDNC.healthPill(card), " ", card.health_reason,
      linkSays ? el("div", { class: "sub", "data-field": "link-state" },
        `link: ${card.link_state.replace("_", " ")}` +
        (card.link_reason ? ` (${card.link_reason})` : "") +
        (card.link_text ? ` — ${card.link_text}` : "")) : null);
    const m = card.maps;
    const v = (x) => (x === null || x === undefined ? "—" : `v${x}`);
    const axes = card.axes.length ? el("table", { class: "terms" },
      el("tr", {}, el("th", {}, "Axis"), el("th", {}, "Position"),
        el("th", {}, "Compensation applied")),
      card.axes.map((a) => el("tr", { class: card.telemetry_stale ? "stale" : null },
        el("td", {}, a.name),
        el("td", { class: "num", "data-field": `pos-${a.name}` }, qty(a.position, posUnit(a), 3)),
        el("td", { class: "num", "data-field": `comp-${a.name}` },
          signed(a.compensation, compUnit(a), 1))))) : el("p", { class: "sub" }, "no axes reported");
    const temps = card.temperatures.length ? el("table", { class: "terms" },
      el("tr", {}, el("th", {}, "Sensor"), el("th", {}, "Temperature")),
      card.temperatures.map((t) => el("tr", { class: t.stale ? "stale" : null },
        el("td", {}, t.name, t.follows ? el("span", { class: "sub" }, ` (${t.follows})`) : null),
        el("td", { class: "num", "data-field": `temp-${t.name}` },
          qty(t.celsius, "°C", 2), t.stale ? " (stale)" : "")))) : null;
    EDNC.fill(document.getElementById("live-values"),
      kv([
        ["Link", card.connected ? `connected from ${card.address}` : "disconnected"],
        card.owner ? ["Served by", card.owner, { "data-field": "owner" }] : null,
        ["Connected since", time(card.connected_since)],
        ["Telemetry", card.telemetry_age_s === null ? "none"
          : age(card.telemetry_age_s) + (card.telemetry_stale ? " (stale)" : ""),
        { class: card.telemetry_stale ? "stale" : null }],
        ["State", card.state || "—", { "data-field": "state" }],
        ["Error map", `latest ${v(m.latest)} · sent ${v(m.sent)}` +
          `${m.sent_state ? " (" + m.sent_state + ")" : ""} · applied ${v(m.applied)}` +
          (m.reported !== null ? ` · machine reports ${m.reported ? "v" + m.reported : "no map applied"}`
            : "")],
        m.reject_reason ? ["Rejected because", m.reject_reason, { class: "problem" }] : null,
      ]),
      axes, temps);
  }

  // ---- description -------------------------------------------------------------------
  function renderDescription(d) {
    const travel = Object.entries(d.travel_mm || {}).map(([k, [lo, hi]]) =>
      `${k} ${num(lo, 0)}…${num(hi, 0)}`).join(", ");
    document.getElementById("description").replaceChildren(
      kv([
        ["Controller", d.controller],
        ["Address", d.ip],
        ["Link", !d.link || d.link.kind === "ednc" ? "EDNC (the machine connects)"
          : d.link.kind === "modbus"
            ? `Modbus/TCP to ${d.link.host || d.ip}:${d.link.port ?? 502}, window at ` +
              `register ${d.link.start_register ?? 0} (${d.link.pmc || "D0000"})`
            : `OPC UA to ${d.link.endpoint} as ${d.link.user}`],
        ["Chain", d.chain || `type ${d.translational_type}/${d.rotary_type || 0}`],
        ["Travel", travel ? `${travel} (mm; rotary °)` : "—"],
        ["Tool length", qty(d.tool_length_mm ?? 0, "mm", 1)],
        d.spindles ? ["Spindles", d.spindles.map((s) => `${s.name} on ${s.axis}`).join(", ")]
          : null,
      ]),
      el("details", {}, el("summary", { class: "sub" }, "description as stored (JSON)"),
        el("pre", { class: "json" }, JSON.stringify(d, null, 2))));
  }

  // ---- error map -----------------------------------------------------------------------
  function heatmap(grid, slice) {
    const [W, H, m] = [360, 300, { l: 52, r: 10, t: 10, b: 40 }];
    const rows = slice.values;
    const nv = rows.length;
    const nu = rows[0].length;
    const gu = grid.grid.find((g) => g.name === grid.u);
    const gv = grid.v ? grid.grid.find((g) => g.name === grid.v) : null;
    const limit = Math.max(Math.abs(slice.min), Math.abs(slice.max)) || 1;
    const cw = (W - m.l - m.r) / nu;
    const ch = (H - m.t - m.b) / nv;
    const root = svg("svg", { viewBox: `0 0 ${W} ${H}`, class: "heatmap",
      "data-output": slice.output, role: "img",
      "aria-label": `map correction of ${slice.output}` });
    for (let j = 0; j < nv; j++) {
      for (let i = 0; i < nu; i++) {
        const value = rows[j][i];
        // v grows upwards, like a drawing of the machine's table.
        root.append(svg("rect", { x: m.l + i * cw, y: H - m.b - (j + 1) * ch,
          width: cw + 0.3, height: ch + 0.3, fill: EDNC.diverging(value / limit) },
        svg("title", {}, `${grid.u} ${num(gu.start + i * gu.step, 1)} ${gu.unit}` +
          (gv ? `, ${grid.v} ${num(gv.start + j * gv.step, 1)} ${gv.unit}` : "") +
          `: ${num(value, 2)} ${slice.unit}`)));
      }
    }
    root.append(svg("rect", { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b,
      class: "frame" }));
    const uEnd = gu.start + (gu.count - 1) * gu.step;
    for (const t of EDNC.ticks(gu.start, uEnd, 4)) {
      const x = m.l + ((t - gu.start) / (uEnd - gu.start || 1)) * (W - m.l - m.r - cw) + cw / 2;
      root.append(svg("text", { x, y: H - m.b + 14, class: "tick", "text-anchor": "middle" },
        num(t, 0)));
    }
    root.append(svg("text", { x: (m.l + W - m.r) / 2, y: H - 6, class: "axis-label",
      "text-anchor": "middle" }, `${grid.u} (${gu.unit})`));
    if (gv) {
      const vEnd = gv.start + (gv.count - 1) * gv.step;
      for (const t of EDNC.ticks(gv.start, vEnd, 4)) {
        const y = H - m.b - ((t - gv.start) / (vEnd - gv.start || 1)) * (H - m.t - m.b - ch)
          - ch / 2;
        root.append(svg("text", { x: m.l - 5, y: y + 4, class: "tick", "text-anchor": "end" },
          num(t, 0)));
      }
      const yc = (m.t + H - m.b) / 2;
      root.append(svg("text", { x: 12, y: yc, class: "axis-label", "text-anchor": "middle",
        transform: `rotate(-90 12 ${yc})` }, `${grid.v} (${gv.unit})`));
    }
    return root;
  }

  /** A map over one grid axis: the correction along it, as a line. */
  function profile(grid, slice) {
    const gu = grid.grid.find((g) => g.name === grid.u);
    const x = slice.values[0].map((_, i) => gu.start + i * gu.step);
    const chart = EDNC.lineChart([{ name: slice.output, cls: "curve", x, y: slice.values[0] }],
      { xLabel: `${grid.u} (${gu.unit})`, yLabel: `correction (${slice.unit})` });
    chart.setAttribute("data-output", slice.output);
    chart.classList.add("map-profile");
    return chart;
  }

  function legend(slice) {
    const limit = Math.max(Math.abs(slice.min), Math.abs(slice.max));
    const bar = svg("svg", { viewBox: "0 0 360 24", class: "heatmap" });
    for (let i = 0; i < 60; i++) {
      bar.append(svg("rect", { x: 52 + i * 5, y: 2, width: 5.3, height: 10,
        fill: EDNC.diverging(i / 29.5 - 1) }));
    }
    bar.append(svg("text", { x: 52, y: 23, class: "tick" }, `${num(-limit, 1)} ${slice.unit}`));
    bar.append(svg("text", { x: 352, y: 23, class: "tick", "text-anchor": "end" },
      `+${num(limit, 1)} ${slice.unit}`));
    return bar;
  }

  function mapControls(grid) {
    const box = document.getElementById("map-controls");
    if (grid.grid.length < 3) {
      box.replaceChildren(grid.v ? "" : "one grid axis");
      return;
    }
    const select = (which, current) => {
      const s = el("select", { "aria-label": which },
        grid.grid.map((g) => el("option", { value: g.name, selected: g.name === current },
          g.name)));
      s.addEventListener("change", () => {
        shown[which] = s.value;
        loadMap(shown.mapLatest);
      });
      return s;
    };
    box.replaceChildren("horizontal", select("u", grid.u), "vertical", select("v", grid.v));
  }

  async function loadMap(latest) {
    const box = document.getElementById("map");
    if (latest === null) {
      document.getElementById("map-controls").replaceChildren();
      box.replaceChildren(el("p", { class: "sub" }, "No error map built for this machine yet."));
      return;
    }
    const params = new URLSearchParams();
    if (shown.u) params.set("u", shown.u);
    if (shown.v) params.set("v", shown.v);
    let grid;
    try {
      grid = await getJSON(`${API}/maps/latest/grid?${params}`);
    } catch (err) {
      box.replaceChildren(el("p", { class: err.status === 404 ? "sub" : "problem" },
        err.status === 404 ? "No error map built for this machine yet." : err.message));
      return;
    }
    mapControls(grid);
    const fixed = Object.entries(grid.fixed)
      .map(([k, v]) => `${k} = ${num(v, 1)} ${grid.grid.find((g) => g.name === k).unit}`)
      .join(", ");
    const kind = grid.kind === "tables"
      ? "component tables the machine evaluates, shown as it computes them on a " +
        `${grid.grid[0].count}-point display grid`
      : grid.kind === "factored"
        ? "factored map: one-axis tables the controller combines (Fanuc-style pitch-error " +
          `layout), shown as it computes them on a ${grid.grid[0].count}-point display grid`
        : `grid of ${grid.grid.map((g) => `${g.name}×${g.count}`).join(" ")} nodes`;
    const built = EDNC.builtAt(grid.built_at_C);
    const thermal = grid.thermal_records
      ? `Drawn without its ${grid.thermal_records} thermal record(s), i.e. at the thermal ` +
        "terms' reference temperatures; the machine adds them at its live temperatures" +
        (built ? ` (built when ${built})` : "") + "."
      : built ? `Drawn as built at ${built}: the thermal terms are in the values.`
        : "The model has no thermal terms: the map is the same at every temperature.";
    const caption = `v${grid.version}, ${EDNC.bytes(grid.bytes)}, ${grid.encoding}` +
      (grid.encoding === "int32" ? ` (${num(grid.increment_mm * 1000, 1)} µm per count)` : "") +
      `, ${kind}` + (fixed ? `; held at ${fixed}` : "") + `. ${thermal}`;
    EDNC.fill(box, ...grid.outputs.map((s) => el("figure", { "data-output": s.output },
      grid.v ? [heatmap(grid, s), legend(s)] : profile(grid, s),
      el("figcaption", {}, el("b", {}, `Correction of ${s.output}`),
        ` ${num(s.min, 1)} … ${num(s.max, 1)} ${s.unit}` +
        (s.reversal !== null ? `; reversal ${signed(s.reversal, s.unit, 1)}` : "")))),
    el("p", { class: "sub", style: "flex-basis: 100%", "data-field": "map-caption" },
      caption));
  }

  // ---- verification ----------------------------------------------------------------
  function renderVerificationSummary(v) {
    const box = document.getElementById("verification");
    if (!v) {
      box.replaceChildren(el("p", { class: "sub" }, "No verification yet."));
      return;
    }
    const labels = Object.keys(v.ranges_before_um);
    EDNC.fill(box, el("table", { class: "terms" },
      el("tr", {}, el("th", {}, "Diagonal"), el("th", {}, "Range before"),
        el("th", {}, "Range after"), el("th", {}, "Improvement")),
      labels.map((k) => el("tr", {}, el("td", {}, k),
        el("td", { class: "num" }, qty(v.ranges_before_um[k], "µm", 2)),
        el("td", { class: "num" }, v.ranges_after_um ? qty(v.ranges_after_um[k], "µm", 2) : "—"),
        el("td", { class: "num" }, v.improvement_pct ? signed(v.improvement_pct[k], "%", 1)
          : "—"))),
      v.improvement_pct ? el("tr", {}, el("th", {}, "overall"), el("td", {}), el("td", {}),
        el("td", { class: "num", "data-field": "improvement" },
          el("b", {}, signed(v.improvement_pct.overall, "%", 1)), " ",
          v.accepted === null ? "" : el("span", { class: v.accepted ? "pill ok small"
            : "pill alarm small" }, v.accepted ? "accepted" : "not accepted"),
          v.acceptance_pct !== null ? ` (needs ≥ ${num(v.acceptance_pct, 0)} %)` : ""))
        : null),
    el("p", { class: "sub" }, `Report ${v.id}, ${time(v.created_at)}`));
  }

  async function loadDiagonals() {
    const box = document.getElementById("diagonals");
    let plots;
    try {
      plots = await getJSON(`${API}/verifications/latest/diagonals`);
    } catch (err) {
      EDNC.fill(box, err.status === 404 ? null : el("p", { class: "problem" },
        `Diagonal profiles unavailable: ${err.message}`));
      return;
    }
    EDNC.fill(box, el("p", { class: "legend", style: "flex-basis: 100%" },
      "Mean deviation along the diagonal at each target: ",
      el("span", { class: "before" }, `before (${plots.before_set})`),
      plots.after_set ? [" and ", el("span", { class: "after" }, `after (${plots.after_set})`)]
        : ""),
    el("p", { class: "sub", style: "flex-basis: 100%", "data-field": "diagonal-offsets" },
      "ISO 230-6 judges each diagonal by its range, largest minus smallest deviation. A " +
      "curve's level as a whole (its offset at the start, where the interferometer was " +
      "set, plus any length error left) does not enter the range: a flat compensated " +
      "curve away from zero is a compensated diagonal. The offset at the start is given " +
      "under each plot."),
    ...plots.diagonals.map((d) => {
      const series = [{ name: "before", cls: "before", x: d.along_mm, y: d.before_um }];
      if (d.after_um) series.push({ name: "after", cls: "after", x: d.after_along_mm,
        y: d.after_um });
      return el("figure", { "data-diagonal": d.label },
        EDNC.lineChart(series, { title: d.label, xLabel: "position along the diagonal (mm)",
          yLabel: "deviation (µm)" }),
        el("figcaption", {}, `range ${qty(d.range_before_um, "µm", 2)}` +
          (d.range_after_um !== null ? ` → ${qty(d.range_after_um, "µm", 2)}` : "") +
          `; offset at the start ${signed(d.before_um[0], "µm", 1)}` +
          (d.after_um ? ` → ${signed(d.after_um[0], "µm", 1)}` : "")));
    }));
  }

  // ---- diagnosis and model -----------------------------------------------------------
  function renderDiagnosis(d) {
    const box = document.getElementById("diagnosis");
    if (!d) {
      box.replaceChildren(el("p", { class: "sub" }, "No diagnosis yet."));
      return;
    }
    box.replaceChildren(kv([
      ["Effect", EDNC.effectText(d), { "data-field": "effect" }],
      ["Estimate", EDNC.estimates(d.estimate) || "—"],
      ["Held-out RMS", `${qty(d.rms_before_um, "µm", 2)} → ${qty(d.rms_after_um, "µm", 2)}`],
      ["When", time(d.created_at)],
    ]));
  }

  function sparkline(c) {
    const chart = EDNC.lineChart([{ name: c.name, cls: "curve", x: c.positions, y: c.values }],
      { width: 260, height: 90, xLabel: "", yLabel: "" });
    chart.setAttribute("style", "width: 260px");
    return chart;
  }

  function renderModel(detail) {
    const box = document.getElementById("model");
    const model = detail.model;
    if (!model) {
      box.replaceChildren(el("p", { class: detail.model_problem ? "problem" : "sub" },
        detail.model_problem || "No model yet."));
      return;
    }
    const comps = model.components.filter((c) => !c.location);
    const locs = model.components.filter((c) => c.location);
    const info = Object.entries(model.info)
      .filter(([, v]) => typeof v === "number" || typeof v === "string")
      .map(([k, v]) => EDNC.infoText(k, v)).join(" · ");
    EDNC.fill(box,
      el("p", { class: "sub" }, `Version ${model.version} (${model.source}), ` +
        `${time(model.created_at)}${info ? " · " + info : ""}`),
      el("table", { class: "terms", id: "components" },
        el("tr", {}, el("th", {}, "Component error"), el("th", {}, "Form"),
          el("th", {}, "Min"), el("th", {}, "Max"), el("th", {}, "Peak to peak"),
          el("th", {}, "Over the travel")),
        comps.map((c) => el("tr", { "data-component": c.name },
          el("td", {}, el("b", {}, c.name)), el("td", {}, c.kind),
          el("td", { class: "num" }, qty(c.min, c.unit, 2)),
          el("td", { class: "num" }, qty(c.max, c.unit, 2)),
          el("td", { class: "num" }, qty(c.max - c.min, c.unit, 2)),
          el("td", {}, sparkline(c))))),
      locs.length ? el("h3", {}, "Location errors (squareness, offsets)") : null,
      locs.length ? el("table", { class: "terms" }, locs.map((c) => el("tr", {},
        el("td", {}, el("b", {}, c.name)), el("td", { class: "num" }, qty(c.min, c.unit, 2)))))
        : null,
      model.terms.length ? el("h3", {}, "Extensions") : null,
      model.terms.length ? el("table", { class: "terms" }, model.terms.map((t) =>
        el("tr", {}, el("td", {}, el("b", {}, t.effect)), el("td", {}, t.axis || ""),
          el("td", {}, Object.entries(t).filter(([k]) => !["effect", "axis"].includes(k))
            .map(([k, v]) => (typeof v === "number" ? EDNC.estimate(k, v, t)
              : `${k.replace(/_/g, " ")}: ${typeof v === "object" ? JSON.stringify(v) : v}`))
            .join(", "))))) : null);
  }

  // ---- history (from the server: /api/machines/{name}/history) --------------------------
  async function loadHistory() {
    let h;
    try {
      h = await getJSON(`${API}/history?window_s=${EDNC.windowS()}&points=300`);
    } catch (err) {
      document.getElementById("history-note").textContent = `unavailable: ${err.message}`;
      return;
    }
    const opts = { width: 520, height: 200, since: Date.parse(h.since) / 1000,
      until: Date.parse(h.until) / 1000 };
    const charts = [EDNC.timeChart(h.temperatures, { ...opts, unit: "°C",
      title: "Temperatures" })];
    for (const unit of ["µm", "µrad"]) {
      const series = h.corrections.filter((s) => s.unit === unit);
      if (series.length || unit === "µm") {
        charts.push(EDNC.timeChart(series, { ...opts, unit,
          title: `Compensation applied per axis (${unit})` }));
      }
    }
    const verified = h.verifications.filter((v) => v.residual_um !== null);
    charts.push(EDNC.timeChart([{ name: "largest diagonal range", t: verified.map((v) =>
      Date.parse(v.at) / 1000), mean: verified.map((v) => v.residual_um) }],
    { ...opts, unit: "µm", title: "Verifications", points: true }));
    charts.forEach((c, i) => c.setAttribute("data-field",
      ["history-temp", "history-comp", "history-comp-rot", "history-verif"][
        i === charts.length - 1 ? 3 : i]));
    const box = document.getElementById("history-charts");
    EDNC.dropCharts(box);
    EDNC.fill(box, ...charts);
    document.getElementById("history-note").textContent =
      `(mean per ${age(h.bucket_s).replace(" ago", "")} bucket, until ${time(h.until)})`;
    EDNC.fill(document.getElementById("deliveries"), h.maps.length ? el("table",
      { class: "terms", id: "delivery-table" },
      el("tr", {}, el("th", {}, "Sent"), el("th", {}, "Map"), el("th", {}, "Answer"),
        el("th", {}, "Model"), el("th", {}, "Size"), el("th", {}, "Built at")),
      h.maps.map((d) => el("tr", {}, el("td", {}, time(d.sent_at)), el("td", {}, `v${d.version}`),
        el("td", { class: `delivery ${d.state}` },
          d.state + (d.reject_reason ? `: ${d.reject_reason}` : "")),
        el("td", {}, d.model_version === null ? "—" : `v${d.model_version}`),
        el("td", { class: "num" }, EDNC.bytes(d.bytes)),
        el("td", { class: "sub" }, EDNC.builtAt(d.built_at_C) || "—"))))
      : el("p", { class: "sub" }, "No map sent in this window."));
    EDNC.fill(document.getElementById("history-events"), h.events.length ? el("table",
      { class: "events" }, [...h.events].reverse().map((e) => el("tr", { class: `event ${e.kind}` },
        el("td", { class: "time" }, time(e.time)),
        el("td", {}, el("span", { class: `kind ${e.kind}` }, e.kind)),
        el("td", {}, e.detail))))
      : el("p", { class: "sub" }, "No events in this window."));
  }

  // ---- wiring ---------------------------------------------------------------------------
  function onCard(card) {
    renderAccuracy(card);
    renderLive(card);
    renderDiagnosis(card.diagnosis);
    const latestMap = card.maps.latest;
    if (shown.mapLatest !== undefined && latestMap !== shown.mapLatest) {
      shown.mapLatest = latestMap;
      loadMap(latestMap);
    }
    const vid = card.verification ? card.verification.id : null;
    if (vid !== shown.verification) {
      shown.verification = vid;
      renderVerificationSummary(card.verification);
      if (vid === null) document.getElementById("diagonals").replaceChildren();
      else loadDiagonals();
    }
  }

  async function start() {
    let detail;
    try {
      detail = await getJSON(`${API}/dashboard`);
    } catch (err) {
      document.getElementById("status").textContent = err.message;
      return;
    }
    renderDescription(detail.description);
    renderModel(detail);
    onCard(detail.card);
    shown.mapLatest = detail.card.maps.latest;
    document.getElementById("window-box").append(EDNC.windowSelect(() => loadHistory()));
    loadHistory();
    setInterval(loadHistory, 30000);
    await loadMap(shown.mapLatest);
    const indicator = document.getElementById("live");
    EDNC.follow((snapshot) => {
      const card = snapshot.machines.find((c) => c.name === NAME);
      if (card) onCard(card);
    }, (state) => EDNC.showLinkState(indicator, state));
  }

  start();
})();
