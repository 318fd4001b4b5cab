"""The regressor columns of a thermal-drift model (:mod:`volumetric.identify.thermal`):
:class:`ThermalTerm`, one column defined by what it is computed from, and
:func:`thermal_regressors`, many of them at once for a larger least-squares problem.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.lag import _as_time, first_order_lag

F64 = NDArray[np.float64]

DEFAULT_TAUS_S: tuple[float, ...] = tuple(300.0 * 2.0**k for k in range(10))
"""Grid of lag time constants (s): 300 s .. 153 600 s (43 h), a factor 2 apart. Machine-tool
structures have thermal time constants from minutes (spindle nose, coolant) to a day (bed,
foundation); a factor 2 is fine enough once each chosen τ is refined continuously."""

TermKind = Literal["level", "lag", "time"]


@dataclass(frozen=True, slots=True)
class ThermalTerm:
    """One regressor column, defined by what it is computed from.

    Attributes
    ----------
    kind : {"level", "lag", "time"}
        ``level``: the signal itself; ``lag``: its first-order lag with ``tau_s``;
        ``time``: the time drift ``(t - t0_s)`` in hours (``source`` is empty).
    source : str
        Name of the temperature (or extra input) the column is built from.
    tau_s : float
        Lag time constant (s); 0 for ``level`` and ``time``.
    """

    kind: TermKind
    source: str = ""
    tau_s: float = 0.0

    @property
    def name(self) -> str:
        """Human-readable column name, e.g. ``"T_t3_C lag 3600 s"``."""
        if self.kind == "time":
            return "time drift h"
        if self.kind == "level":
            return self.source
        return f"{self.source} lag {self.tau_s:.0f} s"

    def column(self, t_s: ArrayLike, signals: Mapping[str, ArrayLike],
               t0_s: float = 0.0) -> F64:
        """The column over a time series.

        Parameters
        ----------
        t_s : array_like, shape (N,)
            Sample times (s), non-decreasing.
        signals : mapping of str to array_like, shape (N,)
            Temperatures (°C) and extra inputs by name; must hold ``source``.
        t0_s : float
            Time origin (s) of the time drift.

        Returns
        -------
        ndarray, shape (N,)
            °C for a temperature level or lag, the input's unit for an extra input, hours
            for the time drift.
        """
        t = _as_time(t_s)
        if self.kind == "time":
            return (t - t0_s) / 3600.0
        if self.source not in signals:
            raise ValueError(f"signal {self.source!r} is missing: the term {self.name!r} "
                             f"needs it (have {sorted(signals)})")
        x = as_signal(self.source, signals[self.source], t.shape[0])
        if self.kind == "level":
            return x
        return first_order_lag(t, x, self.tau_s)


def as_signal(name: str, values: ArrayLike, n: int) -> F64:
    x = np.asarray(values, dtype=np.float64)
    if x.shape != (n,):
        raise ValueError(f"signal {name!r} has shape {x.shape}, expected ({n},) like t_s")
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        raise ValueError(f"signal {name!r} is not finite at row {int(bad[0])}")
    return x


def thermal_regressors(
    t_s: ArrayLike,
    temps: Mapping[str, ArrayLike],
    taus_s: Sequence[float] = DEFAULT_TAUS_S,
    *,
    levels: bool = True,
    rate_taus_s: Sequence[float] = (),
    gradients: Sequence[tuple[str, str]] = (),
    time_drift: bool = False,
    inputs: Mapping[str, ArrayLike] | None = None,
) -> tuple[F64, list[str]]:
    """Dynamic thermal regressors as columns of a design matrix.

    Parameters
    ----------
    t_s : array_like, shape (N,)
        Sample times (s), non-decreasing (sort the readings by time first). Irregular
        spacing and gaps are handled exactly (see :func:`first_order_lag`).
    temps : mapping of str to array_like, shape (N,)
        Temperatures (°C) by column name, e.g. ``{"T_t3_C": ...}``.
    taus_s : sequence of float
        Lag time constants (s); each temperature gets one lag column per value.
    levels : bool
        Include the temperatures themselves.
    rate_taus_s : sequence of float
        For each value τ, a smoothed rate ``(T - L_τ[T]) / τ`` per temperature, in K/h.
    gradients : sequence of (str, str)
        Sensor pairs ``(a, b)`` giving the column ``T_a - T_b`` (K).
    time_drift : bool
        Include ``(t - t_s[0])`` in hours.
    inputs : mapping of str to array_like, shape (N,), optional
        Extra inputs (e.g. ``spindle_rpm``), given a level and the same lags as the
        temperatures. Optional by design: the temperatures alone are enough.

    Returns
    -------
    X : ndarray, shape (N, p)
        The columns, in the order of ``names``.
    names : list of str
        One name per column: ``"T_t3_C"``, ``"T_t3_C lag 3600 s"``, ``"T_t3_C rate 900 s"``
        (K/h), ``"T_t1_C - T_t2_C"``, ``"time drift h"``, ``"spindle_rpm lag 7200 s"``.

    Raises
    ------
    ValueError
        If no column is requested, a signal is missing, mis-shaped or not finite, a
        gradient names an unknown sensor, or ``t_s`` is not sorted.
    """
    t = _as_time(t_s)
    n = t.shape[0]
    temp = {k: as_signal(k, v, n) for k, v in temps.items()}
    extra = {k: as_signal(k, v, n) for k, v in (inputs or {}).items()}
    clash = set(temp) & set(extra)
    if clash:
        raise ValueError(f"names used both as temperature and as input: {sorted(clash)}")
    cols: list[F64] = []
    names: list[str] = []
    for group in (temp, extra):
        if not group:
            continue
        keys = list(group)
        block = np.column_stack([group[k] for k in keys])
        if levels:
            cols.extend(block.T)
            names.extend(keys)
        for tau in taus_s:
            lagged = first_order_lag(t, block, tau)
            cols.extend(lagged.T)
            names.extend(ThermalTerm("lag", k, float(tau)).name for k in keys)
        if group is temp:
            for tau in rate_taus_s:
                rate = (block - first_order_lag(t, block, tau)) * (3600.0 / float(tau))
                cols.extend(rate.T)
                names.extend(f"{k} rate {float(tau):.0f} s" for k in keys)
    for a, b in gradients:
        for k in (a, b):
            if k not in temp:
                raise ValueError(f"gradient ({a!r}, {b!r}): unknown temperature {k!r} "
                                 f"(have {sorted(temp)})")
        cols.append(temp[a] - temp[b])
        names.append(f"{a} - {b}")
    if time_drift:
        cols.append((t - t[0]) / 3600.0)
        names.append("time drift h")
    if not cols:
        raise ValueError("no regressor requested: give temperatures (or inputs) with levels "
                         "or lags, gradients, or time_drift")
    return np.column_stack(cols), names


def merge_signals(temps: Mapping[str, ArrayLike],
                   inputs: Mapping[str, ArrayLike] | None) -> dict[str, ArrayLike]:
    merged: dict[str, ArrayLike] = dict(temps)
    for k, v in (inputs or {}).items():
        if k in merged:
            raise ValueError(f"name {k!r} used both as temperature and as input")
        merged[k] = v
    return merged
