"""Structure left in the residual that no candidate of the library explains.

After the diagnosis has named what it can, its held-out residuals (displacement readings)
are searched for what they still follow. Each *correlate* is a variable and the readings
on which it can show:

==================  ==========================================  ========================
correlate           readings                                    test
==================  ==========================================  ========================
``position k``      tests that move axis k                      means in ``N_BINS``
                                                                quantile bins of q_k
``period P along``  tests that move axis k                      best sinusoid of q_k
``direction k``     tests that move axis k, approach +1 or -1   two groups
``time``            all                                         bins of time
``temperature s``   all (sensor s moving by >= 0.05 K)          bins of T_s
==================  ==========================================  ========================

A correlate is *structure* when an F test of the explained against the remaining variance
gives ``p <= P_MAX`` (a level far below what the few dozen correlates tried could reach by
chance) and the explained part is a sizable share of the residual there
(``eta2 >= ETA2_MIN``) and of the whole residual (its RMS at least ``SHARE_MIN`` of the
residual RMS). Residuals of one test are correlated (its readings share a fitted
model's errors), which makes the F test optimistic; the share gates are what keep a
clean campaign quiet, and both were calibrated on simulated campaigns with no effect,
with one and with two effects of the library (``benchmarks/diagnosis_hit_rate.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import f as f_dist

from volumetric.identify.design import axis_positions
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
N_BINS = 12
"""Quantile bins of a correlate: coarse enough for ~20 readings a bin, fine enough to show
a step or a bend that the rigid model's polynomials (degree <= 3-4) cannot follow."""
P_MAX = 1e-9
ETA2_MIN = 0.1
"""Share of the residual variance, on the correlate's readings, that its bins explain."""
SHARE_MIN = 0.3
"""RMS of the explained part over the RMS of the whole judged residual."""
DEMOTE_RATIO = 0.5
"""A named effect whose own correlate still carries structure of at least this fraction of
what the effect itself explained (RMS) was the nearest candidate, not the cause: a sinusoid
fitted to a step explains less than what stays on the step's position; a real pitch error
explains several times the little structure its slightly-off estimate leaves."""
MIN_ROWS = 60
MIN_MOVE = 0.02
"""A test moves an axis when its positions span this fraction of the axis's travel."""


@dataclass(frozen=True)
class Structure:
    """One correlate the residual follows.

    Attributes
    ----------
    kind : str
        ``position``, ``period``, ``direction``, ``time`` or ``temperature``.
    axis, sensor : str or None
        The axis key (position, period, direction) or temperature column.
    rms_um : float
        RMS over the correlate's readings of the part it explains, µm.
    eta2 : float
        That part's share of the residual variance on those readings.
    p : float
        F-test probability of so much explained variance by chance.
    period_mm : float or None
        For ``period``: the best period along the axis, mm (° for a rotary axis).
    """

    kind: str
    axis: str | None
    sensor: str | None
    rms_um: float
    eta2: float
    p: float
    period_mm: float | None = None

    @property
    def label(self) -> str:
        if self.kind == "temperature":
            return f"temperature {self.sensor}"
        if self.kind == "period":
            return f"period {self.period_mm:.4g} along {self.axis}"
        if self.kind == "time":
            return "time"
        return f"{self.kind} {self.axis}"

    def to_json(self) -> dict[str, object]:
        out: dict[str, object] = {"correlate": self.label, "rms_um": round(self.rms_um, 4),
                                  "eta2": round(self.eta2, 3), "p": float(f"{self.p:.3g}")}
        if self.period_mm is not None:
            out["period"] = round(self.period_mm, 3)
        return out


def _binned(v: F64, r: F64, bins: int) -> tuple[float, float, float] | None:
    """(explained RMS, eta², p) of the means of ``r`` in quantile bins of ``v``.

    Ties in ``v`` stay in one bin (a bin edge never splits equal values), so a
    correlate with few distinct values (a direction) gets as many groups as it has.
    """
    if v.size < MIN_ROWS:
        return None
    order = np.argsort(v, kind="stable")
    vs, rs = v[order], r[order]
    edges = np.unique(np.quantile(vs, np.linspace(0, 1, bins + 1)[1:-1]))
    label = np.searchsorted(edges, vs, side="right")
    groups = np.unique(label)
    k = groups.size
    n = rs.size
    if k < 2 or n - k < 10:
        return None
    counts = np.bincount(label)[groups]
    means = np.bincount(label, weights=rs)[groups] / counts
    fitted = means[np.searchsorted(groups, label)]
    ss_between = float(np.sum((fitted - rs.mean()) ** 2))
    ss_within = float(np.sum((rs - fitted) ** 2))
    total = ss_between + ss_within
    if total <= 0 or ss_within <= 0:
        return None
    f = (ss_between / (k - 1)) / (ss_within / (n - k))
    return (float(np.sqrt(ss_between / n)), ss_between / total,
            float(f_dist.sf(f, k - 1, n - k)))


def _sinusoid(q: F64, r: F64, lo: float, hi: float) -> tuple[float, float, float, float] | None:
    """Best sinusoid of ``q`` with period in [lo, hi]: (period, explained RMS, eta², p)."""
    if r.size < MIN_ROWS or hi <= lo:
        return None
    rc = r - r.mean()
    total = float(np.sum(rc * rc))
    if total <= 0:
        return None
    best = (0.0, 0.0)
    for p in np.geomspace(lo, hi, 200):
        ph = 2 * np.pi * q / p
        a = np.column_stack((np.sin(ph), np.cos(ph), np.ones_like(q)))
        x, *_ = np.linalg.lstsq(a, r, rcond=None)
        fit = a @ x - float(x[2])
        ss = float(np.sum(fit * fit))
        if ss > best[1]:
            best = (float(p), ss)
    period, ss = best
    n = r.size
    if ss >= total:
        return None
    f = (ss / 2) / ((total - ss) / (n - 3))
    # the search over periods is paid for by P_MAX, far below the 200 periods' own level
    return period, float(np.sqrt(ss / n)), ss / total, float(f_dist.sf(f, 2, n - 3))


def residual_structure(
    machine: Machine, m: Measurements, residual: F64, judged: NDArray[np.bool_],
) -> list[Structure]:
    """Every correlate the held-out residual follows (module docstring), strongest first.

    Parameters
    ----------
    machine : Machine
    m : Measurements
    residual : ndarray, shape (N,)
        Held-out residuals, µm (µrad for angle readings, which are not used).
    judged : ndarray of bool, shape (N,)
        The readings the residual is defined on.

    Returns
    -------
    list of Structure
        Sorted by the explained RMS, largest first; empty when the residual is clean.
    """
    rows = judged & ~m.is_angle & np.isfinite(residual)
    if rows.sum() < MIN_ROWS:
        return []
    r_all = residual[rows]
    rms_all = float(np.sqrt(np.mean(r_all * r_all)))
    q = axis_positions(machine, m)
    found: list[Structure] = []

    def keep(kind: str, axis: str | None, sensor: str | None,
             stat: tuple[float, float, float] | None, period: float | None = None) -> None:
        if stat is None:
            return
        rms, eta2, p = stat
        if p <= P_MAX and eta2 >= ETA2_MIN and rms >= SHARE_MIN * rms_all:
            found.append(Structure(kind, axis, sensor, rms, eta2, p, period))

    tests = m.test
    for j, axis in enumerate(machine.axes):
        span = axis.travel[1] - axis.travel[0]
        moves = np.zeros(len(m), dtype=bool)
        for label in np.unique(tests[rows]):
            sel = tests == label
            if float(np.ptp(q[sel, j])) >= MIN_MOVE * span:
                moves |= sel
        sel = rows & moves
        if sel.sum() < MIN_ROWS:
            continue
        qj, rj = q[sel, j], residual[sel]
        keep("position", axis.key, None, _binned(qj, rj, N_BINS))
        distinct = np.unique(np.round(qj, 3))
        if distinct.size >= 8:
            step = float(np.percentile(np.diff(distinct), 20))
            got = _sinusoid(qj, rj, max(2.0 * step, 1e-3), float(np.ptp(qj)) / 2.0)
            if got is not None:
                keep("period", axis.key, None, got[1:], got[0])
        if axis.kind == "linear" and axis.name in ("X", "Y", "Z"):
            d = m.direction[sel, "XYZ".index(axis.name)].astype(float)
            both = d != 0
            if np.unique(d[both]).size == 2:
                keep("direction", axis.key, None, _binned(d[both], rj[both], 2))
    if float(np.ptp(m.time_s[rows])) > 0:
        keep("time", None, None, _binned(m.time_s[rows], r_all, N_BINS))
    for sensor, values in m.temperatures.items():
        if float(np.ptp(values[rows])) >= 0.05:
            keep("temperature", None, m.temperature_columns[sensor],
                 _binned(values[rows], r_all, N_BINS))
    found.sort(key=lambda s: s.rms_um, reverse=True)
    return found


def own_correlates(effect: str, axis: str | None, sensor: str | None) -> set[tuple[str, str]]:
    """The correlates a named effect acts through: (kind, axis or sensor). Structure left
    on one of them means the effect did not explain what it was chosen for."""
    out: set[tuple[str, str]] = set()
    if effect in ("thermal_drift", "thermal_expansion") and sensor:
        out.add(("temperature", sensor))
    if effect in ("periodic", "thermal_expansion", "rotary_periodic") and axis:
        out |= {("position", axis), ("period", axis)}
    if effect == "backlash" and axis:
        out.add(("direction", axis))
    if effect == "time_drift":
        out.add(("time", ""))
    return out


def correlate_key(s: Structure) -> tuple[str, str]:
    return (s.kind, s.sensor or s.axis or "")
