"""The fleet cycle's evaluation of tables maps: many machines per call, few numpy calls.

:meth:`machine_sim.chaineval.ChainBatch.corrections` hands its rows (machine, point) here.
The steps are those of :mod:`machine_sim.chaineval` (protocol/README.md sections 6.2 and
6.3) and exact: no small-angle truncation anywhere, so the reference evaluation
(:meth:`~machine_sim.chaineval.ChainBatch.corrections_reference`) agrees to rounding
(``tests/test_chaineval_fast.py``). What differs is the arrangement for numpy, whose cost
here is a few µs per call plus ~0.2-0.6 ns per element, so a cycle should be few calls on
large arrays and few multiply-adds per row:

- the rows are the last, contiguous axis of every array; a row set's per-machine
  constants are gathered once and kept while the PLC asks for the same rows, already
  combined with what multiplies them (weights with the rows' units and the Jacobian
  columns' units, the operands of the cross products, the tilted turns' bases);
- one gather fetches every table's two values around the position, of every axis,
  component and row; only the intervals that changed since the last cycle are fetched
  again (a machine moves far less than a node spacing per cycle); when an axis's tables
  share their start (as the center builds them) u is one subtraction per axis, and the
  clamp to the tables is skipped while every axis is inside them;
- one set of calls builds every axis's error rotation (exact Rodrigues: the coefficients'
  series below θ² = 1e-4, which are exact to double precision there), one every rotary
  axis's tilted turn, whose sine and cosine come from the nominal angle's by angle
  addition (the two differ by a correction and a location error);
- the chain is walked once per spindle, one matrix-vector product per link step; the
  orientation is multiplied along only when the batch weighs it;
- the nominal tool tip and Jacobian come from one backward pass with the base turns of
  all rotary axes built at once: a rotary axis's column is its axis crossed with the arm
  it turns (the tool tip seen from before it, minus its pivot), and the columns of the
  links after it turn with it, so no forward pass of orientation products is needed;
- the weighted least squares is solved in closed form for all rows at once: the upper
  triangle of the normal matrix is factored as L D Lᵀ (K pivots, each one update of the
  trailing block of all rows); D holds the Schur complements whose square roots are the
  reference's Cholesky pivots, scaled by the squared column norms the reference divides
  out first, so the same rows fall below PIVOT and take the README's SVD; a refinement
  step solves with the factors for its one residual instead of forming the
  pseudo-inverse.

Measured (``benchmarks/fleet_scan.py --mode tables``, 1,000 machines, interleaved in one
process with the previous rows-last evaluation, 2 shared cores under load): 5-axis
2.23 → 1.58 ms CPU per cycle, half 3-axis half 5-axis 1.50 → 1.11 ms, 3-axis 0.62 →
0.43 ms. What remains is numpy's: ~250 calls of ~1 µs for a 5-axis batch of any size,
and ~1,500 element operations per row at 0.3-0.6 ns each; a compiled loop over the rows
would remove most of both.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Final, Protocol

import numpy as np
from numpy.typing import NDArray

from .chaineval_rules import DEG, PIVOT, RCOND, SERIES, STEP_TOL

__all__ = ["ROW_SETS", "FleetCycle"]

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
_DIRS: Final = "XYZABC"
ROW_SETS: Final = 16
"""Row sets whose constants are kept at once (a PLC with a PLC/IPO ratio of n asks for n
groups in turn)."""
_PLANE: Final = ((1, 2), (2, 0), (0, 1))  # the components a turn about x, y, z changes
# flat (row-major) indices of a 3x3 matrix: its diagonal, where [w]x has +w and -w, its
# upper and lower off-diagonal entries
_DIAG: Final = slice(0, 9, 4)
_SKEW_PLUS: Final = [7, 2, 3]  # (2,1) (0,2) (1,0): +w0 +w1 +w2
_SKEW_MINUS: Final = [5, 6, 1]  # (1,2) (2,0) (0,1): -w0 -w1 -w2
_UPPER: Final = [1, 2, 5]  # (0,1) (0,2) (1,2), where [w]x has -w2 +w1 -w0
_LOWER: Final = [3, 6, 7]  # (1,0) (2,0) (2,1), their mirror images
_SKEW_SIGN: Final = np.array([-1.0, 1.0, -1.0])[:, None]
# Rodrigues coefficients sin θ/θ and (1 - cos θ)/θ² as series in θ², rows a and b
_SERIES_C: Final = (np.array([1.0, 0.5])[:, None, None],
                    np.array([-1.0 / 6.0, -1.0 / 24.0])[:, None, None],
                    np.array([1.0 / 120.0, 1.0 / 720.0])[:, None, None])
# sin φ / φ and (1 - cos φ) / φ² as series in φ², rows: the two, columns: powers 0..3
_TURN_C: Final = tuple(np.array(c)[:, None, None] for c in
                       ((1.0, 0.5), (-1.0 / 6.0, -1.0 / 24.0), (1.0 / 120.0, 1.0 / 720.0),
                        (-1.0 / 5040.0, -1.0 / 40320.0)))
_ERROR, _TURN, _MOVE = 0, 1, 2


class ChainArrays(Protocol):
    """What the cycle reads of a :class:`~machine_sim.chaineval.ChainBatch` (M machines,
    A axes, S spindles, K outputs; lengths mm, angles rad, table values mm and rad)."""

    axes: tuple[str, ...]
    rotary: NDArray[np.bool_]  # (A,)
    tool_side: tuple[bool, ...]
    links: tuple[tuple[int, ...], ...]  # per spindle, axis indices workpiece to tool
    outputs: tuple[str, ...]
    out_col: I64  # (K,) axis of each output
    orient: bool
    spindle_axis: tuple[bool, ...]
    direction: F64  # (M, A, 3)
    pivot: F64  # (M, A, 3)
    offset: F64  # (M, A, 3)
    line: F64  # (M, A, 3)
    frame: F64  # (M, A, 3, 3)
    k1t: F64  # (M, A, 3, 3)
    k2t: F64  # (M, A, 3, 3)
    zero: F64  # (M, A)
    tool: F64  # (M, S, 3)
    weights: F64  # (M, S, 6)
    t_first: I64  # (M, A, 6)
    t_last: I64
    t_start: F64
    t_step: F64
    t_next: F64  # every table value (mm, rad) in table order, and one 0 after
    thermal0: F64  # (M, A) µm
    thermal1: F64  # (M, A) µm per mm
    thermal_on: bool
    g_const: F64 | None  # (M, K, R): chains without rotary axes


@dataclass(frozen=True)
class _Rows:
    """A row set's per-machine constants, rows last (N rows; Ar rotary, Al linear axes;
    R residual rows)."""

    key: bytes
    first: I64  # (A, 6, N) index of each table's first value in t_next
    last: F64  # (A, 6, N) count - 1
    start: F64  # (A, 6, N) mm or degrees
    inv_step: F64  # (A, 6, N), 0 for a table of one value or none (its u stays 0)
    shared_start: F64 | None  # (A, N) the start of every table of more than one value,
    # when an axis's tables all start at one position (as the center builds them)
    inside_lo: F64  # (A, N) positions at or above it need no clamp below (max start)
    inside_hi: F64  # (A, N) at or below it none above (min end, less 1e-9 of its size)
    pivot: F64  # (A, 3, N) mm
    direction: F64  # (A, 3, N)
    cross: F64  # (Ar, 3, 3, N) [d]x of the rotary axes: [d]x v = d x v
    lin_direction: F64  # (Al, 3, N)
    frame: F64 | None  # (A, 3, 3, N), spindle axes' own frames (None: none has one)
    turn_at: F64  # (Ar, 3, N) pivot + offset: the actual rotary axis's point, mm
    k1: F64  # (Ar, 3, 3, N) [n]x of the tilted axis n
    k2: F64  # (Ar, 3, 3, N) [n]x²
    zero: F64  # (Ar, N) rad
    line: F64  # (Al, 3, N) the tilted line of each linear axis
    tool: F64  # (S, 3, N) mm
    w_res: F64  # (R, N) √weight · unit of the row (1e3 µm per mm, 1e6 µrad per rad)
    w_jac: F64  # (R, K, N) √weight · unit of the Jacobian entry (per mm or degree)
    g_const: F64 | None  # (K, R, N) pseudo-inverse of linear-only chains, rows in mm, rad
    gathered: dict[str, NDArray[Any]] = field(default_factory=dict)
    """The last table intervals looked up for these rows and their values."""


@dataclass(frozen=True)
class _Solver:
    """The least squares of one cycle's rows, ``dq = -M⁻¹ Jwᵀ (w r)`` with Jw the weighted
    Jacobian and M = JwᵀJw factored as L D Lᵀ."""

    jw: F64  # (R, K, N) weighted Jacobian (not normalised)
    ldl: F64  # (K, K, N) below the diagonal L's multipliers (the rest is spent)
    pivots: F64  # (K, N) D
    bad: I64  # rows solved by SVD
    g_bad: F64  # (K, R, len(bad)) their pseudo-inverse, residual in mm and rad

    def step(self, wres: F64) -> F64:
        """The corrections' change (K, N) for weighted residuals ``w r`` (R, N)."""
        x: F64 = np.einsum("rkN,rN->kN", self.jw, wres)
        k = x.shape[0]
        for j in range(k - 1):  # L z = x
            x[j + 1:] -= self.ldl[j + 1:, j] * x[j]
        x /= self.pivots  # D w = z
        for j in range(k - 2, -1, -1):  # Lᵀ y = w
            x[j] -= np.einsum("kN,kN->N", self.ldl[j + 1:, j], x[j + 1:])
        if self.bad.size:
            x[:, self.bad] = np.einsum("krn,rn->kn", self.g_bad, wres[:, self.bad])
        return x


class FleetCycle:
    """The corrections of many rows of one :class:`~machine_sim.chaineval.ChainBatch`.

    Parameters
    ----------
    batch : ChainArrays
        The batch: its chain structure and per-machine arrays (read, never written; its
        thermal arrays are read at each call, so temperatures set later count).
    """

    def __init__(self, batch: ChainArrays) -> None:
        self.b = batch
        a = len(batch.axes)
        self.rot = np.flatnonzero(batch.rotary)
        self.lin = np.flatnonzero(~batch.rotary)
        self.lin_dirs = np.array([_DIRS.index(batch.axes[j][0]) for j in self.lin],
                                 dtype=np.int64)
        self.base = tuple("ABC".index(batch.axes[j]) if batch.rotary[j] else -1
                          for j in range(a))
        # where each axis sits among the rotary or the linear axes, and its output column
        self.sub = {int(j): k for k, j in enumerate(self.rot)}
        self.sub.update({int(j): k for k, j in enumerate(self.lin)})
        self.out_of = tuple(batch.outputs.index(x) if x in batch.outputs else -1
                            for x in batch.axes)
        # per spindle the actual chain's steps in the order the tool tip meets them (the
        # README table; the order the reference's pose walks)
        self.steps: list[list[tuple[int, int]]] = []
        for links in batch.links:
            steps: list[tuple[int, int]] = []
            for j in reversed(links):
                if batch.rotary[j]:
                    pair = ((_TURN, j), (_ERROR, j)) if batch.tool_side[j] else \
                        ((_ERROR, j), (_TURN, j))
                else:
                    pair = ((_ERROR, j), (_MOVE, j)) if batch.tool_side[j] else \
                        ((_MOVE, j), (_ERROR, j))
                steps += pair
            self.steps.append(steps)
        self.per = 6 if batch.orient else 3
        k = len(batch.outputs)
        self.unit = np.tile([1e3] * 3 + [1e6] * (self.per - 3), len(batch.links))
        out_rot = batch.rotary[batch.out_col]
        col = np.where(out_rot, 1e3 * DEG, 1e3)  # position rows, per mm or degree
        self.jac_unit = np.tile(np.vstack([np.broadcast_to(col, (3, k)),
                                           np.full((self.per - 3, k), 1e6 * DEG)]),
                                (len(batch.links), 1))  # (R, K)
        # a base turn about axis i: 1 at (i, i), cos at (u, u) and (w, w), sin at (w, u),
        # -sin at (u, w)
        self.turn_planes = [(self.base[j], *_PLANE[self.base[j]]) for j in self.rot.tolist()]
        self._cache: dict[bytes, _Rows] = {}  # by row set: a PLC's groups take turns

    def rows(self, idx: I64) -> _Rows:
        """The per-machine constants of these rows, rows last, cached: a PLC fleet asks for
        the same row sets (its groups) cycle after cycle."""
        key = idx.tobytes()
        found = self._cache.get(key)
        if found is not None:
            return found
        b = self.b

        def last(x: NDArray[Any]) -> NDArray[Any]:  # (N, ...) → (..., N), contiguous
            return np.ascontiguousarray(np.moveaxis(x, 0, -1))

        direction = b.direction[idx]
        w = b.weights[idx] if b.orient else b.weights[idx][:, :, :3]
        sw = np.sqrt(w.reshape(idx.shape[0], -1))  # (N, R)
        g_const = None
        if b.g_const is not None:
            g_const = last(b.g_const[idx] * self.unit)
        rows = _Rows(
            key, last(b.t_first[idx]), last(b.t_last[idx].astype(float)),
            last(b.t_start[idx]), *_table_ranges(b.t_start[idx], b.t_step[idx],
                                                 b.t_last[idx]), last(b.pivot[idx]),
            last(direction), last(_skew(direction[:, self.rot])),
            last(direction[:, self.lin]),
            last(b.frame[idx]) if any(b.spindle_axis) else None,
            last((b.pivot + b.offset)[idx][:, self.rot]), last(b.k1t[idx][:, self.rot]),
            last(b.k2t[idx][:, self.rot]), last(b.zero[idx][:, self.rot]),
            last(b.line[idx][:, self.lin]), last(b.tool[idx]), last(sw * self.unit),
            last(sw[:, :, None] * self.jac_unit), g_const)
        if len(self._cache) >= ROW_SETS:  # a caller that changes its rows every call
            self._cache.clear()
        self._cache[key] = rows
        return rows

    # -- step 1: the component errors
    def components(self, g: _Rows, idx: I64, q: F64) -> F64:
        """Component errors (A, 6, N), mm and rad, at positions q (A, N)."""
        if g.shared_start is None:
            u = q[:, None, :] - g.start
            u *= g.inv_step
        else:  # one subtraction per axis, not per table
            u = (q - g.shared_start)[:, None, :] * g.inv_step
        # the clamp to [0, count - 1] changes nothing while every axis is inside all its
        # tables (the usual case): two checks per axis instead of two passes per table
        if not (bool((q >= g.inside_lo).all()) and bool((q <= g.inside_hi).all())):
            np.maximum(u, 0.0, out=u)
            np.minimum(u, g.last, out=u)
        # interval starts as floats (no conversion of every entry); u = count - 1 (the
        # table's end and beyond) starts at the last value and reads one past it, times 0
        i0 = np.floor(u)
        u -= i0
        # the values at the interval starts and their differences to the next, as the
        # reference computes them: a machine moves far less than a node spacing per cycle,
        # so only the intervals that changed since the last call are gathered (the gather's
        # cache misses were most of its cost)
        at = g.gathered.get("at")
        table = self.b.t_next
        if at is None:
            where = i0.astype(np.int64) + g.first
            val = table.take(where)
            dif = table.take(where + 1) - val
            g.gathered["val"], g.gathered["dif"] = val, dif
        else:
            val, dif = g.gathered["val"], g.gathered["dif"]
            moved = np.flatnonzero(i0 != at)
            if moved.size:
                where = i0.reshape(-1)[moved].astype(np.int64) + g.first.reshape(-1)[moved]
                lo = table.take(where)
                val.reshape(-1)[moved] = lo
                dif.reshape(-1)[moved] = table.take(where + 1) - lo
        g.gathered["at"] = i0
        e: F64 = dif * u
        e += val
        if self.b.thermal_on:
            add = (self.b.thermal0[idx].T + self.b.thermal1[idx].T * q) * 1e-3  # µm → mm
            e[self.lin, self.lin_dirs] += add[self.lin]
        return e

    # -- step 2: the poses
    def nominal(self, g: _Rows, q: F64, angles: tuple[F64, F64, F64]
                ) -> tuple[list[F64], list[list[F64]], F64 | None]:
        """Nominal tool tip (3, N) of each spindle at q (A, N) (``angles``: the rotary axes'
        angles in rad, their cosines and sines, (Ar, N) each), its turns (3, 3, N) in the
        order the tool tip meets them, and the nominal Jacobian (R, K, N) without its units
        (None for linear-only chains, whose pseudo-inverse is fixed)."""
        b = self.b
        n = q.shape[1]
        turn = self.base_turns(angles[1], angles[2])
        moves = q[self.lin][:, None, :] * g.lin_direction if self.lin.size else None
        blocks = self.per // 3
        jac = (np.zeros((len(b.links), blocks, 3, len(b.outputs), n))
               if g.g_const is None else None)
        tips: list[F64] = []
        turns: list[list[F64]] = []
        for s, links in enumerate(b.links):
            p = g.tool[s]
            met: list[F64] = []
            filled: list[int] = []  # columns of the links met so far (after j)
            turning: list[int] = []  # those with an orientation row (rotary axes)
            for j in reversed(links):
                k, at = self.out_of[j], self.sub[j]
                if b.rotary[j]:
                    t = turn[at]
                    if jac is not None:  # the links after j turn with it
                        _turn_columns(jac[s, 0], t, filled)
                        if blocks == 2:
                            _turn_columns(jac[s, 1], t, turning)
                    arm = np.einsum("ijN,jN->iN", t, p - g.pivot[j])
                    p = arm + g.pivot[j]
                    if jac is not None and k >= 0:
                        np.einsum("ijN,jN->iN", g.cross[at], arm, out=jac[s, 0, :, k])
                        filled.append(k)
                        if blocks == 2:
                            jac[s, 1, :, k] = g.direction[j]
                            turning.append(k)
                    met.append(t)
                else:
                    if jac is not None and k >= 0:
                        jac[s, 0, :, k] = g.direction[j]
                        filled.append(k)
                    assert moves is not None
                    p = p + moves[at]
            tips.append(p)
            turns.append(met)
        return tips, turns, None if jac is None else jac.reshape(-1, len(b.outputs), n)

    def base_turns(self, cos: F64, sin: F64) -> F64:
        """The nominal turns (Ar, 3, 3, N) of the rotary axes by the angles of cosines and
        sines (Ar, N): about base x, y or z, built entry by entry."""
        out = np.zeros((len(self.rot), 3, 3, cos.shape[-1]))
        for k, (i, u, w) in enumerate(self.turn_planes):
            out[k, i, i] = 1.0
            out[k, u, u] = out[k, w, w] = cos[k]
            out[k, w, u] = sin[k]
            np.negative(sin[k], out=out[k, u, w])
        return out

    def residual(self, g: _Rows, idx: I64, q: F64, tips: list[F64],
                 turns: list[list[F64]], nominal: tuple[F64, F64, F64]) -> F64:
        """Tool-tip errors (R, N) at positions q (A, N) against the nominal tips, mm and
        rad (rows: per spindle x y z, then the orientation's rotation vector when
        weighed); ``nominal`` as the angles of :meth:`nominal`."""
        b = self.b
        e = self.components(g, idx, q)
        delta, eps = e[:, :3], e[:, 3:]
        if g.frame is not None:
            delta = np.einsum("aijN,ajN->aiN", g.frame, delta)
            eps = np.einsum("aijN,ajN->aiN", g.frame, eps)
        rots = _rotations(eps)  # (A, 3, 3, N)
        if self.rot.size:
            sin, omc = _turned(q[self.rot], g.zero, nominal)
            m = g.k1 * sin[:, None, None]  # I + sin θ [n]x + (1 - cos θ) [n]x²
            m += g.k2 * omc[:, None, None]
            m.reshape(-1, 9, q.shape[1])[:, _DIAG] += 1.0
            shift = delta[self.rot] + g.pivot[self.rot]  # error motion about the pivot
        if self.lin.size:
            moves = q[self.lin][:, None, :] * g.line
        res = np.empty((len(self.unit), q.shape[1]))
        for s, steps in enumerate(self.steps):
            p = g.tool[s]
            r: F64 | None = None  # the identity
            for what, j in steps:
                k = self.sub[j]
                if what == _MOVE:
                    p = p + moves[k]
                    continue
                if what == _TURN:
                    c = g.turn_at[k]
                    mat = m[k]
                    p = np.einsum("ijN,jN->iN", mat, p - c)
                    p += c
                else:
                    mat = rots[j]
                    if b.rotary[j]:
                        p = np.einsum("ijN,jN->iN", mat, p - g.pivot[j])
                        p += shift[k]
                    else:
                        p = np.einsum("ijN,jN->iN", mat, p)
                        p += delta[j]
                if self.per == 6:
                    r = mat if r is None else np.einsum("ijN,jkN->ikN", mat, r)
            at = self.per * s
            np.subtract(p, tips[s], out=res[at:at + 3])
            if self.per == 6:
                if r is None:
                    r = np.broadcast_to(np.eye(3)[:, :, None], (3, 3, q.shape[1]))
                for t in turns[s]:  # r Rnomᵀ, Rnom = the turns met, the first last
                    r = np.einsum("ijN,kjN->ikN", r, t)
                _log_into(r, res[at + 3:at + 6])
        return res

    # -- step 3: the corrections
    def solver(self, g: _Rows, jac: F64) -> _Solver:
        """The least squares of the nominal Jacobian (R, K, N) without its units."""
        jw = jac * g.w_jac
        k, n = jw.shape[1], jw.shape[2]
        m = np.empty((k, k, n))  # its upper triangle: all the factorisation reads
        for j in range(k):
            np.einsum("rN,rlN->lN", jw[:, j], jw[:, j:], out=m[j, j:])
        # the reference normalises the columns first; the solution is the same without,
        # and a pivot of the normalised matrix is this one's over its column's squared
        # norm (the Schur complements scale as the diagonal), so the test is scaled
        diag = m.reshape(k * k, n)[::k + 1]
        zero = diag == 0
        diag += zero  # a zero column (an unobservable axis): a unit pivot, so it gets 0
        limit = diag * PIVOT  # the squared norms (1 for a zero column) times PIVOT
        pivots = np.empty((k, n))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            for j in range(k):  # L D Lᵀ without exchanges: M is positive definite
                pivots[j] = m[j, j]
                if j + 1 < k:  # row j right of the pivot is D_j L[j+1:, j]ᵀ
                    low = m[j, j + 1:] / m[j, j]
                    m[j + 1:, j + 1:] -= low[:, None] * m[j, j + 1:]  # upper part is right
                    m[j + 1:, j] = low
        ok = (pivots > limit).all(axis=0)  # NaN after a bad pivot counts as bad
        bad = np.flatnonzero(~ok) if not ok.all() else np.zeros(0, dtype=np.int64)
        g_bad = np.zeros((k, jw.shape[0], 0))
        if bad.size:  # rank-deficient rows: the SVD with the README's tolerance
            scale = np.sqrt(limit[:, bad] / PIVOT)
            a = jw[:, :, bad] / scale
            u, sv, vt = np.linalg.svd(np.moveaxis(a, -1, 0), full_matrices=False)
            keep = sv > RCOND * sv[:, :1]
            si = np.where(keep, 1.0 / np.where(keep, sv, 1.0), 0.0)
            g_bad = np.einsum("nji,nj,nkj->ikn", vt, si, u)
            g_bad /= scale[:, None, :]
        return _Solver(jw, m, pivots, bad, g_bad)

    def corrections(self, idx: I64, q: F64, start: F64 | None, max_steps: int) -> F64:
        """Unrounded, unclamped corrections (K, N) of rows (machine idx (N,), positions q
        (A, N) rows last, contiguous), refined from ``start`` (K, N) or 0."""
        g = self.rows(idx)
        angle = q[self.rot] * DEG
        nominal = (angle, np.cos(angle), np.sin(angle))
        tips, turns, jac = self.nominal(g, q, nominal)
        solve = None if jac is None else self.solver(g, jac)
        out_col = self.b.out_col
        dq = np.zeros_like(q)
        if start is not None:
            dq[out_col] = start
        for step in range(max_steps):
            res = self.residual(g, idx, q + dq, tips, turns, nominal)
            if solve is None:
                assert g.g_const is not None
                delta = np.einsum("krN,rN->kN", g.g_const, res)
            else:
                with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                    delta = solve.step(res * g.w_res)
            dq[out_col] -= delta
            if step + 1 < max_steps and float(np.abs(delta).max(initial=0.0)) <= STEP_TOL:
                break
        out: F64 = dq[out_col]
        return out


# --- small rows-last helpers --------------------------------------------------------------

def _skew(d: F64) -> F64:
    """Cross-product matrices (..., 3, 3) of vectors d (..., 3)."""
    out = np.zeros((*d.shape, 3))
    out[..., 2, 1], out[..., 0, 2], out[..., 1, 0] = d[..., 0], d[..., 1], d[..., 2]
    out[..., 1, 2], out[..., 2, 0], out[..., 0, 1] = -d[..., 0], -d[..., 1], -d[..., 2]
    return out


def _rotations(w: F64) -> F64:
    """Rotation matrices (A, 3, 3, N) of rotation vectors w (A, 3, N), exact Rodrigues:
    ``(1 - b θ²) I + a [w]x + b w wᵀ`` with a = sin θ/θ, b = (1 - cos θ)/θ² (their
    series when every θ² is below SERIES, as the reference chooses)."""
    t2 = np.einsum("aiN,aiN->aN", w, w)
    if float(t2.max(initial=0.0)) < SERIES:
        ab = _SERIES_C[2] * t2
        ab += _SERIES_C[1]
        ab *= t2
        ab += _SERIES_C[0]
        a, b = ab[0], ab[1]
    else:
        pos = t2 > 0
        t = np.sqrt(np.where(pos, t2, 1.0))
        a = np.where(pos, np.sin(t) / t, 1.0)
        b = np.where(pos, (1.0 - np.cos(t)) / (t * t), 0.5)
    n_ax, n = w.shape[0], w.shape[2]
    out = np.empty((n_ax, 9, n))
    bw = b[:, None] * w
    diag = out[:, _DIAG]
    np.multiply(bw, w, out=diag)
    diag += (1.0 - b * t2)[:, None]
    sym = bw[:, [0, 0, 1]] * w[:, [1, 2, 2]]  # b w wᵀ above the diagonal
    skew = a[:, None] * w[:, [2, 1, 0]]
    skew *= _SKEW_SIGN  # a [w]x above the diagonal (below: its negative)
    out[:, _UPPER] = sym + skew
    out[:, _LOWER] = sym - skew
    rot: F64 = out.reshape(n_ax, 3, 3, n)
    return rot


def _table_ranges(start: F64, step: F64, last: I64
                  ) -> tuple[F64, F64 | None, F64, F64]:
    """From the tables (N, A, 6) of a row set, rows last: 1/step (0 for tables of one
    value or none, so their u stays 0 with no clamp), the axes' shared start (None unless
    every axis's tables of more than one value start at one position in every row), and
    the positions (A, N) inside all of an axis's tables, where the clamp is a no-op: at or
    above the largest start, at or below the smallest end less 1e-9 of its size (far more
    than the rounding of u = (q - start) / step, far less than a node spacing)."""
    varying = last > 0
    inv = np.where(varying, 1.0 / step, 0.0)
    end = start + last * step
    lo = np.where(varying, start, -np.inf).max(axis=2)
    hi = np.where(varying, end - 1e-9 * (np.abs(end) + np.abs(start) + 1.0), np.inf).min(axis=2)
    first = np.where(varying, start, np.nan)
    same = np.all(~varying | (first == np.where(np.isfinite(lo), lo, 0.0)[:, :, None]))
    shared = np.where(np.isfinite(lo), lo, 0.0) if same else None

    def rows_last(x: F64) -> F64:
        return np.ascontiguousarray(np.moveaxis(x, 0, -1))

    return (rows_last(inv), None if shared is None else rows_last(shared), rows_last(lo),
            rows_last(hi))


def _turned(q: F64, zero: F64, nominal: tuple[F64, F64, F64]) -> tuple[F64, F64]:
    """sin θ and 1 - cos θ (Ar, N) of θ = q·DEG + zero (q in degrees), from the nominal
    angle's (``nominal``: angle, cos, sin) by the angle-addition formulas: θ is within a
    correction (at most the map's limit) and a location error of it, so the difference φ
    is small and its sine and 1 - cosine are their series, exact to double precision
    below |φ| = 0.01 rad (no sine or cosine of a whole array, ~9 ns an element); beyond,
    sin and cos of θ."""
    angle, cos0, sin0 = nominal
    phi = q * DEG
    phi -= angle
    phi += zero
    p2 = phi * phi
    if float(p2.max(initial=0.0)) >= 1e-4:
        theta = q * DEG
        theta += zero
        return np.sin(theta), 1.0 - np.cos(theta)
    series = _TURN_C[3] * p2  # sin φ / φ and (1 - cos φ) / φ², Horner in φ²
    series += _TURN_C[2]
    series *= p2
    series += _TURN_C[1]
    series *= p2
    series += _TURN_C[0]
    sin_phi = series[0] * phi
    omc_phi = series[1] * p2
    sin = cos0 * sin_phi  # sin(θ0 + φ) = sin θ0 (1 - (1 - cos φ)) + cos θ0 sin φ
    sin -= sin0 * omc_phi
    sin += sin0
    omc = cos0 * omc_phi  # 1 - cos(θ0 + φ) = (1 - cos θ0) + cos θ0 (1 - cos φ) + sin θ0 sin φ
    omc += sin0 * sin_phi
    omc += 1.0 - cos0
    return sin, omc


def _turn_columns(x: F64, t: F64, cols: list[int]) -> None:
    """Turn, in place, the columns ``cols`` of x (3, K, N) by the turns t (3, 3, N): a
    slice when they are contiguous (outputs in chain order), as they usually are."""
    if not cols:
        return
    lo, hi = min(cols), max(cols) + 1
    at: slice | list[int] = slice(lo, hi) if hi - lo == len(cols) else cols
    x[:, at] = np.einsum("ijN,jkN->ikN", t, x[:, at])


def _log_into(r: F64, out: F64) -> None:
    """Rotation vectors (3, N) of rotation matrices r (3, 3, N) into ``out``: the vector
    of r's antisymmetric part times θ / sin θ (θ from the trace); 1 + θ²/6 for θ below
    1e-4, as the reference, where with sin θ = s the factor is 1 + s²/6 to rounding."""
    f = r.reshape(9, -1)
    np.subtract(f[_SKEW_PLUS], f[_SKEW_MINUS], out=out)
    out *= 0.5
    s2 = np.einsum("iN,iN->N", out, out)
    trace = f[_DIAG].sum(axis=0)
    if float(s2.max(initial=0.0)) < 0.98e-8 and float(trace.min(initial=3.0)) > 1.0:
        s2 *= 1.0 / 6.0  # every θ < 1e-4 (sin θ < 0.99e-4 and cos θ > 0)
        s2 += 1.0
        out *= s2
        return
    s = np.sqrt(s2)
    c = np.clip(0.5 * (trace - 1.0), -1.0, 1.0)
    theta = np.arctan2(s, c)
    small = theta < 1e-4
    out *= np.where(small, 1.0 + theta * theta / 6.0, theta / np.where(small, 1.0, s))
