"""Blocked cross-validation of the thermal selection (:mod:`volumetric.identify.thermal`,
steps 2 and 3): leave-one-block-out least squares over contiguous time blocks, and the
continuous refinement of a lag's time constant on it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.thermal.columns import ThermalTerm
from volumetric.model.lag import first_order_lag

F64 = NDArray[np.float64]

_GOLDEN_ITERATIONS = 14
"""Golden-section steps refining log τ over a bracket of ln 4: 0.618^14 · 1.39 ≈ 0.002, i.e.
τ to about 0.2 %, far below what the data can tell apart."""

_RCOND = 1e-12
"""Relative singular-value cut-off of the small normal-equation solves. Columns are
standardised first, so only genuinely collinear candidates (e.g. a lag identical to another)
fall below it; they then add nothing and are not selected."""


class BlockedCV:
    """Leave-one-block-out least squares from per-block Gram matrices.

    Every fit has an intercept; columns are standardised on the training rows so that the
    small normal equations are well scaled (the CV error does not depend on the scaling).
    """

    def __init__(self, y: F64, blocks: NDArray[np.intp]) -> None:
        # Centred: the intercept absorbs the mean anyway, and sums of squares of a drift
        # with a large offset would cancel badly in ``s - 2 c·r + c·G·c`` below.
        self.y = y - y.mean()
        self.n = y.shape[0]
        self.masks = [blocks == b for b in np.unique(blocks)]
        self.sy = np.array([self.y[m] @ self.y[m] for m in self.masks])
        # Held-out error sums are floored here before their ratios are taken: an exact fit
        # (noise-free data) would give 0, and the Gram-matrix arithmetic can round a true
        # zero to a tiny negative number.
        self.sse_floor = 1e-12 * float(self.sy.mean()) + np.finfo(np.float64).tiny

    def block_sse(self, cols: Sequence[F64]) -> F64:
        """Held-out squared error of each block (µm²), shape (n_blocks,)."""
        design = np.column_stack([np.ones(self.n), *cols])
        scale = design.std(axis=0)
        scale[0] = 1.0
        scale[scale == 0.0] = 1.0
        design = design / scale
        grams = [design[m].T @ design[m] for m in self.masks]
        rhs = [design[m].T @ self.y[m] for m in self.masks]
        g_all = sum(grams[1:], grams[0])
        r_all = sum(rhs[1:], rhs[0])
        out = np.empty(len(self.masks))
        for k, (g_k, r_k) in enumerate(zip(grams, rhs, strict=True)):
            c = np.linalg.lstsq(g_all - g_k, r_all - r_k, rcond=_RCOND)[0]
            out[k] = self.sy[k] - 2.0 * c @ r_k + c @ g_k @ c
        return out


def golden_min(f: Callable[[float], float], lo: float, hi: float) -> tuple[float, float]:
    """Minimum of ``f`` on ``[lo, hi]`` by golden-section search: (argmin, min)."""
    ratio = (np.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(_GOLDEN_ITERATIONS):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - ratio * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + ratio * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)


def contiguous_blocks(n_train: int, n_blocks: int) -> NDArray[np.intp]:
    """Block index of each training row: contiguous, equal row counts (±1)."""
    return (np.arange(n_train) * n_blocks) // n_train


def usable_taus(t_train: F64, taus_s: Sequence[float], fraction: float = 1.0
                 ) -> tuple[list[float], tuple[float, float]]:
    """The grid without time constants the training data cannot tell from a level (below
    half the median sampling interval) or from a trend (above ``fraction`` of the training
    span), and the range (s) within which a chosen one may be refined."""
    grid = [float(v) for v in taus_s]
    for v in grid:
        if not (np.isfinite(v) and v > 0.0):
            raise ValueError(f"time constants must be finite and positive, got {v!r}")
    steps = np.diff(t_train)
    steps = steps[steps > 0.0]
    if steps.size == 0:
        return [], (0.0, 0.0)
    lo = 0.5 * float(np.median(steps))
    hi = fraction * float(t_train[-1] - t_train[0])
    usable = sorted({v for v in grid if lo <= v <= hi})
    # a chosen lag is refined up to the longest usable time constant, not only to the
    # longest grid value below it
    return usable, ((usable[0], max(usable[-1], hi)) if usable else (0.0, 0.0))


def refined_lag(cv: BlockedCV, cols: list[F64], term: ThermalTerm, t: F64, x: F64,
                train: NDArray[np.bool_], limits: tuple[float, float]
                ) -> tuple[ThermalTerm, F64]:
    """Golden-section refinement of a lag's τ within a factor 2 of its grid value, kept
    inside ``limits`` (s), the usable span of the grid."""

    def score(log_tau: float) -> float:
        col = first_order_lag(t, x, float(np.exp(log_tau)))[train]
        return float(cv.block_sse([*cols, col]).sum())

    center = float(np.log(term.tau_s))
    lo = max(center - np.log(2.0), float(np.log(limits[0])))
    hi = min(center + np.log(2.0), float(np.log(limits[1])))
    log_tau, value = golden_min(score, lo, hi)
    if value < score(center):
        refined = ThermalTerm("lag", term.source, float(np.exp(log_tau)))
    else:
        refined = term
    return refined, first_order_lag(t, x, refined.tau_s)[train]


def backfit_taus(cv: BlockedCV, chosen: list[ThermalTerm], cols: list[F64], t: F64,
                  signals: Mapping[str, F64], train: NDArray[np.bool_],
                  limits: tuple[float, float]) -> None:
    """Refine every selected lag's τ again with the other selected columns fixed (one pass
    of backfitting, in selection order), in place; each keeps its τ unless the blocked-CV
    error falls."""
    for i, term in enumerate(chosen):
        if term.kind != "lag":
            continue
        others = cols[:i] + cols[i + 1:]
        chosen[i], cols[i] = refined_lag(cv, others, term, t, signals[term.source], train,
                                         limits)
