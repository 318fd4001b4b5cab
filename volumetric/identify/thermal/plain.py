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
    x = np.column_stack(cols)
    sse = [sum(float(np.sum((y_tr[blocks == b] - _ridge(x[blocks != b], y_tr[blocks != b], lam)
                             (x[blocks == b])) ** 2)) for b in range(n_blocks))
           for lam in SHRINKAGE_GRID]
    k = int(np.argmin(sse))
    lam = SHRINKAGE_GRID[k]
    whole = _ridge(x, y_tr, lam)
    leave_out = np.array([_ridge(x[blocks != b], y_tr[blocks != b], lam).coefficients
                          for b in range(n_blocks)])
    spread = leave_out - leave_out.mean(axis=0)
    u = np.sqrt((n_blocks - 1) / n_blocks * np.sum(spread**2, axis=0))
    return ThermalDriftModel(
        terms=tuple(terms), intercept_um=float(whole.coefficients[0]),
        coef=whole.coefficients[1:], intercept_u_um=float(u[0]), coef_u=u[1:],
        t0_s=float(t[0]), train_rms_um=float(np.sqrt(np.mean((y_tr - whole(x)) ** 2))),
        cv_rms_um=float(np.sqrt(sse[k] / n_train)), baseline_cv_rms_um=baseline,
        n_train=n_train, n_blocks=n_blocks, steps=(), selected=tuple(terms),
        shrinkage=lam)


class _Ridge:
    """A ridge fit: intercept and coefficients in the columns' own units."""

    def __init__(self, coefficients: F64) -> None:
        self.coefficients = coefficients  # (1 + p,): intercept, then one per column

    def __call__(self, x: F64) -> F64:
        """Predictions for rows ``x``, shape (n, p) -> (n,)."""
        return np.asarray(self.coefficients[0] + x @ self.coefficients[1:], dtype=np.float64)


def _ridge(x: F64, y: F64, lam: float) -> _Ridge:
    """Ridge regression of ``y`` (n,) on ``x`` (n, p): columns standardised on these rows,
    penalty ``lam · n`` on their coefficients, the intercept free."""
    mu, sd = x.mean(axis=0), x.std(axis=0)
    sd[sd == 0.0] = 1.0
    z = (x - mu) / sd
    ym = float(y.mean())
    c = np.linalg.solve(z.T @ z + lam * y.shape[0] * np.eye(x.shape[1]), z.T @ (y - ym))
    b = c / sd
    return _Ridge(np.concatenate([[ym - float(mu @ b)], b]))
