"""The diagnosis report a metrologist looks at: PNG plots and one HTML page.

Residuals (held-out, displacement readings) of the base and of the extended model against
each axis position, each temperature, time and approach direction, and the candidate
ranking. Written with matplotlib's Agg backend (no display needed).
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from volumetric.diagnose.diagnosis import Diagnosis
from volumetric.identify.design import axis_positions
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine


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


def write_report(machine: Machine, m: Measurements, d: Diagnosis, directory: Path) -> Path:
    """Write the plots and ``index.html`` into ``directory``; return the HTML path."""
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
    for sensor, col in m.temperature_columns.items():
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
    head = (f"<h1>Diagnosis of {html.escape(machine.name)}</h1><p><b>Effect:</b> "
            f"{html.escape(d.effect)} {html.escape(str(d.axis or ''))} "
            f"{html.escape(str(d.sensor or ''))}<br><b>Held-out RMS:</b> "
            f"{d.rms_before_um:.3f} µm with the rigid model, {d.rms_after_um:.3f} µm "
            f"extended</p><pre>{html.escape(json.dumps(d.estimate, indent=1))}</pre>")
    if d.not_assessed:
        items = "".join(f"<li>{html.escape(k)}: {html.escape(v)}</li>"
                        for k, v in d.not_assessed.items())
        head += f"<p>Not assessed:</p><ul>{items}</ul>"
    body = '<h2>Candidates</h2><img src="candidates.png">'
    body += "".join(f"<h2>Residual {html.escape(t)}</h2><img src='{n}'>" for n, t in figures)
    page = directory / "index.html"
    page.write_text(f"<!doctype html><meta charset=utf-8><title>EDNC diagnosis</title>"
                    f"<body style='font-family:sans-serif;max-width:900px'>{head}{body}")
    return page
