"""The candidate library of the diagnosis: physically motivated extensions of the rigid
model, each a few extra columns of the same least-squares problem along one machine axis
(the table of :mod:`volumetric.diagnose.diagnosis`, step 3), and what the readings cannot
support (``not_assessed``).

Every candidate acts along an axis's own line of motion as the rigid chain maps it into
the reading's frame (:func:`along_axes`); a periodic error's period comes from a
least-squares periodogram of a residual along the axis (:func:`_best_period`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.rotary import rotary_candidates
from volumetric.identify.design import Param, axis_positions, branch_rows
from volumetric.measure.measurement import Measurements
from volumetric.model.linear import sensitivities
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
SCREW_LEAD_MM = 25.0
"""Longest usual ballscrew lead; positions that cannot resolve it are reported."""
PERIOD_MAX_MM = 4 * SCREW_LEAD_MM
"""Longest period of the ``periodic`` candidate: a screw's pitch error repeats every lead
(<= ``SCREW_LEAD_MM``); a sinusoid of hundreds of mm would only be the nearest fit to
something else (a step between scale segments), which the search for unexplained
structure reports with its period instead."""


@dataclass(frozen=True)
class Candidate:
    """One physically motivated extension: extra columns and how to read them."""

    effect: str
    axis: str
    sensor: str | None
    columns: F64  # (N, k)
    extra: dict[str, Any] = field(default_factory=dict)  # e.g. the period of a periodic
    drop: tuple[int, ...] = ()  # base columns the extension replaces (not adds to)
    per_fold: tuple[F64, ...] = ()
    """Columns for each fold of the diagnosis's split, (N, k_f) each, when the extension
    is selected again from every fold's training readings (a lagged drift: which sensors
    and time constants is part of what is judged); empty when ``columns`` serve every
    fold."""
    fixed: bool = False
    """The columns are a prediction (µm) that enters with coefficient 1, its shape and
    scale both from a fit of its own (the averaged lagged drift), not columns to fit:
    every least-squares problem takes their sum off the readings instead."""

    def design(self, a0: F64) -> F64:
        """The base design with this extension: ``(N, P - len(drop) + k)`` (``k = 0``
        for a fixed one)."""
        base = np.delete(a0, list(self.drop), axis=1) if self.drop else a0
        return base if self.fixed else np.column_stack((base, self.columns))

    def known(self, f: int | None = None) -> F64:
        """What a fixed extension predicts (µm), shape (N,): its columns' sum, those of
        fold ``f`` when given; zeros for one that is fitted."""
        if not self.fixed:
            return np.zeros(self.columns.shape[0])
        cols = self.columns if f is None else self.in_fold(f).columns
        return np.asarray(cols.sum(axis=1), dtype=np.float64)

    def in_fold(self, f: int) -> Candidate:
        """The extension as fold ``f`` of the split fits it (itself when it has no
        per-fold columns)."""
        if not self.per_fold:
            return self
        return Candidate(self.effect, self.axis, self.sensor, self.per_fold[f], self.extra,
                         self.drop, fixed=self.fixed)

    @property
    def label(self) -> str:
        return f"{self.effect}({self.axis}{', ' + self.sensor if self.sensor else ''})"


def temperature_columns(m: Measurements) -> dict[str, F64]:
    """Temperature readings by column name (``T_<sensor>_C``), °C, shape (N,) each."""
    return {m.temperature_columns[s]: v for s, v in m.temperatures.items()}


def along_axes(machine: Machine, m: Measurements) -> F64:
    """What each displacement reading senses of a 1 µm error along each linear axis's own
    direction of motion (X, Y, Z; 0 for an axis the chain lacks and for angle readings).

    Every candidate acts along an axis's own line of motion, the direction its own
    positioning error moves the tool tip relative to the workpiece. Readings taken in a
    frame that turns with a rotary axis (an R-test on a rotary table: the ball moves with
    the table) see that direction turned by the angle, so the reading's component
    ``u_k`` is not it: a backlash of Y read at C = 90° shows on the x reading. The
    sensitivity of the tool tip to the axis's positioning component (the rigid model's
    first-order chain, the same that builds the base design) is.

    Returns
    -------
    ndarray, shape (N, 3)
        Dimensionless (µm read per µm of error).
    """
    out = np.zeros((len(m), 3))
    q = axis_positions(machine, m)
    disp = ~m.is_angle
    for bname, rows in branch_rows(machine, m).items():
        if rows.size == 0:
            continue
        u = m.u[rows]
        for sens in sensitivities(machine, q[rows], spindle=bname, tool_mm=m.tool_mm[rows]):
            if sens.column is None:
                continue
            axis = machine.axes[sens.column]
            if axis.kind != "linear" or axis.name not in ("X", "Y", "Z"):
                continue
            own = "XYZ".index(axis.name)
            j = sens.names.index(f"E{'XYZ'[own]}{axis.name}")
            out[rows, own] = np.einsum("ni,ni->n", u, sens.matrix[:, :3, j])
    out[~disp] = 0.0
    return out


def candidates(
    machine: Machine, m: Measurements, base_residual: F64, train: NDArray[np.bool_],
    a0: F64 | None = None, w: F64 | None = None,
) -> tuple[list[Candidate], dict[str, str]]:
    """The library of extensions for these readings, and what cannot be assessed.

    Every rotary axis adds its candidates of :mod:`volumetric.diagnose.rotary`: a cyclic
    error beyond the base's harmonics (``rotary_periodic``, on an axis of at least half a
    turn read at angles fine enough) and a reversal error (``rotary_backlash``, when the
    readings say the axis's approach direction); ``a0``, the base design (N, P), is
    what a cyclic error's order is judged beside, and ``w`` (N,), the base fit's weight
    of each reading, how the readings count in that judgement.
    """
    q = axis_positions(machine, m)
    temps = temperature_columns(m)
    out: list[Candidate] = []
    missing: dict[str, str] = {}
    if not temps:
        missing["thermal"] = "no temperature columns (T_<sensor>_C) in the readings"
    linear = [a for a in machine.axes if a.kind == "linear" and a.name in ("X", "Y", "Z")]
    t_mean = float(m.time_s[train].mean())
    along = along_axes(machine, m)
    for axis in linear:
        k = "XYZ".index(axis.name)
        uk = along[:, k]
        sensed = np.abs(uk) > 1e-6
        key = axis.key
        if not sensed.any():
            missing[key] = f"no displacement reading senses along {key}"
            continue
        qk = q[:, machine.axis_names.index(axis.name)]
        lo = axis.travel[0]
        for col, values in temps.items():
            dt = values - float(values[train].mean())
            if np.ptp(values[sensed]) < 0.05:
                missing.setdefault(f"thermal {key}", f"{col} hardly changes (< 0.05 K)")
                continue
            out.append(Candidate("thermal_drift", key, col, (uk * dt)[:, None],
                                 {"along": uk}))
            expansion = uk * dt * (qk - lo) / 1000.0
            if np.ptp(qk[sensed]) > 1e-6:
                out.append(Candidate("thermal_expansion", key, col, expansion[:, None]))
        dirs = m.direction[:, k].astype(float)
        if np.unique(dirs[sensed & (dirs != 0)]).size >= 2:
            out.append(Candidate("backlash", key, None, (-0.5 * uk * dirs)[:, None]))
        else:
            missing[f"backlash {key}"] = f"one approach direction only along {key}"
        span = float(np.ptp(qk[sensed]))
        if span > 0:
            shortest = _shortest_period(qk[sensed])
            if shortest > SCREW_LEAD_MM:
                missing[f"periodic {key}"] = (
                    f"positions along {key} resolve only periods above {shortest:.0f} mm; a "
                    f"ballscrew's lead is {SCREW_LEAD_MM:.0f} mm or less (add a fine "
                    "positioning test)")
            period = _best_period(qk, uk, base_residual, sensed & train, span)
            if period is not None:
                out.append(_periodic(key, uk, qk, period))
        if np.ptp(m.time_s) > 0:
            out.append(Candidate("time_drift", key, None,
                                 (uk * (m.time_s - t_mean) / 3600.0)[:, None]))
    for effect, key, cols, extra in rotary_candidates(machine, m, base_residual, train,
                                                      missing, a0, w):
        out.append(Candidate(effect, key, None, cols, extra))
    return out, missing


def _of_axis(p: Param, axis: str) -> bool:
    """True for a component coefficient (not a location or offset) of ``axis``."""
    return p.degree >= 0 and p.component[2:] == axis


def _shortest_period(q: F64) -> float:
    """Twice the typical spacing of distinct positions (mm): the shortest period they
    resolve (see :func:`_best_period`)."""
    qs = np.unique(np.round(q, 6))
    if qs.size < 2:
        return math.inf
    return max(2.0, 2.0 * float(np.percentile(np.diff(qs), 20)))


def _best_period(q: F64, u: F64, r: F64, rows: NDArray[np.bool_], span: float) -> float | None:
    """The period (mm) whose sinusoid along the axis best explains the residual.

    A least-squares periodogram over periods from twice the typical spacing of the sensed
    positions (their Nyquist limit; 2 mm at least) to a third of the sensed span or
    ``PERIOD_MAX_MM``, whichever is shorter, refined
    on a finer grid around the peak. The typical spacing is the 20th percentile of the
    gaps between distinct positions: a fine test over part of the travel resolves short
    periods, a few stray close targets do not.
    """
    if np.unique(np.round(q[rows], 6)).size < 8:
        return None
    lo = _shortest_period(q[rows])
    hi = min(span / 3.0, PERIOD_MAX_MM)
    if hi <= lo:
        return None
    qq, uu, rr = q[rows], u[rows], r[rows]

    def power(periods: F64) -> F64:
        # the squared norm of the residual's projection on (u sin, u cos) of each period,
        # b·G⁻¹b from the 2x2 normal equations, for a chunk of periods at a time
        out = np.empty(periods.size)
        uu2, ur = uu * uu, uu * rr
        step = max(1, 500_000 // max(qq.size, 1))
        for i in range(0, periods.size, step):
            ph = (2 * np.pi / periods[i:i + step, None]) * qq[None, :]
            sn, cs = np.sin(ph), np.cos(ph)
            s11, s22, s12 = (sn * sn) @ uu2, (cs * cs) @ uu2, (sn * cs) @ uu2
            b1, b2 = sn @ ur, cs @ ur
            det = s11 * s22 - s12 * s12
            full = det > 1e-12 * s11 * s22
            with np.errstate(divide="ignore", invalid="ignore"):
                proj = (s22 * b1 * b1 - 2 * s12 * b1 * b2 + s11 * b2 * b2) / det
                # (nearly) one column: the projection on the larger of the two
                one = np.where(s11 >= s22, b1 * b1 / s11, b2 * b2 / s22)
            out[i:i + step] = np.where(full, proj, np.where(np.isfinite(one), one, 0.0))
        return out

    grid = np.geomspace(lo, hi, 300)
    pw = power(grid)
    best = float(grid[int(np.argmax(pw))])
    fine = np.linspace(best * 0.97, best * 1.03, 61)
    return float(fine[int(np.argmax(power(fine)))])


def periodic_again(machine: Machine, m: Measurements, c: Candidate, resid: F64,
                   train: NDArray[np.bool_]) -> Candidate | None:
    """The periodic candidate of ``c``'s axis with its period found again from ``resid``
    (the residual of the model with every other effect in)."""
    axis = machine.axis(c.axis)
    k = "XYZ".index(axis.name)
    along = c.extra.get("along")
    uk = along_axes(machine, m)[:, k] if along is None else along
    sensed = np.abs(uk) > 1e-6
    qk = axis_positions(machine, m)[:, machine.axis_names.index(axis.name)]
    period = _best_period(qk, uk, resid, sensed & train, float(np.ptp(qk[sensed])))
    if period is None:
        return None
    return _periodic(c.axis, uk, qk, period)


def _periodic(key: str, uk: F64, qk: F64, period: float) -> Candidate:
    """The periodic candidate of axis ``key``: ``u_k sin``, ``u_k cos`` of ``2π q_k / P``,
    keeping ``u_k`` (what each reading senses along the axis) for :func:`periodic_again`."""
    ph = 2 * np.pi * qk / period
    return Candidate("periodic", key, None, np.column_stack((uk * np.sin(ph), uk * np.cos(ph))),
                     {"period_mm": period, "along": uk})
