"""The ``factored`` map kind: sums of products of 1-D tables, for endpoints that can only
look tables up, multiply and add in fixed point (a Fanuc PMC ladder has no trigonometry).

What the machine evaluates. A map has *fields* ``F_f(q)``: the correction of every axis
(fields ``0 .. K-1``, machine axis order, mm or degrees) and, for a machine with rotary
axes, the *sensitivities* ``S_lr`` (one field per linear axis ``l`` and rotary axis ``r``,
mm per degree): how much linear axis ``l`` must move so that the tool tip stays where it
is when rotary axis ``r`` moves by one degree. Each field is a sum of terms, each term one
1-D table of one axis times a product of up to four *basis* tables (each a 1-D table of one
axis, shared by all terms)::

    F_f(q) = Σ_{t: field t = f} T_t(q_{axis t}) · Π_{b ∈ factors t} B_b(q_{axis b})

Every table is linearly interpolated on a uniform grid of its axis (held at the ends) and
its values are int32 times a power of two. So the ladder's loop is lookups, multiplies and
adds; no trigonometry: the trigonometric shapes the chain needs come as basis tables
(``cos θ``, ``sin θ``, ``cos 2θ``, ``sin 2θ`` of each rotary axis on 2° nodes) and the
linear positions as two-node basis tables (an affine function is interpolated exactly).

Why this structure. To first order in the errors, the weighted compensation of a chain
with orthogonal nominal axes is: per rotary axis a function of that axis times trigonometric
functions of the other rotary axes times an affine function of the linear positions (the
rotary axes' errors and location errors, seen from the workpiece); per linear axis a
function of that axis (its component errors) times trigonometric functions (up to the
second harmonic: a rotary correction's lever arm turns with the same rotation that makes
the correction) times an affine function of the other linear positions (an angular error's
lever). The builder offers every such term and fits them by linear least squares over
random samples of the exact corrections (:mod:`volumetric.compensate.solver`; the unknowns
are the term tables' values, the basis tables are fixed), choosing them one table at a
time (:func:`_select`): of the ~265 candidates per field of a 5-axis machine a few dozen
carry the corrections. The table spacing starts at 40 mm on a linear axis and 7.5° on a
rotary axis, and it and the selection's budget shrink while the check below finds the
tolerance missed.

Quantisation-aware corrections (issue 11, item 2). The controller rounds every correction
to whole increments (0.001 mm, 0.001°). Rounding a rotary correction by up to half an
increment moves the tool tip by 0.0005° × the lever (up to ~5 µm at 500 mm); so the
endpoint rounds the rotary corrections first, each down or up, and lets the linear axes
absorb what that leaves: ``lin_l += Σ_r S_lr · (rounded_r - F_r)``, then rounds the linear
ones. Of the 2^R down/up choices it keeps the one whose linear rounding residual is
smallest (sum of squares: with orthogonal linear axes that is the tool tip's displacement).
The error as sent then approaches the linear rounding (at most √3/2 increment), not
0.0005° × the lever. :meth:`FactoredMap.applied` is the center's reference of that rule;
the machine has its own (:mod:`machine_sim.lookup`), pinned to this one by a test.

Thermal terms (``thermal_in_map``) travel as with grid maps of format version 3: the map is
built at their reference temperatures and the endpoint adds ``-ΔE`` of each (constant plus
slope times the axis position) to its axis's correction before rounding.

Units: positions mm or degrees; correction fields mm or degrees; sensitivity fields mm per
degree; tool-tip errors µm.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from itertools import product

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from volumetric.compensate.gridmap import thermal_correction
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
)
from volumetric.compensate.solver import Weights
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
MAX_FACTORS = 4
"""Basis tables one term may multiply (two rotary shapes, a linear position, one spare)."""
VALUE_BITS = 30
"""Table values are int32 with |v| < 2^30 times 2^exponent: one bit of headroom so that
a PLC may add two neighbouring values without overflow."""
BASIS_STEP_DEG = 2.0
"""Spacing of the trigonometric basis tables: linear interpolation of cos at 2° errs by
(2π/180)²/8 = 1.5e-4 of the amplitude, 0.008 µm on a 50 µm correction; the fit sees the
tables as interpolated, so that is all it costs."""
BUDGET_SHARE = 0.1
"""Terms are added to a field until its worst error on the fit samples is at most this
share of the tolerance asked at the tool tip (halved in every further round), or until
more tables stop paying (:data:`STALL_TERMS`). Five correction fields at a tenth each
leave more than half the tolerance to the rounding (the linear axes' own is up to 0.87
increment)."""
MIN_BUDGET_UM = 0.01
"""The smallest per-field budget, µm: below it tables only chase the fit's noise."""
RIDGE = 1e-7
"""Relative ridge of the normal equations (times the mean squared column norm), so that a
table nearly inside the span of those already chosen cannot take large opposite values."""
STALL_TERMS = 10
STALL_GAIN = 0.9
"""A field stops taking tables when its worst error after the last ``STALL_TERMS`` of them
is still above ``STALL_GAIN`` times what it was before: the rest is finer than the tables'
spacing, which only a further round can give (on a 5-axis map, ~200 more tables for the
last 0.05 µm otherwise)."""
_HEADER_BYTES = 64
_AXIS_BYTES = 36
_BASIS_BYTES = 24
_TERM_BYTES = 16
_THERMAL_BYTES = 48
_MAX_ROUNDS = 4


@dataclass(frozen=True, eq=False)
class Table1D:
    """One uniform 1-D table of one axis, linearly interpolated and held at the ends.

    Attributes
    ----------
    axis : int
        Index of the axis (machine axis order) whose position it is looked up at.
    start, step : float
        First node and spacing, mm or degrees (step > 0).
    values : ndarray, shape (n,)
        Node values, each an int32 (|v| < 2^30) times ``2**exponent``; n = 1 is a constant.
    exponent : int
        The power of two of the values' unit.
    """

    axis: int
    start: float
    step: float
    values: F64
    exponent: int

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Table1D):
            return NotImplemented
        return (self.axis, self.start, self.step, self.exponent) == \
            (other.axis, other.start, other.step, other.exponent) and \
            bool(np.array_equal(self.values, other.values))

    __hash__ = None  # type: ignore[assignment]

    def at(self, x: F64) -> F64:
        """Interpolated values at positions ``x`` (N,) of the table's axis → (N,)."""
        n = self.values.shape[0]
        if n == 1:
            return np.full(x.shape[0], float(self.values[0]))
        u = np.clip((x - self.start) / self.step, 0.0, n - 1)
        i = np.minimum(u.astype(np.intp), n - 2)
        f = u - i
        out: F64 = self.values[i] * (1.0 - f) + self.values[i + 1] * f
        return out


@dataclass(frozen=True, eq=False)
class Term:
    """One product: a table of one axis times basis tables, added to one field.

    Attributes
    ----------
    field : int
        The field it adds to: ``0 .. K-1`` corrections, then the sensitivities.
    table : Table1D
        Its own values, mm, degrees or mm per degree.
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
    """The node grid every term table of one axis uses: ``count`` nodes from ``start``."""

    count: int
    start: float
    step: float

    def nodes(self) -> F64:
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
        mm (degrees on a rotary axis) per count.
    limits : tuple of float
        Per axis, the largest |correction|, mm or degrees.
    reversal : tuple of float or None
        Per axis, negative- minus positive-approach correction, mm or degrees (whole
        increments), or None.
    grids : tuple of AxisGrid
        Per axis, the node grid of its term tables.
    bases : tuple of Table1D
        The shared basis tables (dimensionless).
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
        for tab in (*self.bases, *(t.table for t in self.terms)):
            if not 0 <= tab.axis < k:
                raise MapBuildError(f"table of axis {tab.axis}: the map has {k} axes")
            if not np.all(np.isfinite(tab.values)):
                raise MapBuildError("factored map values contain NaN or infinity")
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

    def fields(self, q: ArrayLike) -> F64:
        """Every field at positions ``q``, shape (N, K) → (N, n_fields)."""
        qa = _points(q, len(self.axes))
        basis = [b.at(qa[:, b.axis]) for b in self.bases]
        out = np.zeros((qa.shape[0], self.n_fields))
        for t in self.terms:
            v = t.table.at(qa[:, t.table.axis])
            for b in t.factors:
                v = v * basis[b]
            out[:, t.field] += v
        return out

    def corrections(self, q: ArrayLike,
                    temperatures: Mapping[str, float] | None = None) -> F64:
        """The correction fields plus the thermal terms, before rounding, (N, K)."""
        qa = _points(q, len(self.axes))
        out = self.fields(qa)[:, :len(self.axes)]
        if self.thermal and temperatures:
            out = out + thermal_correction(self.axes, self.thermal, qa, temperatures)
        return out

    def applied(self, q: ArrayLike, temperatures: Mapping[str, float] | None = None) -> F64:
        """What the endpoint applies for a positive approach, mm or degrees, (N, K): the
        corrections rounded rotary-first (module docstring) and clamped to the limits."""
        qa = _points(q, len(self.axes))
        f = self.fields(qa)
        k = len(self.axes)
        c = f[:, :k]
        if self.thermal and temperatures:
            c = c + thermal_correction(self.axes, self.thermal, qa, temperatures)
        lim = np.asarray(self.limits)
        return quantized(c, f[:, k:], self.linear_axes, self.rotary_axes, self.increment, lim)


def quantized(c: F64, sens: F64, lin: Sequence[int], rot: Sequence[int], inc: float,
              limits: F64) -> F64:
    """Round corrections ``c`` (N, K) rotary first: every down/up choice of the rotary
    ones, the linear ones shifted by the sensitivities ``sens`` (N, L·R) times the rotary
    residuals, the choice with the smallest sum of squared linear rounding residuals
    (ties: the first, all down before up, the first rotary axis slowest). Clamped to
    ``±limits`` (K,) at the end. mm or degrees."""
    c = np.clip(c, -limits, limits)
    if not rot or not lin:
        out: F64 = np.rint(c / inc) * inc
        return np.clip(out, -limits, limits)
    n = c.shape[0]
    s = sens.reshape(n, len(lin), len(rot))
    lo = np.floor(c[:, rot] / inc)
    best = np.empty_like(c)
    best_cost = np.full(n, np.inf)
    for choice in product((0, 1), repeat=len(rot)):
        r_counts = lo + np.asarray(choice)
        moved = r_counts * inc - c[:, rot]  # degrees the rotary axes move beyond c
        want = c[:, lin] + np.einsum("nlr,nr->nl", s, moved)
        l_counts = np.rint(want / inc)
        cost = ((want - l_counts * inc) ** 2).sum(axis=1)
        better = cost < best_cost
        best_cost = np.where(better, cost, best_cost)
        cand = np.empty_like(c)
        cand[:, rot] = r_counts * inc
        cand[:, lin] = l_counts * inc
        best[better] = cand[better]
    return np.clip(best, -limits, limits)


def _points(q: ArrayLike, k: int) -> F64:
    qa = np.atleast_2d(np.asarray(q, dtype=float))
    if qa.ndim != 2 or qa.shape[1] != k:
        raise ValueError(f"positions must have shape (N, {k}), got {qa.shape}")
    if not np.all(np.isfinite(qa)):
        raise ValueError("positions contain NaN or infinity")
    return qa


def payload_bytes(m: FactoredMap) -> int:
    """Encoded size: 64 + 36 K + Σ_bases (24 + 4 n) + Σ_terms (16 + 4 n_axis) + 4 + 48 H."""
    return (_HEADER_BYTES + _AXIS_BYTES * len(m.axes)
            + sum(_BASIS_BYTES + 4 * b.values.size for b in m.bases)
            + sum(_TERM_BYTES + 4 * t.table.values.size for t in m.terms)
            + 4 + _THERMAL_BYTES * len(m.thermal))


def fixed_point(values: F64) -> tuple[F64, int]:
    """``values`` as int32 (|v| < 2^30) times a power of two: (the representable values,
    the exponent). The exponent is the smallest that fits, so the relative resolution is
    2^-30 of the table's largest value."""
    big = float(np.abs(values).max(initial=0.0))
    if big == 0.0:
        return np.zeros_like(values), -30
    e = math.frexp(big)[1] - VALUE_BITS  # big < 2^(e + 30)
    e = max(-126, min(126, e))
    ints = np.rint(np.ldexp(values, -e))
    return np.ldexp(ints, e), e


# --- building ---

@dataclass
class _Layout:
    """The candidate terms over one set of axis grids, and their sparse design."""

    machine: Machine
    grids: list[AxisGrid]
    bases: list[Table1D]
    rot_bases: dict[int, list[int | None]]  # per rotary axis: its basis indices (None = 1)
    lin_basis: dict[int, int]  # per linear axis: the basis index of its position
    candidates: list[tuple[int, tuple[int, ...], bool]] = field(default_factory=list)
    """(axis of the term table, basis factors, a constant) of every candidate term."""

    def column_blocks(self) -> list[int]:
        return [1 if const else self.grids[a].count for a, _, const in self.candidates]

    def design(self, q: F64) -> sp.csr_matrix:
        """(N, Σ nodes) sparse: row n holds every candidate's hat weights at q_n times its
        factors (tables as the endpoint interpolates them)."""
        n = q.shape[0]
        basis = [b.at(q[:, b.axis]) for b in self.bases]
        rows, cols, vals = [], [], []
        offset = 0
        r = np.arange(n)
        for axis, factors, const in self.candidates:
            g = self.grids[axis]
            w = np.ones(n)
            for b in factors:
                w = w * basis[b]
            if const or g.count == 1:
                rows.append(r)
                cols.append(np.full(n, offset))
                vals.append(w)
            else:
                u = np.clip((q[:, axis] - g.start) / g.step, 0.0, g.count - 1)
                i = np.minimum(u.astype(np.intp), g.count - 2)
                f = u - i
                rows += [r, r]
                cols += [offset + i, offset + i + 1]
                vals += [w * (1.0 - f), w * f]
            offset += 1 if const else g.count
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                     np.concatenate(cols))),
                             shape=(n, offset))


def _basis_tables(machine: Machine, harmonics: int) -> tuple[list[Table1D],
                                                            dict[int, list[int | None]],
                                                            dict[int, int]]:
    bases: list[Table1D] = []
    rot: dict[int, list[int | None]] = {}
    lin: dict[int, int] = {}
    for i, a in enumerate(machine.axes):
        lo, hi = float(a.travel[0]), float(a.travel[1])
        if a.kind == "rotary":
            count = max(2, math.ceil((hi - lo) / BASIS_STEP_DEG) + 1)
            step = (hi - lo) / (count - 1) if hi > lo else 1.0
            x = np.deg2rad(lo + step * np.arange(count))
            idx: list[int | None] = [None]
            for h in range(1, harmonics + 1):
                for fn in (np.cos, np.sin):
                    v, e = fixed_point(fn(h * x))
                    idx.append(len(bases))
                    bases.append(Table1D(i, lo, step, v, e))
            rot[i] = idx
        else:
            # the position, centred and scaled to ±1: two nodes interpolate it exactly
            half = 0.5 * (hi - lo) if hi > lo else 1.0
            v, e = fixed_point(np.array([-1.0, 1.0]))
            lin[i] = len(bases)
            bases.append(Table1D(i, lo, 2 * half, v, e))
    return bases, rot, lin


def _layout(machine: Machine, lin_nodes: Sequence[int], rot_step: float,
            harmonics: int) -> _Layout:
    bases, rot_b, lin_b = _basis_tables(machine, harmonics)
    grids = []
    for i, a in enumerate(machine.axes):
        lo, hi = float(a.travel[0]), float(a.travel[1])
        n = (max(2, math.ceil((hi - lo) / rot_step) + 1) if a.kind == "rotary"
             else lin_nodes[i])
        grids.append(AxisGrid(n, lo, (hi - lo) / (n - 1) if hi > lo else 1.0))
    lay = _Layout(machine, grids, bases, rot_b, lin_b)
    rot = sorted(rot_b)
    lin = sorted(lin_b)
    for i, _a in enumerate(machine.axes):
        others = [r for r in rot if r != i]
        shapes = list(product(*[rot_b[r] for r in others])) if others else [()]
        positions: list[int | None] = [None] + [lin_b[j] for j in lin if j != i]
        for shape in shapes:
            for p in positions:
                factors = tuple(b for b in (*shape, p) if b is not None)
                lay.candidates.append((i, factors, False))
    # constants times the trigonometric shapes of every rotary axis times one linear
    # position: exactly the sensitivities' form (nominal kinematics)
    if rot:
        for shape in product(*[rot_b[r] for r in rot]):
            for p in [None] + [lin_b[j] for j in lin]:
                factors = tuple(b for b in (*shape, p) if b is not None)
                lay.candidates.append((0, factors, True))
    return lay


def _select(lay: _Layout, a: sp.csr_matrix, targets: F64, tip_scale: F64,
            budget_um: float) -> list[tuple[int, int, F64]]:
    """Terms chosen one table at a time per field (orthogonal matching pursuit over whole
    tables): the candidate whose table alone would remove most of what is left (least
    squares), then all chosen ones fitted again, until the field's worst error on the fit
    samples, times ``tip_scale`` µm per unit of the field, is within ``budget_um``.
    Returns (field, candidate, values) of the chosen terms.

    Why greedy, not all candidates at once: they overlap (``x·cos a`` is an A table times
    x and an X table times cos a), so a fit of all of them spreads every shape over
    several terms, none small enough to drop (1,231 terms, 100 kB on the benchmark's
    5ax-04); the greedy choice keeps one of them (109 terms, 14 kB, and a smaller error).
    The normal matrix is never formed (it cost 8 s of a 10 s build): each step needs
    ``Aᵀ r`` (one sparse product) and the chosen tables' Gram blocks, added to a Cholesky
    factor block by block."""
    blocks = np.asarray(lay.column_blocks())
    edges = np.concatenate([[0], np.cumsum(blocks)])
    a_csc = a.tocsc()
    col_sq = np.asarray(a_csc.multiply(a_csc).sum(axis=0)).ravel()
    ridge = RIDGE * float(col_sq.mean())
    const = np.array([c for _, _, c in lay.candidates])
    # per candidate, the inverse Cholesky factor W_g of its own Gram block: its score is
    # ‖W_g A_gᵀ r‖², the squared residual its table alone would remove
    by_size: dict[int, list[int]] = {}
    for c in range(len(blocks)):
        by_size.setdefault(int(blocks[c]), []).append(c)
    stacked: list[tuple[NDArray[np.intp], F64, NDArray[np.intp]]] = []
    for b, cs in by_size.items():
        inv = []
        for c in cs:
            ag = a_csc[:, edges[c]:edges[c + 1]]
            g = (ag.T @ ag).toarray() + ridge * np.eye(b)
            inv.append(sl.solve_triangular(np.linalg.cholesky(g), np.eye(b), lower=True))
        idx = np.stack([np.arange(edges[c], edges[c + 1]) for c in cs])
        stacked.append((np.asarray(cs), np.stack(inv), idx))
    k = len(lay.machine.axes)
    a_t = a_csc.T.tocsr()
    kept: list[tuple[int, int, F64]] = []
    for f in range(targets.shape[1]):
        y = targets[:, f]
        if float(np.abs(y).max(initial=0.0)) * tip_scale[f] <= budget_um:
            continue
        allowed = const == (f >= k)
        chosen: list[int] = []
        cols = np.zeros(0, dtype=np.intp)
        a_s = sp.csc_matrix((y.size, 0))
        low = np.zeros((0, 0))  # Cholesky factor of the chosen columns' Gram matrix
        aty = np.zeros(0)
        x = np.zeros(0)
        resid = y
        worst: list[float] = []  # µm after each table added
        while True:
            corr = a_t @ resid  # Aᵀ (y − A_S x)
            score = np.full(len(blocks), -1.0)
            for group, w, idx in stacked:
                score[group] = (np.einsum("cij,cj->ci", w, corr[idx]) ** 2).sum(axis=1)
            score[~allowed] = -1.0
            if score.max() <= 0.0:
                break
            best = int(np.argmax(score))
            allowed[best] = False
            new = np.arange(edges[best], edges[best + 1])
            a_new = a_csc[:, new]
            # grow the Cholesky factor by the new block (no refactorisation)
            cross = (a_s.T @ a_new).toarray()
            bmat = sl.solve_triangular(low, cross, lower=True) if cols.size else \
                np.zeros((0, new.size))
            schur = (a_new.T @ a_new).toarray() + ridge * np.eye(new.size) - bmat.T @ bmat
            try:
                cnew = np.linalg.cholesky(schur)
            except np.linalg.LinAlgError:
                continue  # inside the span of the chosen ones
            low = np.block([[low, np.zeros((cols.size, new.size))], [bmat.T, cnew]])
            cols = np.concatenate([cols, new])
            a_s = sp.hstack([a_s, a_new], format="csc")
            aty = np.concatenate([aty, a_new.T @ y])
            chosen.append(best)
            x = sl.solve_triangular(low.T, sl.solve_triangular(low, aty, lower=True),
                                    lower=False)
            resid = y - a_s @ x
            worst.append(float(np.abs(resid).max()) * tip_scale[f])
            if worst[-1] <= budget_um:
                break
            if len(worst) > STALL_TERMS and worst[-1] > STALL_GAIN * worst[-1 - STALL_TERMS]:
                # the last tables bought almost nothing: what is left is below this
                # table spacing (the outer rounds refine it); keep the field as it was
                n_keep = len(chosen) - STALL_TERMS
                chosen = chosen[:n_keep]
                m = int(blocks[chosen].sum())
                x = sl.solve_triangular(low[:m, :m].T, sl.solve_triangular(
                    low[:m, :m], aty[:m], lower=True), lower=False)
                break
        starts = np.concatenate([[0], np.cumsum(blocks[chosen])])
        kept += [(f, c, x[starts[i]:starts[i + 1]].copy()) for i, c in enumerate(chosen)]
    return kept


def sensitivities(prob: MapProblem, q: F64) -> F64:
    """Linear-axis motion (mm) that keeps the tool tips where they are per degree of each
    rotary axis: ``-pinv(J_lin) J_rot`` of the stacked position rows of every tool tip,
    (N, L·R), linear axis slowest."""
    m = prob.machine
    lin = [i for i, a in enumerate(m.axes) if a.kind != "rotary"]
    rot = [i for i, a in enumerate(m.axes) if a.kind == "rotary"]
    if not lin or not rot:
        return np.zeros((q.shape[0], 0))
    blocks = []
    for br in m.branches:
        tool = None if prob.tool_mm is None else prob.tool_mm.get(br.name)
        blocks.append(jacobian(m, q, spindle=br.name, tool_mm=tool)[:, :3])
    j = np.concatenate(blocks, axis=1)  # (N, 3B, n_axes)
    s = -np.linalg.pinv(j[:, :, lin]) @ j[:, :, rot]  # (N, L, R)
    out: F64 = s.reshape(q.shape[0], -1)
    return out


def build_factored_map(
    machine: Machine,
    model: MachineModel,
    temperatures: Mapping[str, float] | None = None,
    *,
    tolerance_um: float = 1.0,
    controller: Controller | None = None,
    increment: float = DEFAULT_INCREMENT,
    limit_mm: float = DEFAULT_LIMIT_MM,
    limit_deg: float = DEFAULT_LIMIT_DEG,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    version: int = 1,
    valid_s: int = 0,
    check_points: int = 8192,
    seed: int = 0,
    max_bytes: int = MAX_MAP_BYTES,
    thermal_in_map: bool = True,
) -> FactoredMap:
    """The factored map of a machine (module docstring).

    Parameters
    ----------
    machine, model, temperatures
        As for :func:`volumetric.compensate.gridmap.build_map`.
    tolerance_um : float
        Largest tool-tip error *as sent* (rounded by the endpoint's rule) allowed on the
        independent check, µm. A tolerance below what whole increments can carry
        (:func:`as_sent_floor_um`: the linear axes' own rounding plus 0.1 µm) is raised to
        it, and the report says so in its ``tolerance_um``: a grid's tolerance is its
        interpolation before rounding, so the center may ask 0.5 µm of every kind.
    controller : {"fanuc"}, optional
        Factored maps are for endpoints that round to ``increment``.
    increment : float
        mm (degrees) per count.
    limit_mm, limit_deg, weights, tool_mm, version, valid_s, seed, max_bytes
        As for :func:`~volumetric.compensate.gridmap.build_map`.
    check_points : int
        Size of the independent random check set over the whole travel.
    thermal_in_map : bool
        Carry the model's thermal terms for the endpoint to apply.

    Raises
    ------
    MapBuildError
        Bad parameters, a non-Fanuc controller, or the tolerance missed after the last
        refinement (:class:`MapTooLargeError` when the map would outgrow ``max_bytes``).
    """
    t0 = time.perf_counter()
    ctrl = check_parameters(machine, model, tolerance_um, controller, increment, limit_mm,
                            limit_deg, check_points)
    if ctrl != "fanuc":
        raise MapBuildError("factored maps are for endpoints that round to whole "
                            "increments (Fanuc); this machine's controller is " + ctrl)
    n_lin = sum(a.kind != "rotary" for a in machine.axes)
    # the tables aim at the tolerance asked (a tenth of it per field), the check at what
    # whole increments can carry: a map asked for 0.1 µm is then the increment's rounding
    # and little else, as a grid built to 0.1 µm is
    budget_um = max(BUDGET_SHARE * tolerance_um, MIN_BUDGET_UM)
    tolerance_um = max(tolerance_um, as_sent_floor_um(n_lin, increment))
    names = machine.axis_names
    thermal = tuple(t for t in model.terms if isinstance(t, ThermalTerm)) if thermal_in_map \
        else ()
    static, temps = model, dict(temperatures or {})
    if thermal:
        for th in thermal:
            if th.axis.upper() not in names:
                raise MapBuildError(f"thermal term on axis {th.axis}: machine "
                                    f"{machine.name!r} has {' '.join(names)}")
        static = MachineModel(model.machine, model.geometry,
                              tuple(t for t in model.terms if not isinstance(t, ThermalTerm)),
                              model.info)
        temps = {t.sensor: t.t_ref_C for t in thermal} | temps
    geometry = geometry_of(static, temps)
    geometry.check(machine)
    w = Weights.default(machine) if weights is None else weights
    prob = MapProblem(machine, geometry, w, tool_mm, machine.travel_lo, machine.travel_hi)
    full = prob if not thermal else MapProblem(machine, geometry_of(model, temps), w,
                                               tool_mm, prob.lo, prob.hi)
    k = len(names)
    rotary = tuple(a.kind == "rotary" for a in machine.axes)
    n_rot = sum(rotary)
    backlash = np.array([model.reversal_um().get(a.key, 0.0) * 1e-3 for a in machine.axes])
    limits = np.array([limit_deg if r else limit_mm for r in rotary])

    rng = np.random.default_rng(seed)
    span = prob.hi - prob.lo
    n_fit = 8192 if n_rot else 4096
    q_fit = prob.lo + span * rng.random((n_fit, k))
    targets = np.hstack([prob.exact(q_fit) + 0.5 * backlash, sensitivities(prob, q_fit)])
    check_rng = np.random.default_rng([seed, 1])
    q_dec = prob.lo + span * rng.random((check_points // 2, k))
    exact_dec = full.exact(q_dec)
    q_chk = prob.lo + span * check_rng.random((check_points, k))
    exact_chk = full.exact(q_chk)
    lever_mm = _lever_mm(machine)
    # µm at the tool tip per unit of each field: 1e3 per mm; a degree of rotation over
    # the longest lever; a sensitivity times the largest rotary residual (1 increment)
    tip_scale = np.array([lever_mm * math.pi / 180 * 1e3 if r else 1e3 for r in rotary]
                         + [increment * 1e3] * (targets.shape[1] - k))

    lin_nodes = [2 if r else max(5, min(33, math.ceil(float(s) / 40.0) + 1))
                 for r, s in zip(rotary, span, strict=True)]
    rot_step = 7.5
    harmonics = 2
    rounds = 0
    last = math.inf
    while True:
        rounds += 1
        lay = _layout(machine, lin_nodes, rot_step, harmonics)
        a = lay.design(q_fit)
        kept = _select(lay, a, targets, tip_scale, budget_um)
        fm = _assemble(machine, version, lay, kept, increment, limits, backlash, model,
                       temps, valid_s, thermal)
        if fm.nbytes > max_bytes:
            raise MapTooLargeError(f"machine {machine.name!r}: a factored map of "
                                   f"{fm.nbytes} bytes is over the {max_bytes}-byte limit")
        worst_dec = _sent_error(full, fm, q_dec, exact_dec, backlash, temps)
        if worst_dec <= tolerance_um or rounds >= _MAX_ROUNDS or worst_dec >= last:
            break
        last = worst_dec
        lin_nodes = [n if r else min(65, math.ceil(1.4 * (n - 1)) + 1)
                     for r, n in zip(rotary, lin_nodes, strict=True)]
        rot_step = max(2.0, rot_step / 1.4)
        budget_um /= 2
    worst_sent = _sent_error(full, fm, q_chk, exact_chk, backlash, temps)
    approx = fm.corrections(q_chk, temps) - 0.5 * backlash - exact_chk
    worst_interp = float(full.tip_um(q_chk, approx).max())
    if worst_sent > tolerance_um:
        raise MapBuildError(f"machine {machine.name!r}: the factored map reaches "
                            f"{worst_sent:.3f} µm as sent, over {tolerance_um} µm (linear "
                            f"rounding alone is up to {0.87 * increment * 1e3:.2f} µm)")
    report = MapReport(
        nodes=fm.entries, bytes=fm.nbytes, tolerance_um=tolerance_um,
        worst_interpolation_um=worst_interp, worst_error_um=worst_sent,
        check_points=check_points, clamped_nodes=0, rounds=rounds,
        build_s=time.perf_counter() - t0, kind="factored",
    )
    return dataclasses.replace(fm, report=report)


def as_sent_floor_um(linear_axes: int, increment: float) -> float:
    """The smallest as-sent tolerance a factored map is built for, µm: half an increment on
    each of ``linear_axes`` orthogonal axes (``√L/2`` increments, what rounding alone can
    leave, 0.87 µm at 0.001 mm on three axes) plus 0.1 µm for the tables themselves."""
    return 0.5 * math.sqrt(max(linear_axes, 1)) * increment * 1e3 + 0.1


def _lever_mm(machine: Machine) -> float:
    """The longest lever a rotary correction can have: workspace diagonal plus tool and
    pivot offsets, mm."""
    diag = float(np.linalg.norm([a.travel[1] - a.travel[0] for a in machine.axes
                                 if a.kind != "rotary"]))
    pivots = [float(np.linalg.norm(a.pivot_mm)) for a in machine.axes if a.kind == "rotary"]
    tools = [float(br.tool_length_mm) for br in machine.branches]
    return diag + max(pivots, default=0.0) + max(tools, default=0.0)


def _assemble(machine: Machine, version: int, lay: _Layout, kept: list[tuple[int, int, F64]],
              increment: float, limits: F64, backlash: F64, model: MachineModel,
              temps: Mapping[str, float], valid_s: int,
              thermal: tuple[ThermalTerm, ...]) -> FactoredMap:
    # only the basis tables some kept term uses travel; renumber them
    used = sorted({b for _, c, _v in kept for b in lay.candidates[c][1]})
    renum = {b: i for i, b in enumerate(used)}
    terms = []
    for f, c, values in kept:
        axis, factors, _ = lay.candidates[c]
        g = lay.grids[axis]
        v, e = fixed_point(values)
        terms.append(Term(f, Table1D(axis, g.start, g.step, v, e),
                          tuple(renum[b] for b in factors)))
    return FactoredMap(
        machine=machine.name, version=version, controller="fanuc",
        axes=machine.axis_names, rotary=tuple(a.kind == "rotary" for a in machine.axes),
        increment=increment, limits=tuple(float(v) for v in limits),
        reversal=reversal_of(machine, model, increment), grids=tuple(lay.grids),
        bases=tuple(lay.bases[b] for b in used), terms=tuple(terms),
        temperatures=dict(temps), valid_s=valid_s, thermal=thermal,
    )


def _sent_error(full: MapProblem, fm: FactoredMap, q: F64, exact: F64, backlash: F64,
                temps: Mapping[str, float]) -> float:
    """Worst tool-tip error (µm) of the map as the endpoint applies it, against the exact
    model (with its thermal terms at ``temps``); the positive-approach shift of a lagging
    axis is not an error."""
    applied = fm.applied(q, temps)
    return float(full.tip_um(q, applied - 0.5 * backlash - exact).max())


__all__ = [
    "MAX_FACTORS",
    "AxisGrid",
    "FactoredMap",
    "Table1D",
    "Term",
    "as_sent_floor_um",
    "build_factored_map",
    "fixed_point",
    "payload_bytes",
    "quantized",
    "sensitivities",
]
