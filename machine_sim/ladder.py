"""The Fanuc-style PMC ladder's map arithmetic, in integers only (protocol/README.md §6.1,
§6.4, §6.5), written from the README.

A map is turned into integer tables once, when it is loaded (:func:`factored_program`,
:func:`grid_program`); every scan then works on int64 numbers alone: positions in counts
of the increment, shifts, integer products rescaled after each multiply, one tie rule
(halves rounded up: ``(x + 2^(s-1)) >> s``). Thermal records fold, once per new
temperature (in m°C), into a constant (2^-16 counts) and a slope (2^-32 counts per count)
per axis. Nothing in this module touches a float: ``tests/test_ladder_integer.py`` checks
its source for float literals, true division and float conversions, and runs it on
Python ints. Converting a position in mm to counts, or a temperature in °C to m°C, is the
caller's business (:mod:`machine_sim.lookup`), as it is the PMC's position register's.

Shapes: positions (N, D) counts; results (N, K) counts, int64.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from protocol.mapfactored import FactoredPayload, FactoredThermal
from protocol.mapformat import THERMAL_DRIFT

I64 = NDArray[np.int64]
__all__ = ["DT_LIMIT_MC", "FactoredProgram", "GridProgram", "directions", "factored_counts",
           "factored_program", "grid_counts", "grid_program", "half_up_shift",
           "thermal_constants"]

DT_LIMIT_MC = 1 << 17
"""ΔT = T − t_ref is clamped to ±2^17 m°C (±131.072 K) before any product (§6): it
bounds ``coefficient · ΔT`` below 2^48."""


def half_up_shift(x: I64, s: int) -> I64:
    """``x / 2^s`` rounded half up, ``(x + 2^(s-1)) >> s`` (arithmetic shift); ``x · 2^-s``
    for s <= 0."""
    if s > 0:
        out: I64 = (x + (1 << (s - 1))) >> s
        return out
    if s < 0:
        left: I64 = x << -s
        return left
    return x


def _i64(values: Sequence[int]) -> I64:
    return np.array(values, dtype=np.int64)


@dataclass(frozen=True)
class _Table:
    start: int
    shift: int
    values: I64

    def lookup(self, q: I64) -> I64:
        """§6.5 step 1: the value at q (counts), times 2^15."""
        v = self.values
        n = v.shape[0]
        if n == 1:
            return np.full(q.shape[0], v[0] << 15, dtype=np.int64)
        x = np.clip(q - self.start, 0, (n - 1) << self.shift)
        i = np.minimum(x >> self.shift, n - 2)
        r = x - (i << self.shift)
        out: I64 = (v[i] << 15) + half_up_shift((v[i + 1] - v[i]) * r, self.shift - 15)
        return out


@dataclass(frozen=True)
class _Term:
    field: int
    axis: int
    exponent: int
    factors: tuple[int, ...]
    table: _Table


@dataclass(frozen=True)
class FactoredProgram:
    """A factored map as integer tables (loaded once)."""

    axes: tuple[str, ...]
    rotary: tuple[int, ...]
    linear: tuple[int, ...]
    limit: I64
    reversal: I64
    n_fields: int
    bases: tuple[tuple[int, _Table], ...]
    terms: tuple[_Term, ...]
    thermal: tuple[FactoredThermal, ...]


def factored_program(p: FactoredPayload) -> FactoredProgram:
    """The integer tables of a decoded factored map (§6.5)."""
    bases = tuple((b.axis, _Table(b.start, b.shift, _i64(b.values))) for b in p.bases)
    terms = tuple(_Term(t.field, t.axis, t.exponent, t.factors,
                        _Table(p.axes[t.axis].start, p.axes[t.axis].shift, _i64(t.values)))
                  for t in p.terms)
    return FactoredProgram(
        axes=tuple(a.name.upper() for a in p.axes),
        rotary=tuple(i for i, a in enumerate(p.axes) if a.rotary),
        linear=tuple(i for i, a in enumerate(p.axes) if not a.rotary),
        limit=_i64([a.limit for a in p.axes]),
        reversal=_i64([0 if a.reversal is None else a.reversal for a in p.axes]),
        n_fields=p.n_fields, bases=bases, terms=terms, thermal=p.thermal)


def thermal_constants(records: Sequence[FactoredThermal], n_axes: int,
                      readings_mC: Mapping[str, int]) -> tuple[I64, I64]:
    """Per axis, the thermal constant (2^-16 counts) and slope (2^-32 counts per count)
    at the readings (m°C by the exact name the Temperatures message carries); a record
    whose sensor has no reading adds nothing (§6.4, §6.5)."""
    c0 = np.zeros(n_axes, dtype=np.int64)
    c1 = np.zeros(n_axes, dtype=np.int64)
    for rec in records:
        t = readings_mC.get(rec.sensor)
        if t is None:
            continue
        dt = min(max(t - rec.t_ref_mC, -DT_LIMIT_MC), DT_LIMIT_MC)
        if rec.kind == THERMAL_DRIFT:
            c0[rec.axis] -= (rec.coefficient * dt + (1 << 15)) >> 16
        else:
            s = (rec.coefficient * dt + (1 << 15)) >> 16
            c1[rec.axis] -= s
            c0[rec.axis] += (s * rec.q_min + (1 << 15)) >> 16
    return c0, c1


def factored_fields(prog: FactoredProgram, q: I64) -> I64:
    """§6.5 steps 1-2: every field at positions q (N, D) counts, in 2^-16 counts
    (corrections) or 2^-16 counts per count (sensitivities), (N, n_fields)."""
    basis = [t.lookup(q[:, axis]) for axis, t in prog.bases]
    acc = np.zeros((q.shape[0], prog.n_fields), dtype=np.int64)
    for term in prog.terms:
        p = term.table.lookup(q[:, term.axis])
        for b in term.factors:
            p = half_up_shift(p * basis[b], 29)
        acc[:, term.field] += half_up_shift(p, -(term.exponent + 1))
    return acc


def directions(previous: I64, q: I64, last: I64) -> I64:
    """§6 "Direction and reversal": an axis moved in a scan when its commanded position
    differs from the previous scan's; its direction is the sign of that move, else the
    last one (+1 at start-up, before any move). previous, q, last: (..., D) → (..., D) of
    ±1."""
    out: I64 = np.where(q > previous, 1, np.where(q < previous, -1, last))
    return out


def factored_counts(prog: FactoredProgram, q: I64, c0: I64, c1: I64,
                    negative: NDArray[np.bool_] | None = None) -> I64:
    """§6.5: the counts the ladder writes at positions q (N, D) counts, thermal constants
    c0, c1 (D,) → (N, D). ``negative`` (N, D) or (D,): the axes whose direction is
    negative, which get their reversal value before the final clamp (step 6); None: a
    positive approach on every axis."""
    d = len(prog.axes)
    acc = factored_fields(prog, q)
    lim = prog.limit
    c = np.clip(acc[:, :d] + c0 + half_up_shift(c1 * q, 16), -(lim << 16), lim << 16)
    rev = (np.zeros((1, d), dtype=np.int64) if negative is None
           else np.where(np.asarray(negative, dtype=bool), prog.reversal, 0))
    rot, lin = _i64(prog.rotary), _i64(prog.linear)
    if not rot.size or not lin.size:
        plain: I64 = np.clip(half_up_shift(c, 16) + rev, -lim, lim)
        return plain
    n = q.shape[0]
    sens = acc[:, d:].reshape(n, len(lin), len(rot))
    # step 5: each rotary axis's nearest count (halves up) and its other neighbour; choice
    # 0 is all nearest, so equal costs (all sensitivities 0, say) round to nearest
    cr = c[:, rot]
    near = half_up_shift(cr, 16)
    far = np.where((near << 16) > cr, near - 1, near + 1)
    best = np.zeros((n, d), dtype=np.int64)
    best_cost = np.zeros(n, dtype=np.int64)
    for choice in range(1 << len(rot)):
        pick = _i64([(choice >> (len(rot) - 1 - j)) & 1 for j in range(len(rot))])
        r_counts = np.where(pick == 1, far, near)
        moved = (r_counts << 16) - cr
        want = c[:, lin] + half_up_shift((sens * moved[:, None, :]).sum(axis=2), 16)
        l_counts = half_up_shift(want, 16)
        resid = want - (l_counts << 16)
        cost = (resid * resid).sum(axis=1)
        win = np.ones(n, dtype=bool) if choice == 0 else cost < best_cost
        best_cost[win] = cost[win]
        best[np.ix_(win, rot)] = r_counts[win]
        best[np.ix_(win, lin)] = l_counts[win]
    out: I64 = np.clip(best + rev, -lim, lim)
    return out


@dataclass(frozen=True)
class GridProgram:
    """An int32 grid map (format version 1 or 3) as integers (loaded once)."""

    start: I64
    step: I64
    count: I64
    strides: I64
    values: I64
    outputs: tuple[str, ...]
    reversal: I64
    thermal: tuple[FactoredThermal, ...]
    slope_cols: I64
    """(K,) the column of the positions holding each output's own position, -1 if none."""


def grid_program(values: bytes, count: Sequence[int], start: Sequence[int],
                 step: Sequence[int], outputs: Sequence[str], reversal: Sequence[int],
                 thermal: Sequence[FactoredThermal], inputs: Sequence[str]) -> GridProgram:
    """The integer form of an int32 grid map (§6.1): its int32 values (row-major, output
    fastest), per grid axis its node count and its start and step in counts (the loader
    converted the f64 fields, §6's rule), per output its name and reversal in counts,
    its thermal records in fixed point; ``inputs`` the axes whose positions a lookup
    takes (grid axes first)."""
    k = len(outputs)
    raw = np.array(np.frombuffer(values, dtype="<i4"), dtype=np.int64).reshape(-1, k)
    cnt = _i64(count)
    strides = np.ones(len(cnt), dtype=np.int64)
    for j in range(len(cnt) - 2, -1, -1):
        strides[j] = strides[j + 1] * cnt[j + 1]
    names = tuple(o.upper() for o in outputs)
    return GridProgram(
        start=_i64(start), step=_i64(step), count=cnt, strides=strides, values=raw,
        outputs=names, reversal=_i64(reversal), thermal=tuple(thermal),
        slope_cols=_i64([list(inputs).index(o) if o in inputs else -1 for o in names]))


def grid_counts(prog: GridProgram, q: I64, c0: I64, c1: I64,
                negative: NDArray[np.bool_] | None = None, limit: int | None = None) -> I64:
    """§6.1 and §6.4: the counts the ladder writes at positions q (N, len(inputs))
    counts, thermal constants c0, c1 (K,) → (N, K). ``negative`` (N, K) or (K,): the
    outputs whose direction is negative, which get their reversal value; ``limit``: the
    controller's compensation range in counts, clamped to after the reversal (step 3);
    None for both: a positive approach, unclamped."""
    d = prog.start.shape[0]
    x = np.clip(q[:, :d] - prog.start, 0, (prog.count - 1) * prog.step)
    i = np.minimum(x // prog.step, prog.count - 2)
    f = ((x - i * prog.step) << 16) // prog.step  # Q16, 0 .. 2^16
    base = (i * prog.strides).sum(axis=1)
    # corners: bit j of the corner index set = the upper node along grid axis j
    corners = [prog.values[base + sum(((c >> (d - 1 - j)) & 1) * int(prog.strides[j])
                                      for j in range(d))] << 16
               for c in range(1 << d)]
    # reduce the last grid axis first: pairs of corners differing in its bit
    for j in range(d - 1, -1, -1):
        fj = f[:, j:j + 1]
        corners = [lo + half_up_shift((hi - lo) * fj, 16)
                   for lo, hi in zip(corners[0::2], corners[1::2], strict=True)]
    g = corners[0]
    cols = prog.slope_cols
    pos = np.where(cols >= 0, q[:, np.maximum(cols, 0)], 0)
    out: I64 = half_up_shift(g + c0 + half_up_shift(c1 * pos, 16), 16)
    if negative is not None:
        out = out + np.where(np.asarray(negative, dtype=bool), prog.reversal, 0)
    if limit is not None:
        out = np.clip(out, -limit, limit)
    return out
