"""Structure left in the residual that no candidate of the library explains.

After the diagnosis has named what it can, its held-out residuals (displacement readings)
are searched for what they still follow. Each *correlate* is a variable and the readings
on which it can show:

==================  ==========================================  ========================
correlate           readings                                    test
==================  ==========================================  ========================
``position k``      tests that move axis k                      means in ``N_BINS``
                                                                quantile bins of q_k;
                                                                or one jump beyond a
                                                                polynomial in q_k
``period P along``  tests that move axis k                      best sinusoid of q_k
``direction k``     tests that move axis k, approach +1 or -1   two groups
``time``            all                                         bins of time
``temperature s``   all (sensor s moving by >= 0.05 K)          bins of T_s
==================  ==========================================  ========================

A step (a joint of two scale segments, a damaged stretch of a guideway) is position
structure that twelve bins find only when it is large: each bin costs a degree of
freedom, and the rigid model's polynomials have already taken the step's smooth part,
leaving a jump on a gentle bend (a 3.6 µm step along X under a sixth-degree positioning
component left a 0.8 µm jump beyond a cubic). The jump test fits the residual with a
polynomial in the position of the degree the rigid model gave that axis's components (at
least cubic), plus one step, at the best of every break between measured positions that
leaves ``STEP_EDGE`` of the readings on either side, and judges the step's share of the
variance with one degree of freedom (the search over breaks is paid for by ``P_MAX``, as
the search over periods is). The stronger of the two tests is the position's figure; a
step reports where it is and how large. Readings of one test at one position count as
one (:func:`_step`): a periodic error's misfit aliased on a coarse grid leaves one
position off the others by a micrometre, which, reading by reading, passes for a jump.
Measured with ``benchmarks/diagnosis_hit_rate.py`` (hidden steps of 2-6 µm): 10/20 -> 20/20
on the seeds it was developed on (0-199), 9/20 -> 20/20 on seeds 2000-2199, with 0 false
alarms on 80 null campaigns and no more ``unexplained`` beside correct answers (0 and 3,
as before); a 1 µm step is found where it is, its size within 5 %
(``tests/test_diagnose_unexplained.py``).

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

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

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
STEP_DEGREE = 3
"""Least degree of the polynomial in the position beyond which a jump is judged; the rigid
model's own degree for the axis when higher (its components take a step's smooth part, a
higher degree more of it: judged beyond a lower degree, the jump's share shrinks by the
part of the step the higher terms took)."""
STEP_EDGE = 0.05
"""Least share of the readings (and at least 10) on either side of a step's break."""
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
    step_at : float or None
        For ``position`` found as a jump: where it is along the axis, mm (°).
    step_um : float or None
        Its size, µm (beyond the axis position, minus before).
    """

    kind: str
    axis: str | None
    sensor: str | None
    rms_um: float
    eta2: float
    p: float
    period_mm: float | None = None
    step_at: float | None = None
    step_um: float | None = None

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
        if self.step_at is not None and self.step_um is not None:
            out["step_at"] = round(self.step_at, 3)
            out["step_um"] = round(self.step_um, 4)
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


def _step(q: F64, r: F64, u: F64, test: NDArray[np.str_], degree: int = STEP_DEGREE
          ) -> tuple[float, float, float, float, float] | None:
    """Best single jump of ``r`` along ``q`` beyond a polynomial of ``degree`` in q, both as
    the readings sense them (``u``: what each senses of 1 µm along the axis), and beyond
    a level of each test: (break position, jump size µm, explained RMS, eta², p).

    The readings of one test at one position form a group: what they share (a periodic
    error's misfit at that position, aliased on a coarse grid) is one value, so the jump
    is judged against the scatter of the groups' means, with as many degrees of freedom
    as groups, not against the readings' repeatability. A test's own level is no jump
    either: a short test on one side of a break would otherwise make one of its level;
    only tests that cross the break carry the evidence, as a scale joint shows in each.

    On the groups' means weighted by their counts (rows scaled by √count), the residual
    after the nuisance (``u·P(q)``, the tests' levels) is ``rc``; a step ``h_k = u·H_k``
    (H_k 1 on the groups at or beyond break k) explains ``(h_k·rc)² / |h_k - B Bᵀ h_k|²``
    more of it (B an orthonormal basis of the nuisance, ``Bᵀ rc = 0``). Sorted by q,
    ``h_k·rc``, ``h_k·h_k`` and ``Bᵀ h_k`` are suffix sums, so every break costs O(1).
    """
    n = r.size
    if n < MIN_ROWS:
        return None
    test_id = np.unique(test, return_inverse=True)[1]
    keys = np.column_stack((test_id, np.round(q, 3), np.round(u, 3)))
    _, group, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    group = group.ravel()
    w = counts.astype(float)
    qg, ug, rg = (np.bincount(group, weights=v) / w for v in (q, u, r))
    tg = np.bincount(group, weights=test_id.astype(float)) / w
    order = np.argsort(qg, kind="stable")
    qg, ug, rg, tg, w = qg[order], ug[order], rg[order], tg[order], w[order]
    n_groups = qg.size
    scale = np.sqrt(w)
    half = max(float(np.ptp(qg)) / 2.0, 1e-12)
    levels = np.eye(int(test_id.max()) + 1)[np.rint(tg).astype(np.intp)]
    nuisance = np.column_stack((ug[:, None] * np.vander((qg - qg.mean()) / half, degree + 1),
                                levels)) * scale[:, None]
    basis = _orthonormal(nuisance)
    dof = n_groups - basis.shape[1] - 1
    if dof < 5:
        return None
    ys, hs = rg * scale, ug * scale
    rc = ys - basis @ (basis.T @ ys)
    # prefix sums with a leading zero: the suffix from k on is total - prefix[k]
    pb = np.vstack((np.zeros(basis.shape[1]), np.cumsum(basis * hs[:, None], axis=0)))
    pu = np.concatenate(([0.0], np.cumsum(hs * hs)))
    pr = np.concatenate(([0.0], np.cumsum(hs * rc)))
    below = np.concatenate(([0.0], np.cumsum(w)))  # readings before break k
    edge = max(10, int(np.ceil(STEP_EDGE * n)))
    k = np.arange(3, n_groups - 2)
    k = k[(qg[k - 1] < qg[k]) & (below[k] >= edge) & (n - below[k] >= edge)]
    if k.size == 0:
        return None
    hb = pb[-1] - pb[k]  # Bᵀ h_k, (K, nuisance columns)
    hh = (pu[-1] - pu[k]) - np.einsum("ij,ij->i", hb, hb)
    hr = pr[-1] - pr[k]
    usable = hh > 1e-9 * n
    if not usable.any():
        return None
    gain = np.where(usable, hr * hr / np.where(usable, hh, 1.0), 0.0)
    best = int(np.argmax(gain))
    g = float(gain[best])
    rss = float(rc @ rc)
    total = float(np.sum((r - r.mean()) ** 2))
    if total <= 0 or g <= 0 or g >= rss:
        return None
    f = g / ((rss - g) / dof)
    at = float(qg[k[best] - 1] + qg[k[best]]) / 2.0
    return (at, float(hr[best] / hh[best]), float(np.sqrt(g / n)), g / total,
            float(f_dist.sf(f, 1, dof)))


def _orthonormal(a: F64) -> F64:
    """An orthonormal basis of the column space of ``a`` (N, k): columns that depend on
    others (a test's level that the polynomial's constant already spans) are dropped."""
    u, sv, _ = np.linalg.svd(a, full_matrices=False)
    keep = sv > 1e-10 * max(float(sv.max(initial=0.0)), 1e-300)
    out: F64 = u[:, keep]
    return out


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
    degrees: Mapping[str, int] | None = None,
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
    degrees : mapping of str to int, optional
        The rigid model's highest degree per component (``FitResult.degrees``): a jump
        along an axis is judged beyond a polynomial of its components' highest degree.

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

    def passes(stat: tuple[float, float, float] | None) -> bool:
        return (stat is not None and stat[2] <= P_MAX and stat[1] >= ETA2_MIN
                and stat[0] >= SHARE_MIN * rms_all)

    def keep(kind: str, axis: str | None, sensor: str | None,
             stat: tuple[float, float, float] | None, period: float | None = None) -> None:
        if stat is not None and passes(stat):
            found.append(Structure(kind, axis, sensor, *stat, period))

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
        # the position's figure: twelve bins, or one jump beyond a cubic, the stronger
        position = []
        binned = _binned(qj, rj, N_BINS)
        if binned is not None and passes(binned):
            position.append(Structure("position", axis.key, None, *binned))
        own = [d for c, d in (degrees or {}).items()
               if len(c) == 3 and c[0] == "E" and c[2] == axis.name]
        # the jump where it shows: readings that sense along the axis (a linear one's
        # direction; a rotary axis's readings as they are)
        if axis.kind == "linear" and axis.name in ("X", "Y", "Z"):
            uj = m.u[sel, "XYZ".index(axis.name)]
        else:
            uj = np.ones(int(sel.sum()))
        sensing = np.abs(uj) >= 0.5
        jump = _step(qj[sensing], rj[sensing], uj[sensing], tests[sel][sensing],
                     max([STEP_DEGREE, *own]))
        if jump is not None and passes(jump[2:]):
            position.append(Structure("position", axis.key, None, *jump[2:],
                                      step_at=jump[0], step_um=jump[1]))
        if position:
            found.append(max(position, key=lambda s: s.rms_um))
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


def unexplained_entry(left: list[Structure], nearest: list[dict[str, Any]],
                      rms_after: float) -> dict[str, Any]:
    """The ``effects`` entry of structure no candidate explains: the strongest correlate
    names it (axis or sensor when it has one), every correlate found is listed, and the
    named effects it displaced (``nearest``) keep their estimates there."""
    top = left[0]
    estimate: dict[str, Any] = {"correlates_with": top.label, "structure_um": round(top.rms_um, 4),
                                "correlates": [s.to_json() for s in left]}
    if nearest:
        estimate["nearest"] = [{k: e[k] for k in ("effect", "axis", "sensor", "estimate")}
                               for e in nearest]
    return {"effect": "unexplained", "axis": top.axis, "sensor": top.sensor,
            "estimate": estimate, "rms_after_um": round(rms_after, 4)}


def with_unexplained(effects: list[dict[str, Any]], left: list[Structure], rms_before: float,
                     rms_after: float) -> list[dict[str, Any]]:
    """``effects`` with the entry of the structure ``left`` (step 7 of
    :mod:`volumetric.diagnose`): an effect whose own correlate (its sensor, its axis's
    position or direction) still carries at least ``DEMOTE_RATIO`` of what it explained
    was the nearest candidate, not the cause, and gives way to ``unexplained`` (first
    when it was first).

    Parameters
    ----------
    effects : list of dict
        The named effects' entries, each with ``rms_after_um`` counting those before it.
    left : list of Structure
        The structure found in the final held-out residuals, strongest first (not empty).
    rms_before, rms_after : float
        Held-out RMS of the base and of the model with every named effect, µm.
    """
    strength = {correlate_key(s): s.rms_um for s in left}
    nearest = []
    before_i = rms_before
    for e in effects:
        # what this effect explained: the held-out RMS it removed (in quadrature)
        explained = math.sqrt(max(before_i ** 2 - float(e["rms_after_um"]) ** 2, 0.0))
        before_i = float(e["rms_after_um"])
        own = own_correlates(e["effect"], e["axis"], e["sensor"])
        if any(strength.get(k, 0.0) >= DEMOTE_RATIO * explained for k in own):
            nearest.append(e)
    kept = [e for e in effects if e not in nearest]
    entry = unexplained_entry(left, nearest, rms_after)
    return [entry, *kept] if nearest and nearest[0] is effects[0] else [*kept, entry]
