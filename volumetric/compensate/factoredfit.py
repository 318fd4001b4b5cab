"""The fit of a factored map: the candidate terms over power-of-two grids in counts, their
sparse design and the one-table-at-a-time selection (:mod:`volumetric.compensate.factoredmap`
builds with them; the module docstring there says why this structure).

Units: positions in counts of the increment (float while fitting), basis tables Q14,
fields as :func:`select` is given them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import product

import numpy as np
import scipy.linalg as sl
import scipy.sparse as sp
from numpy.typing import NDArray

from volumetric.compensate.factoredtables import BASIS_Q, AxisGrid, Table1D
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
BASIS_STEP_DEG = 8.0
"""Spacing of the trigonometric basis tables, degrees (the power of two in counts nearest
it: 8.192° at 0.001°). Linear interpolation of cos θ there errs by (8.192π/180)²/8 =
2.6e-3 of the amplitude (1.0e-2 for cos 2θ), but the fit sees the tables as the endpoint
interpolates them, and the term tables it fits absorb most of that: at 2.048° the basis
tables were a quarter of a 5-axis map (2.3 of 8.8 kB on the Fanuc-style 5ax-09). Measured
on 5ax-09 (fitted model, tolerance 1.0 µm): 2.048° 8,816 B at 0.71 µm as sent, 4.096°
7,680 B at 0.71, 8.192° 7,324 B at 0.72, 8.192° for cos θ with 4.096° for cos 2θ 7,614 B;
``benchmarks/factored_size.py`` 14 maps 14-20 % smaller, the largest as-sent error
unchanged (0.80 µm)."""
MAX_SHIFT = 24
RIDGE = 1e-7
"""Relative ridge of the normal equations (times the mean squared column norm), so that a
table nearly inside the span of those already chosen cannot take large opposite values."""
STALL_TERMS = 10
STALL_GAIN = 0.9
"""A field stops taking tables when its worst error after the last ``STALL_TERMS`` of them
is still above ``STALL_GAIN`` times what it was before: the rest is finer than the tables'
spacing, which only a further round can give (on a 5-axis map, ~200 more tables for the
last 0.05 µm otherwise)."""

@dataclass
class Layout:
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
        """(N, Σ nodes) sparse, positions ``q`` (N, K) in counts: row n holds every
        candidate's hat weights at q_n times its factors (tables as the endpoint
        interpolates them)."""
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
                u = np.clip((q[:, axis] - g.start) / float(g.step), 0.0, g.count - 1)
                i = np.minimum(u.astype(np.intp), g.count - 2)
                f = u - i
                rows += [r, r]
                cols += [offset + i, offset + i + 1]
                vals += [w * (1.0 - f), w * f]
            offset += 1 if const else g.count
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                     np.concatenate(cols))),
                             shape=(n, offset))


def _basis_tables(machine: Machine, per_unit: int, harmonics: int
                  ) -> tuple[list[Table1D], dict[int, list[int | None]], dict[int, int]]:
    bases: list[Table1D] = []
    rot: dict[int, list[int | None]] = {}
    lin: dict[int, int] = {}
    for i, a in enumerate(machine.axes):
        lo, hi = _travel_counts(a.travel, per_unit)
        if a.kind == "rotary":
            shift = shift_for(BASIS_STEP_DEG * per_unit)
            count = max(2, -(-(hi - lo) >> shift) + 1)
            x = np.deg2rad((lo + (np.arange(count) << shift)) / per_unit)
            idx: list[int | None] = [None]
            for h in range(1, harmonics + 1):
                for fn in (np.cos, np.sin):
                    v = np.floor(fn(h * x) * (1 << BASIS_Q) + 0.5).astype(np.int64)
                    idx.append(len(bases))
                    bases.append(Table1D(i, lo, shift, v, -BASIS_Q))
            rot[i] = idx
        else:
            # the position, centred and scaled to ±1 over 2^shift >= the travel: two
            # nodes interpolate it exactly
            shift = max(0, (hi - lo - 1).bit_length())
            lin[i] = len(bases)
            bases.append(Table1D(i, lo, shift, np.array([-(1 << BASIS_Q), 1 << BASIS_Q]),
                                 -BASIS_Q))
    return bases, rot, lin


def _travel_counts(travel: tuple[float, float], per_unit: int) -> tuple[int, int]:
    """An axis's travel in whole counts, widened to whole counts outwards."""
    return math.floor(travel[0] * per_unit), math.ceil(travel[1] * per_unit)


def shift_for(step_counts: float) -> int:
    """The power of two nearest ``step_counts`` (in log), at least 1 count."""
    return max(0, min(MAX_SHIFT, round(math.log2(max(step_counts, 1.0)))))


def layout(machine: Machine, per_unit: int, shifts: Sequence[int],
            harmonics: int) -> Layout:
    bases, rot_b, lin_b = _basis_tables(machine, per_unit, harmonics)
    grids = []
    for a, shift in zip(machine.axes, shifts, strict=True):
        lo, hi = _travel_counts(a.travel, per_unit)
        n = max(2, -(-(hi - lo) >> shift) + 1)
        # the nodes overhang the travel by less than one spacing: half of it at each end,
        # so that no end node is fitted from a sliver of samples
        overhang = ((n - 1) << shift) - (hi - lo)
        grids.append(AxisGrid(n, lo - overhang // 2, shift))
    lay = Layout(machine, grids, bases, rot_b, lin_b)
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


def select(lay: Layout, a: sp.csr_matrix, targets: F64, tip_scale: F64,
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


__all__ = ["Layout", "layout", "select", "shift_for"]
