"""What every map kind shares: its errors, its report, the problem a build evaluates, and the
checks of a build's inputs. Maps are content here (numbers in mm, degrees, µm); how they
travel on the wire is the server's business (:mod:`server.mapcodec`), so the numeric core
never imports :mod:`protocol`.

Map kinds (:mod:`volumetric.compensate.gridmap`, :mod:`volumetric.compensate.tablesmap`):

* ``grid``: corrections on a regular grid of the workspace, looked up multilinearly;
* ``tables``: per-axis 1-D tables of the component errors plus the location constants and
  the chain; the machine's endpoint evaluates the tool-tip error and solves the corrections.

Both are judged alike: the tool-tip displacement ``J_b Δdq`` of the difference between the
corrections a machine applies and the exact weighted compensation, worst over the tool tips
and over random check points that took no part in building the map.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.solver import CompensationError, Weights, corrections
from volumetric.model.components import GeometricErrors
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]
Controller = Literal["fanuc", "siemens"]
MapKind = Literal["grid", "tables", "factored"]
KINDS: tuple[MapKind, ...] = ("grid", "tables", "factored")
DEFAULT_INCREMENT = 0.001
"""Fanuc's least input increment (IS-B): 0.001 mm, or 0.001° on a rotary axis."""
DEFAULT_LIMIT_MM = 0.5
DEFAULT_LIMIT_DEG = 0.05
MAX_MAP_BYTES = 16 * 1024 * 1024
"""The largest map a machine stores; equal to the protocol's limit (a test pins the two)."""
STEP_TOL = 1e-5
"""Refinement stop of the corrections solver for map values, mm or degrees. The step after
one of size s is about s·|de/dq| (the errors' slope, 1e-4 to 1e-3), so stopping at 1e-5
leaves ~0.01 nm: two steps instead of three for the same map."""


class MapBuildError(ValueError):
    """A map that cannot be built as asked (bad parameters, tolerance out of reach)."""


class MapTooLargeError(MapBuildError):
    """The tolerance asked for needs more nodes than the controller's map memory holds."""


@dataclass(frozen=True)
class MapReport:
    """How a map came out of :func:`build_map`.

    Attributes
    ----------
    nodes, bytes : int
        Grid nodes and the length of the encoded payload.
    tolerance_um : float
        The interpolation tolerance asked for.
    worst_interpolation_um : float
        Worst tool-tip error of the unquantised map against the exact compensation on an
        independent check set (random points and cell centres), µm.
    worst_error_um : float
        The same for the map as sent (quantised and clamped), µm.
    check_points : int
        Size of that check set.
    clamped_nodes : int
        Nodes where at least one correction was clamped to the limit.
    rounds : int
        Refinement rounds (full-grid checks) taken.
    build_s : float
        Wall time, s.
    kind : {"grid", "tables"}
        The map kind; ``nodes`` counts grid nodes or table entries.
    check_s : float
        Of ``build_s``, the wall time spent on the independent check (tables kind), s.
    """

    nodes: int
    bytes: int
    tolerance_um: float
    worst_interpolation_um: float
    worst_error_um: float
    check_points: int
    clamped_nodes: int
    rounds: int
    build_s: float
    kind: MapKind = "grid"
    check_s: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind, "nodes": self.nodes, "bytes": self.bytes,
            "tolerance_um": self.tolerance_um,
            "worst_interpolation_um": self.worst_interpolation_um,
            "worst_error_um": self.worst_error_um, "check_points": self.check_points,
            "clamped_nodes": self.clamped_nodes, "rounds": self.rounds,
            "build_s": self.build_s, "check_s": self.check_s,
        }


@dataclass
class MapProblem:
    """What the build evaluates: the exact compensation and the tool-tip metric."""

    machine: Machine
    geometry: GeometricErrors
    weights: Weights
    tool_mm: Mapping[str, float] | None
    lo: F64
    hi: F64

    def exact(self, q: F64) -> F64:
        try:
            return corrections(self.machine, self.geometry, q, weights=self.weights,
                               tool_mm=self.tool_mm, step_tol=STEP_TOL)
        except CompensationError as exc:
            raise MapBuildError(str(exc)) from None

    def tip_um(self, q: F64, ddq: F64) -> F64:
        """Largest tool-tip displacement over the branches caused by ``ddq``, µm, (N,)."""
        constant = not any(a.kind == "rotary" for a in self.machine.axes)
        worst = np.zeros(q.shape[0])
        for br in self.machine.branches:
            tool = None if self.tool_mm is None else self.tool_mm.get(br.name)
            j = jacobian(self.machine, q[:1] if constant else q, spindle=br.name,
                         tool_mm=tool)[:, :3]
            d = np.einsum("nij,nj->ni", j, ddq)
            worst = np.maximum(worst, np.linalg.norm(d, axis=1))
        return worst


def shrink(tolerance_um: float, worst_um: float) -> float:
    """Budget factor after a check found ``worst_um`` > tolerance: aim 5 % under the
    tolerance (interpolation error ∝ spacing², so error and budget scale alike), but move
    by 5 % at least and by half at most."""
    return max(0.5, min(0.95, 0.95 * tolerance_um / worst_um))


def check_parameters(machine: Machine, model: MachineModel, tolerance_um: float,
                      controller: str | None, increment: float, limit_mm: float,
                      limit_deg: float, check_points: int) -> Controller:
    if model.machine and model.machine != machine.name:
        raise MapBuildError(f"the model is for machine {model.machine!r}, the description "
                            f"is of {machine.name!r}")
    if not (math.isfinite(tolerance_um) and tolerance_um > 0):
        raise MapBuildError(f"tolerance must be a positive number of µm, got {tolerance_um}")
    ctrl = (controller or machine.controller).lower()
    if ctrl not in ("fanuc", "siemens"):
        raise MapBuildError(f"controller must be 'fanuc' or 'siemens', got {ctrl!r}")
    if not (math.isfinite(increment) and 0 < increment <= 1):
        raise MapBuildError(f"increment must be in (0, 1] mm, got {increment}")
    for name, v in (("limit_mm", limit_mm), ("limit_deg", limit_deg)):
        if not (math.isfinite(v) and v > 0):
            raise MapBuildError(f"{name} must be positive, got {v}")
    if check_points < 16:
        raise MapBuildError(f"check_points must be at least 16, got {check_points}")
    return "fanuc" if ctrl == "fanuc" else "siemens"


def geometry_of(model: MachineModel, temperatures: Mapping[str, float] | None) -> GeometricErrors:
    temps = dict(temperatures or {})
    for k, v in temps.items():
        if not isinstance(v, int | float) or not math.isfinite(v):
            raise MapBuildError(f"temperature {k} = {v!r} is not a finite number of °C")
    for i, term in enumerate(model.terms):
        for f in fields(term):
            name, value = f.name, getattr(term, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                kind = getattr(term, "kind", type(term).__name__)
                raise MapBuildError(f"model term {i} ({kind}, axis {term.axis}): {name} = "
                                    f"{value} is not finite")
    try:
        return model.geometry_at(temps)
    except ValueError as exc:
        raise MapBuildError(str(exc)) from None


def reversal_of(machine: Machine, model: MachineModel,
              inc: float | None) -> tuple[float | None, ...]:
    rev = {k.lower(): v for k, v in model.reversal_um().items()}
    keys = {a.key for a in machine.axes}
    unknown = sorted(set(rev) - keys)
    if unknown:
        raise MapBuildError(f"the model has backlash for axes {unknown}; machine "
                            f"{machine.name!r} has {sorted(keys)}")
    out: list[float | None] = []
    for a in machine.axes:
        r = rev.get(a.key)
        if r is None:
            out.append(None)
            continue
        if not math.isfinite(r) or r < 0:
            raise MapBuildError(f"backlash of axis {a.key} is {r} µm; expected >= 0")
        mm = -r * 1e-3  # negative minus positive approach correction of a lagging axis
        # what the wire carries: whole counts (Fanuc) or a float32 (Siemens)
        out.append(float(np.rint(mm / inc) * inc) if inc is not None else
                   float(np.float32(mm)))
    return tuple(out)


__all__ = [
    "DEFAULT_INCREMENT",
    "DEFAULT_LIMIT_DEG",
    "DEFAULT_LIMIT_MM",
    "KINDS",
    "MAX_MAP_BYTES",
    "Controller",
    "MapBuildError",
    "MapKind",
    "MapProblem",
    "MapReport",
    "MapTooLargeError",
    "check_parameters",
    "geometry_of",
    "reversal_of",
    "shrink",
]
