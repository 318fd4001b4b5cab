"""The plain least squares on every sensor, the reference a selected thermal model must not
lose to (:mod:`volumetric.identify.thermal`; issue 27), and its shrunk (ridge) version.

Every temperature's level, and optionally its first-order lag at one time constant, in one
least-squares fit with an intercept. No selection of sensors or terms, so nothing in it is
chosen on the rows it is judged on. A level and a lag of one sensor span its smoothed rate
``(T - L_τ[T]) / τ`` (K/h), so the version with lags is the static model with the rates
``dT/dt`` of every sensor, each computed causally (a centred derivative would read the
next reading, which a machine applying the model live does not have yet).

Sixteen collinear sensors (thirty-two columns with their lags) fitted on a few heat
cycles take large coefficients of opposite signs that cancel on the training rows and
not after them. ``shrink=True`` fits the same columns by ridge regression instead
(Hoerl & Kennard 1970): standardised columns, the intercept not penalised, the penalty
λ chosen from :data:`SHRINKAGE_GRID` by the blocked cross-validation of the selection
(contiguous time blocks of the training rows, each predicted from the others). Which
of these the diagnosis saves is for its forward split to say (:mod:`volumetric.diagnose.lagged`;
figures on the real test in the README, from ``benchmarks/thermal_fl_study.py``).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.identify.thermal.blocked_cv import BlockedCV, contiguous_blocks
from volumetric.identify.thermal.columns import ThermalTerm, as_signal
from volumetric.identify.thermal.fits import final_fit
from volumetric.identify.thermal.model import ThermalDriftModel
from volumetric.model.lag import _as_time, first_order_lag

F64 = NDArray[np.float64]

SHRINKAGE_GRID: tuple[float, ...] = tuple(10.0**k for k in range(-6, 2))
"""Ridge penalties λ tried, per training row on standardised columns (1e-6 .. 10): from
practically least squares to a model that keeps little more than the intercept."""


def fit_all_sensors(
    t_s: ArrayLike,
    temps: Mapping[str, ArrayLike],
    y: ArrayLike,
    train_mask: ArrayLike | None = None,
    *,
    rate_tau_s: float | None = None,
    shrink: bool = False,
    n_blocks: int = 5,
) -> ThermalDriftModel:
    """Least squares of ``y`` on the intercept and every temperature (and its lag).

    Parameters
    ----------
    t_s : array_like, shape (N,)
        Sample times (s), non-decreasing.
    temps : mapping of str to array_like, shape (N,)
        Temperatures (°C) by column name; every one is a column.
    y : array_like, shape (N,)
        Drift (µm); rows outside ``train_mask`` are not read.
    train_mask : array_like of bool, shape (N,), optional
        Rows to fit on; default all. Lags run over all N rows.
    rate_tau_s : float, optional
        With a value τ (s), every sensor's lag ``L_τ[T]`` joins its level (the two span
        its rate); None for the levels alone.
    shrink : bool
        Ridge instead of ordinary least squares, λ by blocked CV (module docstring).
    n_blocks : int
        Contiguous blocks of the training rows for the blocked CV (figure, λ) and the
        block-jackknife uncertainties (>= 3).

    Returns
    -------
    ThermalDriftModel
        Terms: the levels in the order of ``temps``, then the lags; no ``steps`` (nothing
        was selected); ``shrinkage`` the λ taken (0 without ``shrink``); ``cv_rms_um``
        the blocked-CV RMS (µm) with that λ.

    Raises
    ------
    ValueError
        No temperatures, bad shapes or values, a bad ``rate_tau_s``, or fewer than two
        training rows per column and block.
    """
    t = _as_time(t_s)
    n = t.shape[0]
    if not temps:
        raise ValueError("no temperatures given: a thermal model needs at least one")
    names = list(temps)
    levels = np.column_stack([as_signal(k, temps[k], n) for k in names])
    y_all = np.asarray(y, dtype=np.float64)
    if y_all.shape != (n,):
        raise ValueError(f"y has shape {y_all.shape}, expected ({n},) like t_s")
    train = np.ones(n, dtype=bool) if train_mask is None else np.asarray(train_mask)
    if train.shape != (n,) or train.dtype != np.bool_:
        raise ValueError(f"train_mask must be a boolean array of shape ({n},)")
    if n_blocks < 3:
        raise ValueError(f"n_blocks must be at least 3, got {n_blocks}")
    terms = [ThermalTerm("level", k) for k in names]
    cols = list(levels[train].T)
    if rate_tau_s is not None:
        tau = float(rate_tau_s)
        if not (np.isfinite(tau) and tau > 0.0):
            raise ValueError(f"rate_tau_s must be finite and positive, got {rate_tau_s!r}")
        terms += [ThermalTerm("lag", k, tau) for k in names]
        cols += list(first_order_lag(t, levels, tau)[train].T)
    n_train = int(train.sum())
    if n_train < 2 * n_blocks * (len(cols) + 1):
        raise ValueError(f"{n_train} training rows are too few for {len(cols) + 1} columns "
                         f"in {n_blocks} blocks")
    y_tr = y_all[train]
    bad = np.flatnonzero(~np.isfinite(y_tr))
    if bad.size:
        raise ValueError(f"y is not finite at training row {int(bad[0])}")
    blocks = contiguous_blocks(n_train, n_blocks)
    cv = BlockedCV(y_tr, blocks)
    baseline = float(np.sqrt(cv.block_sse([]).sum() / n_train))
    if not shrink:
        return final_fit(terms, cols, y_tr, n_blocks, float(t[0]),
                         cv_rms=float(np.sqrt(cv.block_sse(cols).sum() / n_train)),
                         baseline=baseline, steps=())
    lam, coefficients, leave_out, sse = _ridge_by_blocks(np.column_stack(cols), y_tr, blocks,
                                                         n_blocks)
    design = np.column_stack([np.ones(n_train), *cols])
    spread = leave_out - leave_out.mean(axis=0)
    u = np.sqrt((n_blocks - 1) / n_blocks * np.sum(spread**2, axis=0))
    return ThermalDriftModel(
        terms=tuple(terms), intercept_um=float(coefficients[0]), coef=coefficients[1:],
        intercept_u_um=float(u[0]), coef_u=u[1:], t0_s=float(t[0]),
        train_rms_um=float(np.sqrt(np.mean((y_tr - design @ coefficients) ** 2))),
        cv_rms_um=float(np.sqrt(sse / n_train)), baseline_cv_rms_um=baseline,
        n_train=n_train, n_blocks=n_blocks, steps=(), selected=tuple(terms), shrinkage=lam)


def _ridge_by_blocks(x: F64, y: F64, blocks: NDArray[np.intp], n_blocks: int
                     ) -> tuple[float, F64, F64, float]:
    """Ridge regression of ``y`` (n,) on ``x`` (n, p) with λ from :data:`SHRINKAGE_GRID`
    by leave-one-block-out CV, all from per-block Gram matrices.

    The columns are standardised once on all ``n`` rows (so a fold's penalty is the same
    λ on the same scale), the intercept is not penalised, and a fit on ``m`` rows takes
    the penalty ``λ · m``. Held-out squared errors come from the Gram sums, as in
    :class:`~volumetric.identify.thermal.blocked_cv.BlockedCV`.

    Returns
    -------
    lam : float
        The λ of least held-out squared error.
    coefficients : ndarray, shape (1 + p,)
        Intercept and one coefficient per column (the columns' own units), fitted with
        ``lam`` on all rows.
    leave_out : ndarray, shape (n_blocks, 1 + p)
        The same, fitted with every block left out in turn.
    sse : float
        The held-out squared error (µm²) with ``lam``, summed over the blocks.
    """
    mu, sd = x.mean(axis=0), x.std(axis=0)
    sd[sd == 0.0] = 1.0
    ym = float(y.mean())
    # centred: sums of squares of a drift with a large offset would cancel badly below
    z = np.column_stack([np.ones(y.shape[0]), (x - mu) / sd])
    yc = y - ym
    masks = [blocks == b for b in range(n_blocks)]
    grams = [z[k].T @ z[k] for k in masks]
    rhs = [z[k].T @ yc[k] for k in masks]
    sy = [float(yc[k] @ yc[k]) for k in masks]
    rows = [int(k.sum()) for k in masks]
    g_all, r_all, n = sum(grams[1:], grams[0]), sum(rhs[1:], rhs[0]), y.shape[0]
    penalty = np.ones(z.shape[1])
    penalty[0] = 0.0  # the intercept is free

    def solve(g: F64, r: F64, m: int, lam: float) -> F64:
        return np.asarray(np.linalg.solve(g + np.diag(lam * m * penalty), r), dtype=np.float64)

    def held_out(lam: float) -> float:
        out = 0.0
        for g_b, r_b, s_b, n_b in zip(grams, rhs, sy, rows, strict=True):
            c = solve(g_all - g_b, r_all - r_b, n - n_b, lam)
            out += s_b - 2.0 * float(c @ r_b) + float(c @ g_b @ c)
        return out

    sse = [held_out(lam) for lam in SHRINKAGE_GRID]
    best = int(np.argmin(sse))
    lam = SHRINKAGE_GRID[best]

    def in_units(c: F64) -> F64:
        b = c[1:] / sd
        return np.concatenate([[ym + c[0] - float(mu @ b)], b])

    whole = in_units(solve(g_all, r_all, n, lam))
    leave_out = np.array([in_units(solve(g_all - g_b, r_all - r_b, n - n_b, lam))
                          for g_b, r_b, n_b in zip(grams, rhs, rows, strict=True)])
    return lam, whole, leave_out, sse[best]
