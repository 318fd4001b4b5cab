"""The content of a ``grid`` map: its axes, node values and reversal, the lookup by
multilinear interpolation, and the thermal corrections an endpoint adds (built by
:mod:`volumetric.compensate.gridmap`; the module docstring there says how).

Units: positions mm or degrees, corrections mm or degrees, thermal coefficients as in
:class:`volumetric.model.model.ThermalTerm`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.compensate.maps import Controller, MapBuildError, MapReport
from volumetric.model.model import ThermalTerm

F64 = NDArray[np.float64]
_HEADER_BYTES = 64  # encoded grid payload: 64 + 24 D + 12 K + 4 N K (protocol/README.md §6)
_THERMAL_BYTES = 48  # one thermal record of a version-3 payload, after a 4-byte count


@dataclass(frozen=True)
class GridDim:
    """One grid dimension: ``count`` nodes at ``start + i·step`` of machine axis ``name``.

    Attributes
    ----------
    name : str
        Machine axis name (``"X"``, ``"Z1"``, ``"C"``).
    start, step : float
        mm or degrees.
    count : int
        At least 2 (an axis with one node is not a grid dimension).
    """

    name: str
    start: float
    step: float
    count: int

    def __post_init__(self) -> None:
        if not (math.isfinite(self.start) and math.isfinite(self.step) and self.step > 0):
            raise MapBuildError(f"grid axis {self.name}: need finite start and step > 0, "
                                f"got start {self.start}, step {self.step}")
        if not isinstance(self.count, int) or self.count < 2:
            raise MapBuildError(f"grid axis {self.name}: count must be an int >= 2, "
                                f"got {self.count!r}")

    @property
    def stop(self) -> float:
        """The last node, mm or degrees."""
        return self.start + (self.count - 1) * self.step

    def nodes(self) -> F64:
        """Node positions, shape (count,)."""
        return np.asarray(self.start + self.step * np.arange(self.count), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class ErrorMap:
    """A machine's compensation on a regular grid, as a controller receives it.

    Attributes
    ----------
    machine : str
    version : int
        Map version (>= 1), increasing with every map pushed to the machine.
    controller : {"fanuc", "siemens"}
        Fanuc maps hold whole multiples of ``increment``; Siemens maps float32 values.
    grid : tuple of GridDim
        The dimensions the correction depends on, in lookup order.
    outputs : tuple of str
        Corrected machine axes, the last index of ``values``.
    values : ndarray, shape (*counts, n_outputs)
        Corrections to add to the commands at the nodes, mm or degrees, as sent
        (quantised and clamped).
    increment : float or None
        Fanuc: the value unit, mm or degrees per count; Siemens: None.
    limits : tuple of float
        Per output, the largest |correction| allowed, mm or degrees.
    reversal : tuple of float or None
        Per output, what the controller adds while the axis last moved negative: the
        negative-approach minus the positive-approach correction (minus the backlash of an
        axis that lags behind its motion), mm or degrees, or None.
    temperatures : mapping of str to float
        The temperatures (°C) the map was built for.
    valid_s : int
        Seconds the map stays valid once applied, 0 = no limit.
    report : MapReport or None
        Build statistics (None for a map decoded from a payload).
    thermal : tuple of ThermalTerm
        Thermal terms the controller applies itself at its latest temperatures (each on
        an output axis); ``values`` are then the corrections at the terms' reference
        temperatures (see :meth:`thermal_correction`).
    """

    machine: str
    version: int
    controller: Controller
    grid: tuple[GridDim, ...]
    outputs: tuple[str, ...]
    values: F64
    increment: float | None
    limits: tuple[float, ...]
    reversal: tuple[float | None, ...]
    temperatures: Mapping[str, float] = field(default_factory=dict)
    valid_s: int = 0
    report: MapReport | None = None
    thermal: tuple[ThermalTerm, ...] = ()

    def __post_init__(self) -> None:
        if not self.grid:
            raise MapBuildError("an error map needs at least one grid dimension")
        want = (*(g.count for g in self.grid), len(self.outputs))
        if self.values.shape != want:
            raise MapBuildError(f"map values have shape {self.values.shape}, grid and "
                                f"outputs need {want}")
        if not np.all(np.isfinite(self.values)):
            raise MapBuildError("map values contain NaN or infinity")
        if len(self.limits) != len(self.outputs) or len(self.reversal) != len(self.outputs):
            raise MapBuildError("limits and reversal need one entry per output axis")
        if self.controller not in ("fanuc", "siemens"):
            raise MapBuildError(f"controller must be 'fanuc' or 'siemens', "
                                f"got {self.controller!r}")
        if (self.controller == "fanuc") != (self.increment is not None):
            raise MapBuildError("a Fanuc map needs an increment, a Siemens map none")
        names = [g.name for g in self.grid]
        if len(set(names)) != len(names) or len(set(self.outputs)) != len(self.outputs):
            raise MapBuildError(f"grid {names} or outputs {self.outputs} repeat a name")
        for t in self.thermal:
            if t.axis.upper() not in self.outputs:
                raise MapBuildError(f"thermal term on axis {t.axis} ({t.sensor}): not an "
                                    f"output of the map ({' '.join(self.outputs)})")

    def __eq__(self, other: object) -> bool:
        """Equal content (the build report does not count)."""
        if not isinstance(other, ErrorMap):
            return NotImplemented
        return (self.machine == other.machine and self.version == other.version
                and self.controller == other.controller and self.grid == other.grid
                and self.outputs == other.outputs and self.increment == other.increment
                and self.reversal == other.reversal and self.valid_s == other.valid_s
                and self.thermal == other.thermal
                and bool(np.array_equal(self.values, other.values)))

    __hash__ = None  # type: ignore[assignment]

    @property
    def dims(self) -> tuple[str, ...]:
        """Names of the grid dimensions: the columns :meth:`lookup` expects."""
        return tuple(g.name for g in self.grid)

    @property
    def nodes(self) -> int:
        return math.prod(g.count for g in self.grid)

    @property
    def nbytes(self) -> int:
        """Length of the encoded payload (protocol/README.md §6)."""
        return payload_bytes(len(self.grid), len(self.outputs), self.nodes, len(self.thermal))

    def thermal_correction(self, positions: ArrayLike,
                           temperatures: Mapping[str, float]) -> F64:
        """What the controller adds for the thermal terms, mm, shape (N, n_outputs).

        Parameters
        ----------
        positions : array_like, shape (N, n_outputs)
            Commanded positions of the output axes (:attr:`outputs` order), mm or degrees.
        temperatures : mapping of str to float
            °C per sensor column; a sensor not named is at its reference (adds nothing).
        """
        q = np.atleast_2d(np.asarray(positions, dtype=float))
        return thermal_correction(self.outputs, self.thermal, q, temperatures)

    def lookup(self, points: ArrayLike) -> F64:
        """Multilinear interpolation of the corrections, clamped at the grid edges.

        Parameters
        ----------
        points : array_like, shape (N, n_dims)
            Coordinates in :attr:`dims` order, mm or degrees.

        Returns
        -------
        ndarray, shape (N, n_outputs)
            Corrections, mm or degrees.
        """
        p = np.asarray(points, dtype=float)
        if p.ndim == 1:
            p = p[None, :]
        if p.ndim != 2 or p.shape[1] != len(self.grid):
            raise ValueError(f"lookup points must have shape (N, {len(self.grid)}) for axes "
                             f"{' '.join(self.dims)}; got {p.shape}")
        if not np.all(np.isfinite(p)):
            raise ValueError("lookup points contain NaN or infinity")
        return _multilinear(self.grid, self.values, p)

    def select(self, q: ArrayLike, axes: Sequence[str]) -> F64:
        """The lookup columns of machine coordinates ``q`` (N, len(axes)) named ``axes``."""
        qa = np.asarray(q, dtype=float)
        qa = qa[None, :] if qa.ndim == 1 else qa
        keys = [a.upper() for a in axes]
        missing = [d for d in self.dims if d.upper() not in keys]
        if missing:
            raise ValueError(f"coordinates for axes {axes} lack map axes {missing}")
        out: F64 = qa[:, [keys.index(d.upper()) for d in self.dims]]
        return out


def payload_bytes(n_dims: int, n_outputs: int, nodes: int, n_thermal: int = 0) -> int:
    """Encoded size of a grid map: 64 + 24 D + 12 K + 4 N K bytes, plus 4 + 48 H for H
    thermal records (format version 3, protocol/README.md §6)."""
    trailer = 4 + _THERMAL_BYTES * n_thermal if n_thermal else 0
    return _HEADER_BYTES + 24 * n_dims + 12 * n_outputs + 4 * nodes * n_outputs + trailer


def thermal_correction(axes: Sequence[str], thermal: Sequence[ThermalTerm], q: F64,
                       temperatures: Mapping[str, float]) -> F64:
    """The corrections that cancel thermal terms, mm, shape (N, len(axes)).

    Each term's error ``ΔE`` (µm, :meth:`ThermalTerm.component` at its sensor's
    temperature) is along its own axis's line of motion, so that axis moving by ``-ΔE``
    cancels it exactly: ``-k·ΔT·1e-3`` mm for a drift, ``-k·ΔT·(q - q_min)·1e-6`` mm for
    an expansion (k in µm/(m·K), q in mm). A sensor without a temperature adds nothing.

    Parameters
    ----------
    axes : sequence of str
        Names of the columns of ``q`` (upper case machine axes).
    thermal : sequence of ThermalTerm
    q : ndarray, shape (N, len(axes))
        Commanded positions, mm or degrees.
    temperatures : mapping of str to float
        °C per sensor column.
    """
    out = np.zeros(q.shape)
    names = [a.upper() for a in axes]
    for t in thermal:
        celsius = temperatures.get(t.sensor)
        if celsius is None:
            continue
        j = names.index(t.axis.upper())
        out[:, j] -= 1e-3 * np.asarray(t.component(float(celsius))(q[:, j]), dtype=float)
    return out


def _multilinear(grid: Sequence[GridDim], values: F64, p: F64) -> F64:
    k = values.shape[-1]
    flat = values.reshape(-1, k)
    counts = [g.count for g in grid]
    strides = [math.prod(counts[d + 1:]) for d in range(len(grid))]
    idx, frac = [], []
    for d, g in enumerate(grid):
        u = (p[:, d] - g.start) / g.step
        i = np.clip(np.floor(u), 0, g.count - 2).astype(np.intp)
        idx.append(i)
        frac.append(np.clip(u - i, 0.0, 1.0))  # clamped: the edge value holds outside
    out = np.zeros((p.shape[0], k))
    for corner in range(1 << len(grid)):
        w = np.ones(p.shape[0])
        off = np.zeros(p.shape[0], dtype=np.intp)
        for d in range(len(grid)):
            if corner >> d & 1:
                w = w * frac[d]
                off = off + (idx[d] + 1) * strides[d]
            else:
                w = w * (1.0 - frac[d])
                off = off + idx[d] * strides[d]
        out += w[:, None] * flat[off]
    return out


__all__ = ["ErrorMap", "GridDim", "payload_bytes", "thermal_correction"]
