"""The machine endpoint's evaluation of a ``tables`` map: chain, errors, corrections.

Written from protocol/README.md sections 6.2 and 6.3 alone, on purpose without importing
:mod:`volumetric` (a PLC programmer has only the README); ``tests/test_sim_tables.py``
pins it against the center's solver. Per point and cycle:

1. each axis's six component errors: its tables interpolated linearly at the axis's
   commanded position (end values hold outside), µm and µrad; thermal records add
   ``coefficient · ΔT`` (drift) or ``coefficient · ΔT · (q - q_min) · 1e-3`` (expansion)
   to ``E<K><K>`` at the latest temperatures;
2. the tool tip's pose relative to the workpiece, per spindle, exactly: a backward pass
   from the tool over the branch's links, each link one rigid motion (README table),
   error rotations by the exact Rodrigues formula; once with and once without errors;
3. the corrections: ``dq = -G e`` with ``G`` the column-normalised, weighted minimum-norm
   pseudo-inverse of the nominal Jacobian at q (singular values below 1e-9 σ_max count as
   zero; computed from a Cholesky factorisation of the normal matrix for well-posed rows,
   by SVD for the others), refined ``dq ← dq - G r(dq)`` with the exact residual at
   ``q + dq`` until no correction changes by more than 1e-7 mm (deg), at most 6 steps;
4. clamp to ±limit (mm or deg), round to the map's encoding, add the reversal while the
   axis last moved in the negative direction.

Everything is vectorised over rows of (machine, point): :class:`ChainBatch` holds M
machines whose maps share one chain structure (same axes, sides, branches, outputs) and
evaluates any number of rows, each with its machine index, in one call; a whole fleet's
PLC cycle is one call per chain structure (``benchmarks/fleet_scan.py``).

Two evaluations of the same steps: :meth:`ChainBatch.corrections` hands the rows to
:class:`machine_sim.chaineval_cycle.FleetCycle` (the fleet cycle: the rows as the last
axis of every array, every table value of every row in one gather, every axis's error
rotation in one set of calls, one matrix-vector product per link step, the Jacobian from
the nominal backward pass, the least squares factored in closed form for all rows), and
:meth:`ChainBatch.corrections_reference` writes the steps as above with the rows first
(stacked 3x3 products), the check of the first (``tests/test_chaineval_fast.py``). Both
are exact (no small-angle truncation): they agree to rounding.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from protocol.codes import MapEncoding
from protocol.maptables import THERMAL_DRIFT, ComponentTable, TablesPayload

from .chaineval_cycle import ROW_SETS, FleetCycle
from .chaineval_rules import DEG, MAX_STEPS, PIVOT, RCOND, SERIES, STEP_TOL

__all__ = ["MAX_STEPS", "PIVOT", "RCOND", "STEP_TOL", "ChainBatch", "StructureError",
           "sensor_key", "structure_of"]

F64 = NDArray[np.float64]
I64 = NDArray[np.int64]
_DEG = DEG
_SERIES = SERIES
_DIRS = "XYZABC"
_EYE = np.eye(3)


class StructureError(ValueError):
    """Maps that cannot share one batch (different chains), or bad evaluation input."""


def sensor_key(name: str) -> str:
    """The machine sensor a label names: ``T_spindle_C`` and ``spindle`` are the same."""
    if len(name) > 4 and name.startswith("T_") and name.endswith("_C"):
        return name[2:-2]
    return name


def structure_of(p: TablesPayload) -> tuple[object, ...]:
    """What maps must share to be evaluated in one batch."""
    return (tuple((a.name, a.rotary, a.tool_side) for a in p.axes),
            tuple(s.axes for s in p.spindles), tuple(o.name for o in p.outputs))


# --- small vectorised rigid-body helpers over (N, 3) -----------------------------------

def _cross(a: F64, b: F64) -> F64:
    return np.stack((a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]), axis=-1)


def _rodrigues(w: F64) -> tuple[F64, F64]:
    """sin θ/θ and (1 - cos θ)/θ² of rotation vectors w (..., 3)."""
    t2 = np.einsum("...i,...i->...", w, w)
    if float(np.max(t2, initial=0.0)) < _SERIES:
        return 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0), 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0)
    t = np.sqrt(t2)
    safe = np.where(t2 > 0, t, 1.0)
    return (np.where(t2 > 0, np.sin(safe) / safe, 1.0),
            np.where(t2 > 0, (1.0 - np.cos(safe)) / (safe * safe), 0.5))


def _rotate(w: F64, v: F64) -> F64:
    """Rotate v (N, 3) by rotation vectors w (N, 3): exact."""
    a, b = _rodrigues(w)
    wv = _cross(w, v)
    out: F64 = v + a[..., None] * wv + b[..., None] * _cross(w, wv)
    return out


def _skew(w: F64) -> F64:
    z = np.zeros(w.shape[:-1])
    return np.stack((np.stack((z, -w[..., 2], w[..., 1]), -1),
                     np.stack((w[..., 2], z, -w[..., 0]), -1),
                     np.stack((-w[..., 1], w[..., 0], z), -1)), -2)


def _matrix(w: F64) -> F64:
    """Rotation matrices (N, 3, 3) of rotation vectors (N, 3): exact Rodrigues,
    ``I + a [w]x + b [w]x²`` with ``[w]x² = w wᵀ - |w|² I``, written entry by entry."""
    a, b = _rodrigues(w)
    t2 = np.einsum("ni,ni->n", w, w)
    out: F64 = b[:, None, None] * (w[:, :, None] * w[:, None, :])
    diag = 1.0 - b * t2
    aw = a[:, None] * w
    for i, (u, v) in enumerate(((1, 2), (2, 0), (0, 1))):
        out[:, i, i] += diag
        out[:, v, u] += aw[:, i]
        out[:, u, v] -= aw[:, i]
    return out


def _turn_matrix(d: F64, theta: F64) -> F64:
    """Rotations (N, 3, 3) by θ (N,) rad about unit axes d (N, 3)."""
    k = _skew(d)
    out: F64 = (np.eye(3) + np.sin(theta)[:, None, None] * k
                + (1.0 - np.cos(theta))[:, None, None] * (k @ k))
    return out


class _Identity:
    """The orientation before the first link: multiplying by it costs nothing."""


_IDENTITY: Final = _Identity()


Orient = F64 | _Identity | None
"""An orientation being walked: (N, 3, 3), the identity, or None when not wanted."""


def _times(m: F64, r: Orient) -> F64 | None:
    """``m @ r`` for orientations (N, 3, 3), None or the identity."""
    if r is None:
        return None
    if isinstance(r, _Identity):
        return m
    out: F64 = m @ r
    return out


def _spd_inverse(m: F64) -> tuple[F64, NDArray[np.bool_]]:
    """Inverses (N, n, n) of symmetric positive definite matrices by a Cholesky
    factorisation written over the N rows (LAPACK's batched calls cost more than the
    arithmetic for n <= 16), and which rows are well-posed: every pivot above PIVOT."""
    n = m.shape[1]
    low: dict[tuple[int, int], F64] = {}
    ok = np.ones(m.shape[0], dtype=bool)
    for j in range(n):
        s = m[:, j, j] - sum((low[j, k] ** 2 for k in range(j)), np.zeros(m.shape[0]))
        ok &= s > PIVOT
        low[j, j] = np.sqrt(np.where(s > PIVOT, s, 1.0))
        for i in range(j + 1, n):
            acc = m[:, i, j] - sum((low[i, k] * low[j, k] for k in range(j)),
                                   np.zeros(m.shape[0]))
            low[i, j] = acc / low[j, j]
    inv_l: dict[tuple[int, int], F64] = {}
    for i in range(n):
        inv_l[i, i] = 1.0 / low[i, i]
        for j in range(i):
            acc = sum((low[i, k] * inv_l[k, j] for k in range(j, i)), np.zeros(m.shape[0]))
            inv_l[i, j] = -acc / low[i, i]
    out = np.empty_like(m)
    for i in range(n):
        for j in range(i + 1):
            v = sum((inv_l[k, i] * inv_l[k, j] for k in range(i, n)), np.zeros(m.shape[0]))
            out[:, i, j] = v
            out[:, j, i] = v
    return out, ok


def _log(r: F64) -> F64:
    """Rotation vectors (N, 3) of rotation matrices (N, 3, 3)."""
    v = 0.5 * np.stack((r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0],
                        r[:, 1, 0] - r[:, 0, 1]), -1)
    s = np.sqrt(np.einsum("ni,ni->n", v, v))
    c = np.clip(0.5 * (np.trace(r, axis1=1, axis2=2) - 1.0), -1.0, 1.0)
    theta = np.arctan2(s, c)
    small = theta < 1e-4
    factor = np.where(small, 1.0 + theta * theta / 6.0, theta / np.where(small, 1.0, s))
    out: F64 = v * factor[:, None]
    return out


def _frame_from_z(d: tuple[float, float, float]) -> F64:
    """The smallest rotation taking the base z axis onto unit d (spindle axes' frame)."""
    dv = np.asarray(d, dtype=float)
    axis = np.cross([0.0, 0.0, 1.0], dv)
    s, c = float(np.linalg.norm(axis)), float(dv[2])
    if s < 1e-15:
        flip: F64 = np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
        return flip
    out: F64 = _turn_matrix((axis / s)[None, :], np.array([math.atan2(s, c)]))[0]
    return out


# --- the batch --------------------------------------------------------------------------

@dataclass(frozen=True)
class _Pose:
    p: F64  # (N, 3) mm
    r: F64 | None  # (N, 3, 3)


class ChainBatch:
    """M tables maps with one chain structure, evaluated together.

    Parameters
    ----------
    maps : sequence of TablesPayload
        All with the same :func:`structure_of`.

    Attributes
    ----------
    axes : tuple of str
        Chain axes: the columns of the positions ``q`` (mm, degrees).
    outputs : tuple of str
        Corrected axes: the columns of the corrections.
    """

    def __init__(self, maps: Sequence[TablesPayload]) -> None:
        if not maps:
            raise StructureError("a ChainBatch needs at least one map")
        first = structure_of(maps[0])
        for i, p in enumerate(maps):
            if structure_of(p) != first:
                raise StructureError(f"map {i} ({p.machine}) has another chain structure "
                                     f"than map 0 ({maps[0].machine})")
        p0 = maps[0]
        self.maps = tuple(maps)
        self.axes = p0.axis_names
        self.outputs = tuple(o.name for o in p0.outputs)
        self.rotary = np.array([a.rotary for a in p0.axes])
        self.tool_side = tuple(a.tool_side for a in p0.axes)
        self.links = tuple(tuple(self.axes.index(a) for a in s.axes) for s in p0.spindles)
        self.out_col = np.array([self.axes.index(o) for o in self.outputs], dtype=np.int64)
        self.out_rotary = self.rotary[self.out_col]
        m, a = len(maps), len(self.axes)
        self.direction = np.array([[x.direction for x in p.axes] for p in maps])  # (M, A, 3)
        self.pivot = np.array([[x.pivot_mm for x in p.axes] for p in maps])
        self.frame = np.array([[_frame_from_z(x.direction) if x.name[1:] else np.eye(3)
                                for x in p.axes] for p in maps])  # (M, A, 3, 3)
        self.spindle_axis = tuple(bool(x.name[1:]) for x in p0.axes)  # own, tilted frame
        self.tool = np.array([[np.multiply(s.tool_length_mm, s.tool_direction)
                               for s in p.spindles] for p in maps])  # (M, S, 3)
        self.weights = np.array([[s.weights for s in p.spindles] for p in maps])  # (M, S, 6)
        self.orient = bool(np.any(self.weights[:, :, 3:] > 0))
        self._locations(maps)
        self._tables(maps)
        self.thermal0 = np.zeros((m, a))  # µm added to E<K><K>, constant part
        self.thermal1 = np.zeros((m, a))  # µm per mm of q
        lim = np.array([[p.limit_mm, p.limit_deg] for p in maps])
        self.limit = np.where(self.out_rotary[None, :], lim[:, 1:2], lim[:, 0:1])  # (M, K)
        self.int32 = np.array([p.encoding is MapEncoding.INT32_INCREMENTS for p in maps])
        self.increment = np.array([p.increment_mm if p.encoding is
                                   MapEncoding.INT32_INCREMENTS else 1.0 for p in maps])
        self.reversal = np.array([[0.0 if o.reversal is None else o.reversal
                                   for o in p.outputs] for p in maps])  # encoding units
        self._gathered: tuple[bytes, dict[str, NDArray[Any]]] | None = None
        self.g_const: F64 | None = None
        """(M, K, R): the pseudo-inverse of chains without rotary axes (the same at every q)."""
        self.thermal_on = False
        if not self.rotary.any():
            idx = np.arange(m)
            self.g_const = self._pinv(idx, self.jacobian(idx, np.zeros((m, a))))
        self._cycle = FleetCycle(self)
        self._limits: dict[bytes, F64] = {}  # finish's limits by row set

    def __len__(self) -> int:
        return len(self.maps)

    # -- set-up
    def _locations(self, maps: Sequence[TablesPayload]) -> None:
        m, a = len(maps), len(self.axes)
        self.tilt = np.zeros((m, a, 3))  # rad, base frame
        self.offset = np.zeros((m, a, 3))  # mm
        self.zero = np.zeros((m, a))  # rad
        for i, p in enumerate(maps):
            loc = dict(p.locations)
            for j, ax in enumerate(p.axes):
                ang = np.array([loc.get(f"E{c}0{ax.name}", 0.0) for c in "ABC"]) * 1e-6
                if ax.rotary:
                    d = self.direction[i, j]
                    self.zero[i, j] = float(ang @ d)
                    self.tilt[i, j] = ang - self.zero[i, j] * d
                    self.offset[i, j] = np.array(
                        [loc.get(f"E{c}0{ax.name}", 0.0) for c in "XYZ"]) * 1e-3
                else:
                    self.tilt[i, j] = self.frame[i, j] @ ang
        # a linear axis's tilted line of motion and a rotary axis's tilt, once
        self.line = _rotate(self.tilt.reshape(-1, 3),
                            self.direction.reshape(-1, 3)).reshape(m, a, 3)
        # a rotary axis turning about its tilted line: Rot(τ) Turn(d, θ) Rot(τ)ᵀ is the turn
        # about Rot(τ) d, so one Rodrigues form per cycle (README step 3)
        tilted = _rotate(self.tilt.reshape(-1, 3), self.direction.reshape(-1, 3))
        k1 = _skew(tilted)
        self.k1t = k1.reshape(m, a, 3, 3)
        self.k2t = (k1 @ k1).reshape(m, a, 3, 3)

    def _tables(self, maps: Sequence[TablesPayload]) -> None:
        m, a = len(maps), len(self.axes)
        values: list[float] = [0.0]  # entry 0: the shared zero of every missing table
        self.t_first = np.zeros((m, a, 6), dtype=np.int64)
        self.t_last = np.zeros((m, a, 6), dtype=np.int64)  # count - 1
        self.t_start = np.zeros((m, a, 6))
        self.t_step = np.ones((m, a, 6))
        found: dict[tuple[int, int, int], ComponentTable] = {}
        for i, p in enumerate(maps):
            for t in p.tables:
                found[self.axes.index(t.axis), _DIRS.index(t.name[1]), i] = t
        # one component's tables of every machine side by side: a cycle reads them in
        # that order, through a few pages instead of the whole array (the gather is
        # bound by cache and TLB misses, not arithmetic)
        for (j, c, i), t in sorted(found.items()):
            self.t_first[i, j, c] = len(values)
            self.t_last[i, j, c] = len(t.values) - 1
            self.t_start[i, j, c] = t.start
            self.t_step[i, j, c] = t.step if len(t.values) > 1 else 1.0
            values.extend(t.values)
        self.t_values = np.asarray(values, dtype=np.float64)
        self.t_cap = np.maximum(self.t_last - 1, 0)
        self.t_end = self.t_first + self.t_last  # index of each table's last value
        # the values in mm and rad (each belongs to one component: its unit is known)
        unit = np.zeros(len(values))
        for c, f in enumerate((1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6)):
            for first, last in zip(self.t_first[:, :, c].ravel(), self.t_last[:, :, c].ravel(),
                                   strict=True):
                unit[first:first + last + 1] = f
        # the fleet cycle reads each interval's two values side by side (one cache line:
        # its gather is bound by cache misses); at a table's end it reads one past the
        # last value with u = 0, so one more value ends the array (t_si is a view of it)
        self.t_next = np.zeros(len(values) + 1)
        np.multiply(self.t_values, unit, out=self.t_next[:-1])
        self.t_si = self.t_next[:-1]

    def set_temperatures(self, machine: int, temperatures: Mapping[str, float]) -> None:
        """Fold machine ``machine``'s thermal records at these temperatures (°C, keyed by
        sensor label or ``T_<label>_C``) into its errors; a sensor without a value counts
        as at its reference temperature."""
        temps = {sensor_key(k): float(v) for k, v in temperatures.items()}
        self.thermal0[machine] = 0.0
        self.thermal1[machine] = 0.0
        for rec in self.maps[machine].thermal:
            t = temps.get(sensor_key(rec.sensor))
            if t is None or not math.isfinite(t):
                continue
            j = self.axes.index(rec.axis)
            dt = t - rec.t_ref_C
            if rec.kind == THERMAL_DRIFT:
                self.thermal0[machine, j] += rec.coefficient * dt
            else:
                slope = rec.coefficient * dt * 1e-3
                self.thermal0[machine, j] -= slope * rec.q_min
                self.thermal1[machine, j] += slope
        self.thermal_on = bool(self.thermal0.any() or self.thermal1.any())

    def _rows_of(self, idx: I64) -> dict[str, NDArray[Any]]:
        """The per-machine constants gathered for these rows, cached: a PLC fleet asks
        for the same rows (its groups) every cycle."""
        key = idx.tobytes()
        if self._gathered is None or self._gathered[0] != key:
            names = ("t_first", "t_last", "t_cap", "t_end", "t_start", "t_step", "pivot",
                     "frame",
                     "direction", "line", "k1t", "k2t", "offset", "zero", "tool")
            self._gathered = (key, {k: getattr(self, k)[idx] for k in names})
        return self._gathered[1]

    # -- step 1: component errors
    def components(self, idx: I64, q: F64) -> F64:
        """Component errors (N, A, 6) in mm and rad of rows (machine idx, positions q)."""
        g = self._rows_of(idx)
        u = np.clip((q[:, :, None] - g["t_start"]) / g["t_step"], 0.0, g["t_last"])
        i0 = np.minimum(u.astype(np.int64), g["t_cap"])  # u >= 0: truncation is floor
        at = g["t_first"] + i0
        lo = self.t_si[at]
        e: F64 = lo + (u - i0) * (self.t_si[np.minimum(at + 1, g["t_end"])] - lo)
        if self.thermal0.any() or self.thermal1.any():
            add = (self.thermal0[idx] + self.thermal1[idx] * q) * 1e-3  # µm → mm
            for j, name in enumerate(self.axes):
                if not self.rotary[j]:
                    e[:, j, _DIRS.index(name[0])] += add[:, j]
        return e

    # -- step 2: the pose
    def pose(self, idx: I64, q: F64, spindle: int, comps: F64 | None,
             orientation: bool) -> _Pose:
        """Tool tip pose of one spindle relative to the workpiece: position (N, 3) mm and
        orientation (N, 3, 3); ``comps`` None for the nominal machine.

        A backward pass from the tool: each link is a rigid motion ``x ↦ M x + t`` applied
        to the tool tip (and M to the orientation), in the order of the README's table."""
        n, na = q.shape
        g = self._rows_of(idx)
        p = g["tool"][:, spindle].copy()
        r: Orient = _IDENTITY if orientation else None
        if comps is not None:  # every axis's error motion at once: fewer, larger calls
            delta, eps = comps[:, :, :3], comps[:, :, 3:]
            if any(self.spindle_axis):
                delta = np.einsum("naij,naj->nai", g["frame"], delta)
                eps = np.einsum("naij,naj->nai", g["frame"], eps)
            rots = _matrix(np.ascontiguousarray(eps).reshape(-1, 3)).reshape(n, na, 3, 3)
        for j in reversed(self.links[spindle]):
            qj = q[:, j]
            err = None if comps is None else (delta[:, j], rots[:, j])
            if self.rotary[j]:
                if self.tool_side[j]:
                    p, r = self._rotary(idx, j, qj, p, r, comps is not None)
                    p, r = self._error(err, g["pivot"][:, j], p, r)
                else:
                    p, r = self._error(err, g["pivot"][:, j], p, r)
                    p, r = self._rotary(idx, j, qj, p, r, comps is not None)
            else:
                d = g["line"][:, j] if comps is not None else g["direction"][:, j]
                if self.tool_side[j]:
                    p, r = self._error(err, None, p, r)
                    p = p + qj[:, None] * d
                else:
                    p = p + qj[:, None] * d
                    p, r = self._error(err, None, p, r)
        if isinstance(r, _Identity):  # no rotation on the way (linear axes, nominal)
            r = np.broadcast_to(_EYE, (n, 3, 3)).copy()
        return _Pose(p, r)

    @staticmethod
    def _error(err: tuple[F64, F64] | None, pivot: F64 | None, p: F64, r: Orient
               ) -> tuple[F64, Orient]:
        """The axis's error motion (translation δ, rotation matrix E about the pivot)."""
        if err is None:
            return p, r
        delta, rot = err
        if pivot is None:
            p = np.einsum("nij,nj->ni", rot, p) + delta
        else:
            p = np.einsum("nij,nj->ni", rot, p - pivot) + pivot + delta
        return p, _times(rot, r)

    def _turns(self, idx: I64, j: int, theta: F64) -> F64:
        """Rotations (N, 3, 3) by θ (N,) rad about rotary axis j (A, B, C turn about the
        base x, y, z), entry by entry."""
        i = "ABC".index(self.axes[j])
        u, v = ((1, 2), (2, 0), (0, 1))[i]
        c, s = np.cos(theta), np.sin(theta)
        out = np.zeros((theta.shape[0], 3, 3))
        out[:, i, i] = 1.0
        out[:, u, u] = c
        out[:, v, v] = c
        out[:, u, v] = -s
        out[:, v, u] = s
        return out

    def _rotary(self, idx: I64, j: int, qj: F64, p: F64, r: Orient, actual: bool
                ) -> tuple[F64, Orient]:
        g = self._rows_of(idx)
        c = g["pivot"][:, j]
        if not actual:
            turn = self._turns(idx, j, qj * _DEG)
            p = np.einsum("nij,nj->ni", turn, p - c) + c
            return p, _times(turn, r)
        # L R(θ + zero) L⁻¹: L the axis's tilt about the pivot, then its offset; the
        # conjugated turn is the turn about the tilted axis
        theta = qj * _DEG + g["zero"][:, j]
        m = (_EYE + np.sin(theta)[:, None, None] * g["k1t"][:, j]
             + (1.0 - np.cos(theta))[:, None, None] * g["k2t"][:, j])
        c = c + g["offset"][:, j]
        p = np.einsum("nij,nj->ni", m, p - c) + c
        return p, _times(m, r)

    # -- step 3: the corrections
    def _rows(self, idx: I64) -> F64:
        """Weights (N, R) of the stacked error rows (per spindle x y z, then a b c when
        the batch weighs orientation)."""
        w = self.weights[idx] if self.orient else self.weights[idx][:, :, :3]
        out: F64 = w.reshape(idx.shape[0], -1)
        return out

    def nominal(self, idx: I64, q: F64) -> tuple[list[_Pose], F64]:
        """Nominal pose of every spindle at q and the nominal Jacobian (N, R, K) there:
        rows µm and µrad, columns per mm or degree of each output axis."""
        n = q.shape[0]
        per = 6 if self.orient else 3
        jac = np.zeros((n, per * len(self.links), len(self.outputs)))
        poses = []
        turns = {j: self._turns(idx, j, q[:, j] * _DEG) for j in range(len(self.axes))
                 if self.rotary[j]}
        for s, links in enumerate(self.links):
            after: dict[int, F64] = {}
            p = self.tool[idx, s].copy()
            for j in reversed(links):  # tool tip seen from after each link
                after[j] = p
                if self.rotary[j]:
                    c = self.pivot[idx, j]
                    p = np.einsum("nij,nj->ni", turns[j], p - c) + c
                else:
                    p = p + q[:, j, None] * self.direction[idx, j]
            rot = np.broadcast_to(_EYE, (n, 3, 3))
            for j in links:  # rotation of the frame before each link, forwards
                d = self.direction[idx, j]
                hits = np.flatnonzero(self.out_col == j)
                if self.rotary[j]:
                    if hits.size:
                        arm = np.einsum("nij,nj->ni", turns[j], after[j] - self.pivot[idx, j])
                        k = int(hits[0])
                        jac[:, per * s:per * s + 3, k] = np.einsum(
                            "nij,nj->ni", rot, _cross(d, arm)) * (1e3 * _DEG)
                        if self.orient:
                            jac[:, per * s + 3:per * s + 6, k] = np.einsum(
                                "nij,nj->ni", rot, d) * (1e6 * _DEG)
                    rot = rot @ turns[j]
                elif hits.size:
                    jac[:, per * s:per * s + 3, int(hits[0])] = np.einsum(
                        "nij,nj->ni", rot, d) * 1e3
            poses.append(_Pose(p, rot if self.orient else None))
        return poses, jac

    def jacobian(self, idx: I64, q: F64) -> F64:
        """Nominal Jacobian (N, R, K) at q (see :meth:`nominal`)."""
        return self.nominal(idx, q)[1]

    def _pinv(self, idx: I64, jac: F64) -> F64:
        """``G`` (N, K, R) with ``dq = -G e``: weighted, column-normalised min-norm
        pseudo-inverse of the nominal Jacobian."""
        sw = np.sqrt(self._rows(idx))
        a = jac * sw[:, :, None]
        norms = np.sqrt(np.einsum("nri,nri->ni", a, a))
        scale = np.where(norms > 0, norms, 1.0)
        a = a / scale[:, None, :]
        # well-posed rows: (AᵀA)⁻¹Aᵀ, the min-norm pseudo-inverse when A has full column
        # rank; a zero column (an unobservable axis) gets a unit pivot and so 0
        m = np.swapaxes(a, 1, 2) @ a
        k = np.arange(a.shape[2])
        m[:, k, k] += norms == 0
        inv, ok = _spd_inverse(m)
        g = inv @ np.swapaxes(a, 1, 2)
        if not ok.all():  # rank-deficient rows: the SVD with the README's tolerance
            bad = np.flatnonzero(~ok)
            u, s, vt = np.linalg.svd(a[bad], full_matrices=False)
            keep = s > RCOND * s[:, :1]
            si = np.where(keep, 1.0 / np.where(keep, s, 1.0), 0.0)
            g[bad] = np.einsum("nji,nj,nkj->nik", vt, si, u)
        out: F64 = g / scale[:, :, None] * sw[:, None, :]
        return out

    def _residual(self, idx: I64, q: F64, dq: F64, nominal: list[_Pose]) -> F64:
        """Stacked tool-tip errors (N, R) at q + dq against the nominal poses at q."""
        qc = q + dq
        comps = self.components(idx, qc)
        rows = []
        for s in range(len(self.links)):
            act = self.pose(idx, qc, s, comps, self.orient)
            rows.append((act.p - nominal[s].p) * 1e3)
            r_act, r_nom = act.r, nominal[s].r
            if r_act is not None and r_nom is not None:
                rows.append(_log(r_act @ np.swapaxes(r_nom, 1, 2)) * 1e6)
        return np.concatenate(rows, axis=1)

    def errors(self, idx: I64 | None, q: F64) -> F64:
        """Tool-tip errors (N, R) at q: per spindle position µm (and orientation µrad when
        weighed), before any correction."""
        idx, q = self._check(idx, q)
        return self._residual(idx, q, np.zeros_like(q), self.nominal(idx, q)[0])

    def corrections(self, idx: I64 | None, q: F64, start: F64 | None = None,
                    max_steps: int = MAX_STEPS) -> F64:
        """Unrounded, unclamped corrections (N, K), mm or degrees, of the outputs.

        The steps of :meth:`corrections_reference` arranged for a fleet's cycle
        (:class:`~machine_sim.chaineval_cycle.FleetCycle`: the rows as the last axis of
        every array, few numpy calls per link); equal to it to rounding, within 3e-12 mm
        on the same rows (``tests/test_chaineval_fast.py``).

        Parameters
        ----------
        idx : ndarray of int, shape (N,), or None
            The machine of each row (None: machine 0 for every row).
        q : ndarray, shape (N, A)
            Commanded positions of the chain axes, mm or degrees.
        start : ndarray, shape (N, K), optional
            Where the refinement starts (0 by default). A PLC passes its previous cycle's
            corrections: the refinement has one fixed point, reached in fewer steps from
            nearby.
        max_steps : int
            Refinement steps at most (README: 6). A PLC tracking a moving machine from
            its previous cycle's corrections may take 1 per cycle: the fixed point moves by
            far less between cycles than one step corrects (the step contracts the gap by
            the errors' slope, ~1e-4).
        """
        idx, q = self._check(idx, q)
        st = None if start is None else np.asarray(start, dtype=np.float64).T
        dq = self._cycle.corrections(idx, np.ascontiguousarray(q.T), st, max_steps)
        out: F64 = np.ascontiguousarray(dq.T)
        return out

    def corrections_reference(self, idx: I64 | None, q: F64, start: F64 | None = None,
                              max_steps: int = MAX_STEPS) -> F64:
        """:meth:`corrections` the straightforward way: rows first, stacked 3x3 products,
        every step as the README writes it (the check of the fleet cycle's layout).
        Parameters and result as for :meth:`corrections`."""
        idx, q = self._check(idx, q)
        nominal, jac = self.nominal(idx, q)
        g = self.g_const[idx] if self.g_const is not None else self._pinv(idx, jac)
        dq = np.zeros_like(q)
        if start is not None:
            dq[:, self.out_col] = start
        for _ in range(max_steps):
            res = self._residual(idx, q, dq, nominal)
            delta = -np.einsum("nkr,nr->nk", g, res)
            dq[:, self.out_col] += delta
            if float(np.abs(delta).max(initial=0.0)) <= STEP_TOL:
                break
        out: F64 = dq[:, self.out_col]
        return out

    def applied(self, idx: I64 | None, q: F64, directions: NDArray[np.generic] | None = None,
                start: F64 | None = None) -> F64:
        """What the machine applies (N, K), mm or degrees: corrections clamped to ±limit,
        rounded to the encoding, plus the reversal where ``directions`` (N, K) < 0;
        ``start`` as for :meth:`corrections`."""
        idx, q = self._check(idx, q)
        return self.finish(idx, self.corrections(idx, q, start), directions)

    def finish(self, idx: I64, c: F64, directions: NDArray[np.generic] | None = None) -> F64:
        """Corrections ``c`` (N, K) as applied (protocol/README.md §6.3 step 6): rounded
        to the encoding, the reversal added where ``directions`` (N, K) < 0, then clamped
        to ±limit (int32: ±floor(limit / increment) counts), a float32 map's values
        finally the nearest float32."""
        key = idx.tobytes()  # a PLC fleet finishes the same row sets cycle after cycle
        limit = self._limits.get(key)
        if limit is None:
            if len(self._limits) >= ROW_SETS:
                self._limits.clear()
            limit = self._limits[key] = self.limit[idx]
        neg = (None if directions is None
               else np.asarray(directions, dtype=float) < 0)
        if not self.int32.any():  # float32 maps only (Siemens-style): no increments
            if neg is not None:
                c = c + np.where(neg, self.reversal[idx], 0.0)
            c = np.minimum(np.maximum(c, -limit), limit)
            out: F64 = c.astype(np.float32).astype(np.float64)
            return out
        inc = self.increment[idx][:, None]
        int32 = self.int32[idx][:, None]
        # int32: halves up, the one tie rule of protocol/README.md section 6
        rounded = np.where(int32, np.floor(c / inc + 0.5), c)
        if neg is not None:
            rounded = rounded + np.where(neg, self.reversal[idx], 0.0)
        lim = np.where(int32, np.floor(limit / inc), limit)
        rounded = np.minimum(np.maximum(rounded, -lim), lim)
        out = np.where(int32, rounded * inc, rounded.astype(np.float32).astype(np.float64))
        return out

    def _check(self, idx: I64 | None, q: F64) -> tuple[I64, F64]:
        qa = np.asarray(q, dtype=np.float64)
        if qa.ndim != 2 or qa.shape[1] != len(self.axes):
            raise StructureError(f"positions must have shape (N, {len(self.axes)}) for axes "
                                 f"{' '.join(self.axes)}, got {qa.shape}")
        if not np.all(np.isfinite(qa)):
            raise StructureError("positions contain NaN or infinity")
        ia = (np.zeros(qa.shape[0], dtype=np.int64) if idx is None
              else np.asarray(idx, dtype=np.int64))
        if ia.shape != (qa.shape[0],) or (ia.size and not 0 <= ia.min() <= ia.max()
                                          < len(self.maps)):
            raise StructureError(f"machine indices must have shape ({qa.shape[0]},) and lie "
                                 f"in 0..{len(self.maps) - 1}")
        return ia, qa
