"""The ``tables`` map kind: per-axis 1-D tables of the component errors, evaluated by the
machine.

Instead of corrections on a D-dimensional grid (whose size grows as (1/tolerance)^(D/2)),
the machine receives what the controllers of the trade evaluate themselves (Siemens CEC/VCS,
Heidenhain KinematicsComp, ISO 230-1 tables): its chain, per axis the 1-D tables of the six
component errors over the travel, the location constants, the thermal terms of the model,
the solver weights and the reversal values. Its endpoint interpolates the tables at the
current coordinates, evaluates the tool-tip error through the chain and solves the
corrections (protocol/README.md §6 says how, for PLC programmers).

Table spacing. A table interpolated linearly over spacing ``h`` errs by about
``h² |f''| / 8``; each table gets the fewest uniform nodes that keep its interpolation error
(measured on 2,049 points along the axis) under a budget: ``b`` µm for a displacement
error, ``b / L`` µrad for an angular one, ``L`` (m) the longest lever the machine can give
an angle (workspace diagonal plus tool and pivot offsets), so that every table moves the
tool tip by at most about ``b``. A component that is constant is a single value; an
absent one is not sent. The budget starts at the tolerance and shrinks while the check
below finds the tool-tip error over the tolerance.

Check. The corrections the machine will compute (the solver on the tables as sent, float32
values, thermal terms at the given temperatures) are compared with the exact weighted
compensation of the model at 8,192 random points over the whole travel, rotary axes
included, that took no part in choosing the spacing; the error is the tool-tip
displacement ``J_b Δdq`` worst over the tool tips (:class:`~volumetric.compensate.maps.MapProblem`).

Backlash: the positive-approach error of a lagging linear axis is its mean error minus
``B/2``; that constant is folded into the axis's positioning table, and the reversal
(negative minus positive approach correction, ``-B``) travels per axis as for grids.

Units: positions mm or degrees, table values µm or µrad, corrections mm or degrees.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.compensate.maps import (
    DEFAULT_LIMIT_DEG,
    DEFAULT_LIMIT_MM,
    STEP_TOL,
    Controller,
    MapBuildError,
    MapProblem,
    MapReport,
    check_parameters,
    geometry_of,
    reversal_of,
    shrink,
)
from volumetric.compensate.solver import CompensationError, Weights, corrections
from volumetric.model.components import (
    Component,
    GeometricErrors,
    Polynomial,
    Table,
    add_components,
    component_names,
    is_angular,
)
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
_DENSE = 2049  # points per axis on which a table's interpolation error is measured
_MAX_ROUNDS = 12
_MAX_TABLE_NODES = 4096


@dataclass(frozen=True, eq=False)
class ComponentSamples:
    """One component error of one axis as a uniform table.

    Attributes
    ----------
    name : str
        ISO 230-1 name (``"EXX"``, ``"EBC"``).
    start, step : float
        Position of ``values[0]`` and the spacing, mm or degrees (step 0 for a constant).
    values : ndarray, shape (n,)
        µm or µrad, float32-representable (as sent); linear interpolation, the end values
        hold outside.
    """

    name: str
    start: float
    step: float
    values: F64

    def component(self) -> Component:
        """The table as a component function (what the machine interpolates)."""
        if self.values.size == 1:
            return Polynomial((float(self.values[0]),))
        positions = self.start + self.step * np.arange(self.values.size)
        return Table(tuple(float(p) for p in positions), tuple(float(v) for v in self.values))


@dataclass(frozen=True, eq=False)
class TablesMap:
    """A machine's compensation as component tables its endpoint evaluates.

    Attributes
    ----------
    machine : Machine
        The chain the endpoint evaluates (axes, pivots, tool branches).
    version : int
    controller : {"fanuc", "siemens"}
    tables : tuple of ComponentSamples
    locations : mapping of str to float
        Location errors, µm or µrad.
    thermal : tuple of ThermalTerm
        The model's thermal terms, applied by the endpoint with its latest temperatures.
    reversal : tuple of float or None
        Per axis (``machine.axes`` order), negative minus positive approach correction.
    weights : Weights
    tool_mm : mapping of str to float
        Tool length per branch, mm.
    limits : tuple of float
        Per axis, the largest |correction|, mm or degrees.
    valid_s : int
    temperatures : mapping of str to float
        The temperatures the build was checked at, °C.
    report : MapReport or None
    increment_mm : float or None
        None: the endpoint takes its corrections in mm (float32 encoding); else it writes
        whole counts of this increment (int32 encoding: a PLC that only writes counts,
        such as the Structured Text program of ``plc/``), reversals in whole counts.
    """

    machine: Machine
    version: int
    controller: Controller
    tables: tuple[ComponentSamples, ...]
    locations: Mapping[str, float]
    thermal: tuple[ThermalTerm, ...]
    reversal: tuple[float | None, ...]
    weights: Weights
    tool_mm: Mapping[str, float]
    limits: tuple[float, ...]
    valid_s: int = 0
    temperatures: Mapping[str, float] = field(default_factory=dict)
    report: MapReport | None = None
    increment_mm: float | None = None

    @property
    def outputs(self) -> tuple[str, ...]:
        return self.machine.axis_names

    @property
    def entries(self) -> int:
        """Table values sent, all tables together."""
        return sum(t.values.size for t in self.tables)

    @property
    def sensors(self) -> tuple[str, ...]:
        return tuple(sorted({t.sensor for t in self.thermal}))

    def geometry(self, temperatures: Mapping[str, float] | None = None) -> GeometricErrors:
        """The component errors the endpoint evaluates at ``temperatures`` (°C per sensor;
        a sensor without a value contributes nothing: its term is at its reference)."""
        temps = dict(temperatures or {})
        comps: dict[str, Component] = {t.name: t.component() for t in self.tables}
        for term in self.thermal:
            if term.sensor in temps:
                name = f"E{term.axis.upper()}{term.axis.upper()}"
                comps[name] = add_components(comps.get(name), term.component(temps[term.sensor]))
        return GeometricErrors(comps, dict(self.locations))

    def corrections(self, q: ArrayLike,
                    temperatures: Mapping[str, float] | None = None) -> F64:
        """Positive-approach corrections the endpoint applies at ``q``, (N, n_axes), mm or
        degrees, clamped to the limits (float64: the center's reference evaluation)."""
        dq = corrections(self.machine, self.geometry(temperatures), q, weights=self.weights,
                         tool_mm=self.tool_mm, step_tol=STEP_TOL)
        lim = np.asarray(self.limits)
        out: F64 = np.clip(dq, -lim, lim)
        return out


def _lever_m(machine: Machine, tool_mm: Mapping[str, float]) -> float:
    """The longest arm an angular error can act on, m: workspace diagonal plus the largest
    tool and pivot offsets."""
    spans = [a.travel[1] - a.travel[0] for a in machine.axes if a.kind == "linear"]
    diag = math.sqrt(sum(s * s for s in spans))
    tool = max((abs(v) for v in tool_mm.values()), default=0.0)
    pivot = max((math.hypot(*a.pivot_mm) for a in machine.axes if a.kind == "rotary"),
                default=0.0)
    return max(1e-3 * (diag + tool + pivot), 1e-3)


def _f32(v: F64) -> F64:
    out: F64 = v.astype(np.float32).astype(np.float64)
    return out


def _sample(name: str, f: Component, lo: float, hi: float, budget: float,
            dense: F64, dense_values: F64) -> ComponentSamples | None:
    """The fewest uniform nodes whose linear interpolation of ``f`` stays within ``budget``
    on ``dense`` (float32 rounding of the values included)."""
    if not np.any(dense_values):
        return None
    spread = float(dense_values.max() - dense_values.min())
    if spread <= budget or hi <= lo:
        mid = 0.5 * (float(dense_values.max()) + float(dense_values.min()))
        return ComponentSamples(name, lo, 0.0, _f32(np.array([mid])))
    n = 2
    while True:
        nodes = np.linspace(lo, hi, n)
        values = _f32(np.asarray(f(nodes), dtype=float))
        err = float(np.abs(np.interp(dense, nodes, values) - dense_values).max())
        if err <= budget:
            return ComponentSamples(name, lo, (hi - lo) / (n - 1), values)
        if n >= _MAX_TABLE_NODES:
            raise MapBuildError(f"component {name}: {_MAX_TABLE_NODES} table entries do not "
                                f"reach {budget:.3g} (µm or µrad); ask for a larger tolerance")
        # interpolation error ∝ h²: jump to the spacing the measured error predicts
        want = (n - 1) * math.sqrt(err / budget) * 1.05
        n = min(_MAX_TABLE_NODES, max(n + 1, math.ceil(want) + 1))


def build_tables_map(
    machine: Machine,
    model: MachineModel,
    temperatures: Mapping[str, float] | None = None,
    *,
    tolerance_um: float = 0.5,
    controller: Controller | None = None,
    limit_mm: float = DEFAULT_LIMIT_MM,
    limit_deg: float = DEFAULT_LIMIT_DEG,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    version: int = 1,
    valid_s: int = 0,
    check_points: int = 8192,
    seed: int = 0,
) -> TablesMap:
    """The ``tables`` map of a machine.

    Parameters
    ----------
    machine : Machine
    model : MachineModel
        Its thermal terms travel with the map; every other term is folded into the tables.
    temperatures : mapping of str to float, optional
        °C per sensor, at which the map is checked (each sensor's reference by default).
    tolerance_um : float
        Largest tool-tip error allowed, µm, as the machine computes it (float32 tables).
    controller : {"fanuc", "siemens"}, optional
        The machine's own by default; the endpoint writes float32 (Siemens) corrections.
    limit_mm, limit_deg : float
        Clamp of the corrections, mm and degrees.
    weights : Weights, optional
    tool_mm : mapping of str to float, optional
        Tool length per branch, mm; each branch's default otherwise.
    version, valid_s : int
    check_points : int
        Random points of the independent check (whole travel, rotary axes included).
    seed : int

    Returns
    -------
    TablesMap
        With its :class:`MapReport` (``kind="tables"``, ``nodes`` = table entries; ``bytes``
        is filled in by the encoder).

    Raises
    ------
    MapBuildError
        Bad parameters, backlash on a rotary axis (not expressible as a table constant), or
        a tolerance the tables cannot reach.
    """
    t0 = time.perf_counter()
    ctrl = check_parameters(machine, model, tolerance_um, controller, 0.001, limit_mm,
                            limit_deg, check_points)
    thermal = tuple(t for t in model.terms if isinstance(t, ThermalTerm))
    static = MachineModel(model.machine, model.geometry,
                          tuple(t for t in model.terms if not isinstance(t, ThermalTerm)),
                          model.info)
    temps = {t.sensor: t.t_ref_C for t in thermal} | dict(temperatures or {})
    # terms the tables cannot carry (a lagged thermal model) fold in at the temperatures given
    geometry = geometry_of(static, dict(temperatures or {}))
    geometry.check(machine)
    full = geometry_of(model, temps)  # the exact model the map is judged against
    reversal = reversal_of(machine, model, None)
    backlash = {k.lower(): v for k, v in model.reversal_um().items() if v}
    for a in machine.axes:
        if a.key in backlash and a.kind == "rotary":
            raise MapBuildError(f"axis {a.name}: backlash of a rotary axis is not expressible "
                                "in the tables kind")
    w = Weights.default(machine) if weights is None else weights
    tools = {b.name: (tool_mm or {}).get(b.name, b.tool_length_mm) for b in machine.branches}
    lever = _lever_m(machine, tools)
    limits = tuple(limit_deg if a.kind == "rotary" else limit_mm for a in machine.axes)

    # the dense samples do not depend on the budget: evaluate them once
    dense: dict[str, tuple[float, float, F64, F64, Component]] = {}
    for a in machine.axes:
        lo, hi = float(a.travel[0]), float(a.travel[1])
        x = np.linspace(lo, hi, _DENSE)
        for name in component_names(a):
            f = geometry.components.get(name)
            if f is None:
                continue
            v = np.asarray(f(x), dtype=float)
            if name == f"E{a.name}{a.name}" and a.key in backlash:
                v = v - 0.5 * backlash[a.key]  # positive approach: the tool lags by B/2
            dense[name] = (lo, hi, x, v, f)

    prob = MapProblem(machine, full, w, tools, machine.travel_lo, machine.travel_hi)
    rng = np.random.default_rng([seed, 2])
    check_q = prob.lo + (prob.hi - prob.lo) * rng.random((check_points, len(machine.axes)))
    t_check = time.perf_counter()
    exact = prob.exact(check_q)
    check_exact_s = time.perf_counter() - t_check
    locations = {k: float(np.float32(v)) for k, v in geometry.locations.items()}
    # the tables' errors add up at the tool tip with mixed signs: start each at the
    # root-sum-square share, so that the first check usually passes
    varying = sum(1 for (_, _, _, v, _) in dense.values() if np.ptp(v) > 0)
    budget = tolerance_um / math.sqrt(max(varying, 1))
    check_s = check_exact_s
    rounds = 0
    while True:
        rounds += 1
        tables = []
        for name, (lo, hi, x, v, f) in dense.items():
            b = budget / lever if is_angular(name) else budget  # µrad · m = µm
            fb = _shifted(f, v, x, name, machine, backlash)
            s = _sample(name, fb, lo, hi, b, x, v)
            if s is not None:
                tables.append(s)
        tmap = TablesMap(machine, version, ctrl, tuple(tables), locations, thermal, reversal,
                         w, tools, limits, valid_s, temps)
        t_check = time.perf_counter()
        try:
            got = tmap.corrections(check_q, temps)
        except CompensationError as exc:
            raise MapBuildError(str(exc)) from None
        check_s += time.perf_counter() - t_check
        # the positive-approach shift is not an error (judged on the direction-free part)
        shift = np.array([0.5 * backlash.get(a.key, 0.0) * 1e-3 for a in machine.axes])
        worst = float(prob.tip_um(check_q, got - shift - np.clip(exact, -np.asarray(limits),
                                                                np.asarray(limits))).max())
        if worst <= tolerance_um:
            break
        if rounds == _MAX_ROUNDS:
            raise MapBuildError(f"machine {machine.name!r}: no tables met {tolerance_um} µm "
                                f"after {_MAX_ROUNDS} rounds (worst {worst:.3g} µm)")
        budget *= shrink(tolerance_um, worst)
    report = MapReport(
        nodes=tmap.entries, bytes=0, tolerance_um=tolerance_um,
        worst_interpolation_um=worst, worst_error_um=worst, check_points=check_points,
        clamped_nodes=int(np.any(np.abs(exact) > np.asarray(limits), axis=1).sum()),
        rounds=rounds, build_s=time.perf_counter() - t0, kind="tables", check_s=check_s,
    )
    return TablesMap(machine, version, ctrl, tmap.tables, locations, thermal, reversal, w,
                     tools, limits, valid_s, temps, report)


def _shifted(f: Component, v: F64, x: F64, name: str, machine: Machine,
             backlash: Mapping[str, float]) -> Component:
    """``f`` with the positive-approach backlash constant of its axis folded in."""
    for a in machine.axes:
        if name == f"E{a.name}{a.name}" and a.key in backlash:
            return add_components(f, Polynomial((-0.5 * backlash[a.key],)))
    return f


__all__ = ["ComponentSamples", "TablesMap", "build_tables_map"]
