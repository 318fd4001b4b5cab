// The machines dashboard: a fleet health strip, one row per registered machine with small
// trends (temperature, applied compensation, map version), redrawn from every snapshot of
// /api/live (about once a second), and the recent events below.
"use strict";

(() => {
  const { el, svg, num, qty, signed, age, time, posUnit, compUnit } = EDNC;

  // Trends are kept in the page from the snapshots it received (about one a second): the
  // last TREND_POINTS of each machine's hottest sensor, largest applied compensation and
  // applied map version.
  const TREND_POINTS = 300;
  const history = new Map();

  function remember(card) {
    let h = history.get(card.name);
    if (!h) {
      h = { temp: [], comp: [], version: [] };
      history.set(card.name, h);
    }
    const push = (list, v) => {
      list.push(v);
      if (list.length > TREND_POINTS) list.shift();
    };
    const temps = card.temperatures.filter((t) => t.celsius !== null).map((t) => t.celsius);
    push(h.temp, temps.length ? Math.max(...temps) : null);
    const comps = card.axes.filter((a) => !a.rotary && a.compensation !== null)
      .map((a) => Math.abs(a.compensation));  // µm (rotary axes in µrad stay out)
    push(h.comp, comps.length ? Math.max(...comps) : null);
    push(h.version, card.maps.applied ?? null);
    return h;
  }

  /** A small line over the last values (nulls are gaps), labelled with the latest. */
  function sparkline(values, field, unit, digits) {
    const width = 120, height = 28;
    const known = values.map((v, i) => [i, v]).filter(([, v]) => v !== null);
    const root = svg("svg", { class: "spark", viewBox: `0 0 ${width} ${height}`,
      "data-field": field, "data-points": String(known.length) });
    if (known.length) {
      const ys = known.map(([, v]) => v);
      const lo = Math.min(...ys), hi = Math.max(...ys);
      const span = hi - lo || 1;
      const X = (i) => (i / Math.max(TREND_POINTS - 1, 1)) * width;
      const Y = (v) => height - 3 - ((v - lo) / span) * (height - 6);
      const d = known.map(([i, v], k) => `${k ? "L" : "M"}${X(i).toFixed(1)},${Y(v).toFixed(1)}`)
        .join("");
      root.append(svg("path", { d, class: "spark-line" }));
      root.append(svg("title", {}, `${num(lo, digits)} … ${num(hi, digits)} ${unit} over ` +
        `the last ${known.length} s`));
    }
    return root;
  }

  function trendCell(card, h) {
    const last = (list) => (list.length ? list[list.length - 1] : null);
    const row = (label, values, field, unit, digits) => el("div", { class: "trend" },
      el("span", { class: "sub" }, label), sparkline(values, field, unit, digits),
      el("span", { class: "num" }, last(values) === null ? "—" : qty(last(values), unit, digits)));
    const changes = h.version.filter((v, i) => i > 0 && v !== h.version[i - 1]).length;
    return el("td", { class: "trends" },
      row("temp", h.temp, "trend-temp", "°C", 1),
      row("comp", h.comp, "trend-comp", "µm", 1),
      el("div", { class: "sub", "data-field": "trend-version" },
        card.maps.applied ? `map v${card.maps.applied}, ${changes} change(s) seen` : "no map"));
  }

  /** One segment per machine, coloured by health, in the header. */
  function healthStrip(machines) {
    const strip = document.getElementById("health-strip");
    strip.replaceChildren(...machines.map((c) => el("a", {
      class: `seg health-${c.health}`, href: `/machines/${encodeURIComponent(c.name)}`,
      title: `${c.name}: ${c.health}${c.health_reason ? " — " + c.health_reason : ""}`,
      "data-machine": c.name }, c.name)));
  }

  function machineCell(card) {
    return el("td", { class: "machine" },
      el("a", { href: `/machines/${encodeURIComponent(card.name)}`, class: "name",
        "data-field": "name" }, card.name),
      el("div", { class: "sub" }, `${card.controller} · ${card.ip}`),
      el("div", { class: "sub chain", "data-field": "chain" }, card.chain));
  }

  function statusCell(card) {
    return el("td", {},
      EDNC.healthPill(card),
      el("div", { class: "sub", "data-field": "health-reason" }, card.health_reason),
      card.state ? el("div", { class: "sub" }, "state: ",
        el("b", { "data-field": "state" }, card.state)) : null);
  }

  function linkCell(card) {
    const tele = card.telemetry_age_s === null ? "no telemetry"
      : `telemetry ${age(card.telemetry_age_s)}`;
    return el("td", {},
      el("div", { "data-field": "connected" }, card.connected ? "connected" : "disconnected"),
      el("div", { class: "sub" }, card.address || "no address yet"),
      card.owner ? el("div", { class: "sub", "data-field": "owner" }, `served by ${card.owner}`)
        : null,
      el("div", { class: card.telemetry_stale ? "sub stale" : "sub" }, tele));
  }

  function mapCell(card) {
    const m = card.maps;
    const v = (x) => (x === null || x === undefined ? "—" : `v${x}`);
    return el("td", { class: "map" },
      el("div", { class: "versions", "data-field": "maps" },
        `${v(m.latest)} / ${v(m.sent)} / ${v(m.applied)}`),
      m.sent_state ? el("div", { class: `sub delivery ${m.sent_state}` },
        `v${m.sent} ${m.sent_state}${m.reject_reason ? ": " + m.reject_reason : ""}`) : null,
      m.reported !== null && m.reported !== undefined
        ? el("div", { class: "sub" }, `machine reports ${m.reported ? "v" + m.reported : "none"}`)
        : null);
  }

  function axesCell(card, render) {
    if (!card.axes.length) return el("td", { class: "sub" }, "—");
    return el("td", {}, el("table", { class: "axes" }, card.axes.map((a) =>
      el("tr", { class: card.telemetry_stale ? "stale" : null },
        el("th", {}, a.name), render(a)))));
  }

  function temperatureCell(card) {
    if (!card.temperatures.length) return el("td", { class: "sub" }, "no sensors");
    return el("td", {}, el("table", { class: "axes" }, card.temperatures.map((t) =>
      el("tr", { class: t.stale ? "stale" : null },
        el("th", {}, t.name),
        el("td", { class: "num", "data-field": `temp-${t.name}`,
          title: `${t.follows ?? t.source}${t.age_s === null ? "" : ", " + age(t.age_s)}` },
        qty(t.celsius, "°C", 1)),
        t.stale ? el("td", { class: "stale-tag" }, "stale") : null))));
  }

  function verificationCell(card) {
    const v = card.verification;
    if (!v) return el("td", { class: "sub" }, "none");
    const before = Math.max(...Object.values(v.ranges_before_um), 0);
    const after = v.ranges_after_um ? Math.max(...Object.values(v.ranges_after_um), 0) : null;
    const gain = v.improvement_pct ? v.improvement_pct.overall : null;
    const verdict = v.accepted === null ? null : el("span",
      { class: v.accepted ? "pill ok small" : "pill alarm small" },
      v.accepted ? "accepted" : "not accepted");
    return el("td", { "data-field": "verification" },
      el("div", { title: "largest diagonal range before → after compensation" },
        `${qty(before, "µm")} → ${after === null ? "—" : qty(after, "µm")}`),
      gain === null ? null : el("div", {}, el("b", {}, signed(gain, "%", 0)), " better ",
        verdict),
      el("div", { class: "sub" }, time(v.created_at)));
  }

  function diagnosisCell(card) {
    const d = card.diagnosis;
    if (!d) return el("td", { class: "sub" }, "none");
    const what = [d.effect, d.axis ? `on ${d.axis}` : null, d.sensor ? `(${d.sensor})` : null]
      .filter(Boolean).join(" ");
    const estimate = Object.entries(d.estimate).map(([k, v]) => EDNC.estimate(k, v))
      .join(", ");
    return el("td", { "data-field": "diagnosis" },
      el("div", {}, el("b", {}, what)),
      estimate ? el("div", { class: "sub" }, estimate) : null,
      d.rms_before_um !== null ? el("div", { class: "sub" },
        `RMS ${qty(d.rms_before_um, "µm", 2)} → ${qty(d.rms_after_um, "µm", 2)}`) : null);
  }

  function row(card) {
    return el("tr", { class: `health-${card.health}`, "data-machine": card.name },
      machineCell(card), statusCell(card), linkCell(card), mapCell(card),
      axesCell(card, (a) => el("td", { class: "num", "data-field": `pos-${a.name}` },
        qty(a.position, posUnit(a), 3))),
      axesCell(card, (a) => el("td", { class: "num", "data-field": `comp-${a.name}` },
        signed(a.compensation, compUnit(a), 1))),
      temperatureCell(card), trendCell(card, remember(card)), verificationCell(card),
      diagnosisCell(card));
  }

  function eventRow(e) {
    return el("tr", { class: `event ${e.kind}`, "data-kind": e.kind },
      el("td", { class: "time" }, time(e.time)),
      el("td", {}, el("span", { class: `kind ${e.kind}` }, e.kind)),
      el("td", {}, e.machine),
      el("td", {}, e.detail));
  }

  function render(snapshot) {
    const machines = snapshot.machines;
    document.querySelector("#machines > tbody").replaceChildren(...machines.map(row));
    healthStrip(machines);
    document.getElementById("no-machines").hidden = machines.length > 0;
    document.querySelector("#events > tbody").replaceChildren(...snapshot.events.map(eventRow));
    const count = (h) => machines.filter((c) => c.health === h).length;
    document.getElementById("summary").textContent =
      `${machines.length} machines · ${machines.filter((c) => c.connected).length} connected · ` +
      `${count("alarm")} alarm · ${count("warn")} attention`;
    document.getElementById("footer").textContent =
      `EDNC ${snapshot.version} · node ${snapshot.node_id} · snapshot ` +
      `${time(snapshot.generated_at)} · telemetry older than ${snapshot.stale_after_s} s ` +
      "is marked stale";
  }

  const indicator = document.getElementById("live");
  EDNC.follow(render, (state) => EDNC.showLinkState(indicator, state));
})();
