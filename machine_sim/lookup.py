"""Error-map lookup as a PLC does it, for both map kinds.

A ``grid`` map (format version 1) is looked up by multilinear interpolation on a regular
grid, below; a grid of format version 3 also carries thermal records, which
:class:`GridMap` applies at the latest temperatures (:meth:`GridMap.set_temperatures`):
each adds ``-ΔE`` (protocol/README.md §6.4) to its axis's correction, a constant per
output and, for an expansion, a slope times that axis's position; so the positions a
lookup takes are :attr:`GridMap.inputs`, the grid axes then any record axis outside the
grid. A ``tables`` map (format version 2) is evaluated through the machine's chain
by :mod:`machine_sim.chaineval`; :class:`TablesMap` wraps it with the same face as
:class:`GridMap` (``lookup``, ``outputs``, ``reversal``), and :func:`active_map` builds
whichever a payload calls for.

A map (``protocol.mapformat``) holds K output values at every node of a regular grid of
D dimensions (``start + i·step``, ``i = 0 .. count-1``), row-major with the output axis
fastest, then the last grid dimension. At a position q the lookup interpolates
multilinearly between the 2^D surrounding nodes; outside the grid it holds the edge value
(each coordinate is clamped to the grid), as a pitch-error table does at the end of
travel.

:class:`GridMap` is one decoded map, values in mm (degrees for rotary outputs).
:class:`FleetLookup` packs the maps of many machines into one flat array so one vectorised
call serves a whole fleet's PLC scan (:mod:`benchmarks.fleet_scan` measures it); both use
the same :func:`interpolate`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from protocol.codes import MapEncoding
from protocol.mapfactored import FactoredPayload, thermal_fixed
from protocol.mapformat import THERMAL_DRIFT, ErrorMapPayload, ThermalRecord
from protocol.maptables import TablesPayload

from . import ladder
from .chaineval import ChainBatch, sensor_key
from .ladder_point import FactoredPoint, Wide

__all__ = ["ActiveMap", "FactoredLadder", "FleetLadder", "FleetLookup", "GridLadder", "GridMap",
           "TablesMap", "active_map", "interpolate", "positions_in_counts", "readings_mC"]

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]


def interpolate(values: F64, base: I64, start: F64, step: F64, count: I64, strides: I64,
                q: F64) -> F64:
    """Multilinear interpolation of M points, each on its own grid in one flat table.

    Parameters
    ----------
    values : ndarray, shape (T, K)
        Node values of every grid, one row per node, grids one after the other.
    base : ndarray of int, shape (M,)
        Row of each point's grid's first node.
    start, step : ndarray, shape (M, D)
        Grid origin and spacing per point (mm or degrees).
    count, strides : ndarray of int, shape (M, D)
        Nodes per dimension (>= 2) and the row stride of each dimension.
    q : ndarray, shape (M, D)
        Positions, same units as ``start``.

    Returns
    -------
    ndarray, shape (M, K)
        Interpolated values; coordinates outside a grid are clamped to its edge.
    """
    u = np.clip((q - start) / step, 0.0, count - 1)
    i0 = np.minimum(u.astype(np.int64), count - 2)  # u >= 0, so truncation is floor
    f = u - i0
    m, d = q.shape
    # weights and row offsets of the 2^D corners, built one dimension at a time:
    # corner bit j set = the upper node along dimension j
    w = np.ones((m, 1))
    off = np.zeros((m, 1), dtype=np.int64)
    for j in range(d):
        fj, sj = f[:, j:j + 1], strides[:, j:j + 1]
        w = np.concatenate((w * (1.0 - fj), w * fj), axis=1)
        off = np.concatenate((off, off + sj), axis=1)
    row = (base + np.einsum("md,md->m", i0, strides))[:, None] + off
    out: F64 = np.einsum("mc,mck->mk", w, values[row])
    return out


def _strides(count: Sequence[int]) -> I64:
    s = np.ones(len(count), dtype=np.int64)
    for j in range(len(count) - 2, -1, -1):
        s[j] = s[j + 1] * count[j + 1]
    return s


@dataclass(frozen=True, eq=False)
class GridMap:
    """A decoded error map, values in mm (degrees for rotary outputs).

    Attributes
    ----------
    machine : str
    version, valid_s : int
    grid : tuple of str
        Grid dimension names (machine axis names, upper case), D of them.
    start, step : ndarray, shape (D,)
    count : ndarray of int, shape (D,)
    outputs : tuple of str
        Corrected axes (upper case), K of them.
    values : ndarray, shape (N_nodes, K)
        Node values, row-major over the grid.
    reversal : ndarray, shape (K,)
        Per output, the negative-approach minus the positive-approach correction, mm; 0
        where the map gives none.
    thermal : tuple of ThermalRecord
        The map's thermal records (format version 3), applied by :meth:`lookup` at the
        temperatures of the last :meth:`set_temperatures`.
    inputs : tuple of str
        The axes whose positions :meth:`lookup` takes: ``grid``, then the axes of thermal
        expansion records that are not grid axes.
    """

    machine: str
    version: int
    valid_s: int
    grid: tuple[str, ...]
    start: F64
    step: F64
    count: I64
    outputs: tuple[str, ...]
    values: F64
    reversal: F64
    thermal: tuple[ThermalRecord, ...] = ()
    inputs: tuple[str, ...] = ()
    thermal_mm: F64 = field(default_factory=lambda: np.zeros((2, 0)), repr=False)
    """(2, K): per output, the thermal correction's constant (mm) and its slope (mm per mm
    of the output's position), at the last temperatures; updated in place."""
    slope_cols: I64 = field(init=False, repr=False)
    """(K,): the column of ``inputs`` holding each output's position, -1 where none is
    needed (no expansion record on it)."""

    def __post_init__(self) -> None:
        if not self.inputs:  # frozen: set once, here
            extra = [r.axis.upper() for r in self.thermal
                     if r.kind != THERMAL_DRIFT and r.axis.upper() not in self.grid]
            object.__setattr__(self, "inputs", (*self.grid, *dict.fromkeys(extra)))
        if self.thermal_mm.shape != (2, len(self.outputs)):
            object.__setattr__(self, "thermal_mm", np.zeros((2, len(self.outputs))))
        cols = [self.inputs.index(o) if o in self.inputs else -1 for o in self.outputs]
        object.__setattr__(self, "slope_cols", np.array(cols, dtype=np.int64))

    @staticmethod
    def from_payload(p: ErrorMapPayload,
                     temperatures: Mapping[str, float] | None = None) -> GridMap:
        """Convert a payload (int32 counts times its increment, or float32 mm) to mm, its
        thermal records at ``temperatures`` (°C by sensor label or ``T_<label>_C``)."""
        raw = np.frombuffer(p.values, dtype=p.dtype).reshape(-1, len(p.outputs))
        int32 = p.encoding is MapEncoding.INT32_INCREMENTS
        scale = p.increment_mm if int32 else 1.0
        rev = np.array([0.0 if o.reversal is None else o.reversal * scale for o in p.outputs])
        g = GridMap(
            machine=p.machine, version=p.version, valid_s=p.valid_s,
            grid=tuple(g.name.upper() for g in p.grid),
            start=np.array([g.start for g in p.grid]), step=np.array([g.step for g in p.grid]),
            count=np.array([g.count for g in p.grid], dtype=np.int64),
            outputs=tuple(o.name.upper() for o in p.outputs),
            values=raw.astype(np.float64) * scale, reversal=rev, thermal=p.thermal,
        )
        if temperatures:
            g.set_temperatures(temperatures)
        return g

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """The latest temperatures, °C by sensor label (``spindle`` or ``T_spindle_C``),
        folded into the thermal records' constants and slopes: what a ladder computes
        once per new temperature, so that the scan only multiplies and adds. A sensor
        without a value counts as at its reference."""
        temps = {sensor_key(k): float(v) for k, v in temperatures.items()}
        self.thermal_mm[:] = 0.0
        for rec in self.thermal:
            t = temps.get(sensor_key(rec.sensor))
            if t is None or not np.isfinite(t):
                continue
            k = self.outputs.index(rec.axis.upper())
            dt = t - rec.t_ref_C
            if rec.kind == THERMAL_DRIFT:  # -ΔE = -k·ΔT µm
                self.thermal_mm[0, k] -= rec.coefficient * dt * 1e-3
            else:  # -ΔE = -k·ΔT·(q - q_min)·1e-3 µm, q in mm
                slope = rec.coefficient * dt * 1e-6
                self.thermal_mm[0, k] += slope * rec.q_min
                self.thermal_mm[1, k] -= slope

    @property
    def strides(self) -> I64:
        return _strides(self.count.tolist())

    def node_values(self) -> F64:
        """Values shaped (count_1, ..., count_D, K)."""
        return self.values.reshape((*self.count.tolist(), len(self.outputs)))

    def lookup(self, q: F64) -> F64:
        """Interpolated values plus the thermal records' corrections at positions q, shape
        (N, len(inputs)) in :attr:`inputs` order → (N, K), mm."""
        qa = np.atleast_2d(np.asarray(q, dtype=float))
        if qa.shape[1] != len(self.inputs):
            raise ValueError(f"map of grid {self.grid} needs positions of axes "
                             f"{' '.join(self.inputs)}: shape (N, {len(self.inputs)}), got "
                             f"{qa.shape}")
        n, d = qa.shape[0], len(self.grid)
        qg = qa[:, :d]
        out = interpolate(self.values, np.zeros(n, dtype=np.int64),
                          np.broadcast_to(self.start, qg.shape),
                          np.broadcast_to(self.step, qg.shape),
                          np.broadcast_to(self.count, qg.shape),
                          np.broadcast_to(self.strides, qg.shape), qg)
        if self.thermal:  # the ladder's multiply-add, per output
            cols = self.slope_cols
            pos = np.where(cols >= 0, qa[:, np.maximum(cols, 0)], 0.0)
            out += self.thermal_mm[0] + self.thermal_mm[1] * pos
        return out


@dataclass(eq=False)
class TablesMap:
    """A decoded tables map, evaluated through the chain every lookup.

    Attributes
    ----------
    machine : str
    version, valid_s : int
    grid : tuple of str
        The chain axes (upper case): the columns of the positions ``lookup`` takes (the
        name matches :class:`GridMap`, whose looked-up axes are its grid); ``inputs`` is
        the same.
    outputs : tuple of str
        Corrected axes.
    reversal : ndarray, shape (K,)
        Per output, negative- minus positive-approach correction, mm (degrees).
    batch : ChainBatch
        The evaluation (one machine).
    """

    machine: str
    version: int
    valid_s: int
    grid: tuple[str, ...]
    outputs: tuple[str, ...]
    reversal: F64
    batch: ChainBatch
    payload: TablesPayload = field(repr=False)

    @staticmethod
    def from_payload(p: TablesPayload,
                     temperatures: Mapping[str, float] | None = None) -> TablesMap:
        """Build the evaluation of ``p`` with its thermal records at ``temperatures``."""
        batch = ChainBatch([p])
        if temperatures:
            batch.set_temperatures(0, temperatures)
        scale = p.increment_mm if p.encoding is MapEncoding.INT32_INCREMENTS else 1.0
        rev = np.array([0.0 if o.reversal is None else o.reversal * scale for o in p.outputs])
        return TablesMap(p.machine, p.version, p.valid_s, batch.axes, batch.outputs, rev,
                         batch, p)

    @property
    def inputs(self) -> tuple[str, ...]:
        """The axes whose positions :meth:`lookup` takes (the chain axes)."""
        return self.grid

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """The latest temperatures, °C by sensor label, for the thermal records."""
        self.batch.set_temperatures(0, temperatures)

    def lookup(self, q: F64) -> F64:
        """Applied corrections for a positive approach at positions q, shape (N, A) in
        ``grid`` order → (N, K), mm or degrees: solved, clamped and rounded to the
        encoding."""
        qa = np.atleast_2d(np.asarray(q, dtype=float))
        return self.batch.applied(None, qa)

    def lookup_directed(self, q: F64, negative: NDArray[np.bool_]) -> F64:
        """Applied corrections at positions q (N, A) with the outputs ``negative`` (N, K)
        approaching negatively: rounded, the reversal added, then clamped (§6.3 step 6)."""
        qa = np.atleast_2d(np.asarray(q, dtype=float))
        return self.batch.applied(None, qa, np.where(negative, -1, 1))

    def corrections(self, q: F64) -> F64:
        """The solver's corrections (N, K) before clamping and rounding, mm or degrees."""
        return self.batch.corrections(None, np.atleast_2d(np.asarray(q, dtype=float)))


def positions_in_counts(q: F64, counts_per_unit: int) -> I64:
    """Positions (mm or degrees) as the PMC's position registers hold them: counts,
    ``floor(q · P + 0.5)`` in double precision (protocol/README.md §6.1)."""
    return np.floor(np.asarray(q, dtype=np.float64) * counts_per_unit + 0.5).astype(np.int64)


def readings_mC(temperatures: Mapping[str, float]) -> dict[str, int]:
    """Temperatures (°C) by the name the Temperatures message carries, in m°C rounded
    half up (exactly, from the double): what the ladder's thermal records match, by exact
    name. The machine's own store keys a sensor by its column (``T_spindle_C``): that is
    the store's spelling of ``spindle``, undone here."""
    out: dict[str, int] = {}
    for key, celsius in temperatures.items():
        c = float(celsius)
        if not np.isfinite(c):
            continue
        name = key[2:-2] if len(key) > 4 and key.startswith("T_") and key.endswith("_C") \
            else key
        out[name] = (Fraction(c) * 1000 + Fraction(1, 2)).__floor__()
    return out


def _thermal_view(c0: I64, c1: I64, per_unit: int) -> F64:
    """The ladder's thermal constants (2^-16 counts, 2^-32 counts per count) as mm and mm
    per mm, (2, K)."""
    return np.vstack([c0 / 65536.0 / per_unit, c1 / 4294967296.0])


def _whole(x: Fraction, per_unit: int, what: str) -> int:
    """``x · per_unit``, which must be a whole number (within 1e-6 of one, the f64's
    rounding of a decimal), rounded half up."""
    v = x * per_unit
    n = (v + Fraction(1, 2)).__floor__()
    if abs(v - n) > Fraction(1, 1_000_000):
        raise ValueError(f"{what} is not a whole number of counts")
    return n


class FactoredLadder:
    """A factored map (format version 5) as the PMC ladder evaluates it: the integer
    arithmetic of :mod:`machine_sim.ladder` (protocol/README.md §6.5), the tables decoded
    once at load. Positions in mm (degrees) are rounded to counts first, as the PMC's
    position registers hold them; temperatures are folded (in m°C) into a constant and a
    slope per axis when they change.
    """

    def __init__(self, p: FactoredPayload,
                 temperatures: Mapping[str, float] | None = None) -> None:
        self.payload = p
        self.machine, self.version, self.valid_s = p.machine, p.version, p.valid_s
        self.program = ladder.factored_program(p)
        self.grid = self.program.axes
        self.outputs = self.grid
        self.per_unit = p.counts_per_unit
        self.inc = p.increment_mm
        self.reversal = self.program.reversal.astype(np.float64) * self.inc
        d = len(self.grid)
        self._point: FactoredPoint | None = None
        self.c0 = np.zeros(d, dtype=np.int64)
        self.c1 = np.zeros(d, dtype=np.int64)
        self._consts: tuple[list[int], list[int]] = ([0] * d, [0] * d)
        """c0 and c1 as Python ints, for :attr:`point`."""
        self.thermal_mm = np.zeros((2, d))
        """(2, D) the thermal constant (mm) and slope (mm per mm) the ladder holds, in
        float for display and tests: ``c0 / 2^16`` counts and ``c1 / 2^32``."""
        if temperatures:
            self.set_temperatures(temperatures)

    @property
    def inputs(self) -> tuple[str, ...]:
        """The axes whose positions :meth:`lookup` takes: all of the map's, in order."""
        return self.grid

    @property
    def point(self) -> FactoredPoint:
        """The one-point evaluation of :attr:`program` (built at the first scan: a map
        the store only probes never needs it)."""
        if self._point is None:
            self._point = FactoredPoint(self.program)
        return self._point

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """Fold the latest temperatures (°C by sensor label) into constants and slopes."""
        self.c0, self.c1 = ladder.thermal_constants(self.program.thermal, len(self.grid),
                                                    readings_mC(temperatures))
        self._consts = (self.c0.tolist(), self.c1.tolist())
        self.thermal_mm = _thermal_view(self.c0, self.c1, self.per_unit)

    def _counts_in(self, q: F64) -> I64:
        qa = np.atleast_2d(np.asarray(q, dtype=float))
        if qa.shape[1] != len(self.grid):
            raise ValueError(f"factored map needs positions of axes {' '.join(self.grid)}: "
                             f"shape (N, {len(self.grid)}), got {qa.shape}")
        return positions_in_counts(qa, self.per_unit)

    def fields(self, q: F64) -> F64:
        """Every field at positions q (N, D) → (N, n_fields), mm (degrees) and counts per
        count, from the ladder's fixed-point accumulators."""
        acc = ladder.factored_fields(self.program, self._counts_in(q)).astype(np.float64)
        acc /= 65536.0
        acc[:, :len(self.grid)] *= self.inc
        return acc

    def counts(self, q: F64, negative: NDArray[np.bool_] | None = None) -> I64:
        """What the ladder writes, counts (N, D): for a positive approach, or with the
        reversal of the axes ``negative`` (N, D) added before the final clamp (§6.5
        step 6)."""
        return ladder.factored_counts(self.program, self._counts_in(q), self.c0, self.c1,
                                      negative)

    def counts_at(self, q: Sequence[float], negative: Sequence[bool] | None = None
                  ) -> list[int]:
        """:meth:`counts` at one point, q (D,) mm or degrees → (D,) counts, the same
        integers (a scan's case: Python ints, :class:`~machine_sim.ladder_point.FactoredPoint`;
        a point whose arithmetic leaves int64 goes through :meth:`counts`, which wraps)."""
        per = self.per_unit
        try:
            # floor(q · P + 0.5) in double precision, as positions_in_counts
            qc = [math.floor(v * per + 0.5) for v in q]
            if all(-(1 << 63) <= v < (1 << 63) for v in qc):
                return self.point.counts(qc, self._consts[0], self._consts[1], negative)
        except (Wide, ValueError, OverflowError):  # a wrap, NaN or infinity: the arrays'
            pass
        neg = None if negative is None else np.array([negative], dtype=bool)
        out: list[int] = self.counts(np.array([q], dtype=float), neg)[0].tolist()
        return out

    def lookup_directed_at(self, q: Sequence[float], negative: Sequence[bool]
                           ) -> list[float]:
        """:meth:`lookup_directed` at one point: q (D,) → (D,), mm or degrees."""
        inc = self.inc
        return [float(n) * inc for n in self.counts_at(q, negative)]

    def lookup_directed(self, q: F64, negative: NDArray[np.bool_]) -> F64:
        """Applied corrections at positions q (N, D) with the axes ``negative`` (N, D)
        approaching negatively, mm or degrees (whole increments)."""
        out: F64 = self.counts(q, negative).astype(np.float64) * self.inc
        return out

    def lookup(self, q: F64) -> F64:
        """Applied corrections for a positive approach at positions q (N, D) → (N, D),
        mm or degrees (whole increments)."""
        out: F64 = self.counts(q).astype(np.float64) * self.inc
        return out


@dataclass(frozen=True, eq=False)
class GridLadder(GridMap):
    """An int32 grid map (format version 1 or 3) as the Fanuc-style ladder evaluates it:
    :func:`machine_sim.ladder.grid_counts` (protocol/README.md §6.1, §6.4), integers
    only; :meth:`lookup` gives whole increments. :class:`GridMap`'s float values stay for
    the store's checks and the fleet benchmark."""

    program: ladder.GridProgram | None = field(default=None, repr=False)
    per_unit: int = 1000
    consts: list[I64] = field(default_factory=list, repr=False)

    @staticmethod
    def from_payload(p: ErrorMapPayload,
                     temperatures: Mapping[str, float] | None = None) -> GridLadder:
        """The ladder of an int32 grid payload (ValueError for float32 or a grid whose
        start or step is not whole counts)."""
        if p.encoding is not MapEncoding.INT32_INCREMENTS:
            raise ValueError("the integer ladder takes int32 grid maps only")
        g = GridMap.from_payload(p)
        # the loader's conversion of the f64 fields (protocol/README.md §6), once
        per_unit = _whole(1 / Fraction(p.increment_mm), 1, "the increment's reciprocal")
        prog = ladder.grid_program(
            p.values, [a.count for a in p.grid],
            [_whole(Fraction(a.start), per_unit, f"grid axis {a.name} start") for a in p.grid],
            [_whole(Fraction(a.step), per_unit, f"grid axis {a.name} step") for a in p.grid],
            g.outputs, [0 if o.reversal is None else int(o.reversal) for o in p.outputs],
            [thermal_fixed(r, g.outputs.index(r.axis.upper()), per_unit) for r in p.thermal],
            g.inputs)
        if min((int(v) for v in prog.step), default=1) < 1:
            raise ValueError("a grid step must be at least one count")
        k = len(g.outputs)
        out = GridLadder(
            machine=g.machine, version=g.version, valid_s=g.valid_s, grid=g.grid,
            start=g.start, step=g.step, count=g.count, outputs=g.outputs, values=g.values,
            reversal=g.reversal, thermal=g.thermal, inputs=g.inputs, program=prog,
            per_unit=per_unit,
            consts=[np.zeros(k, dtype=np.int64), np.zeros(k, dtype=np.int64)])
        if temperatures:
            out.set_temperatures(temperatures)
        return out

    def set_temperatures(self, temperatures: Mapping[str, float]) -> None:
        """The latest temperatures (°C by sensor label), folded in m°C into the ladder's
        constants and slopes (exact names)."""
        if self.program is None:
            return
        c0, c1 = ladder.thermal_constants(self.program.thermal, len(self.outputs),
                                          readings_mC(temperatures))
        # new objects, not in-place updates: a copy of the map keeps its temperatures
        object.__setattr__(self, "consts", [c0, c1])
        object.__setattr__(self, "thermal_mm", _thermal_view(c0, c1, self.per_unit))

    def counts(self, q: F64, negative: NDArray[np.bool_] | None = None) -> I64:
        """What the ladder writes, counts (N, K), at positions q (N, len(inputs)) mm or
        degrees: for a positive approach, or with the reversal of the outputs
        ``negative`` (N, K) added (before the controller's clamp, §6.1 step 3)."""
        assert self.program is not None
        qa = np.atleast_2d(np.asarray(q, dtype=float))
        if qa.shape[1] != len(self.inputs):
            raise ValueError(f"map of grid {self.grid} needs positions of axes "
                             f"{' '.join(self.inputs)}: shape (N, {len(self.inputs)}), got "
                             f"{qa.shape}")
        return ladder.grid_counts(self.program, positions_in_counts(qa, self.per_unit),
                                  self.consts[0], self.consts[1], negative)

    def lookup(self, q: F64) -> F64:
        """Applied corrections (whole increments), mm, (N, K)."""
        out: F64 = self.counts(q).astype(np.float64) / self.per_unit
        return out


ActiveMap = GridMap | TablesMap | FactoredLadder
"""The map a machine has in use, of any kind."""


def active_map(p: ErrorMapPayload | TablesPayload | FactoredPayload,
               temperatures: Mapping[str, float] | None = None) -> ActiveMap:
    """The evaluable form of a decoded payload of any kind."""
    if isinstance(p, TablesPayload):
        return TablesMap.from_payload(p, temperatures)
    if isinstance(p, FactoredPayload):
        return FactoredLadder(p, temperatures)
    return GridMap.from_payload(p, temperatures)


class FleetLookup:
    """The maps of many machines in one table, looked up all at once.

    All maps must have the same number of grid dimensions D and outputs K (their sizes,
    origins and spacings may differ). Row m of every call belongs to ``maps[m]``. Thermal
    records are not applied here (the interpolation alone, as measured by the fleet
    benchmark).
    """

    def __init__(self, maps: Sequence[GridMap]) -> None:
        if not maps:
            raise ValueError("FleetLookup needs at least one map")
        d, k = len(maps[0].grid), len(maps[0].outputs)
        for i, g in enumerate(maps):
            if len(g.grid) != d or len(g.outputs) != k:
                raise ValueError(f"map {i} ({g.machine}) has {len(g.grid)} grid dimensions "
                                 f"and {len(g.outputs)} outputs, map 0 has {d} and {k}")
        sizes = [g.values.shape[0] for g in maps]
        self.values = np.vstack([g.values for g in maps])
        self.base = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.start = np.vstack([g.start for g in maps])
        self.step = np.vstack([g.step for g in maps])
        self.count = np.vstack([g.count for g in maps])
        self.strides = np.vstack([g.strides for g in maps])

    def __len__(self) -> int:
        return int(self.base.shape[0])

    def lookup(self, q: F64) -> F64:
        """Values (M, K), mm, at one position per machine, q shape (M, D)."""
        if q.shape != self.start.shape:
            raise ValueError(f"positions must have shape {self.start.shape}, got {q.shape}")
        return interpolate(self.values, self.base, self.start, self.step, self.count,
                           self.strides, q)


class FleetLadder:
    """The Fanuc ladder of :mod:`machine_sim.fanuc` for a whole fleet in one call per scan.

    Quantises each machine's looked-up compensation to increments, clamps it to
    ``±limit_counts`` and moves each shift by at most ``max_step_counts`` per scan, like
    :meth:`machine_sim.fanuc.FanucPMC.scan` in ramp mode, for M machines at once.
    """

    def __init__(self, maps: Sequence[GridMap], *, increment_mm: float = 0.001,
                 limit_counts: int = 500, max_step_counts: int = 5) -> None:
        self.lookup = FleetLookup(maps)
        self.increment_mm = increment_mm
        self.limit_counts = limit_counts
        self.max_step_counts = max_step_counts
        self.shifts = np.zeros((len(maps), len(maps[0].outputs)), dtype=np.int64)

    def scan(self, q: F64) -> I64:
        """One scan: positions (M, D) in each map's grid order → shifts (M, K), counts."""
        # halves up, the tie rule of protocol/README.md section 6 (the interpolation itself
        # is in float here: the fleet benchmark's vectorised stand-in for GridLadder)
        target = np.floor(self.lookup.lookup(q) / self.increment_mm + 0.5).astype(np.int64)
        np.clip(target, -self.limit_counts, self.limit_counts, out=target)
        step = np.clip(target - self.shifts, -self.max_step_counts, self.max_step_counts)
        self.shifts += step
        return self.shifts
