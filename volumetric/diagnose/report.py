"""The diagnosis report a metrologist looks at: one HTML page, with its plots as PNG files.

``index.html`` opens with what was diagnosed from what: machine and data file names, when
the report was made and the span of the readings, then a summary table (cause, estimate
± standard uncertainty, held-out RMS with the rigid and with the extended model), the
sign conventions of the estimate, and the plots, embedded in the page (so the one file
can be mailed or archived) and also written next to it as PNG files.

Plots: the candidate ranking, then held-out residuals (displacement readings) of the
rigid and of the extended model against each axis position, time and approach direction.
Residuals against a temperature are shown only when temperature matters here: the
diagnosed cause names that sensor, or a thermal candidate with it passed the diagnosis's
significance test (``z >= Z_MIN``); the page says which were left out and why. Written
with matplotlib's Agg backend (no display needed).
"""

from __future__ import annotations

import base64
import datetime as dt
import html
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from volumetric.diagnose.diagnosis import Z_MIN, Diagnosis
from volumetric.diagnose.text import estimate_rows
from volumetric.identify.design import axis_positions
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine

__all__ = ["estimate_rows", "relevant_sensors", "write_report"]

STYLE = """
body { font-family: system-ui, sans-serif; max-width: 60rem; margin: 2rem auto;
       padding: 0 1rem; color: #1c2833; line-height: 1.45; }
h1 { font-size: 1.5rem; margin-bottom: 0.2rem; }
h2 { font-size: 1.1rem; margin-top: 2rem; border-bottom: 1px solid #d5d8dc; }
p.meta { color: #566573; margin-top: 0; }
table { border-collapse: collapse; margin: 0.8rem 0; }
th, td { text-align: left; padding: 0.3rem 0.8rem; border-bottom: 1px solid #e5e8e8; }
th { background: #f4f6f6; font-weight: 600; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.note { background: #fef9e7; border-left: 3px solid #f1c40f; padding: 0.4rem 0.8rem; }
figure { margin: 1rem 0; }
figure img { max-width: 100%; border: 1px solid #e5e8e8; }
figcaption { color: #566573; font-size: 0.9rem; }
"""

SIGN_NOTES = {
    "backlash": (
        "reversal_um is B ≥ 0, the lost motion of the axis. 'lags behind the motion': the "
        "tool stops B/2 short of the commanded position in the direction of travel, so an "
        "ISO 230-2 test of the axis shows Bi = x̄↑ − x̄↓ = −B. The error map carries "
        "corrections, the negative of errors: its reversal (negative-approach minus "
        "positive-approach correction, protocol/README.md) is −B, e.g. −0.008 mm for "
        "B = 8 µm. For 'leads the motion' each of these signs flips."),
    "thermal_drift": (
        "um_per_K > 0: the tool moves along +axis relative to the workpiece as the sensor "
        "warms; the map applies the negative."),
    "thermal_expansion": (
        "um_per_m_K > 0: as the sensor warms, the tool ends up further along +axis than "
        "commanded, in proportion to its distance from the start of the axis's travel."),
}


def _scatter(path: Path, x: np.ndarray, before: np.ndarray, after: np.ndarray, xlabel: str,
             title: str) -> None:
    fig, ax = plt.subplots(figsize=(7, 3.2), dpi=90)
    ax.scatter(x, before, s=4, alpha=0.5, label="rigid model", color="#c0392b")
    ax.scatter(x, after, s=4, alpha=0.5, label="extended model", color="#2471a3")
    ax.axhline(0, color="0.5", lw=0.7)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("held-out residual (µm)")
    ax.set_title(title)
    ax.legend(loc="upper right", fontsize=8, markerscale=3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def relevant_sensors(d: Diagnosis, columns: Mapping[str, str]) -> tuple[list[str], str]:
    """The sensors whose plots matter, and a sentence on the ones left out.

    ``columns`` maps sensor to its CSV column (``Measurements.temperature_columns``).
    """
    named = {d.sensor} if d.sensor else set()
    significant = {c["sensor"] for c in d.candidates
                   if c.get("sensor") and float(c.get("z", 0.0)) >= Z_MIN
                   and float(c.get("gain", 0.0)) > 0}
    keep = [s for s, col in columns.items() if col in named | significant]
    left = [col for s, col in columns.items() if s not in keep]
    if not left:
        return keep, ""
    thermal = [c for c in d.candidates if c.get("sensor")]
    best = (f" (the best, {thermal[0]['effect']} {thermal[0]['axis']} "
            f"{thermal[0]['sensor']}, has z = {float(thermal[0]['z']):.2f})" if thermal else "")
    return keep, (f"Residuals against {', '.join(left)} are left out: no thermal candidate "
                  f"with {'it' if len(left) == 1 else 'them'} passed the significance test "
                  f"(z ≥ {Z_MIN:g}){best}.")


def _effects_table(effects: list[dict[str, Any]]) -> str:
    """One row per named effect: what, axis, sensor, estimate, held-out RMS after it."""
    e = html.escape
    rows = []
    for n, x in enumerate(effects, start=1):
        est = x.get("estimate") or {}
        if x.get("effect") == "unexplained":
            what = (f"the residual still follows {est.get('correlates_with', '?')} "
                    f"({float(est.get('structure_um', float('nan'))):.3g} µm RMS); no effect "
                    "of the library explains it")
            estimate = e(what)
        else:
            estimate = "<br>".join(f"{e(k)}: {e(v)}" for k, v in estimate_rows(est)
                                   if k not in ("dynamic", "components")) or "—"
        rows.append(f"<tr><td class='num'>{n}</td><td>{e(str(x.get('effect')))}</td>"
                    f"<td>{e(str(x.get('axis') or ''))}</td>"
                    f"<td>{e(str(x.get('sensor') or ''))}</td><td>{estimate}</td>"
                    f"<td class='num'>{float(x.get('rms_after_um', float('nan'))):.3f}</td>"
                    "</tr>")
    return ("<table class='effects'><tr><th>#</th><th>effect</th><th>axis</th>"
            "<th>sensor</th><th>estimate</th><th>held-out RMS after (µm)</th></tr>"
            + "".join(rows) + "</table>")


def _image(path: Path, caption: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f"<figure><img alt='{html.escape(caption)}' src='data:image/png;base64,{data}'>"
            f"<figcaption>{html.escape(caption)} ({html.escape(path.name)})</figcaption>"
            "</figure>")


def write_report(machine: Machine, m: Measurements, d: Diagnosis, directory: Path, *,
                 data_file: Path | str | None = None,
                 machine_file: Path | str | None = None,
                 now: dt.datetime | None = None) -> Path:
    """Write the plots and ``index.html`` into ``directory``; return the HTML path.

    ``data_file`` and ``machine_file`` are the input files' names as the user gave them
    (shown on the page); ``now`` is the report's date (default: the current UTC time).
    """
    directory.mkdir(parents=True, exist_ok=True)
    rows = np.flatnonzero(d.judged)
    before, after = d.residual_before[rows], d.residual_after[rows]
    q = axis_positions(machine, m)[rows]
    figures: list[tuple[str, str]] = []
    for j, axis in enumerate(machine.axes):
        if np.ptp(q[:, j]) > 0:
            name = f"position_{axis.key}.png"
            unit = "mm" if axis.kind == "linear" else "deg"
            _scatter(directory / name, q[:, j], before, after, f"{axis.key} ({unit})",
                     f"residual against {axis.key}")
            figures.append((name, f"against position {axis.key}"))
    sensors, left_out = relevant_sensors(d, m.temperature_columns)
    for sensor in sensors:
        col = m.temperature_columns[sensor]
        name = f"temperature_{sensor}.png"
        _scatter(directory / name, m.temperatures[sensor][rows], before, after,
                 f"{col} (°C)", f"residual against {col}")
        figures.append((name, f"against temperature {col}"))
    _scatter(directory / "time.png", m.time_s[rows] / 3600.0, before, after, "time (h)",
             "residual against time")
    figures.append(("time.png", "against time"))
    for k, axis_name in enumerate("xyz"):
        dirs = m.direction[rows, k]
        if np.unique(dirs[dirs != 0]).size >= 2:
            name = f"direction_{axis_name}.png"
            jitter = np.random.default_rng(0).uniform(-0.15, 0.15, dirs.size)
            _scatter(directory / name, dirs + jitter, before, after,
                     f"approach direction along {axis_name}", "residual by approach direction")
            figures.append((name, f"by approach direction {axis_name}"))
    top = d.candidates[:12]
    fig, ax = plt.subplots(figsize=(7, 0.35 * len(top) + 1.2), dpi=90)
    labels = [f"{c['effect']} {c['axis']} {c.get('sensor') or ''} {c.get('model', '')}"
              for c in top]
    ax.barh(range(len(top)), [c["rms_after_um"] for c in top], color="#2471a3")
    ax.axvline(d.rms_before_um, color="#c0392b", lw=1.2, label="rigid model")
    ax.set_yticks(range(len(top)), labels, fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("held-out RMS (µm)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(directory / "candidates.png")
    plt.close(fig)

    page = directory / "index.html"
    page.write_text(_page(machine, m, d, figures, left_out, data_file, machine_file,
                          now or dt.datetime.now(dt.UTC), directory), encoding="utf-8")
    return page


def _page(machine: Machine, m: Measurements, d: Diagnosis, figures: list[tuple[str, str]],
          left_out: str, data_file: Path | str | None, machine_file: Path | str | None,
          now: dt.datetime, directory: Path) -> str:
    e = html.escape
    cause = " ".join(x for x in (d.effect, d.axis or "", d.sensor or "") if x)
    span_h = float(np.ptp(m.time_s)) / 3600.0 if len(m) else 0.0
    data_name = str(data_file) if data_file is not None else "(not given)"
    machine_name = (f"{machine.name} ({machine_file})" if machine_file is not None
                    else machine.name)
    estimate = "<br>".join(f"{e(k)}: {e(v)}" for k, v in estimate_rows(d.estimate)) or "—"
    summary = [
        ("machine", e(machine_name)),
        ("data file", e(data_name)),
        ("readings", f"{len(m)} over {span_h:.1f} h"),
        ("report made", e(now.strftime("%Y-%m-%d %H:%M UTC"))),
        ("cause", e(cause)),
        ("estimate", estimate),
        ("held-out RMS, rigid model", f"{d.rms_before_um:.3f} µm"),
        ("held-out RMS, extended model", f"{d.rms_after_um:.3f} µm"),
    ]
    table = "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in summary)
    parts = [f"<h1>Diagnosis of {e(machine.name)}</h1>",
             f"<p class='meta'>{e(data_name)} · {e(now.strftime('%Y-%m-%d %H:%M UTC'))}</p>",
             f"<table class='summary'>{table}</table>"]
    effects: list[dict[str, Any]] = list(d.details.get("effects", []))
    if effects:
        parts.append("<h2>Effects found</h2><p>Every cause the diagnosis names, strongest "
                     "first; the held-out RMS is with all effects up to and including "
                     "this one.</p>" + _effects_table(effects))
    for kind in dict.fromkeys(str(x.get("effect")) for x in effects or [{"effect": d.effect}]):
        if kind in SIGN_NOTES:
            parts.append(f"<p class='note'>Sign convention: {e(SIGN_NOTES[kind])}</p>")
    if d.not_assessed:
        items = "".join(f"<li>{e(k)}: {e(v)}</li>" for k, v in d.not_assessed.items())
        parts.append(f"<h2>Not assessed</h2><ul>{items}</ul>")
    cand = "".join(
        f"<tr><td>{e(str(c['effect']))}</td><td>{e(str(c['axis']))}</td>"
        f"<td>{e(str(c.get('sensor') or ''))}</td>"
        f"<td class='num'>{float(c['rms_after_um']):.3f}</td>"
        f"<td class='num'>{float(c['z']):.2f}</td></tr>" for c in d.candidates[:12])
    parts.append("<h2>Candidates</h2><table><tr><th>effect</th><th>axis</th><th>sensor</th>"
                 "<th>held-out RMS (µm)</th><th>z</th></tr>" + cand + "</table>")
    parts.append(_image(directory / "candidates.png", "held-out RMS of each candidate"))
    parts.append("<h2>Residuals</h2>")
    if left_out:
        parts.append(f"<p>{e(left_out)}</p>")
    parts += [_image(directory / name, f"residual {title}") for name, title in figures]
    return ("<!doctype html><html lang=en><meta charset=utf-8>"
            f"<title>EDNC diagnosis: {e(machine.name)}</title><style>{STYLE}</style>"
            f"<body>{''.join(parts)}</body></html>\n")
