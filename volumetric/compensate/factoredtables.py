"""The content of a ``factored`` map and the center's reference of the endpoint's integer
arithmetic (protocol/README.md §6.5, format version 5).

A map has *fields*: the correction of every axis (fields ``0 .. K-1``) and, with rotary
axes, the *sensitivities* ``S_lr`` (one per linear axis ``l`` and rotary axis ``r``):
how far linear axis ``l`` moves to keep the tool tip in place per unit of rotary axis
``r``. Each field is a sum of terms, each a 1-D table of one axis times up to four shared
*basis* tables::

    F_f(q) = Σ_{t: field t = f} T_t(q_{axis t}) · Π_{b ∈ factors t} B_b(q_{axis b})

Everything is in counts of the increment (``1 / counts_per_unit`` mm, or degrees on a
rotary axis): positions, table starts, the node spacing (a power of two, so that the
endpoint's index is a shift), the correction fields; a sensitivity is counts per count
(mm per degree when both increments are equal). Basis tables hold int16 values in Q14,
term tables int16 values times ``2^exponent``. :func:`applied_counts` is the endpoint's
integer evaluation as the README states it (every product rescaled, one tie rule: halves
up), vectorised over points; the machine has its own (:mod:`machine_sim.ladder`), pinned
to this one by tests.

Units: positions mm or degrees at the public methods, counts inside; corrections mm or
degrees from :meth:`FactoredMap.corrections` and :meth:`FactoredMap.applied`; tool-tip
errors µm.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from fractions import Fraction
from typing import overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.compensate.gridmap import thermal_correction
from volumetric.compensate.maps import Controller, MapBuildError, MapReport
from volumetric.model.model import ThermalTerm

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
MAX_FACTORS = 4
"""Basis tables one term may multiply (two rotary shapes, a linear position, one spare)."""
VALUE_MAX = (1 << 15) - 1
"""Term values are int16, |v| <= 2^15 - 1."""
BASIS_Q = 14
"""Basis values are Q14: 2^14 is 1.0."""
EXPONENT_RANGE = (-60, 8)
FRACTION_BITS = 16
"""Fields accumulate in 2^-16 counts (corrections) or 2^-16 counts per count."""
_HEADER_BYTES = 64
_AXIS_BYTES = 20
_TABLE_BYTES = 8
_THERMAL_BYTES = 32
DRIFT_SHIFT = 32
EXPANSION_SHIFT = 48


@overload
def rshift_round(x: I64, s: int) -> I64: ...
@overload
def rshift_round(x: int, s: int) -> int: ...
def rshift_round(x: I64 | int, s: int) -> I64 | int:
    """``x / 2^s`` rounded half up (``(x + 2^(s-1)) >> s``, arithmetic); ``x · 2^-s`` for
    s <= 0. The one tie rule of the README."""
    if s > 0:
        return (x + (1 << (s - 1))) >> s
    return x << -s if s < 0 else x


def to_counts(q_mm: ArrayLike, counts_per_unit: int) -> I64:
    """Positions (mm or degrees) as the endpoint's counts: ``floor(q · P + 0.5)`` in
    double precision (the README's rule for a position given in mm)."""
    qa = np.asarray(q_mm, dtype=np.float64)
    return np.floor(qa * counts_per_unit + 0.5).astype(np.int64)


@dataclass(frozen=True, eq=False)
class Table1D:
    """One 1-D table of one axis: ``values`` at ``start + i·2^shift`` counts, linearly
    interpolated and held at the ends.

    Attributes
    ----------
    axis : int
        Index of the axis (machine axis order) whose position it is looked up at.
    start : int
        First node, counts.
    shift : int
        Node spacing ``2^shift`` counts.
    values : ndarray of int64, shape (n,)
        Mantissas: int16 for terms (value ``v · 2^exponent``), Q14 for basis tables.
    exponent : int
        The power of two of the values' unit (-14 for basis tables).
    """

    axis: int
    start: int
    shift: int
    values: I64
    exponent: int

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Table1D):
            return NotImplemented
        return (self.axis, self.start, self.shift, self.exponent) == \
            (other.axis, other.start, other.shift, other.exponent) and \
            bool(np.array_equal(self.values, other.values))

    __hash__ = None  # type: ignore[assignment]

    def at(self, x: F64) -> F64:
        """Interpolated values (float, for the fit) at positions ``x`` (N,), counts."""
        n = self.values.shape[0]
        v = np.ldexp(self.values.astype(np.float64), self.exponent)
        if n == 1:
            return np.full(x.shape[0], float(v[0]))
        u = np.clip((x - self.start) / float(1 << self.shift), 0.0, n - 1)
        i = np.minimum(u.astype(np.intp), n - 2)
        f = u - i
        out: F64 = v[i] * (1.0 - f) + v[i + 1] * f
        return out

    def lookup(self, qc: I64) -> I64:
        """The README's integer lookup at positions ``qc`` (N,) counts: the value
        interpolated, times 2^15 (of the mantissa's unit), int64."""
        v = self.values
        n = v.shape[0]
        if n == 1:
            return np.full(qc.shape[0], int(v[0]) << 15, dtype=np.int64)
        x = np.clip(qc - self.start, 0, (n - 1) << self.shift)
        i = np.minimum(x >> self.shift, n - 2)
        r = x - (i << self.shift)
        dv = v[i + 1] - v[i]
        out: I64 = (v[i] << 15) + rshift_round(dv * r, self.shift - 15)
        return out


@dataclass(frozen=True, eq=False)
class Term:
    """One product: a table of one axis times basis tables, added to one field.

    Attributes
    ----------
    field : int
        The field it adds to: ``0 .. K-1`` corrections (counts), then the sensitivities
        (counts per count).
    table : Table1D
    factors : tuple of int
        Indices into :attr:`FactoredMap.bases` (at most :data:`MAX_FACTORS`).
    """

    field: int
    table: Table1D
    factors: tuple[int, ...] = ()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Term):
            return NotImplemented
        return (self.field, self.factors) == (other.field, other.factors) and \
            self.table == other.table

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True)
class AxisGrid:
    """The node grid every term table of one axis uses: ``count`` nodes from ``start``
    counts, spacing ``2^shift`` counts."""

    count: int
    start: int
    shift: int

    @property
    def step(self) -> int:
        return 1 << self.shift

    def nodes(self) -> F64:
        """Node positions, counts (float)."""
        return np.asarray(self.start + self.step * np.arange(self.count), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class FactoredMap:
    """A machine's compensation as fields of sums of products of 1-D tables.

    Attributes
    ----------
    machine : str
    version : int
    controller : {"fanuc"}
        Factored maps are rounded to whole increments by the endpoint.
    axes : tuple of str
        The machine's axes (upper case): the inputs and the outputs, K of them.
    rotary : tuple of bool
        Per axis, whether it is rotary.
    increment : float
        mm (degrees on a rotary axis) per count, ``1 / counts_per_unit``.
    limits : tuple of float
        Per axis, the largest |correction|, mm or degrees (whole counts).
    reversal : tuple of float or None
        Per axis, negative- minus positive-approach correction, mm or degrees (whole
        increments), or None.
    grids : tuple of AxisGrid
        Per axis, the node grid of its term tables.
    bases : tuple of Table1D
        The shared basis tables (dimensionless, Q14).
    terms : tuple of Term
    temperatures : mapping of str to float
        °C the map was built for.
    valid_s : int
    report : MapReport or None
    thermal : tuple of ThermalTerm
        Terms the endpoint applies itself at its latest temperatures.
    """

    machine: str
    version: int
    controller: Controller
    axes: tuple[str, ...]
    rotary: tuple[bool, ...]
    increment: float
    limits: tuple[float, ...]
    reversal: tuple[float | None, ...]
    grids: tuple[AxisGrid, ...]
    bases: tuple[Table1D, ...]
    terms: tuple[Term, ...]
    temperatures: Mapping[str, float] = field(default_factory=dict)
    valid_s: int = 0
    report: MapReport | None = None
    thermal: tuple[ThermalTerm, ...] = ()

    def __post_init__(self) -> None:
        k = len(self.axes)
        if not k or len(self.rotary) != k or len(self.limits) != k or \
                len(self.reversal) != k or len(self.grids) != k:
            raise MapBuildError("a factored map needs rotary, limits, reversal and grids "
                                "per axis")
        counts_per_unit(self.increment)
        for tab in (*self.bases, *(t.table for t in self.terms)):
            if not 0 <= tab.axis < k:
                raise MapBuildError(f"table of axis {tab.axis}: the map has {k} axes")
        for t in self.terms:
            if not 0 <= t.field < self.n_fields:
                raise MapBuildError(f"term of field {t.field}: the map has {self.n_fields}")
            if len(t.factors) > MAX_FACTORS or any(not 0 <= b < len(self.bases)
                                                   for b in t.factors):
                raise MapBuildError(f"term factors {t.factors}: bad basis index or more "
                                    f"than {MAX_FACTORS}")
        for th in self.thermal:
            if th.axis.upper() not in self.axes:
                raise MapBuildError(f"thermal term on axis {th.axis}: not an axis of the map")

    def __eq__(self, other: object) -> bool:
        """Equal content (the build report and temperatures do not count)."""
        if not isinstance(other, FactoredMap):
            return NotImplemented
        return (self.machine, self.version, self.controller, self.axes, self.rotary,
                self.increment, self.reversal, self.grids, self.valid_s, self.thermal) == \
            (other.machine, other.version, other.controller, other.axes, other.rotary,
             other.increment, other.reversal, other.grids, other.valid_s, other.thermal) \
            and self.bases == other.bases and self.terms == other.terms

    __hash__ = None  # type: ignore[assignment]

    @property
    def counts_per_unit(self) -> int:
        return counts_per_unit(self.increment)

    @property
    def outputs(self) -> tuple[str, ...]:
        return self.axes

    @property
    def linear_axes(self) -> tuple[int, ...]:
        return tuple(i for i, r in enumerate(self.rotary) if not r)

    @property
    def rotary_axes(self) -> tuple[int, ...]:
        return tuple(i for i, r in enumerate(self.rotary) if r)

    @property
    def n_fields(self) -> int:
        """K corrections plus one sensitivity per linear and rotary axis pair."""
        return len(self.axes) + len(self.linear_axes) * len(self.rotary_axes)

    def sensitivity_field(self, linear: int, rotary: int) -> int:
        """The field of ``S_lr`` for axis indices ``linear`` and ``rotary``."""
        lin, rot = self.linear_axes, self.rotary_axes
        return len(self.axes) + lin.index(linear) * len(rot) + rot.index(rotary)

    @property
    def entries(self) -> int:
        """Table values carried (basis and term tables)."""
        return sum(t.values.size for t in self.bases) + \
            sum(t.table.values.size for t in self.terms)

    @property
    def nbytes(self) -> int:
        """Length of the encoded payload (protocol/README.md §6.5)."""
        return payload_bytes(self)

    def limit_counts(self) -> I64:
        return np.array([round(v / self.increment) for v in self.limits], dtype=np.int64)

    def fields(self, q: ArrayLike) -> F64:
        """Every field at positions ``q`` (N, K) mm or degrees, in float (what the tables
        hold, before the endpoint's fixed point) → (N, n_fields): corrections in mm or
        degrees, sensitivities in counts per count (mm per degree)."""
        qa = _points(q, len(self.axes)) * self.counts_per_unit
        basis = [b.at(qa[:, b.axis]) for b in self.bases]
        out = np.zeros((qa.shape[0], self.n_fields))
        for t in self.terms:
            v = t.table.at(qa[:, t.table.axis])
            for b in t.factors:
                v = v * basis[b]
            out[:, t.field] += v
        out[:, :len(self.axes)] *= self.increment
        return np.asarray(out, dtype=np.float64)

    def corrections(self, q: ArrayLike,
                    temperatures: Mapping[str, float] | None = None) -> F64:
        """The correction fields plus the thermal terms, before rounding, (N, K)."""
        qa = _points(q, len(self.axes))
        out = self.fields(qa)[:, :len(self.axes)]
        if self.thermal and temperatures:
            out = out + thermal_correction(self.axes, self.thermal, qa, temperatures)
        return out

    def thermal_constants(self, temperatures: Mapping[str, float] | None) -> tuple[I64, I64]:
        """Per axis, the thermal records' constant (2^-16 counts) and slope (2^-32 counts
        per count) at ``temperatures`` (°C by model column), the README's integer rule."""
        c0 = np.zeros(len(self.axes), dtype=np.int64)
        c1 = np.zeros(len(self.axes), dtype=np.int64)
        for th in self.thermal:
            celsius = (temperatures or {}).get(th.sensor)
            if celsius is None:
                continue
            d = self.axes.index(th.axis.upper())
            coef, t_ref, q_min = thermal_ints(th, self.counts_per_unit)
            # ΔT clamped to ±2^17 m°C (protocol/README.md §6): bounds every product
            dt = min(max(_half_up(Fraction(float(celsius)) * 1000) - t_ref, -(1 << 17)),
                     1 << 17)
            if th.kind == "thermal_drift":
                c0[d] -= rshift_round(coef * dt, 16)
            else:
                s = rshift_round(coef * dt, 16)
                c1[d] -= s
                c0[d] += rshift_round(s * q_min, 16)
        return c0, c1

    def applied_counts(self, q: ArrayLike,
                       temperatures: Mapping[str, float] | None = None) -> I64:
        """What the endpoint applies for a positive approach, counts (N, K): positions
        rounded to counts, then :func:`applied_counts`."""
        qc = to_counts(_points(q, len(self.axes)), self.counts_per_unit)
        c0, c1 = self.thermal_constants(temperatures)
        return applied_counts(self, qc, c0, c1)

    def applied(self, q: ArrayLike, temperatures: Mapping[str, float] | None = None) -> F64:
        """What the endpoint applies for a positive approach, mm or degrees, (N, K)."""
        return np.asarray(self.applied_counts(q, temperatures) * self.increment,
                          dtype=np.float64)


def counts_per_unit(increment: float) -> int:
    """The integer ``P`` with ``increment = 1 / P`` (1000 for 0.001 mm); MapBuildError
    when the increment is not the reciprocal of an integer."""
    if not (math.isfinite(increment) and increment > 0):
        raise MapBuildError(f"increment must be > 0, got {increment}")
    p = round(1.0 / increment)
    if p < 1 or abs(p * increment - 1.0) > 1e-9:
        raise MapBuildError(f"a factored map's increment must be 1/P for an integer P "
                            f"(0.001, 0.0001), got {increment}")
    return int(p)


def _half_up(x: Fraction) -> int:
    return (x + Fraction(1, 2)).__floor__()


def thermal_ints(th: ThermalTerm, per_unit: int) -> tuple[int, int, int]:
    """A thermal term's fixed-point record (coefficient, t_ref m°C, q_min counts), the
    README's conversion: drift in 2^-32 counts per m°C, expansion in 2^-48 counts per count
    per m°C, halves up."""
    coef = Fraction(float(th.coefficient))
    if th.kind == "thermal_drift":
        k = _half_up(coef * per_unit / 1_000_000 * (1 << DRIFT_SHIFT))
        q_min = 0
    else:
        k = _half_up(coef / 1_000_000_000 * (1 << EXPANSION_SHIFT))
        q_min = _half_up(Fraction(float(th.q_min)) * per_unit)
    return k, _half_up(Fraction(float(th.t_ref_C)) * 1000), q_min


def applied_counts(fm: FactoredMap, qc: I64, c0: I64, c1: I64) -> I64:
    """The endpoint's integer evaluation (protocol/README.md §6.5) at positions ``qc``
    (N, K) counts, thermal constants ``c0`` (K,) 2^-16 counts and ``c1`` (K,) 2^-32 counts
    per count → counts (N, K) for a positive approach. int64 throughout."""
    n, k = qc.shape
    basis = [b.lookup(qc[:, b.axis]) for b in fm.bases]
    acc = np.zeros((n, fm.n_fields), dtype=np.int64)
    for t in fm.terms:
        p = t.table.lookup(qc[:, t.table.axis])
        for b in t.factors:
            p = rshift_round(p * basis[b], 29)
        acc[:, t.field] += rshift_round(p, -(t.table.exponent + 1))
    lim = fm.limit_counts()
    c = acc[:, :k] + c0 + rshift_round(c1 * qc, 16)
    c = np.clip(c, -(lim << 16), lim << 16)
    lin, rot = list(fm.linear_axes), list(fm.rotary_axes)
    if not lin or not rot:
        out: I64 = np.clip(rshift_round(c, 16), -lim, lim)
        return out
    s = acc[:, k:].reshape(n, len(lin), len(rot))
    # each rotary axis's nearest count (halves up) and its other neighbour, nearest
    # first: equal costs keep the nearest (protocol/README.md §6.5 step 5)
    cr = c[:, rot]
    near = rshift_round(cr, 16)
    far = np.where((near << 16) > cr, near - 1, near + 1)
    best = np.zeros((n, k), dtype=np.int64)
    best_cost = np.full(n, -1, dtype=np.int64)
    for choice in range(1 << len(rot)):
        pick = np.array([(choice >> (len(rot) - 1 - j)) & 1 for j in range(len(rot))],
                        dtype=np.int64)
        r_counts = np.where(pick == 1, far, near)
        moved = (r_counts << 16) - cr
        want = c[:, lin] + rshift_round(np.einsum("nlr,nr->nl", s, moved), 16)
        l_counts = rshift_round(want, 16)
        resid = want - (l_counts << 16)
        cost = (resid * resid).sum(axis=1)
        win = (best_cost < 0) | (cost < best_cost)
        best_cost = np.where(win, cost, best_cost)
        best[np.ix_(win, rot)] = r_counts[win]
        best[np.ix_(win, lin)] = l_counts[win]
    clamped: I64 = np.clip(best, -lim, lim)
    return clamped


def _points(q: ArrayLike, k: int) -> F64:
    qa = np.atleast_2d(np.asarray(q, dtype=float))
    if qa.ndim != 2 or qa.shape[1] != k:
        raise ValueError(f"positions must have shape (N, {k}), got {qa.shape}")
    if not np.all(np.isfinite(qa)):
        raise ValueError("positions contain NaN or infinity")
    return qa


def payload_bytes(m: FactoredMap) -> int:
    """Encoded size: 64 + 20 K + Σ_tables (8 + 2 n) + 32 H."""
    return (_HEADER_BYTES + _AXIS_BYTES * len(m.axes)
            + sum(_TABLE_BYTES + 2 * b.values.size for b in m.bases)
            + sum(_TABLE_BYTES + 2 * t.table.values.size for t in m.terms)
            + _THERMAL_BYTES * len(m.thermal))


def fixed_point(values: F64) -> tuple[I64, int]:
    """``values`` as int16 mantissas (|v| <= 2^15 - 1) times a power of two: (mantissas,
    exponent), the smallest exponent that fits (relative resolution 2^-15 of the table's
    largest value), within :data:`EXPONENT_RANGE`."""
    big = float(np.abs(values).max(initial=0.0))
    if big == 0.0:
        return np.zeros(values.shape, dtype=np.int64), EXPONENT_RANGE[0]
    e = math.frexp(big)[1] - 15  # big < 2^(e + 15)
    if round(big * 2.0 ** -e) > VALUE_MAX:
        e += 1
    e = max(EXPONENT_RANGE[0], e)
    if e > EXPONENT_RANGE[1]:
        raise MapBuildError(f"a table value of {big:.3g} does not fit int16 · 2^"
                            f"{EXPONENT_RANGE[1]}")
    ints = np.floor(np.ldexp(values, -e) + 0.5).astype(np.int64)
    return ints, e


__all__ = [
    "MAX_FACTORS",
    "AxisGrid",
    "FactoredMap",
    "Table1D",
    "Term",
    "applied_counts",
    "counts_per_unit",
    "fixed_point",
    "payload_bytes",
    "rshift_round",
    "thermal_ints",
    "to_counts",
]
