"""Estimate of a named effect (step 5 of :mod:`volumetric.diagnose`): the candidate
fitted with the base model, its coefficient in physical units with its standard
uncertainty, and the model term it adds to the saved :class:`MachineModel`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate, temperature_columns
from volumetric.diagnose.rotary import harmonic_estimate
from volumetric.diagnose.splits import solve_normal
from volumetric.identify.design import Param
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine
from volumetric.model.model import BacklashTerm, PeriodicTerm, Term, ThermalTerm

F64 = NDArray[np.float64]


def offsets_of(params: list[Param], values: F64) -> dict[str, float]:
    """The tool-tip offsets (``OFFSET_X`` ...) of a solution, µm."""
    return {p.name: float(v) for p, v in zip(params, values, strict=True)
            if p.component == "OFFSET"}


def estimate_effect(
    machine: Machine, m: Measurements, a0: F64, w: F64, y: F64,
    train: NDArray[np.bool_], c: Candidate,
) -> tuple[dict[str, Any], Term | None, F64]:
    """Fit base + candidate on the training readings: the effect in physical units, its
    model term, and the rigid parameters of the joint fit."""
    if c.fixed:
        raise ValueError(f"{c.label} is a fixed prediction: it has no coefficient to estimate")
    a = c.design(a0)
    at, wt, yt = a[train], w[train], y[train]
    g = at.T @ (at * wt[:, None])
    x = solve_normal(g, (at * wt[:, None]).T @ yt)
    r = yt - at @ x
    dof = max(int(train.sum()) - a.shape[1], 1)
    s2 = float(np.sum(wt * r * r) / dof)
    if c.effect == "rotary_periodic":
        # a dozen columns of very different scales beside the base: the inverse of the
        # scaled matrix (the unscaled one loses the small directions to round-off)
        dg = np.sqrt(np.clip(np.diag(g), 1e-300, None))
        cov = np.linalg.pinv(g / np.outer(dg, dg)) / np.outer(dg, dg) * s2
    else:
        cov = np.linalg.pinv(g) * s2
    kx = c.columns.shape[1]
    coef = x[-kx:]
    std = np.sqrt(np.clip(np.diag(cov)[-kx:], 0, None))
    axis = machine.axis(c.axis)
    temps = temperature_columns(m)
    est, term = physical(c, coef, std, axis.travel[0], temps, train)
    if c.effect == "rotary_periodic":
        # a dozen columns, some nearly collinear on a given set of balls: their joint
        # significance (Wald, per column), where the norm ratio would let the worst
        # determined column drown the others
        # computed as the drop of the weighted residual sum of squares that the columns
        # make, over s², which is the Wald statistic of a linear least-squares problem and
        # needs no inverse of their (ill-conditioned) covariance block
        a_b = a[:, :-kx]
        gb = a_b[train].T @ (a_b[train] * wt[:, None])
        r0 = yt - a_b[train] @ solve_normal(gb, (a_b[train] * wt[:, None]).T @ yt)
        wald = float(np.sum(wt * r0 * r0) - np.sum(wt * r * r)) / max(s2, 1e-300)
        est["_t"] = math.sqrt(max(wald, 0.0) / kx)
    else:
        est["_t"] = float(np.linalg.norm(coef) / max(float(np.linalg.norm(std)), 1e-300))
    return est, term, x[:-kx]


def physical(
    c: Candidate, coef: F64, std: F64, q_min: float, temps: dict[str, F64],
    train: NDArray[np.bool_],
) -> tuple[dict[str, Any], Term | None]:
    if c.effect == "thermal_expansion":
        assert c.sensor is not None
        tref = float(temps[c.sensor][train].mean())
        return ({"um_per_m_K": float(coef[0]), "um_per_m_K_std": float(std[0])},
                ThermalTerm("thermal_expansion", c.axis, c.sensor, float(coef[0]), tref,
                            q_min))
    if c.effect == "thermal_drift":
        assert c.sensor is not None
        tref = float(temps[c.sensor][train].mean())
        return ({"um_per_K": float(coef[0]), "um_per_K_std": float(std[0])},
                ThermalTerm("thermal_drift", c.axis, c.sensor, float(coef[0]), tref))
    if c.effect == "backlash":
        return ({"reversal_um": abs(float(coef[0])), "reversal_um_std": float(std[0]),
                 "sign": "lags behind the motion" if coef[0] >= 0 else "leads the motion"},
                BacklashTerm(c.axis, abs(float(coef[0]))))
    if c.effect == "periodic":
        a_s, a_c = float(coef[0]), float(coef[1])
        amp = math.hypot(a_s, a_c)
        amp_std = float(math.sqrt((a_s * std[0]) ** 2 + (a_c * std[1]) ** 2) / max(amp, 1e-12))
        phase = math.atan2(a_c, a_s)
        period = c.extra["period_mm"]
        return ({"amplitude_um": amp, "period_mm": period, "amplitude_um_std": amp_std,
                 "phase_rad": phase},
                PeriodicTerm(c.axis, amp, period, phase))
    if c.effect == "time_drift":
        return ({"um_per_h": float(coef[0]), "um_per_h_std": float(std[0])}, None)
    if c.effect == "rotary_periodic":
        est = rotary_estimate(c.extra["params"], coef, std)
        est["order_limit"] = c.extra["order_limit"]
        est["_harmonics"] = harmonic_estimate(c.extra["params"], coef)
        return est, None
    if c.effect == "rotary_backlash":
        return ({"reversal_urad": abs(float(coef[0])), "reversal_urad_std": float(std[0]),
                 "sign": "lags behind the motion" if coef[0] >= 0 else "leads the motion"},
                None)
    raise ValueError(f"unknown effect {c.effect}")


def rotary_estimate(params: list[Param], coef: F64, std: F64) -> dict[str, Any]:
    """Harmonic amplitudes of a rotary axis's components: the strongest order per turn,
    its largest radial/axial (µm) and angular (µrad) amplitude, and every component's
    amplitudes by order (with standard uncertainties, first order propagated).

    ``params`` are all the candidate's parameters; only the harmonics count."""
    amp: dict[str, dict[int, tuple[float, float]]] = {}
    parts: dict[tuple[str, int], list[tuple[float, float]]] = {}
    for p, v, u in zip(params, coef, std, strict=True):
        if p.basis != "fourier":
            continue
        parts.setdefault((p.component, (p.degree + 1) // 2), []).append((float(v), float(u)))
    for (comp, k), vu in parts.items():
        a = math.hypot(*(v for v, _ in vu))
        ua = math.sqrt(sum((v * u) ** 2 for v, u in vu)) / max(a, 1e-12)
        amp.setdefault(comp, {})[k] = (a, ua)
    # the order whose harmonics, in units of their own uncertainty, stand out most
    score: dict[int, float] = {}
    for by_k in amp.values():
        for k, (a, ua) in by_k.items():
            score[k] = score.get(k, 0.0) + (a / max(ua, 1e-12)) ** 2
    order = max(score, key=lambda k: score[k])
    radial = [(a, ua) for comp, by_k in amp.items() if comp[1] in "XYZ"
              for k, (a, ua) in by_k.items() if k == order]
    angular = [(a, ua) for comp, by_k in amp.items() if comp[1] in "ABC"
               for k, (a, ua) in by_k.items() if k == order]
    best_r = max(radial, default=(0.0, 0.0))
    best_a = max(angular, default=(0.0, 0.0))
    return {"order": order, "radial_um": best_r[0], "radial_um_std": best_r[1],
            "angular_urad": best_a[0], "angular_urad_std": best_a[1],
            "components": {comp: {str(k): round(a, 3) for k, (a, _) in sorted(by_k.items())}
                           for comp, by_k in sorted(amp.items())}}

