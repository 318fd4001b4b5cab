"""Held-out readings of the diagnosis (step 2 of :mod:`volumetric.diagnose`): how the
readings are split (``runs``, ``forward``, ``chronological``), the held-out residuals of a
design on that split, and the least-squares solves they share.

Every figure the diagnosis judges by is a held-out residual: the readings of a fold
predicted by a weighted fit on the readings that fold does not judge.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.measure.measurement import Measurements

F64 = NDArray[np.float64]


K_FOLDS = 5
SCHUR_CUT = 1e-8
"""Smallest scaled eigenvalue, relative to the largest, of a fold's base normal matrix and
of a candidate's Schur complement for :class:`BaseGrams` to solve by the complement; a
hundred times the minimum-norm solve's cut (:func:`solve_normal`), so that where it is
used the two agree to rounding."""

def fold_labels(m: Measurements, k: int = K_FOLDS) -> NDArray[np.intp]:
    """Fold of each reading (see module docstring, step 2)."""
    folds = np.zeros(len(m), dtype=np.intp)
    for label in np.unique(m.test):
        rows = np.flatnonzero(m.test == label)
        runs = np.unique(m.run[rows])
        if runs.size >= 2:
            # whole runs to folds, in time order of the runs
            starts = [float(m.time_s[rows[m.run[rows] == r]].min()) for r in runs]
            order = runs[np.argsort(starts)]
            fold_of = {int(r): i % k for i, r in enumerate(order)}
            folds[rows] = [fold_of[int(r)] for r in m.run[rows]]
        else:
            by_time = rows[np.argsort(m.time_s[rows], kind="stable")]
            folds[by_time] = (np.arange(by_time.size) * k) // max(by_time.size, 1)
    return folds


def heldout_residuals(a: F64, y: F64, w: F64, folds: NDArray[np.intp]) -> F64:
    """Residual of every reading predicted by a weighted fit on the other folds.

    Rank-deficient training sets (a column unobserved without the fold) are solved in the
    minimum-norm sense with a stated eigenvalue cut (1e-10 of the largest).
    """
    aw = a * w[:, None]
    g_all = a.T @ aw
    b_all = aw.T @ y
    r = np.empty_like(y)
    for f in np.unique(folds):
        rows = folds == f
        g = g_all - a[rows].T @ aw[rows]
        b = b_all - aw[rows].T @ y[rows]
        x = solve_normal(g, b)
        r[rows] = y[rows] - a[rows] @ x
    return r


def solve_normal(g: F64, b: F64) -> F64:
    d = np.sqrt(np.clip(np.diag(g), 0, None))
    d[d == 0] = 1.0
    lam, vec = np.linalg.eigh(g / np.outer(d, d))
    keep = lam > 1e-10 * max(float(lam.max(initial=0.0)), 1e-300)
    z = vec[:, keep].T @ (b / d)
    out: F64 = (vec[:, keep] @ (z / lam[keep])) / d
    return out


def rms_of(r: F64) -> float:
    return float(np.sqrt(np.mean(r * r))) if r.size else float("nan")


FORWARD_BLOCKS = 6
"""Contiguous time blocks of forward chaining (equal counts of readings in time order)."""
FIRST_JUDGED = FORWARD_BLOCKS // 2
"""The first block judged: every judged block is predicted by a model fitted on all the
blocks before it, at least half of the campaign (a thermal model fitted on a sixth of a
heat cycle says little of the next one, and would make the figure a measure of how soon
the campaign started to repeat itself)."""
TIME_ORDERED_SPAN = 0.5
"""A campaign is time-ordered when every test's readings span at least this fraction of
the campaign's duration: the same tests repeat over time, so the past predicts the future."""


def time_ordered(m: Measurements) -> bool:
    """True when the readings are one long time series of repeated tests (see
    :data:`TIME_ORDERED_SPAN`): a thermal test, a long-term drift run. A campaign of
    different tests one after the other is not: a later block would hold tests no earlier
    block saw."""
    span = float(np.ptp(m.time_s)) if len(m) else 0.0
    if span <= 0:
        return False
    for label in np.unique(m.test):
        t = m.time_s[m.test == label]
        if float(np.ptp(t)) < TIME_ORDERED_SPAN * span:
            return False
    return True


def forward_blocks(m: Measurements, k: int = FORWARD_BLOCKS) -> NDArray[np.intp]:
    """Block (0 .. k-1) of each reading: equal counts of readings in time order."""
    order = np.argsort(m.time_s, kind="stable")
    blocks = np.empty(len(m), dtype=np.intp)
    blocks[order] = (np.arange(len(m)) * k) // max(len(m), 1)
    return blocks


def forward_residuals(a: F64, y: F64, w: F64, blocks: NDArray[np.intp]) -> F64:
    """Residual of every reading of blocks ``FIRST_JUDGED`` .. predicted by a weighted fit
    on the blocks before its own (NaN in the earlier blocks, which only train)."""
    r = np.full(len(y), np.nan)
    for k in range(FIRST_JUDGED, int(blocks.max(initial=0)) + 1):
        tr = blocks < k
        rows = blocks == k
        x = solve_normal(a[tr].T @ (a[tr] * w[tr, None]), (a[tr] * w[tr, None]).T @ y[tr])
        r[rows] = y[rows] - a[rows] @ x
    return r


Fits = list[tuple[NDArray[np.bool_], NDArray[np.bool_]]]
"""The (fitted, judged) readings of every fold of a split, as boolean masks of shape (N,)."""


def fold_fits(split: str, folds: NDArray[np.intp], train: NDArray[np.bool_]) -> Fits:
    """The fitted and judged readings of every fold of ``split`` (step 2), in the order of
    a candidate's ``per_fold`` columns."""
    if split == "chronological":
        return [(train, ~train)]
    if split == "forward":
        return [(folds < k, folds == k)
                for k in range(FIRST_JUDGED, int(folds.max(initial=0)) + 1)]
    return [(folds != f, folds == f) for f in np.unique(folds)]


def heldout_per_fold(a0: F64, cands: list[Candidate], y: F64, w: F64, fits: Fits,
                     cells: NDArray[np.intp]) -> F64:
    """Held-out residuals of the base design extended by ``cands``, each fold fitted with
    every candidate's columns of that fold (NaN where no fold judges); ``cells`` as for
    :class:`BaseGrams`, whose base here is ``a0`` with the candidates that serve every
    fold (a replacing one included)."""
    serve_all = [c for c in cands if not c.per_fold]
    return BaseGrams(combined(a0, serve_all), y - known_sum(len(y), serve_all), w, fits,
                     cells).heldout([c for c in cands if c.per_fold])


class BaseGrams:
    """The base design's weighted normal equations summed over each fold's fitted readings,
    computed once per diagnosis: a candidate judged adds only its own columns' rows and
    cross terms, O(N·P·k) per fold for k extra columns instead of O(N·P²) for the whole
    design again (the base design holds a hundred columns; a candidate one to a few).

    Parameters
    ----------
    a0 : ndarray, shape (N, P)
    y, w : ndarray, shape (N,)
        Readings and their weights.
    fits : Fits
    cells : ndarray of int, shape (N,)
        Labels such that every fold's fitted readings are a union of cells.
    """

    def __init__(self, a0: F64, y: F64, w: F64, fits: Fits, cells: NDArray[np.intp]) -> None:
        self.a0, self.y, self.w, self.fits = a0, y, w, fits
        aw = a0 * w[:, None]
        labels = [int(c) for c in np.unique(cells)]
        g_cell = {c: aw[cells == c].T @ a0[cells == c] for c in labels}
        b_cell = {c: aw[cells == c].T @ y[cells == c] for c in labels}
        p = a0.shape[1]
        self.g: list[F64] = []
        self.b: list[F64] = []
        for tr, _ in fits:
            inside = [int(c) for c in np.unique(cells[tr])]
            if not np.array_equal(np.isin(cells, inside), tr):
                raise ValueError("the fitted readings of a fold are not a union of cells")
            self.g.append(sum((g_cell[c] for c in inside), np.zeros((p, p))))
            self.b.append(sum((b_cell[c] for c in inside), np.zeros(p)))
        self._inv: list[F64 | None] = [None] * len(fits)

    def _base_inverse(self, f: int) -> F64 | None:
        """The inverse of fold ``f``'s base normal matrix when it is well conditioned
        (scaled, smallest eigenvalue above ``SCHUR_CUT`` of the largest), else None;
        computed once."""
        if self._inv[f] is None:
            g = self.g[f]
            d = np.sqrt(np.clip(np.diag(g), 0, None))
            if np.all(d > 0):
                lam, vec = np.linalg.eigh(g / np.outer(d, d))
                if lam.size and lam.min() > SCHUR_CUT * max(float(lam.max()), 1e-300):
                    self._inv[f] = ((vec / lam) @ vec.T) / np.outer(d, d)
            if self._inv[f] is None:
                self._inv[f] = np.zeros((0, 0))
        inv = self._inv[f]
        return None if inv is None or inv.size == 0 else inv

    def heldout(self, cands: list[Candidate]) -> F64:
        """Held-out residuals of the base extended by ``cands`` (none replacing base
        columns), each fold with every candidate's columns of that fold (a fixed one's
        taken off the readings)."""
        w = self.w
        p = self.a0.shape[1]
        r = np.full(len(self.y), np.nan)
        free = [c for c in cands if not c.fixed]
        for f, (tr, te) in enumerate(self.fits):
            e = (np.column_stack([c.in_fold(f).columns for c in free]) if free
                 else np.zeros((len(self.y), 0)))
            known = known_sum(len(self.y), cands, f)
            y = self.y - known
            # the fold's fitted rows only, weighted; no copy of the (N, P) base
            ew = e * (w * tr)[:, None]
            g_be = self.a0.T @ ew
            g_ee = ew.T @ e
            b = self.b[f] - self.a0.T @ (w * tr * known) if known.any() else self.b[f]
            b_e = ew.T @ y
            x = self._schur(f, g_be, g_ee, b, b_e)
            if x is None:
                g = np.block([[self.g[f], g_be], [g_be.T, g_ee]])
                x = solve_normal(g, np.concatenate((b, b_e)))
            r[te] = (y - self.a0 @ x[:p] - e @ x[p:])[te]
        return r

    def _schur(self, f: int, g_be: F64, g_ee: F64, b: F64, b_e: F64) -> F64 | None:
        """The joint solution of the base and k extra columns of fold ``f`` by their
        Schur complement (a k x k solve beside the base's inverse, computed once per
        fold, instead of a (P + k) square one per candidate), or None when the base or
        the complement is not well conditioned (``SCHUR_CUT``): then the general
        minimum-norm solve decides, as it always did."""
        inv = self._base_inverse(f)
        if inv is None:
            return None
        if g_ee.shape[0] == 0:
            out: F64 = inv @ b
            return out
        ib = inv @ g_be  # (P, k)
        s = g_ee - g_be.T @ ib
        d = np.sqrt(np.clip(np.diag(s), 0, None))
        d0 = np.sqrt(np.clip(np.diag(g_ee), 0, None))
        if not np.all(d > SCHUR_CUT ** 0.5 * np.maximum(d0, 1e-300)):
            return None  # a column (nearly) inside the base's span
        lam, vec = np.linalg.eigh(s / np.outer(d, d))
        if lam.min() <= SCHUR_CUT * max(float(lam.max()), 1e-300):
            return None
        x_e = ((vec / lam) @ vec.T) @ ((b_e - ib.T @ b) / d) / d
        x_b = inv @ b - ib @ x_e
        return np.concatenate((x_b, x_e))


def block_table(blocks: NDArray[np.intp], judge: NDArray[np.bool_], before: F64,
                 ids: list[int], after: F64 | None = None) -> dict[str, Any]:
    """Per judged block: held-out RMS before (and after) the extension; mean and worst."""
    rows = []
    for k in ids:
        sel = judge & (blocks == k)
        item = {"block": k, "n": int(sel.sum()), "rms_before_um": round(rms_of(before[sel]), 4)}
        if after is not None:
            item["rms_after_um"] = round(rms_of(after[sel]), 4)
        rows.append(item)
    key = "rms_after_um" if after is not None else "rms_before_um"
    values = [float(r[key]) for r in rows]
    return {"per_block": rows, "mean_rms_um": round(float(np.mean(values)), 4),
            "worst_rms_um": round(float(np.max(values)), 4)}


def combined(a0: F64, cands: list[Candidate]) -> F64:
    """The base design extended by several candidates (a replacing one, a rotary axis's
    harmonics, first; at most one of those); a fixed one adds no column (its prediction,
    :func:`known_sum`, is taken off the readings)."""
    replacing = [c for c in cands if c.drop]
    a = replacing[0].design(a0) if replacing else a0
    extra = [c.columns for c in cands if not c.drop and not c.fixed]
    return np.column_stack((a, *extra)) if extra else a


def known_sum(n: int, cands: list[Candidate], f: int | None = None) -> F64:
    """What the fixed candidates among ``cands`` predict (µm), shape (n,), their columns
    of fold ``f`` when given: the readings less this are what the others are fitted to."""
    out = np.zeros(n)
    for c in cands:
        if c.fixed:
            out += c.known(f)
    return out



@dataclass(frozen=True)
class Split:
    """How one diagnosis holds readings out (step 2 of :mod:`volumetric.diagnose`).

    Attributes
    ----------
    name : str
        ``runs``, ``forward`` or ``chronological`` (the JSON's ``split``).
    folds : ndarray of int, shape (N,)
        Fold (``runs``), time block (``forward``) or side (``chronological``: 0 fitted,
        1 judged) of each reading.
    train : ndarray of bool, shape (N,)
        The readings the models are fitted on (all but the judged side of a
        chronological split).
    judge : ndarray of bool, shape (N,)
        The displacement readings whose held-out residuals are judged.
    fold_ids : list of int
        The judged folds or blocks.
    order : ndarray of int, shape (N,)
        All readings in time order.
    """

    name: str
    folds: NDArray[np.intp]
    train: NDArray[np.bool_]
    judge: NDArray[np.bool_]
    fold_ids: list[int]
    order: NDArray[np.intp]

    @property
    def order_judge(self) -> NDArray[np.intp]:
        """The judged readings in time order."""
        return self.order[self.judge[self.order]]


def choose_split(m: Measurements, holdout_after: float | None) -> Split:
    """The split of ``m`` chosen from the data alone (or by ``holdout_after``).

    Raises
    ------
    ValueError
        ``holdout_after`` leaves no readings on one side.
    """
    disp = ~m.is_angle
    order = np.argsort(m.time_s, kind="stable")
    if holdout_after is not None:
        folds = (m.time_s >= holdout_after).astype(np.intp)
        if folds.all() or not folds.any():
            raise ValueError(f"holdout_after={holdout_after} s leaves no readings on one "
                             "side of the split")
        train = folds == 0
        judge = ~train & disp
        fold_ids: list[int] = [1]
    elif time_ordered(m):
        # forward chaining: block k is judged by a model fitted on blocks 0 .. k-1 only
        folds = forward_blocks(m)
        train = np.ones(len(m), dtype=bool)
        judge = disp & (folds >= FIRST_JUDGED)
        fold_ids = sorted(int(f) for f in np.unique(folds) if f >= FIRST_JUDGED)
    else:
        folds = fold_labels(m)
        train = np.ones(len(m), dtype=bool)
        judge = disp
        fold_ids = sorted(int(f) for f in np.unique(folds))
    name = ("chronological" if holdout_after is not None
            else "forward" if judge.sum() < disp.sum() else "runs")
    return Split(name, folds, train, judge, fold_ids, order)


class Judge:
    """Held-out residuals of the base design ``a0`` and its extensions on one split.

    Parameters
    ----------
    split : Split
    a0 : ndarray, shape (N, P)
        The base design.
    y, w : ndarray, shape (N,)
        Readings and their weights.
    """

    def __init__(self, split: Split, a0: F64, y: F64, w: F64) -> None:
        self.split, self.a0, self.y, self.w = split, a0, y, w
        self.fits = fold_fits(split.name, split.folds, split.train)
        self.grams = BaseGrams(a0, y, w, self.fits, split.folds)

    def heldout(self, a: F64, y: F64 | None = None) -> F64:
        """Held-out residuals of design ``a`` fitted to ``y`` (the readings by default);
        NaN where no fold judges."""
        sp, w = self.split, self.w
        y = self.y if y is None else y
        if sp.name == "forward":
            return forward_residuals(a, y, w, sp.folds)
        if sp.name == "chronological":
            tr = sp.train
            r = np.full(len(y), np.nan)
            x = solve_normal(a[tr].T @ (a[tr] * w[tr, None]), (a[tr] * w[tr, None]).T @ y[tr])
            r[~tr] = y[~tr] - a[~tr] @ x
            return r
        return heldout_residuals(a, y, w, sp.folds)

    def of(self, cands: list[Candidate]) -> F64:
        """Held-out residuals of the base extended by ``cands``: a candidate selected again
        per fold is judged fold by fold with those columns; one that replaces base columns
        (a rotary axis's harmonics) changes the base."""
        if any(c.drop for c in cands):
            if any(c.per_fold for c in cands):
                return heldout_per_fold(self.a0, cands, self.y, self.w, self.fits,
                                        self.split.folds)
            return self.heldout(combined(self.a0, cands), self.y - known_sum(len(self.y), cands))
        return self.grams.heldout(cands)

    def rms(self, r: F64) -> float:
        """RMS of the judged readings of held-out residuals ``r``."""
        return rms_of(r[self.split.judge])


HeldoutOf = Callable[[list[Candidate]], F64]
"""Held-out residuals of the base extended by a list of candidates (:meth:`Judge.of`)."""
