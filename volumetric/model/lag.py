"""The first-order lag of a sampled signal: how a structure's temperature follows a sensor's.

It lives with the model, not with identification, because a saved model applies it too
(:class:`volumetric.model.model.DynamicThermalTerm`); :mod:`volumetric.identify.thermal`
builds its regressors from it.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]

_CHUNK_TAUS = 50.0
"""Largest span, in time constants, of one vectorised chunk of :func:`first_order_lag`.
Within a chunk the closed form divides by decay factors ``exp(-(t - t_s)/τ)`` no smaller
than e^-50 ≈ 2e-22, far from underflow; the large terms of its cumulative sum are the
recent inputs, the ones the output is made of, so the result keeps full relative
precision."""


def _as_time(t_s: ArrayLike, what: str = "t_s") -> F64:
    t = np.asarray(t_s, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"{what} must be one-dimensional, got shape {t.shape}")
    if t.size == 0:
        raise ValueError(f"{what} is empty")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError(f"{what} is not finite at row {int(bad[0])}")
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = int(back[0]) + 1
        raise ValueError(
            f"{what} must be sorted by time (non-decreasing): row {k} ({t[k]} s) comes after "
            f"row {k - 1} ({t[k - 1]} s); sort the readings by time first")
    return t


def first_order_lag(t_s: ArrayLike, x: ArrayLike, tau_s: float,
                    x0: float | ArrayLike | None = None) -> F64:
    """Response of the first-order lag ``τ dy/dt = x(t) - y`` sampled at the times ``t_s``.

    The input is taken as piecewise linear between samples (first-order hold), for which
    the recursion is exact at any spacing, so irregular sampling and gaps need nothing
    special: across a gap the input is interpolated linearly and the lag relaxes towards
    it. With ``a = exp(-Δt/τ)`` and ``b = 1 - (τ/Δt)(1 - a)``::

        y_k = a y_{k-1} + (1 - a - b) x_{k-1} + b x_k

    (for a constant input this is ``y_k = y_{k-1} + (1 - a)(x - y_{k-1})``). Repeated
    times (``Δt = 0``) leave ``y`` unchanged.

    Parameters
    ----------
    t_s : array_like, shape (N,)
        Sample times (s), non-decreasing.
    x : array_like, shape (N,) or (N, k)
        Input (any unit, e.g. °C); a 2-D input is filtered column by column.
    tau_s : float
        Time constant (s), > 0.
    x0 : float or array_like of shape (k,), optional
        Output at ``t_s[0]``. Default ``x[0]``: the system at rest (steady state) when
        the record starts.

    Returns
    -------
    ndarray, same shape as ``x``
        The lagged signal, in the unit of ``x``.

    Raises
    ------
    ValueError
        If ``t_s`` is not sorted, shapes disagree, a value is not finite or ``tau_s <= 0``.
    """
    t = _as_time(t_s)
    xa = np.asarray(x, dtype=np.float64)
    if xa.ndim not in (1, 2) or xa.shape[0] != t.shape[0]:
        raise ValueError(f"x must have shape ({t.shape[0]},) or ({t.shape[0]}, k) to match "
                         f"t_s, got {xa.shape}")
    bad = np.argwhere(~np.isfinite(xa))
    if bad.size:
        raise ValueError(f"x is not finite at row {int(bad[0][0])}")
    tau = float(tau_s)
    if not (np.isfinite(tau) and tau > 0.0):
        raise ValueError(f"tau_s must be a finite positive number of seconds, got {tau_s!r}")
    y = np.empty_like(xa)
    if x0 is None:
        y[0] = xa[0]
    else:
        start = np.asarray(x0, dtype=np.float64)
        if start.shape not in ((), xa.shape[1:]):
            raise ValueError(f"x0 must be a scalar or have shape {xa.shape[1:]}, "
                             f"got {start.shape}")
        if not np.all(np.isfinite(start)):
            raise ValueError("x0 is not finite")
        y[0] = start
    n = t.shape[0]
    if n == 1:
        return y
    dt = np.diff(t)
    h = dt / tau
    a = np.exp(-h)
    # b = 1 - (1 - a)/h, written with expm1 so that small steps keep their precision;
    # Δt = 0 gives h = 0 and b = 0 (no step), handled without dividing by zero.
    safe_h = np.where(h > 0.0, h, 1.0)
    b = np.where(h > 0.0, 1.0 + np.expm1(-h) / safe_h, 0.0)
    if xa.ndim == 2:
        a_c, b_c = a[:, None], b[:, None]
    else:
        a_c, b_c = a, b
    u = (1.0 - a_c - b_c) * xa[:-1] + b_c * xa[1:]
    # y_k = a_k y_{k-1} + u_k, solved chunk by chunk in closed form:
    # y_k = E_k (y_s + Σ_{j=s+1..k} u_j / E_j) with E_k = exp(-(t_k - t_s)/τ).
    s = 0
    while s < n - 1:
        e = int(np.searchsorted(t, t[s] + _CHUNK_TAUS * tau, side="right")) - 1
        if e <= s + 1:
            y[s + 1] = a_c[s] * y[s] + u[s]
            s += 1
            continue
        decay = np.exp(-(t[s + 1:e + 1] - t[s]) / tau)
        if xa.ndim == 2:
            decay = decay[:, None]
        y[s + 1:e + 1] = decay * (y[s] + np.cumsum(u[s:e] / decay, axis=0))
        s = e
    return y


def lag_step(y_prev: float, x_prev: float, x_now: float, dt_s: float, tau_s: float) -> float:
    """One step of :func:`first_order_lag`'s recursion: the output at a new sample.

    For a caller that receives the samples one at a time (the center following a
    machine's sensor live) and must land exactly where :func:`first_order_lag` over the
    whole series would.

    Parameters
    ----------
    y_prev : float
        Output at the previous sample.
    x_prev, x_now : float
        Input at the previous and at this sample (first-order hold between them).
    dt_s : float
        Time since the previous sample, s (``<= 0``: the output is unchanged).
    tau_s : float
        Time constant, s (> 0).

    Returns
    -------
    float
        The output at this sample, in the unit of the input.
    """
    if not tau_s > 0:
        raise ValueError(f"tau_s must be > 0, got {tau_s!r}")
    if dt_s <= 0:
        return y_prev
    h = dt_s / tau_s
    a = math.exp(-h)
    b = 1.0 + math.expm1(-h) / h  # as first_order_lag: expm1 keeps short steps precise
    return a * y_prev + (1.0 - a - b) * x_prev + b * x_now
