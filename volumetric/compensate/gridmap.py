"""Error maps: the compensation over a regular grid of the workspace, for a PLC to look up.

A PLC loop reads the machine's coordinates, interpolates the map multilinearly at them and
applies the result as a shift of every axis (Fanuc's external machine zero point shift,
Siemens' SD43900). :func:`build_map` samples the exact weighted compensation of
:mod:`volumetric.compensate.solver` on a grid whose spacing it chooses per axis: the fewest nodes
that keep the interpolation error under a stated tolerance.

The interpolation error is measured where it matters, at the tool tips: the difference
between the interpolated and the exact correction, ``Δdq``, moves tool tip ``b`` by
``J_b Δdq`` (:func:`volumetric.model.linear.jacobian`, position rows), and the error of a map at a
point is the largest ``|J_b Δdq|`` over the tool tips, in µm. For a 3-axis machine that is
simply ``|Δdq|`` in µm; for rotary axes it weighs a degree by its lever arm.

Grid choice (greedy refinement). Multilinear interpolation of a smooth function errs by
about the sum over axes of the 1-D errors ``h_i² |∂²f/∂q_i²| / 8``. The 1-D error of each
axis is measured on random lines through the workspace along that axis, at its current
node count (1 node: the axis is not a grid dimension at all, the correction is taken at
mid-travel). Starting from one node per axis, the axis whose refinement buys the largest
predicted error reduction per relative growth of the map is refined, until the
root-sum-square of the 1-D errors is below a budget, at first the tolerance. (The sum would
bound the error but overshoots: the axes' contributions rarely peak at one point with one
sign. On the benchmark machines the root-sum-square gives maps 2 to 3 times smaller that
still pass the checks.) The full grid is then checked at random points and cell centres;
if the worst error exceeds the tolerance, the budget shrinks by the overshoot and
refinement goes on. The reported error comes from a separate random check set that took no
part in any decision (if that set finds an overshoot, it joins the decision set and a fresh
one is drawn).

Quantisation and limits come last: values are clamped to ±limit, then rounded to whole
increments (Fanuc) or to float32 (Siemens). The report gives the worst error both before
and after that step; Fanuc's rounding adds up to half an increment per axis.

Thermal terms in the map (``thermal_in_map=True``, for controllers that apply them: a
Fanuc PMC ladder by multiply-add, protocol/README.md §6.4). The grid is then built from the
model without its :class:`~volumetric.model.model.ThermalTerm` s (at their reference
temperatures), and the terms travel with the map: the machine adds, per term and cycle,
``-ΔE`` to the correction of the term's own axis (a positioning error of an axis is
cancelled by that axis moving back along its own line of motion, exactly, whatever the
chain). The check judges the map as the machine applies it at the given temperatures
(each sensor's reference when not given), against the exact model with its terms, so the
reported worst error stays honest. A temperature change then needs no new map.

Units: grid positions and values in mm (linear axes) or degrees (rotary axes).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.gridvalues import (
    ErrorMap,
    GridDim,
    _multilinear,
    payload_bytes,
    thermal_correction,
)
from volumetric.compensate.maps import (
    DEFAULT_INCREMENT,
    DEFAULT_LIMIT_DEG,
    DEFAULT_LIMIT_MM,
    MAX_MAP_BYTES,
    Controller,
    MapBuildError,
    MapProblem,
    MapReport,
    MapTooLargeError,
    check_parameters,
    geometry_of,
    reversal_of,
    shrink,
)
from volumetric.compensate.solver import Weights
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
_MAX_ROUNDS = 40


# --- building ---

def _interval_count(c: int) -> int:
    """The next node count of an axis: 1 → 2 → 3 → ... growing by about a quarter."""
    if c == 1:
        return 2
    m = c - 1
    return c + max(1, math.ceil(m / 4))


class _Lines:
    """Random lines along each axis, on which the axis's 1-D interpolation error is
    measured (see module docstring)."""

    def __init__(self, prob: MapProblem, rng: np.random.Generator, n_lines: int) -> None:
        self.prob = prob
        self.rng = rng
        n = len(prob.lo)
        self.base = [prob.lo + (prob.hi - prob.lo) * rng.random((n_lines, n)) for _ in range(n)]

    def error(self, axis: int, count: int) -> float:
        prob = self.prob
        lo, hi = prob.lo[axis], prob.hi[axis]
        if count == 1:
            nodes = np.array([0.5 * (lo + hi)])
            tests = np.linspace(lo, hi, 9)
        else:
            nodes = np.linspace(lo, hi, count)
            h = nodes[1] - nodes[0]
            starts = nodes[:-1]
            tests = np.concatenate([starts + 0.5 * h,
                                    starts + h * self.rng.uniform(0.1, 0.9, count - 1)])
        base = self.base[axis]
        s, nn, nt = base.shape[0], nodes.size, tests.size
        q = np.repeat(base, nn + nt, axis=0)
        q[:, axis] = np.tile(np.concatenate([nodes, tests]), s)
        dq = prob.exact(q).reshape(s, nn + nt, -1)
        at_nodes, at_tests = dq[:, :nn], dq[:, nn:]
        if count == 1:
            interp = np.broadcast_to(at_nodes[:, :1], at_tests.shape)
        else:
            u = (tests - lo) / (nodes[1] - nodes[0])
            i = np.clip(np.floor(u), 0, count - 2).astype(np.intp)
            f = (u - i)[None, :, None]
            interp = at_nodes[:, i] * (1 - f) + at_nodes[:, i + 1] * f
        qt = q.reshape(s, nn + nt, -1)[:, nn:].reshape(s * nt, -1)
        ddq = (interp - at_tests).reshape(s * nt, -1)
        return float(prob.tip_um(qt, ddq).max())


def _grid_for(prob: MapProblem, names: Sequence[str], counts: Sequence[int],
              increment: float | None = None) -> list[GridDim]:
    """The grid of ``counts`` nodes per axis over the travel; with an ``increment`` (an
    int32 map) start and step are whole counts (the ladder's integer index, protocol/README.md
    §6.1), the step rounded up so that the grid still covers the travel."""
    dims = []
    for i, c in enumerate(counts):
        if c >= 2:
            lo, hi = float(prob.lo[i]), float(prob.hi[i])
            if increment is None:
                dims.append(GridDim(names[i], lo, (hi - lo) / (c - 1), c))
                continue
            per_unit = round(1.0 / increment)
            lo_c = math.floor(lo * per_unit + 1e-9)
            step_c = max(1, math.ceil((hi * per_unit - lo_c) / (c - 1) - 1e-9))
            dims.append(GridDim(names[i], lo_c / per_unit, step_c / per_unit, c))
    return dims


def _node_positions(prob: MapProblem, names: Sequence[str], grid: Sequence[GridDim]) -> F64:
    mid = 0.5 * (prob.lo + prob.hi)
    mesh = np.meshgrid(*[g.nodes() for g in grid], indexing="ij")
    q = np.tile(mid, (mesh[0].size, 1))
    for g, m in zip(grid, mesh, strict=True):
        q[:, list(names).index(g.name)] = m.ravel()
    return q


def _cell_centres(prob: MapProblem, names: Sequence[str], grid: Sequence[GridDim],
                  rng: np.random.Generator, n: int) -> F64:
    q = prob.lo + (prob.hi - prob.lo) * rng.random((n, len(names)))
    for g in grid:
        cell = rng.integers(0, g.count - 1, n)
        q[:, list(names).index(g.name)] = g.start + (cell + 0.5) * g.step
    return q


def _map_error(prob: MapProblem, names: Sequence[str], grid: Sequence[GridDim], values: F64,
               q: F64, exact: F64) -> F64:
    cols = [list(names).index(g.name) for g in grid]
    return prob.tip_um(q, _multilinear(grid, values, q[:, cols]) - exact)


def build_map(
    machine: Machine,
    model: MachineModel,
    temperatures: Mapping[str, float] | None = None,
    *,
    tolerance_um: float = 0.5,
    controller: Controller | None = None,
    increment: float = DEFAULT_INCREMENT,
    limit_mm: float = DEFAULT_LIMIT_MM,
    limit_deg: float = DEFAULT_LIMIT_DEG,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    version: int = 1,
    valid_s: int = 0,
    check_points: int = 4096,
    seed: int = 0,
    max_bytes: int = MAX_MAP_BYTES,
    thermal_in_map: bool = False,
) -> ErrorMap:
    """The error map of a machine at given temperatures.

    Parameters
    ----------
    machine : Machine
    model : MachineModel
        What ``ednc fit`` wrote; its geometry is taken at ``temperatures``.
    temperatures : mapping of str to float, optional
        °C per sensor column (``"T_x_C"``); every sensor the model uses must be there.
    tolerance_um : float
        Largest tool-tip interpolation error allowed, µm (see module docstring).
    controller : {"fanuc", "siemens"}, optional
        The machine's own by default. Fanuc: whole multiples of ``increment``; Siemens:
        float32 mm.
    increment : float
        Fanuc least input increment, mm (or degrees on rotary axes) per count.
    limit_mm, limit_deg : float
        Corrections are clamped to ±limit (linear, rotary axes); the report counts the
        nodes where that happened.
    weights : Weights, optional
        Solver weights, :meth:`Weights.default` when omitted.
    tool_mm : mapping of spindle name to float, optional
        Tool lengths, mm; each branch's default otherwise.
    version, valid_s : int
        Carried into the payload.
    check_points : int
        Size of the random check sets (the independent one is twice as large).
    seed : int
        Seed of the random check points and lines: builds are reproducible.
    max_bytes : int
        Largest payload allowed (the protocol's limit by default).
    thermal_in_map : bool
        Carry the model's thermal terms for the controller to apply (module docstring):
        the grid is built at their reference temperatures, the check applies them at
        ``temperatures`` (a sensor not given: at its reference).

    Returns
    -------
    ErrorMap
        With :class:`MapReport` in ``report``.

    Raises
    ------
    MapBuildError
        Bad parameters, a temperature missing or not finite, or a tolerance that needs a
        map larger than ``max_bytes``.
    ComponentErrorSpecError
        A model that does not fit the machine (unknown axis, non-finite value).
    """
    t0 = time.perf_counter()
    ctrl = check_parameters(machine, model, tolerance_um, controller, increment, limit_mm,
                             limit_deg, check_points)
    names = machine.axis_names
    thermal = tuple(t for t in model.terms if isinstance(t, ThermalTerm)) if thermal_in_map \
        else ()
    static, temps = model, dict(temperatures or {})
    if thermal:
        for t in thermal:
            if t.axis.upper() not in names:
                raise MapBuildError(f"thermal term on axis {t.axis}: machine {machine.name!r} "
                                    f"has {' '.join(names)}")
        static = MachineModel(model.machine, model.geometry,
                              tuple(t for t in model.terms if not isinstance(t, ThermalTerm)),
                              model.info)
        temps = {t.sensor: t.t_ref_C for t in thermal} | temps
    geometry = geometry_of(static, temps)
    geometry.check(machine)
    w = Weights.default(machine) if weights is None else weights
    prob = MapProblem(machine, geometry, w, tool_mm, machine.travel_lo, machine.travel_hi)
    n_out = len(names)
    rng = np.random.default_rng(seed)
    lines = _Lines(prob, rng, n_lines=16)

    counts = [1] * len(names)
    errs = [lines.error(i, 1) for i in range(len(names))]
    budget = tolerance_um  # the full-grid checks below tighten it when needed
    check_q = prob.lo + (prob.hi - prob.lo) * rng.random((check_points, len(names)))
    check_exact = prob.exact(check_q)
    indep_rng = np.random.default_rng([seed, 1])
    rounds = 0
    while True:
        rounds += 1
        if rounds > _MAX_ROUNDS:
            raise MapBuildError(f"machine {machine.name!r}: no grid met {tolerance_um} µm "
                                f"after {_MAX_ROUNDS} rounds")
        while math.sqrt(sum(e * e for e in errs)) > budget:
            i = _best_axis(counts, errs)
            counts[i] = _interval_count(counts[i])
            nodes = math.prod(counts)
            if payload_bytes(len(names), n_out, nodes, len(thermal)) > max_bytes:
                raise MapTooLargeError(
                    f"machine {machine.name!r}: {tolerance_um} µm needs more than {nodes} "
                    f"nodes ({' x '.join(map(str, counts))}), over the {max_bytes}-byte map "
                    "limit; ask for a larger tolerance"
                )
            errs[i] = lines.error(i, counts[i])
        if all(c == 1 for c in counts):  # constant correction: one axis, two equal nodes
            counts[0] = 2
        grid = _grid_for(prob, names, counts, increment if ctrl == "fanuc" else None)
        values = prob.exact(_node_positions(prob, names, grid)).reshape(
            (*(g.count for g in grid), n_out))
        centres = _cell_centres(prob, names, grid, rng, check_points // 2)
        worst = max(float(_map_error(prob, names, grid, values, check_q, check_exact).max()),
                    float(_map_error(prob, names, grid, values, centres,
                                     prob.exact(centres)).max()))
        if worst > tolerance_um:
            budget *= shrink(tolerance_um, worst)
            continue
        # independent check: random points and cell centres that took no part above
        indep = np.vstack([
            prob.lo + (prob.hi - prob.lo) * indep_rng.random((check_points, len(names))),
            _cell_centres(prob, names, grid, indep_rng, check_points),
        ])
        indep_exact = prob.exact(indep)
        worst_indep = float(_map_error(prob, names, grid, values, indep, indep_exact).max())
        if worst_indep <= tolerance_um:
            break
        # the decision set missed something: learn from this set, draw a fresh one
        check_q = np.vstack([check_q, indep])
        check_exact = np.vstack([check_exact, indep_exact])
        budget *= shrink(tolerance_um, worst_indep)

    # Backlash: the tool lags half the reversal behind the motion (volumetric.model.model), so
    # the positive-approach correction the values carry is the mean one plus B/2, and the
    # negative approach differs by -B (protocol/README.md section 6: reversal = negative-
    # approach correction minus positive-approach correction).
    backlash_mm = np.array([model.reversal_um().get(a.key, 0.0) * 1e-3 for a in machine.axes])
    values = values + 0.5 * backlash_mm
    limits = np.array([limit_deg if a.kind == "rotary" else limit_mm for a in machine.axes])
    over = np.abs(values) > limits
    clamped_nodes = int(over.any(axis=-1).sum())
    sent = np.clip(values, -limits, limits)
    inc = increment if ctrl == "fanuc" else None
    sent = np.rint(sent / inc) * inc if inc is not None else sent.astype(np.float32).astype(float)
    # judged on the direction-free part: the positive-approach shift is not an error
    if thermal:
        worst_sent = _thermal_error(prob, model, names, grid, sent, thermal, temps, inc,
                                    indep)
    else:
        worst_sent = float(_map_error(prob, names, grid, sent - 0.5 * backlash_mm, indep,
                                      indep_exact).max())
    reversal = reversal_of(machine, model, inc)
    report = MapReport(
        nodes=math.prod(g.count for g in grid),
        bytes=payload_bytes(len(grid), n_out, math.prod(g.count for g in grid), len(thermal)),
        tolerance_um=tolerance_um, worst_interpolation_um=worst_indep,
        worst_error_um=worst_sent, check_points=indep.shape[0],
        clamped_nodes=clamped_nodes, rounds=rounds, build_s=time.perf_counter() - t0,
    )
    return ErrorMap(
        machine=machine.name, version=version, controller=ctrl, grid=tuple(grid),
        outputs=names, values=sent, increment=inc, limits=tuple(float(v) for v in limits),
        reversal=reversal, temperatures=temps, valid_s=valid_s,
        report=report, thermal=thermal,
    )


def _thermal_error(prob: MapProblem, model: MachineModel, names: Sequence[str],
                   grid: Sequence[GridDim], sent: F64, thermal: Sequence[ThermalTerm],
                   temps: Mapping[str, float], inc: float | None, q: F64) -> float:
    """Worst tool-tip error (µm) at ``q`` of a map with thermal terms as the controller
    applies it at ``temps`` (interpolated values plus the terms' corrections, rounded
    together to increments), against the exact model with its thermal terms there."""
    backlash_mm = np.array([model.reversal_um().get(a.key, 0.0) * 1e-3
                            for a in prob.machine.axes])
    full = MapProblem(prob.machine, geometry_of(model, temps), prob.weights, prob.tool_mm,
                      prob.lo, prob.hi)
    cols = [list(names).index(g.name) for g in grid]
    applied = _multilinear(grid, sent, q[:, cols]) + thermal_correction(names, thermal, q,
                                                                         temps)
    if inc is not None:  # the ladder rounds the sum to whole increments
        applied = np.rint(applied / inc) * inc
    return float(full.tip_um(q, applied - 0.5 * backlash_mm - full.exact(q)).max())


def build_map_within(
    machine: Machine,
    model: MachineModel,
    temperatures: Mapping[str, float] | None = None,
    *,
    tolerance_um: float = 0.5,
    max_tolerance_um: float = 4.0,
    **options: Any,
) -> ErrorMap:
    """:func:`build_map` at the tightest tolerance that fits the map memory.

    Starts at ``tolerance_um`` and doubles it while the map would be too large (a
    five-axis map over five dimensions can be), up to ``max_tolerance_um``; the report of
    the returned map states the tolerance it met.

    Raises
    ------
    MapTooLargeError
        Even ``max_tolerance_um`` does not fit.
    """
    tol = tolerance_um
    while True:
        try:
            return build_map(machine, model, temperatures, tolerance_um=tol, **options)
        except MapTooLargeError:
            if tol * 2 > max_tolerance_um:
                raise
            tol *= 2


def _best_axis(counts: Sequence[int], errs: Sequence[float]) -> int:
    """The axis whose next refinement buys the largest predicted error reduction per
    relative growth of the map (linear interpolation: error ∝ spacing²)."""
    best, best_gain = 0, -1.0
    for i, (c, e) in enumerate(zip(counts, errs, strict=True)):
        nxt = _interval_count(c)
        predicted = 0.25 * e if c == 1 else e * ((c - 1) / (nxt - 1)) ** 2
        gain = (e - predicted) / math.log(nxt / c)
        if gain > best_gain:
            best, best_gain = i, gain
    return best


__all__ = [
    "DEFAULT_INCREMENT",
    "DEFAULT_LIMIT_DEG",
    "DEFAULT_LIMIT_MM",
    "ErrorMap",
    "GridDim",
    "MapBuildError",
    "MapReport",
    "MapTooLargeError",
    "build_map",
    "build_map_within",
    "payload_bytes",
    "thermal_correction",
]
