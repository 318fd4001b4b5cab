"""ISO 230-2:2014 evaluation of a bidirectional positioning test of one linear axis.

The test moves one axis to m target positions P_i, j = 1..n times from each side, and reads
the positional deviation x_ij = (actual - target) along the axis. Definitions (clause 3 of
ISO 230-2:2014; the arrow ↑ is approach in the positive direction, ↓ in the negative):

- mean unidirectional positional deviation  x̄i↑ = (1/n) Σ_j x_ij↑ (and ↓)
- estimator of the unidirectional standard uncertainty of positioning
  si↑ = sqrt( Σ_j (x_ij↑ - x̄i↑)² / (n - 1) )
- reversal value at a position  Bi = x̄i↑ - x̄i↓;  of the axis  B = max |Bi|;  mean  B̄
- unidirectional positioning repeatability  Ri↑ = 4 si↑,  R↑ = max Ri↑
- bidirectional positioning repeatability at a position
  Ri = max(2 si↑ + 2 si↓ + |Bi|, Ri↑, Ri↓),  R = max Ri
- unidirectional systematic positioning error  E↑ = max x̄i↑ - min x̄i↑
- bidirectional systematic positioning error  E = max(x̄i↑, x̄i↓) - min(x̄i↑, x̄i↓),
  extremes taken over all positions *and* both directions
- mean bidirectional positional deviation  x̄i = (x̄i↑ + x̄i↓) / 2,  M = max x̄i - min x̄i
- unidirectional accuracy  A↑ = max(x̄i↑ + 2 si↑) - min(x̄i↑ - 2 si↑)
- bidirectional accuracy  A = max(x̄i↑ + 2 si↑, x̄i↓ + 2 si↓) - min(x̄i↑ - 2 si↑, x̄i↓ - 2 si↓)

How measurement CSV rows map onto the test (formats.md section 2): ``run`` is the cycle j,
the moving axis is the one linear axis whose commanded coordinate varies, its ``dir_*`` is
the approach direction, targets are the distinct commanded positions (within
``target_tol_mm``), and the deviation is ``value`` (µm) signed along the axis (``u`` must be
parallel or antiparallel to it). The standard's minimum of five targets is not enforced, so
short checks can be evaluated; at least two targets and two cycles per target and
direction are.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.measurement import U_NORM_TOL, Measurements

__all__ = ["PositioningResult", "PositioningTestError", "cluster_targets", "evaluate_positioning"]

AXES = ("x", "y", "z", "a", "b", "c")
FloatArray = NDArray[np.float64]


class PositioningTestError(ValueError):
    """Readings that do not form an ISO 230-2 bidirectional positioning test."""


@dataclass(frozen=True, slots=True)
class PositioningResult:
    """ISO 230-2 evaluation of one axis; all deviations in µm.

    Attributes
    ----------
    axis : str
        The moving axis, ``x``, ``y`` or ``z``.
    targets_mm : ndarray, shape (m,)
        Target positions P_i (mm), ascending.
    n_up, n_down : ndarray of int64, shape (m,)
        Cycles approached in the positive (↑) and negative (↓) direction.
    mean_up_um, mean_down_um : ndarray, shape (m,)
        x̄i↑, x̄i↓.
    s_up_um, s_down_um : ndarray, shape (m,)
        si↑, si↓ (n - 1 in the denominator).
    mean_um : ndarray, shape (m,)
        x̄i, the mean bidirectional positional deviation.
    reversal_um : ndarray, shape (m,)
        Bi = x̄i↑ - x̄i↓.
    repeatability_up_um, repeatability_down_um, repeatability_um : ndarray, shape (m,)
        Ri↑ = 4 si↑, Ri↓ = 4 si↓ and the bidirectional Ri.
    A_um, B_um, E_um, M_um, R_um : float
        Bidirectional accuracy, reversal value (max |Bi|), bidirectional systematic
        positioning error, mean bidirectional positional deviation range, bidirectional
        repeatability.
    B_mean_um : float
        Mean reversal value B̄.
    A_up_um, A_down_um, E_up_um, E_down_um, R_up_um, R_down_um : float
        The unidirectional values.
    """

    axis: str
    targets_mm: FloatArray
    n_up: NDArray[np.int64]
    n_down: NDArray[np.int64]
    mean_up_um: FloatArray
    mean_down_um: FloatArray
    s_up_um: FloatArray
    s_down_um: FloatArray
    mean_um: FloatArray
    reversal_um: FloatArray
    repeatability_up_um: FloatArray
    repeatability_down_um: FloatArray
    repeatability_um: FloatArray
    A_um: float
    B_um: float
    E_um: float
    M_um: float
    R_um: float
    B_mean_um: float
    A_up_um: float
    A_down_um: float
    E_up_um: float
    E_down_um: float
    R_up_um: float
    R_down_um: float

    def summary(self) -> dict[str, float]:
        """The five axis values of ``ednc iso230-2 --json``: A, B, E, M, R in µm."""
        return {"A_um": self.A_um, "B_um": self.B_um, "E_um": self.E_um,
                "M_um": self.M_um, "R_um": self.R_um}


def evaluate_positioning(m: Measurements, *, target_tol_mm: float = 1e-3
                         ) -> PositioningResult:
    """Evaluate readings of one bidirectional positioning test after ISO 230-2:2014.

    Parameters
    ----------
    m : Measurements
        The test's readings: displacement rows of one test label, one moving linear axis.
    target_tol_mm : float
        Commanded positions closer than this (mm) are the same target, and a coordinate
        that varies less than this does not move (it absorbs float noise in the commands).

    Returns
    -------
    PositioningResult

    Raises
    ------
    PositioningTestError
        No readings, angle readings, several test labels, no or several moving axes, a
        sensing direction not along the axis, an approach direction of 0, a target
        without readings from one side, fewer than two cycles of a target and direction,
        a cycle that reads a target twice from the same side, or readings from one side
        only.
    """
    if len(m) == 0:
        raise PositioningTestError("no readings to evaluate")
    if m.is_angle.any():
        i = int(np.flatnonzero(m.is_angle)[0])
        raise PositioningTestError(
            f"{int(m.is_angle.sum())} angle reading(s) (first: test {str(m.test[i])!r}, run "
            f"{m.run[i]}); an ISO 230-2 positioning test reads displacements along the axis")
    labels = np.unique(m.test)
    if labels.size > 1:
        raise PositioningTestError(
            f"readings of {labels.size} tests ({', '.join(map(repr, labels.tolist()))}); "
            "evaluate one test at a time")
    axis = _moving_axis(m, target_tol_mm)
    pos = m.q[:, axis]
    _check_sensing_direction(m, axis, pos)
    deviation = m.value * np.sign(m.u[:, axis])
    approach = m.direction[:, axis]
    name = AXES[axis]
    if (approach == 0).any():
        i = int(np.flatnonzero(approach == 0)[0])
        raise PositioningTestError(
            f"dir_{name} is 0 at {name} = {pos[i]:g} mm (run {m.run[i]}): each reading must "
            "say from which side its target was approached")
    if (approach > 0).all() or (approach < 0).all():
        side = "positive" if approach[0] > 0 else "negative"
        raise PositioningTestError(
            f"every reading approaches its target in the {side} direction (dir_{name}); "
            "the bidirectional evaluation needs both")

    # The axis spans more than the tolerance, so this finds at least two targets (or
    # raises on positions chained across the tolerance).
    targets, which = cluster_targets(pos, target_tol_mm, name)
    n_up, mean_up, s_up = _side_stats(deviation, which, approach, m.run, +1, targets, name)
    n_down, mean_down, s_down = _side_stats(deviation, which, approach, m.run, -1, targets,
                                            name)

    reversal = mean_up - mean_down
    r_up, r_down = 4.0 * s_up, 4.0 * s_down
    r_bi = np.maximum.reduce([2.0 * s_up + 2.0 * s_down + np.abs(reversal), r_up, r_down])
    mean_bi = 0.5 * (mean_up + mean_down)
    both = np.concatenate([mean_up, mean_down])
    upper = np.concatenate([mean_up + 2.0 * s_up, mean_down + 2.0 * s_down])
    lower = np.concatenate([mean_up - 2.0 * s_up, mean_down - 2.0 * s_down])
    return PositioningResult(
        axis=name, targets_mm=targets, n_up=n_up, n_down=n_down,
        mean_up_um=mean_up, mean_down_um=mean_down, s_up_um=s_up, s_down_um=s_down,
        mean_um=mean_bi, reversal_um=reversal,
        repeatability_up_um=r_up, repeatability_down_um=r_down, repeatability_um=r_bi,
        A_um=float(upper.max() - lower.min()),
        B_um=float(np.abs(reversal).max()),
        E_um=float(both.max() - both.min()),
        M_um=float(mean_bi.max() - mean_bi.min()),
        R_um=float(r_bi.max()),
        B_mean_um=float(reversal.mean()),
        A_up_um=float((mean_up + 2.0 * s_up).max() - (mean_up - 2.0 * s_up).min()),
        A_down_um=float((mean_down + 2.0 * s_down).max() - (mean_down - 2.0 * s_down).min()),
        E_up_um=float(np.ptp(mean_up)),
        E_down_um=float(np.ptp(mean_down)),
        R_up_um=float(r_up.max()),
        R_down_um=float(r_down.max()),
    )


def _moving_axis(m: Measurements, tol: float) -> int:
    span = m.q.max(axis=0) - m.q.min(axis=0)
    moving = np.flatnonzero(span > tol)
    if moving.size == 0:
        raise PositioningTestError(
            f"no axis moves (every commanded coordinate varies by at most {tol:g})")
    if moving.size > 1:
        spans = ", ".join(f"{AXES[j]} by {span[j]:g}" for j in moving)
        raise PositioningTestError(
            f"more than one axis moves ({spans}); a positioning test moves one axis")
    axis = int(moving[0])
    if axis >= 3:
        raise PositioningTestError(
            f"the moving axis is the rotary axis {AXES[axis]}; this evaluation covers "
            "linear axes")
    return axis


def _check_sensing_direction(m: Measurements, axis: int, pos: FloatArray) -> None:
    off = np.abs(m.u[:, axis]) < 1.0 - U_NORM_TOL
    if off.any():
        i = int(np.flatnonzero(off)[0])
        raise PositioningTestError(
            f"the reading at {AXES[axis]} = {pos[i]:g} mm (run {m.run[i]}) senses along "
            f"u = {tuple(m.u[i].tolist())}, not along the {AXES[axis]} axis")


def cluster_targets(pos: FloatArray, tol: float, name: str
                     ) -> tuple[FloatArray, NDArray[np.intp]]:
    """Distinct commanded positions and each reading's target index.

    Parameters
    ----------
    pos : ndarray, shape (N,)
        Commanded positions (mm).
    tol : float
        Positions closer than this (mm) are one target.
    name : str
        What the positions are, for error messages (``x``, ``s along diag-PPP``).

    Returns
    -------
    targets : ndarray, shape (m,)
        Mean commanded position of each target (mm), ascending.
    which : ndarray of intp, shape (N,)
        Index into ``targets`` of each reading.

    Raises
    ------
    PositioningTestError
        Positions chained closer than ``tol`` that spread wider than ``tol``.
    """
    order = np.argsort(pos, kind="stable")
    ordered = pos[order]
    cluster = np.concatenate([[0], np.cumsum(np.diff(ordered) > tol)])
    which = np.empty_like(order)
    which[order] = cluster
    count = int(cluster[-1]) + 1
    lo = np.full(count, np.inf)
    hi = np.full(count, -np.inf)
    np.minimum.at(lo, which, pos)
    np.maximum.at(hi, which, pos)
    wide = np.flatnonzero(hi - lo > tol)
    if wide.size:
        k = int(wide[0])
        raise PositioningTestError(
            f"commanded {name} positions from {lo[k]:g} to {hi[k]:g} mm are chained closer "
            f"than {tol:g} mm: they are neither one target nor distinct targets")
    targets = np.bincount(which, weights=pos, minlength=count) / np.bincount(
        which, minlength=count)
    return targets, which


def _side_stats(deviation: FloatArray, which: NDArray[np.intp], approach: NDArray[np.int8],
                run: NDArray[np.int64], side: int, targets: FloatArray, name: str
                ) -> tuple[NDArray[np.int64], FloatArray, FloatArray]:
    """Per target: cycles, mean deviation (µm) and standard uncertainty s (µm) of one side."""
    word = "positive" if side > 0 else "negative"
    counts = np.zeros(targets.size, dtype=np.int64)
    means = np.zeros(targets.size)
    sds = np.zeros(targets.size)
    for k, target in enumerate(targets):
        rows = np.flatnonzero((which == k) & (approach == side))
        where = f"target {name} = {target:g} mm, approach in the {word} direction"
        if rows.size == 0:
            raise PositioningTestError(f"{where}: no readings (the reversal value needs both "
                                       "sides of every target)")
        runs, seen = np.unique(run[rows], return_counts=True)
        if (seen > 1).any():
            raise PositioningTestError(
                f"{where}: run {runs[seen > 1][0]} reads it {seen.max()} times; ISO 230-2 "
                "takes one reading per target, direction and cycle")
        if rows.size < 2:
            raise PositioningTestError(
                f"{where}: only {rows.size} cycle (run {run[rows[0]]}); the standard "
                "uncertainty needs at least 2")
        counts[k] = rows.size
        means[k] = deviation[rows].mean()
        sds[k] = deviation[rows].std(ddof=1)
    return counts, means, sds
