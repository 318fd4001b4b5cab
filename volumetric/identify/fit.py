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
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.design import (
    Param,
    branch_rows,
    build_design,
    component_fourier,
    component_polynomial,
    design_params,
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


@dataclass
class Normal:
    """Normal equations of a weighted problem, accumulated block by block per weight group.

    Weights are constant within a group (0: displacements, 1: angles), so the normal
    matrix for any group weights is a weighted sum of per-group matrices formed once:
    degree selection, null-space analysis and re-weighting then never touch the (N, P)
    design, and the design itself is never whole in memory (one block of rows at a time).

    Attributes
    ----------
    g : ndarray, shape (2, P, P)
        ``A_g^T A_g`` per group (units of the readings squared per parameter unit squared).
    b : ndarray, shape (2, P)
        ``A_g^T y_g`` per group.
    yy : ndarray, shape (2,)
        ``y_g^T y_g`` per group (µm², µrad²).
    n : ndarray of int, shape (2,)
        Readings per group.
    """

    g: F64
    b: F64
    yy: F64
    n: NDArray[np.int64]

    @staticmethod
    def empty(p: int) -> Normal:
        return Normal(np.zeros((2, p, p)), np.zeros((2, p)), np.zeros(2),
                      np.zeros(2, dtype=np.int64))

    def add(self, a: F64, y: F64, is_angle: NDArray[np.bool_]) -> None:
        """Add a block of design rows ``a`` (n, P) with their readings ``y`` (n,)."""
        for k, mask in enumerate((~is_angle, is_angle)):
            count = int(mask.sum())
            if count == 0:
                continue
            ag = a if count == a.shape[0] else a[mask]
            yg = y if count == a.shape[0] else y[mask]
            self.g[k] += ag.T @ ag
            self.b[k] += ag.T @ yg
            self.yy[k] += float(yg @ yg)
            self.n[k] += count

    @property
    def groups(self) -> list[int]:
        """The groups that have readings."""
        return [k for k in range(2) if self.n[k] > 0]

    def restricted(self, cols: NDArray[np.intp]) -> Normal:
        """The same sums for a subset of the parameters."""
        return Normal(self.g[:, cols][:, :, cols], self.b[:, cols], self.yy.copy(),
                      self.n.copy())

    def combined(self, weights: list[float]) -> tuple[F64, F64, float]:
        """``(G, b, y^T W y)`` for the given weight of each group of :attr:`groups`."""
        g = np.zeros_like(self.g[0])
        b = np.zeros_like(self.b[0])
        yy = 0.0
        for k, w in zip(self.groups, weights, strict=True):
            g += w * self.g[k]
            b += w * self.b[k]
            yy += w * float(self.yy[k])
        return g, b, yy

    def rss(self, k: int, cols: NDArray[np.intp], x: F64) -> float:
        """Unweighted residual sum of squares of group ``k`` at parameters ``x`` on
        ``cols``: ``y^T y - 2 x^T A^T y + x^T A^T A x``, never below zero."""
        g = self.g[k][np.ix_(cols, cols)]
        return max(float(self.yy[k] - 2.0 * x @ self.b[k][cols] + x @ g @ x), 0.0)


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
    residual : ndarray, shape (N,), or None
        Reading minus prediction (µm or µrad); None from :func:`fit_blocks`, which does
        not keep the readings.
    rms : dict of str to float
        Residual RMS of displacements (µm) and angles (µrad).
    weights : ndarray, shape (N,)
        The final weight (1/σ² of its group) of every reading; empty from
        :func:`fit_blocks`.
    group_weights : dict of str to float
        The final weight of each group that has readings: ``displacement`` (1/µm²),
        ``angle`` (1/µrad²).
    """

    model: MachineModel
    params: list[Param]
    values: F64
    std: F64
    degrees: dict[str, int]
    unidentifiable: list[dict[str, Any]]
    not_measured: list[str]
    residual: F64 | None
    rms: dict[str, float]
    weights: F64 = field(repr=False, default_factory=lambda: np.zeros(0))
    group_weights: dict[str, float] = field(default_factory=dict)


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


BLOCK_ROWS = 20_000
"""Readings per block of design rows: about 16 MB of design for a 3-axis model's ~100
parameters, large enough for the matrix products to run at full speed."""


def fit(
    machine: Machine,
    m: Measurements,
    *,
    degrees: Mapping[str, int] | None = None,
    select: bool = True,
    fourier: bool | frozenset[str] = True,
) -> FitResult:
    """Identify the rigid model of a machine from readings.

    The design is built and reduced to normal equations ``BLOCK_ROWS`` readings at a
    time (:func:`fit_blocks`); the residual of every reading is then formed in a second
    pass over the blocks.

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
    # one block: its design is kept for the residuals; more: built again block by block
    kept: list[F64] | None = [] if len(m) <= BLOCK_ROWS else None
    result = fit_blocks(machine, _blocks(m), degrees=degrees, select=select,
                        fourier=fourier, keep=kept)
    residual = np.empty(len(m))
    if kept:
        layout = {p.name: j for j, p in
                  enumerate(design_params(machine, degrees=degrees, fourier=fourier))}
        cols = np.array([layout[p.name] for p in result.params], dtype=np.intp)
        residual[:] = m.value - kept[0][:, cols] @ result.values
    else:
        for start, block in zip(range(0, len(m), BLOCK_ROWS), _blocks(m), strict=True):
            a = build_design(machine, block, degrees=degrees, fourier=fourier,
                             params=result.params).matrix
            residual[start : start + len(block)] = block.value - a @ result.values
    w = np.where(m.is_angle, result.group_weights.get("angle", 1.0),
                 result.group_weights.get("displacement", 1.0))
    return replace(result, residual=residual, weights=w)


def _blocks(m: Measurements) -> Iterator[Measurements]:
    if len(m) <= BLOCK_ROWS:
        yield m  # no copy
        return
    for start in range(0, len(m), BLOCK_ROWS):
        yield m.select(np.arange(start, min(start + BLOCK_ROWS, len(m))))


def fit_blocks(
    machine: Machine,
    blocks: Iterable[Measurements],
    *,
    degrees: Mapping[str, int] | None = None,
    select: bool = True,
    fourier: bool | frozenset[str] = True,
    keep: list[F64] | None = None,
) -> FitResult:
    """Identify the rigid model from readings that arrive block by block.

    Each block's design rows are reduced at once to per-group normal equations
    (:class:`Normal`), so memory holds one block and the (P, P) sums whatever the number
    of readings; the blocks are read once. Every step of the fit works on the sums
    (module docstring), and the residual statistics come from them too
    (:meth:`Normal.rss`): the result has no per-reading residual.

    Parameters
    ----------
    machine : Machine
    blocks : iterable of Measurements
        The readings, in any number of blocks (for example
        :func:`volumetric.measure.measurement.read_measurement_blocks`).
    degrees, select, fourier
        As for :func:`fit`.
    keep : list, optional
        Each block's design, with every column of :func:`design_params`, is appended here
        (for a caller that keeps the readings anyway and wants their residuals).

    Returns
    -------
    FitResult
        With ``residual`` None and ``weights`` empty.

    Raises
    ------
    FitError
        As :func:`fit`; a block that names an unknown spindle.
    """
    layout = design_params(machine, degrees=degrees, fourier=fourier)
    normal = Normal.empty(len(layout))
    present: set[str] = set()
    for block in blocks:
        if len(block) == 0:
            continue
        try:
            rows = branch_rows(machine, block)
            design = build_design(machine, block, degrees=degrees, fourier=fourier,
                                  params=layout)
        except ValueError as exc:
            raise FitError(str(exc)) from None
        present.update(b for b, r in rows.items() if r.size)
        normal.add(design.matrix, block.value, block.is_angle)
        if keep is not None:
            keep.append(design.matrix)
    n = int(normal.n.sum())
    if n == 0:
        raise FitError("no readings")
    # the columns of the branches that have readings, in the order a design of exactly
    # these readings has (what the degree selection's tie-breaks see)
    branches = [b.name for b in machine.branches if b.name in present]
    params = design_params(machine, degrees=degrees, fourier=fourier, branches=branches)
    where = {p.name: i for i, p in enumerate(layout)}
    normal = normal.restricted(np.array([where[p.name] for p in params], dtype=np.intp))
    return _identify(machine, params, normal, select)


def _identify(machine: Machine, all_params: list[Param], normal: Normal, select: bool
              ) -> FitResult:
    """Steps 1-5 of the module docstring on accumulated normal equations."""
    n = int(normal.n.sum())
    norms = np.sqrt(np.clip(np.diag(normal.g[0] + normal.g[1]), 0.0, None))
    observed = np.flatnonzero(norms > 1e-9 * max(float(norms.max(initial=0.0)), 1e-300))
    comps_all = {p.component for p in all_params if p.component != "OFFSET"}
    comps_seen = {all_params[i].component for i in observed}
    not_measured = sorted(comps_all - comps_seen)
    if observed.size == 0:
        raise FitError("the readings observe none of the model's parameters")
    groups = normal.groups
    weights = [1.0] * len(groups)  # 1/σ² per group: 1 µm and 1 µrad to start with
    g, b, yy = normal.combined(weights)
    cols, report = remove_confounded(all_params, g, observed)
    for _round in range(2):
        if select:
            cols = select_degrees(all_params, g, b, yy, n, cols)
        if n <= cols.size:
            raise FitError(f"{n} readings cannot identify {cols.size} parameters: measure more")
        x = _solve_normal(g, b, cols)
        weights = [1.0 / max(normal.rss(k, cols, x) / int(normal.n[k]), 1e-12)
                   for k in groups]
        g, b, yy = normal.combined(weights)
    values, std = _solve_with_std(normal, weights, cols, n)
    params = [all_params[i] for i in cols]
    model = model_from_parameters(machine, params, values)
    deg: dict[str, int] = {}
    for p in params:
        if p.degree >= 0:
            deg[p.component] = max(deg.get(p.component, 0), p.degree)
    labels = ("displacement_um", "angle_urad")
    rms = {labels[k]: math.sqrt(normal.rss(k, cols, values) / int(normal.n[k]))
           for k in groups}
    info = {
        "n_readings": n,
        "degrees": deg,
        "parameters": [
            {"name": p.name, "value": float(v), "std": float(s), "unit": p.unit}
            for p, v, s in zip(params, values, std, strict=True)
        ],
        "unidentifiable": report,
        "not_measured": not_measured,
        "rms": rms,
        # the readings' zero: a prediction applies it (volumetric.diagnose.predict)
        "offsets_um": {p.name: float(v) for p, v in zip(params, values, strict=True)
                       if p.component == "OFFSET"},
    }
    model = MachineModel(model.machine, model.geometry, (), info)
    group_weights = {("displacement", "angle")[k]: w for k, w in zip(groups, weights,
                                                                    strict=True)}
    return FitResult(model, params, values, std, deg, report, not_measured, None, rms,
                     np.zeros(0), group_weights)



def _solve_with_std(normal: Normal, weights: list[float], cols: NDArray[np.intp], n: int
                    ) -> tuple[F64, F64]:
    """Parameters on ``cols`` and their standard uncertainties (covariance scaled by the
    residual variance of unit weight, ``Σ w_k rss_k / (n - p)``), from the sums.

    Raises
    ------
    FitError
        When the columns are linearly dependent (callers remove such columns first).
    """
    g, b, _ = normal.combined(weights)
    gs = g[np.ix_(cols, cols)]
    d = np.sqrt(np.diag(gs))
    d[d == 0] = 1.0
    try:
        chol = np.linalg.cholesky(gs / np.outer(d, d))
    except np.linalg.LinAlgError:
        raise FitError("the parameters are linearly dependent (remove confounded ones)") from None
    xs = np.linalg.solve(chol.T, np.linalg.solve(chol, b[cols] / d))
    x: F64 = xs / d
    rss = sum(w * normal.rss(k, cols, x) for k, w in zip(normal.groups, weights, strict=True))
    sigma2 = rss / max(n - cols.size, 1)
    inv = np.linalg.inv(chol)
    std: F64 = np.sqrt(np.clip(np.einsum("ij,ij->j", inv, inv), 0, None) * sigma2) / d
    return x, std


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
