// The machines dashboard. First screen: every machine's accuracy state, worst first, with
// the reasons (is it within its tolerance, and if not, why). Below: one row per registered
// machine with its live values, redrawn from every snapshot of /api/live (about once a
// second), and trend charts of its temperatures and applied corrections drawn from the
// server's history (/api/history: they survive a reload), refreshed every 30 s; the
// recent events at the bottom.
"use strict";

(() => {
  const { el, num, qty, signed, age, time, posUnit, compUnit } = EDNC;

  const HISTORY_EVERY_MS = 30000;
  const HISTORY_POINTS = 120;
  // The trend cell of each machine is kept across snapshots (a chart is not redrawn every
  // second), and replaced when the history is fetched again.
  const trendNodes = new Map();

  function trendBox(name) {
    let box = trendNodes.get(name);
    if (!box) {
      box = el("div", { class: "trend-box", "data-machine": name },
        el("p", { class: "sub" }, "loading history…"));
      trendNodes.set(name, box);
    }
    return box;
  }

  function drawTrends(h) {
    for (const m of h.machines) {
      const opts = { width: 280, height: 130, since: Date.parse(h.since) / 1000,
        until: Date.parse(h.until) / 1000 };
      const linear = m.corrections.filter((s) => s.unit === "µm");
      EDNC.dropCharts(trendBox(m.machine));
      EDNC.fill(trendBox(m.machine),
        m.temperatures.length ? EDNC.timeChart(m.temperatures, { ...opts, unit: "°C" })
          : el("p", { class: "sub nodata", "data-unit": "°C" }, "no temperatures recorded"),
        linear.length ? EDNC.timeChart(linear, { ...opts, unit: "µm" })
          : el("p", { class: "sub nodata", "data-unit": "µm" }, "no corrections recorded"));
      trendBox(m.machine).querySelectorAll(".trend-chart").forEach((c) => {
        c.setAttribute("data-field", `trend-${c.getAttribute("data-unit") === "°C" ? "temp"
          : "comp"}`);
      });
    }
    document.getElementById("history-note").textContent =
      `(mean per ${age(h.bucket_s).replace(" ago", "")} bucket, until ${time(h.until)})`;
  }

  async function loadHistory() {
    try {
      drawTrends(await EDNC.getJSON(
        `/api/history?window_s=${EDNC.windowS()}&points=${HISTORY_POINTS}`));
    } catch (err) {
      document.getElementById("history-note").textContent = `history unavailable: ${err.message}`;
    }
  }

  /** One segment per machine, coloured by its accuracy state, in the header. */
  function healthStrip(machines) {
    const strip = document.getElementById("health-strip");
    strip.replaceChildren(...machines.map((c) => el("a", {
      class: `seg health-${c.health}`, href: `/machines/${encodeURIComponent(c.name)}`,
      title: `${c.name}: ${EDNC.HEALTH_TEXT[c.health] || c.health} — ${c.health_reason}`,
      "data-machine": c.name }, c.name)));
  }

  function residualText(card) {
    const a = card.accuracy;
    if (!a || a.residual_um === null) return el("span", { class: "sub" }, "never verified");
    const over = a.residual_um > a.tolerance_um;
    return el("span", { class: over ? "problem" : null },
      `${qty(a.residual_um, "µm", 1)} / ${qty(a.tolerance_um, "µm", 0)}`,
      a.residual_compensated ? "" : " (uncompensated run)",
      el("div", { class: "sub" }, time(a.verified_at)));
  }

  function accuracyRow(card) {
    return el("tr", { class: `health-${card.health}`, "data-machine": card.name },
      el("td", {}, EDNC.healthPill(card)),
      el("td", {}, el("a", { href: `/machines/${encodeURIComponent(card.name)}`, class: "name" },
        card.name)),
      el("td", {}, EDNC.reasonList(card)),
      el("td", { "data-field": "residual" }, residualText(card)),
      el("td", { class: "sub", "data-field": "map-facts" }, EDNC.mapFacts(card.maps)));
  }

  // how a machine is reached, as the plant says it (server/schemas/link.py's kinds)
  const LINK_NAMES = { modbus: "Modbus/TCP", opcua: "OPC UA",
    sinumerik_sd: "SINUMERIK setting data (OPC UA)" };

  function machineCell(card) {
    return el("td", { class: "machine" },
      el("a", { href: `/machines/${encodeURIComponent(card.name)}`, class: "name",
        "data-field": "name" }, card.name),
      el("div", { class: "sub", "data-field": "link" },
        `${card.controller} · ${card.ip}` + (card.link && card.link !== "ednc"
          ? ` · ${LINK_NAMES[card.link] || card.link} link` : "")),
      linkLine(card),
      el("div", { class: "sub chain", "data-field": "chain" }, card.chain));
  }

  // what the link does when it is not simply connected (or offline): the operator sees
  // "unreachable (no_answer)" with the controller's own words in the tooltip
  function linkLine(card) {
    const st = card.link_state;
    if (!st || st === "offline" || (st === "connected" && !card.link_reason)) return null;
    const head = st.replace("_", " ") + (card.link_reason ? ` (${card.link_reason})` : "");
    return el("div", { class: "sub", "data-field": "link-state", title: card.link_text || "" },
      "link: ", el("b", {}, head));
  }

  function statusCell(card) {
    const more = card.accuracy ? card.accuracy.reasons.length - 1 : 0;
    return el("td", {},
      EDNC.healthPill(card),
      el("div", { class: "sub", "data-field": "health-reason" }, card.health_reason),
      more > 0 ? el("div", { class: "sub" }, el("a", { href: "#accuracy-section" },
        `+${more} more reason${more > 1 ? "s" : ""}`)) : null,
      card.state ? el("div", { class: "sub" }, "machine state: ",
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
    const built = EDNC.builtAt(m.built_at_C);
    return el("td", { class: "map" },
      el("div", { class: "versions", "data-field": "maps" },
        `${v(m.latest)} / ${v(m.sent)} / ${v(m.applied)}`),
      m.latest !== null ? el("div", { class: "sub", "data-field": "map-kind" },
        `${EDNC.KIND_TEXT[m.kind] || "map"}, ${EDNC.bytes(m.bytes)}`) : null,
      m.age_s !== null ? el("div", { class: "sub", "data-field": "map-age" },
        `applied ${age(m.age_s)}`) : null,
      m.error_um !== null ? el("div", { class: "sub" },
        `error as sent ${qty(m.error_um, "µm", 2)}`) : null,
      built ? el("div", { class: "sub" }, `built at ${built}`) : null,
      m.sent_state ? el("div", { class: `sub delivery ${m.sent_state}` },
        `v${m.sent} ${m.sent_state}${m.reject_reason ? ": " + m.reject_reason : ""}`) : null,
      m.reported !== null && m.reported !== undefined
        ? el("div", { class: "sub" }, `machine reports ${m.reported ? "v" + m.reported
          : "no map applied"}`) : null);
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
    if (!v) return el("td", { class: "sub" }, "never verified");
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
    if (!d) return el("td", { class: "sub" }, "no diagnosis yet");
    const estimate = EDNC.estimates(d.estimate);
    return el("td", { "data-field": "diagnosis" },
      el("div", { class: d.effect === "none" ? "sub" : null }, d.effect === "none"
        ? EDNC.effectText(d) : el("b", {}, EDNC.effectText(d))),
      estimate ? el("div", { class: "sub" }, estimate) : null,
      d.rms_before_um !== null ? el("div", { class: "sub" },
        `held-out RMS ${qty(d.rms_before_um, "µm", 2)} → ${qty(d.rms_after_um, "µm", 2)}`)
        : null,
      el("div", { class: "sub" }, time(d.created_at)));
  }

  function row(card) {
    return el("tr", { class: `health-${card.health}`, "data-machine": card.name },
      machineCell(card), statusCell(card), linkCell(card), mapCell(card),
      axesCell(card, (a) => el("td", { class: "num", "data-field": `pos-${a.name}` },
        qty(a.position, posUnit(a), 3))),
      axesCell(card, (a) => el("td", { class: "num", "data-field": `comp-${a.name}` },
        signed(a.compensation, compUnit(a), 1))),
      temperatureCell(card), el("td", { class: "trends" }, trendBox(card.name)),
      verificationCell(card), diagnosisCell(card));
  }

  function eventRow(e) {
    return el("tr", { class: `event ${e.kind}`, "data-kind": e.kind },
      el("td", { class: "time" }, time(e.time)),
      el("td", {}, el("span", { class: `kind ${e.kind}` }, e.kind)),
      el("td", {}, e.machine),
      el("td", {}, e.detail));
  }

  let known = "";

  function render(snapshot) {
    const machines = snapshot.machines;
    const worst = [...machines].sort((a, b) =>
      EDNC.SEVERITY.indexOf(b.health) - EDNC.SEVERITY.indexOf(a.health) ||
      a.name.localeCompare(b.name));
    document.querySelector("#accuracy > tbody").replaceChildren(...worst.map(accuracyRow));
    document.querySelector("#machines > tbody").replaceChildren(...machines.map(row));
    healthStrip(worst);
    document.getElementById("no-machines").hidden = machines.length > 0;
    document.querySelector("#events > tbody").replaceChildren(...snapshot.events.map(eventRow));
    const count = (h) => machines.filter((c) => c.health === h).length;
    document.getElementById("summary").textContent =
      `${machines.length} machines · ${count("out_of_tolerance")} out of tolerance · ` +
      `${count("alarm")} alarm · ${count("warn")} attention · ${count("unknown")} unknown · ` +
      `${machines.filter((c) => c.connected).length} connected`;
    document.getElementById("footer").textContent =
      `EDNC ${snapshot.version} · node ${snapshot.node_id} · snapshot ` +
      `${time(snapshot.generated_at)} · telemetry older than ${snapshot.stale_after_s} s ` +
      "is marked stale";
    const names = machines.map((c) => c.name).join("\n");
    if (names !== known) {  // a machine added: its history too
      known = names;
      loadHistory();
    }
  }

  document.getElementById("window-box").append(EDNC.windowSelect(() => loadHistory()));
  setInterval(loadHistory, HISTORY_EVERY_MS);
  const indicator = document.getElementById("live");
  EDNC.follow(render, (state) => EDNC.showLinkState(indicator, state));
})();
