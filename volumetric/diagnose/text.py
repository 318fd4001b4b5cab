"""The diagnosis in words: estimates with their uncertainties and units, and the effects
found one per line (what ``ednc diagnose`` prints without ``--json``; the HTML report
uses the same estimate rows). No plotting here, so the command stays light."""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

from volumetric.diagnose.diagnosis import TIE, Diagnosis

# Units of the estimate's keys, by suffix (diagnosis.py's naming), longest first.
UNITS = (("_um_per_m_K", "µm/(m·K)"), ("_um_per_K", "µm/K"), ("_um_per_h", "µm/h"),
         ("_urad", "µrad"), ("_um", "µm"), ("_mm", "mm"), ("_deg", "°"), ("_s", "s"))


def estimate_rows(estimate: Mapping[str, Any]) -> list[tuple[str, str]]:
    """(name, value ± uncertainty with unit) for each estimate; ``<k>_std`` joins ``<k>``."""
    rows = []
    for key, value in estimate.items():
        if key.endswith("_std") and key[:-4] in estimate:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            text = value if isinstance(value, str) else json.dumps(value)
            rows.append((key, text))
            continue
        # "um_per_K" is a whole key, "amplitude_um" a name with a unit suffix
        unit = next((u for suffix, u in UNITS if f"_{key}".endswith(suffix)), "")
        std = estimate.get(f"{key}_std")
        pm = f" ± {float(std):.2g}" if isinstance(std, (int, float)) else ""
        rows.append((key, f"{float(value):.4g}{pm} {unit}".rstrip()))
    return rows


def _what(e: Mapping[str, Any]) -> str:
    where = " ".join(x for x in (e.get("axis") or "", e.get("sensor") or "") if x)
    return f"{e['effect']} {where}".rstrip()


def effects_text(d: Diagnosis) -> list[str]:
    """One line per effect found, strongest first: what, axis and sensor, each estimate
    ± its standard uncertainty, and the held-out RMS before and after it; structure no
    candidate explains with what it correlates with; ``none`` when nothing is found."""
    effects: list[dict[str, Any]] = d.details.get("effects", [])
    lines = [f"held-out RMS of the rigid model: {d.rms_before_um:.3f} µm "
             f"({d.details.get('split', 'runs')} split)"]
    if not effects:
        lines.append("effect: none (no candidate makes a significant held-out gain)")
        return lines
    before = d.rms_before_um
    for i, e in enumerate(effects, start=1):
        after = float(e["rms_after_um"])
        if e["effect"] == "unexplained":
            est = e["estimate"]
            top = (est.get("correlates") or [{}])[0]
            jump = (f", a jump of {top['step_um']:.3g} µm at {e['axis']} = {top['step_at']:.4g}"
                    if "step_at" in top else "")
            lines.append(f"{i}. unexplained: the residual still follows "
                         f"{est['correlates_with']} ({est['structure_um']:.3g} µm RMS{jump}); "
                         "no effect of the library explains it")
            others = [c["correlate"] for c in est.get("correlates", [])[1:]]
            if others:
                lines.append(f"     also correlates with: {', '.join(others)}")
            for n in est.get("nearest", []):
                vals = ", ".join(f"{k} {v}" for k, v in estimate_rows(n["estimate"]))
                lines.append(f"     nearest candidate (not the cause): {_what(n)}: {vals}")
            continue
        vals = ", ".join(f"{k} {v}" for k, v in estimate_rows(e["estimate"])
                         if k not in ("dynamic", "components"))
        lines.append(f"{i}. {_what(e)}: {vals}")
        if "dynamic" in e["estimate"]:
            lines.append(f"     {_dynamic_text(e['estimate']['dynamic'])}")
        if e.get("alternatives"):
            lines.append("     the readings cannot tell it from: "
                         f"{', '.join(e['alternatives'])} (within {TIE:.0%} held-out RMS)")
        for c in e.get("correlation", []):
            lines.append(f"     estimated jointly with {_what(c)} (correlation of the two "
                         f"estimates {c['r']:+.2f})")
        if e["effect"] == "backlash":
            # the sign that confuses: stated where the value is read (report.SIGN_NOTES)
            lines.append("     reversal_um is B >= 0, the axis's lost motion; a map carries "
                         "the correction's reversal, -B/1000 mm (negative minus positive "
                         "approach)")
        lines.append(f"     held-out RMS {before:.3f} -> {after:.3f} µm")
        before = after
    return lines


def _dynamic_text(dyn: Mapping[str, Any]) -> str:
    """The lagged model behind a thermal drift's figure, in one line: the terms selected,
    and the all-sensor part averaged with them when it joined."""
    terms = dyn.get("terms", [])
    selected = dyn.get("selected", [t["name"] for t in terms])
    line = f"lagged model: {', '.join(selected)}"
    every = dyn.get("all_sensors")
    if every:
        # the plain model on every sensor (no selection): say what it holds and how fitted
        tau = every.get("rate_tau_s")
        levels = sum(t["kind"] == "level" for t in terms)
        line = (f"thermal model on every sensor: {levels} levels"
                + (f" and their lags of {tau / 60:.0f} min (their rates)" if tau else "")
                + (f", ridge λ {every['shrinkage']:.0e}" if every.get("shrinkage")
                   else ", least squares"))
    comb = dyn.get("combination")
    if comb and "saved_rms_after_um" in comb:
        # the combination saved in place of the chosen model: both held-out figures named,
        # since the effect's own (below) is the chosen model's
        line = (f"saved: the combination of {len(comb.get('weights', {}))} thermal models "
                f"({len(terms)} terms) in place of the chosen one ({comb['chosen']}); "
                f"held-out RMS {comb['saved_rms_after_um']:.3f} µm saved, "
                f"{comb['chosen_rms_after_um']:.3f} µm chosen")
    taus = dyn.get("all_sensor_taus_s")
    if taus:
        line += (f"; averaged with every sensor's level and lags of {min(taus) / 60:.0f} min"
                 f" to {max(taus) / 3600:.1f} h ({len(terms)} terms in all)")
    steady = dyn.get("steady_um_per_K")
    if steady:
        worst = max(steady, key=lambda k: abs(steady[k]))
        line += (f"; at steady state a sensor 1 K off moves the drift by up to "
                 f"{abs(steady[worst]):.3g} µm ({worst})")
    return line
