"""The readings of a measurement campaign (formats.md section 2) as columns: the
:class:`Measurements` container, the columns the format names, the error a reader raises,
and :func:`subsample`. Reading and writing the CSV is :mod:`volumetric.measure.measurement`.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "OPTIONAL_ROTARY",
    "REQUIRED_COLUMNS",
    "U_NORM_TOL",
    "FloatArray",
    "MeasurementFormatError",
    "Measurements",
    "subsample",
]

REQUIRED_COLUMNS: tuple[str, ...] = (
    "test", "run", "time_s", "x_mm", "y_mm", "z_mm", "dir_x", "dir_y", "dir_z",
    "tool_mm", "quantity", "ux", "uy", "uz", "value",
)  # fmt: skip
OPTIONAL_ROTARY: tuple[str, str, str] = ("a_deg", "b_deg", "c_deg")
U_NORM_TOL = 1e-3
"""Largest accepted | |u| - 1 | of a row's sensing direction."""

_TEXT_COLUMNS = frozenset({"test", "quantity", "spindle"})
_NUMERIC_REQUIRED = tuple(c for c in REQUIRED_COLUMNS if c not in _TEXT_COLUMNS)
_TEMPERATURE = re.compile(r"^T_(.+)_C$")


class MeasurementFormatError(ValueError):
    """A measurement file that does not follow the format; names the line and column.

    Attributes
    ----------
    line : int or None
        1-based line number in the file (the header is line 1), when one line is at fault.
    column : str or None
        The column name, when one column is at fault.
    """

    def __init__(self, source: str, message: str, *, line: int | None = None,
                 column: str | None = None) -> None:
        where = source
        if line is not None:
            where += f", line {line}"
        if column is not None:
            where += f", column {column!r}"
        super().__init__(f"{where}: {message}")
        self.line = line
        self.column = column


FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False, slots=True)
class Measurements:
    """Readings of a measurement campaign, column-wise; every array has length N.

    Attributes
    ----------
    test : ndarray of str, shape (N,)
        Test label, e.g. ``X-positioning`` or ``diag-PPP``.
    run : ndarray of int64, shape (N,)
        Run (cycle) number within the test.
    time_s : ndarray of float64, shape (N,)
        Seconds since the campaign started.
    q : ndarray of float64, shape (N, 6)
        Commanded x, y, z (mm) and a, b, c (degrees); rotary columns absent from the file
        are 0.0.
    direction : ndarray of int8, shape (N, 3)
        ``dir_x, dir_y, dir_z``: -1, 0 or +1, the direction each linear axis last moved.
    tool_mm : ndarray of float64, shape (N,)
        Tool length (mm).
    is_angle : ndarray of bool, shape (N,)
        True where ``quantity`` is ``angle`` (value in µrad), False for ``displacement`` (µm).
    u : ndarray of float64, shape (N, 3)
        Sensing direction (displacement) or rotation axis (angle), unit length within
        :data:`U_NORM_TOL`, stored as given.
    value : ndarray of float64, shape (N,)
        The reading: µm for a displacement, µrad for an angle.
    has_rotary : tuple of 3 bool
        Whether ``a_deg``, ``b_deg``, ``c_deg`` were present.
    temperatures : dict of str to ndarray of float64, shape (N,)
        °C, keyed by the *sensor name*: column ``T_t1_C`` is sensor ``t1``.
    temperature_columns : dict of str to str
        Sensor name to its column name (``"t1" -> "T_t1_C"``), in file order. Reports that
        name "the temperature column" (the ``sensor`` key of ``ednc diagnose``) can use
        either; this mapping makes both available.
    spindle : ndarray of str, shape (N,), or None
        Which tool tip, on a multi-spindle machine; None when the column is absent.
    extra : dict of str to ndarray, shape (N,)
        Every other column: float64 when all its cells are numbers, str otherwise.
    """

    test: NDArray[np.str_]
    run: NDArray[np.int64]
    time_s: FloatArray
    q: FloatArray
    direction: NDArray[np.int8]
    tool_mm: FloatArray
    is_angle: NDArray[np.bool_]
    u: FloatArray
    value: FloatArray
    has_rotary: tuple[bool, bool, bool] = (False, False, False)
    temperatures: dict[str, FloatArray] = field(default_factory=dict)
    temperature_columns: dict[str, str] = field(default_factory=dict)
    spindle: NDArray[np.str_] | None = None
    extra: dict[str, NDArray[Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = self.test.shape[0]
        shapes: dict[str, tuple[int, ...]] = {
            "test": (n,), "run": (n,), "time_s": (n,), "q": (n, 6), "direction": (n, 3),
            "tool_mm": (n,), "is_angle": (n,), "u": (n, 3), "value": (n,),
        }  # fmt: skip
        for name, shape in shapes.items():
            got = getattr(self, name).shape
            if got != shape:
                raise ValueError(f"Measurements.{name} has shape {got}, expected {shape}")
        columns: list[tuple[str, str, NDArray[Any]]] = [
            ("temperatures", k, v) for k, v in self.temperatures.items()]
        columns += [("extra", k, v) for k, v in self.extra.items()]
        if self.spindle is not None:
            columns.append(("spindle", "", self.spindle))
        for group, key, arr in columns:
            if arr.shape != (n,):
                raise ValueError(f"Measurements.{group}[{key!r}] has shape {arr.shape}, "
                                 f"expected {(n,)}")
        if set(self.temperature_columns) != set(self.temperatures):
            raise ValueError("Measurements.temperature_columns must name exactly the sensors "
                             "of Measurements.temperatures")

    def __len__(self) -> int:
        return int(self.test.shape[0])

    @property
    def xyz(self) -> FloatArray:
        """Commanded linear coordinates (mm), shape (N, 3): a view of ``q[:, :3]``."""
        return self.q[:, :3]

    def select(self, rows: NDArray[np.bool_] | NDArray[np.integer[Any]] | Sequence[int]
               ) -> Measurements:
        """The readings picked by a boolean mask of shape (N,) or by integer indices.

        Raises
        ------
        ValueError
            A boolean mask whose length is not N.
        """
        idx = np.asarray(rows)
        if idx.dtype == np.bool_ and idx.shape != (len(self),):
            raise ValueError(f"mask has shape {idx.shape}, expected {(len(self),)}")
        if idx.dtype != np.bool_ and idx.size == 0:
            idx = idx.astype(np.intp)  # an empty list would otherwise index as float
        return Measurements(
            test=self.test[idx], run=self.run[idx], time_s=self.time_s[idx], q=self.q[idx],
            direction=self.direction[idx], tool_mm=self.tool_mm[idx],
            is_angle=self.is_angle[idx], u=self.u[idx], value=self.value[idx],
            has_rotary=self.has_rotary,
            temperatures={k: v[idx] for k, v in self.temperatures.items()},
            temperature_columns=dict(self.temperature_columns),
            spindle=None if self.spindle is None else self.spindle[idx],
            extra={k: v[idx] for k, v in self.extra.items()},
        )

    @staticmethod
    def concat(parts: Sequence[Measurements]) -> Measurements:
        """Readings of several campaigns one after the other.

        All parts must carry the same temperature sensors, the same extra columns (of the
        same kind, numeric or text) and either all or none a ``spindle`` column; a rotary
        column present in any part is kept (its 0.0 stands for the parts without it).

        Raises
        ------
        ValueError
            No parts, or parts whose optional columns differ.
        """
        if not parts:
            raise ValueError("Measurements.concat needs at least one part")
        first = parts[0]
        for k, p in enumerate(parts[1:], start=1):
            if p.temperature_columns != first.temperature_columns:
                raise ValueError(f"part {k} has temperature columns "
                                 f"{sorted(p.temperature_columns.values())}, part 0 has "
                                 f"{sorted(first.temperature_columns.values())}")
            if set(p.extra) != set(first.extra) or any(
                    (p.extra[c].dtype.kind == "f") != (first.extra[c].dtype.kind == "f")
                    for c in first.extra):
                raise ValueError(f"part {k} has extra columns {sorted(p.extra)} that differ "
                                 f"from part 0's {sorted(first.extra)} (or in kind)")
            if (p.spindle is None) != (first.spindle is None):
                raise ValueError(f"part {k} and part 0 differ in having a spindle column")

        def cat(get: Any) -> Any:
            return np.concatenate([get(p) for p in parts])

        rotary = tuple(any(p.has_rotary[j] for p in parts) for j in range(3))
        return Measurements(
            test=cat(lambda p: p.test), run=cat(lambda p: p.run),
            time_s=cat(lambda p: p.time_s), q=cat(lambda p: p.q),
            direction=cat(lambda p: p.direction), tool_mm=cat(lambda p: p.tool_mm),
            is_angle=cat(lambda p: p.is_angle), u=cat(lambda p: p.u),
            value=cat(lambda p: p.value),
            has_rotary=(rotary[0], rotary[1], rotary[2]),
            temperatures={s: cat(lambda p, s=s: p.temperatures[s]) for s in first.temperatures},
            temperature_columns=dict(first.temperature_columns),
            spindle=None if first.spindle is None else cat(lambda p: p.spindle),
            extra={c: cat(lambda p, c=c: p.extra[c]) for c in first.extra},
        )


def subsample(m: Measurements, limit: int, *, per_test: int = 2000, seed: int = 0
              ) -> Measurements:
    """About ``limit`` of the readings, drawn at random (seeded) within each test, in file
    order; ``m`` itself when it has no more than ``limit``.

    Every test keeps the same share of its readings, and at least ``per_test`` of them (or
    all it has): a short fine test among millions of readings keeps what makes it useful
    (the positions that resolve a ballscrew's period, a reversal). A random draw, not a
    stride, so no pattern in the order of the readings (targets visited in turn) is
    aliased. Runs, times and temperatures stay with their readings, so folds of runs and
    blocks of time are formed from the draw as from the file.

    Parameters
    ----------
    m : Measurements
    limit : int
        Readings wanted (0 or less: all).
    per_test : int
        Fewest readings a test keeps.
    seed : int
        Seed of the draw: the same file gives the same readings every time.
    """
    n = len(m)
    if limit <= 0 or n <= limit:
        return m
    rng = np.random.default_rng(seed)
    share = limit / n
    _, inverse, counts = np.unique(m.test, return_inverse=True, return_counts=True)
    by_test = np.split(np.argsort(inverse, kind="stable"), np.cumsum(counts)[:-1])
    keep = np.zeros(n, dtype=bool)
    for rows in by_test:
        take = min(rows.size, max(round(share * rows.size), per_test))
        keep[rng.choice(rows, take, replace=False)] = True
    return m.select(keep)
