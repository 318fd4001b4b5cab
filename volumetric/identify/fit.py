"""Identification: the machine's component errors from measured readings.

One weighted least-squares problem over every reading (:mod:`volumetric.identify.design`):

1. Columns the readings do not observe at all are dropped; their components are reported
   as not measured.
2. Each component's polynomial degree is chosen by the Bayesian information criterion,
   component by component until no change (the normal equations are formed once, so a
   candidate costs one small solve).
3. Displacements (µm) and angles (µrad) are weighted by their own residual scatter,
   estimated from the fit and refined once.
4. Parameters the data cannot separate (a null space of the scaled normal matrix, found
   by eigen-decomposition with a stated tolerance) are reported with the parameters they
   are confounded with and fixed at zero, never returned as arbitrary numbers.
5. Standard uncertainties come from the covariance scaled by the residual variance.

A failed identification raises :class:`FitError` with a message naming the problem.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.design import (
    Param,
    build_design,
    component_fourier,
    component_polynomial,
)
from volumetric.measure.measurement import Measurements
from volumetric.model.components import Component, GeometricErrors
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]
NULL_TOL = 1e-10
"""Eigenvalue of the unit-diagonal normal matrix, relative to the largest, below which a
direction of parameter space is taken as unobservable (singular value ratio 1e-5)."""


class FitError(ValueError):
    """Identification impossible with these readings; the message says why."""


@dataclass(frozen=True)
class Solution:
    """A weighted least-squares solution.

    Attributes
    ----------
    values, std : ndarray, shape (p,)
        Parameters and their standard uncertainties.
    residual : ndarray, shape (N,)
        Reading minus prediction, in the readings' units.
    sigma2 : float
        Residual variance of unit weight.
    """

    values: F64
    std: F64
    residual: F64
    sigma2: float


def solve(a: F64, y: F64, w: F64) -> Solution:
    """Weighted least squares ``min Σ w (y − a x)²`` through scaled normal equations.

    Parameters
    ----------
    a : ndarray, shape (N, p)
    y, w : ndarray, shape (N,)

    Raises
    ------
    FitError
        When the columns are linearly dependent (callers remove such columns first).
    """
    n, p = a.shape
    if p == 0:
        r = y.copy()
        return Solution(np.zeros(0), np.zeros(0), r, float(np.sum(w * r * r) / max(n, 1)))
    aw = a * w[:, None]
    g = a.T @ aw
    b = aw.T @ y
    d = np.sqrt(np.diag(g))
    d[d == 0] = 1.0
    gs = g / np.outer(d, d)
    try:
        chol = np.linalg.cholesky(gs)
    except np.linalg.LinAlgError:
        raise FitError("the parameters are linearly dependent (remove confounded ones)") from None
    xs = np.linalg.solve(chol.T, np.linalg.solve(chol, b / d))
    x = xs / d
    r = y - a @ x
    dof = max(n - p, 1)
    sigma2 = float(np.sum(w * r * r) / dof)
    inv = np.linalg.inv(chol)
    cov_s = inv.T @ inv
    std = np.sqrt(np.clip(np.diag(cov_s), 0, None) * sigma2) / d
    return Solution(x, std, r, sigma2)


@dataclass(frozen=True)
class Normal:
    """Normal equations of a weighted problem, kept per weight group.

    Weights are constant within a group (displacements, angles), so the normal matrix
    for any group weights is a weighted sum of per-group matrices formed once: degree
    selection, null-space analysis and re-weighting then never touch the (N, P) matrix.
    """

    g: list[F64]  # per group, (P, P)
    b: list[F64]  # per group, (P,)
    yy: list[float]
    n: int

    @staticmethod
    def build(a: F64, y: F64, groups: list[NDArray[np.bool_]]) -> Normal:
        gs, bs, yys = [], [], []
        for mask in groups:
            ag = a[mask]
            gs.append(ag.T @ ag)
            bs.append(ag.T @ y[mask])
            yys.append(float(y[mask] @ y[mask]))
        return Normal(gs, bs, yys, len(y))

    def combined(self, weights: list[float]) -> tuple[F64, F64, float]:
        g = sum((w * g for w, g in zip(weights, self.g, strict=True)), np.zeros_like(self.g[0]))
        b = sum((w * b for w, b in zip(weights, self.b, strict=True)), np.zeros_like(self.b[0]))
        yy = float(sum(w * v for w, v in zip(weights, self.yy, strict=True)))
        return g, b, yy


def _rss(g: F64, b: F64, yy: float, cols: NDArray[np.intp]) -> float:
    """Weighted residual sum of squares of the sub-model on ``cols`` (full column rank)."""
    if cols.size == 0:
        return yy
    gs = g[np.ix_(cols, cols)]
    d = np.sqrt(np.diag(gs))
    d[d == 0] = 1.0
    try:
        chol = np.linalg.cholesky(gs / np.outer(d, d))
    except np.linalg.LinAlgError:
        return yy  # not full rank: never preferred
    z = np.linalg.solve(chol, b[cols] / d)
    return max(yy - float(z @ z), 1e-300)


def _null_direction(g: F64, cols: NDArray[np.intp]) -> F64 | None:
    """The least observable direction of ``cols`` if it is unobservable, else None."""
    gs = g[np.ix_(cols, cols)]
    d = np.sqrt(np.diag(gs))
    d[d == 0] = 1.0
    lam, vec = np.linalg.eigh(gs / np.outer(d, d))
    if lam[0] > NULL_TOL * lam[-1]:
        return None
    out: F64 = vec[:, 0]
    return out


def _bic(rss: float, k: int, n: int) -> float:
    return n * math.log(rss / n) + k * math.log(n)


@dataclass(frozen=True)
class FitResult:
    """What identification found.

    Attributes
    ----------
    model : MachineModel
    params : list of Param
        The identified parameters.
    values, std : ndarray, shape (p,)
        Their values and standard uncertainties (µm or µrad).
    degrees : dict of str to int
        Highest polynomial degree chosen per component (absent: none).
    unidentifiable : list of dict
        ``{"parameter", "confounded_with"}`` for parameters fixed at zero.
    not_measured : list of str
        Components the readings do not observe at all.
    residual : ndarray, shape (N,)
    rms : dict of str to float
        Residual RMS of displacements (µm) and angles (µrad).
    """

    model: MachineModel
    params: list[Param]
    values: F64
    std: F64
    degrees: dict[str, int]
    unidentifiable: list[dict[str, Any]]
    not_measured: list[str]
    residual: F64
    rms: dict[str, float]
    weights: F64 = field(repr=False, default_factory=lambda: np.zeros(0))


def select_degrees(
    params: list[Param], g: F64, b: F64, yy: float, n: int, cols: NDArray[np.intp]
) -> NDArray[np.intp]:
    """Choose each component's degree by BIC, coordinate-wise until stable.

    Parameters
    ----------
    params : list of Param
        All parameters (indexed like ``g``).
    g, b, yy : normal equations (weighted)
    n : int
        Number of readings.
    cols : ndarray of int
        Candidate columns, free of confounding.

    Returns
    -------
    ndarray of int
        The selected columns.
    """
    by_comp: dict[str, list[int]] = {}
    for c in cols:
        by_comp.setdefault(params[c].component, []).append(int(c))
    for js in by_comp.values():
        js.sort(key=lambda j: params[j].degree)
    # polynomial components can lose their top coefficients; locations and offsets stay
    comps = [c for c, js in by_comp.items() if params[js[0]].degree >= 0]
    level = {c: len(by_comp[c]) for c in comps}

    def chosen() -> NDArray[np.intp]:
        out: list[int] = []
        for c, js in by_comp.items():
            out += js[: level[c]] if c in level else js
        return np.array(sorted(out), dtype=np.intp)

    def bic(sel: NDArray[np.intp]) -> float:
        return _bic(_rss(g, b, yy, sel), sel.size, n)

    best = bic(chosen())
    for _sweep in range(4):
        changed = False
        for c in comps:
            current = level[c]
            for cand in range(len(by_comp[c]) + 1):
                if cand == current:
                    continue
                level[c] = cand
                score = bic(chosen())
                if score < best - 1e-9:
                    best, current, changed = score, cand, True
            level[c] = current
        if not changed:
            break
    return chosen()


def remove_confounded(
    params: list[Param], g: F64, cols: NDArray[np.intp]
) -> tuple[NDArray[np.intp], list[dict[str, Any]]]:
    """Drop parameters the readings cannot separate, and say with what they are confounded.

    The null space of the unit-diagonal normal matrix names the confounded groups; from
    each, the parameter least like a physical property is fixed at zero: a polynomial
    coefficient of high degree before a low one, a component before a location error.
    """
    cols = cols.copy()
    report: list[dict[str, Any]] = []
    for _ in range(len(cols)):
        v = _null_direction(g, cols)
        if v is None:
            break
        v = np.abs(v)
        involved = [int(j) for j in np.flatnonzero(v > 0.2 * v.max())]
        ranked = [(_drop_priority(params[int(cols[j])]), j) for j in involved]
        drop = max(ranked)[1]
        report.append({
            "parameter": params[cols[drop]].name,
            "confounded_with": [params[cols[j]].name for j in involved if j != drop],
        })
        cols = np.delete(cols, drop)
    return cols, report


def _solve_normal(g: F64, b: F64, cols: NDArray[np.intp]) -> F64:
    gs = g[np.ix_(cols, cols)]
    d = np.sqrt(np.diag(gs))
    d[d == 0] = 1.0
    xs = np.linalg.solve(gs / np.outer(d, d), b[cols] / d)
    out: F64 = xs / d
    return out


def _drop_priority(p: Param) -> tuple[int, int]:
    # offsets last, then location errors, then polynomial coefficients by degree
    kind = 0 if p.component == "OFFSET" else 1 if p.degree < 0 else 2
    return (kind, p.degree)


def fit(
    machine: Machine,
    m: Measurements,
    *,
    degrees: Mapping[str, int] | None = None,
    select: bool = True,
    fourier: bool | frozenset[str] = True,
) -> FitResult:
    """Identify the rigid model of a machine from readings.

    Parameters
    ----------
    machine : Machine
    m : Measurements
    degrees : mapping, optional
        Highest degree per component; chosen from the data when ``select``.
    select : bool
        Choose degrees by BIC (otherwise use the maxima).
    fourier : bool or frozenset of str
        Components of rotary axes of long travel in the Fourier basis of the angle
        (:mod:`volumetric.identify.design`): all, none (polynomials for every axis) or
        those named.

    Returns
    -------
    FitResult

    Raises
    ------
    FitError
        No readings, readings that observe nothing, or fewer readings than parameters.
    """
    if len(m) == 0:
        raise FitError("no readings")
    try:
        design = build_design(machine, m, degrees=degrees, fourier=fourier)
    except ValueError as exc:
        raise FitError(str(exc)) from None
    y = m.value
    norms = np.sqrt(np.sum(design.matrix**2, axis=0))
    observed = np.flatnonzero(norms > 1e-9 * max(float(norms.max(initial=0.0)), 1e-300))
    comps_all = {p.component for p in design.params if p.component != "OFFSET"}
    comps_seen = {design.params[i].component for i in observed}
    not_measured = sorted(comps_all - comps_seen)
    if observed.size == 0:
        raise FitError("the readings observe none of the model's parameters")
    groups = [g for g in (~m.is_angle, m.is_angle) if g.any()]
    normal = Normal.build(design.matrix, y, groups)
    weights = [1.0] * len(groups)  # 1/σ² per group: 1 µm and 1 µrad to start with
    g, b, yy = normal.combined(weights)
    cols, report = remove_confounded(design.params, g, observed)
    for _round in range(2):
        if select:
            cols = select_degrees(design.params, g, b, yy, len(y), cols)
        if len(y) <= cols.size:
            raise FitError(
                f"{len(y)} readings cannot identify {cols.size} parameters: measure more"
            )
        x = _solve_normal(g, b, cols)
        r = y - design.matrix[:, cols] @ x
        weights = [1.0 / max(float(np.mean(r[grp] ** 2)), 1e-12) for grp in groups]
        g, b, yy = normal.combined(weights)
    w = np.zeros(len(y))
    for grp, wt in zip(groups, weights, strict=True):
        w[grp] = wt
    sol = solve(design.matrix[:, cols], y, w)
    params = [design.params[i] for i in cols]
    model = model_from_parameters(machine, params, sol.values)
    deg: dict[str, int] = {}
    for p in params:
        if p.degree >= 0:
            deg[p.component] = max(deg.get(p.component, 0), p.degree)
    rms = {}
    for label, mask in (("displacement_um", ~m.is_angle), ("angle_urad", m.is_angle)):
        if mask.any():
            rms[label] = float(np.sqrt(np.mean(sol.residual[mask] ** 2)))
    info = {
        "n_readings": len(m),
        "degrees": deg,
        "parameters": [
            {"name": p.name, "value": float(v), "std": float(s), "unit": p.unit}
            for p, v, s in zip(params, sol.values, sol.std, strict=True)
        ],
        "unidentifiable": report,
        "not_measured": not_measured,
        "rms": rms,
        # the readings' zero: a prediction applies it (volumetric.diagnose.predict)
        "offsets_um": {p.name: float(v) for p, v in zip(params, sol.values, strict=True)
                       if p.component == "OFFSET"},
    }
    model = MachineModel(model.machine, model.geometry, (), info)
    return FitResult(model, params, sol.values, sol.std, deg, report, not_measured,
                     sol.residual, rms, w)


def model_from_parameters(machine: Machine, params: list[Param], values: F64) -> MachineModel:
    """The rigid model of identified parameters (Legendre coefficients, locations)."""
    coeffs: dict[str, dict[int, float]] = {}
    basis: dict[str, str] = {}
    locations: dict[str, float] = {}
    for p, v in zip(params, values, strict=True):
        if p.component == "OFFSET":
            continue
        if p.degree < 0:
            locations[p.component] = float(v)
        else:
            coeffs.setdefault(p.component, {})[p.degree] = float(v)
            basis[p.component] = p.basis
    comps: dict[str, Component] = {}
    for name, c in coeffs.items():
        axis = machine.axis(name[2:])
        comps[name] = (component_fourier(c) if basis[name] == "fourier"
                       else component_polynomial(axis, c))
    return MachineModel(machine.name, GeometricErrors(comps, locations))
