// The machines dashboard: one row per registered machine, redrawn from every snapshot of
// /api/live (about once a second), and the recent events below.
"use strict";

(() => {
  const { el, num, qty, signed, age, time, posUnit, compUnit } = EDNC;

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
          title: `${t.source}${t.age_s === null ? "" : ", " + age(t.age_s)}` },
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
      temperatureCell(card), verificationCell(card), diagnosisCell(card));
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
