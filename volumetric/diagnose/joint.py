"""Thermal effects on one axis judged and estimated jointly (step 6 of
:mod:`volumetric.diagnose`, issue 33).

A drift (``u_k ΔT_s``, position-independent) and an expansion (``u_k ΔT_s' (q_k − q_min)``,
position-dependent) on one axis share variance: over the readings the expansion's mean
over positions is a drift of its sensor. Named one after the other, the first takes that
share (a drift on the screw's sensor, or a drift model whose terms include it), and the
second is estimated on what is left: the expansion comes out at a third of its size, or
the two sensors swap. Here every pair of a drift and an expansion of the axis (each of its
sensors) is judged with both in the model and every other named effect beside them, and
the best pair replaces the axis's thermal effects when it explains the held-out readings
better than what was named; a second effect joins a single one only when it passes the
three gates of any further effect against the best single thermal effect of the axis
(gain ``MIN_GAIN``, significance ``Z_MIN``, each coefficient ``T_MIN``). The estimates are
then those of one fit with both columns (:func:`joint_fit`), and the correlation between
them is reported.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.gates import (
    MAX_EFFECTS,
    MIN_GAIN,
    T_MIN,
    THERMAL_FAMILY,
    TIE,
    Z_MIN,
    Scored,
    significance,
)
from volumetric.diagnose.splits import combined, known_sum, rms_of, solve_normal

F64 = NDArray[np.float64]
PAIR = ("thermal_drift", "thermal_expansion")
"""The position-independent and the position-dependent thermal effect of one axis."""



@dataclass(frozen=True)
class JointFit:
    """Base and extension columns fitted together on the training readings.

    Attributes
    ----------
    x : ndarray, shape (P + K,)
        Base parameters then every free candidate's coefficients, in order.
    cov : ndarray, shape (P + K, P + K)
        Their covariance (µm² in the readings' units, scaled by the residual variance).
    slices : dict of int to slice
        Index of a candidate in the fitted list → its coefficients in ``x``.
    """

    x: F64
    cov: F64
    slices: dict[int, slice]

    def coef(self, i: int) -> F64:
        return self.x[self.slices[i]]

    def std(self, i: int) -> F64:
        d = np.diag(self.cov)[self.slices[i]]
        return np.sqrt(np.clip(d, 0, None))

    def correlation(self, i: int, j: int) -> float:
        """Correlation of the first coefficients of candidates ``i`` and ``j``."""
        a, b = self.slices[i].start, self.slices[j].start
        den = math.sqrt(max(float(self.cov[a, a] * self.cov[b, b]), 1e-300))
        return float(self.cov[a, b] / den)


def joint_fit(a0: F64, w: F64, y: F64, train: NDArray[np.bool_], cands: list[Candidate]
              ) -> JointFit:
    """The base design ``a0`` (N, P) and every free candidate of ``cands`` fitted together
    on the training readings (a fixed one's prediction taken off the readings first), with
    the covariance of the solution from the weighted residual variance."""
    a = combined(a0, cands)
    yk = y - known_sum(len(y), cands)
    at, wt, yt = a[train], w[train], yk[train]
    g = at.T @ (at * wt[:, None])
    x = solve_normal(g, (at * wt[:, None]).T @ yt)
    r = yt - at @ x
    s2 = float(np.sum(wt * r * r) / max(int(train.sum()) - a.shape[1], 1))
    cov: F64 = np.asarray(np.linalg.pinv(g) * s2, dtype=np.float64)
    slices: dict[int, slice] = {}
    at_col = a.shape[1] - sum(c.columns.shape[1] for c in cands if not c.drop and not c.fixed)
    for i, c in enumerate(cands):
        if c.drop or c.fixed:
            continue
        k = c.columns.shape[1]
        slices[i] = slice(at_col, at_col + k)
        at_col += k
    return JointFit(x, cov, slices)


def _t(fit: JointFit, i: int) -> float:
    coef, std = fit.coef(i), fit.std(i)
    return float(np.linalg.norm(coef) / max(float(np.linalg.norm(std)), 1e-300))


def best_pair(tried: list[tuple[float, Candidate, Candidate, F64]]
              ) -> tuple[float, Candidate, Candidate, F64]:
    """The pair of a drift and an expansion of one axis to judge, of every pair ``tried``
    (held-out RMS in µm, drift, expansion, held-out residuals (N,)): the lowest held-out
    RMS among those whose two members read different sensors, unless a pair on one sensor
    beats every such pair by more than ``TIE``.

    A drift and an expansion of one sensor are one body's growth about another fixed
    point (``k ΔT + α ΔT (q − q_min) = α ΔT (q − q_0)``), not two effects. Where the
    screws follow the same shop air, every pair of them fits the readings to within a
    few tenths of a percent, and the pair on one sensor wins that tie by the sensors'
    reading noise alone: its two columns carry the same noise, which cancels where the
    drift and the expansion cancel, while two sensors' noises add (errors in the
    variables). It then names the expansion's sensor for the drift too, with both sizes
    right (issue 33: 3 of the 7 misses of the same-axis family at noise x2, the true pair
    within 0.1-0.8 % of it). Where the readings cannot tell them apart (``TIE``, the
    margin that lists another sensor as an alternative), two sensors are kept.
    """
    if not tried:
        raise ValueError("no pair to judge")
    best = min(tried, key=lambda t: t[0])
    two = [t for t in tried if t[1].sensor != t[2].sensor]
    if two:
        best_two = min(two, key=lambda t: t[0])
        if best_two[0] <= best[0] * (1 + TIE):
            return best_two
    return best


def same_axis_pairs(
    chosen: list[Candidate], scored: list[Scored],
    heldout_of: Callable[[list[Candidate]], F64], judge: NDArray[np.bool_],
    order_judge: NDArray[np.intp], fit_of: Callable[[list[Candidate]], JointFit],
) -> list[Candidate]:
    """``chosen`` with the thermal effects of each axis that holds a drift or an expansion
    replaced by the best jointly judged pair of a drift and an expansion of that axis, when
    that pair explains the held-out readings better than they do and its weaker member
    passes the gates against the best single thermal effect of the axis (module
    docstring); else ``chosen`` as it was.

    ``heldout_of`` gives the held-out residuals (N,) of the base with a list of
    candidates; ``fit_of`` their joint fit on the training readings.
    """
    out = list(chosen)
    axes = sorted({c.axis for c in out if c.effect in PAIR})
    for axis in axes:
        on_axis = [c for c in out if c.effect in THERMAL_FAMILY and c.axis == axis]
        others = [c for c in out if not any(c is x for x in on_axis)]
        if len(others) + 2 > MAX_EFFECTS:
            continue
        pool = {e: [s.candidate for s in scored
                    if s.candidate.effect == e and s.candidate.axis == axis
                    and not s.candidate.drop and "lagged" not in s.candidate.extra]
                for e in PAIR}
        if not pool[PAIR[0]] or not pool[PAIR[1]]:
            continue
        singles = [(c, heldout_of([*others, c])) for e in PAIR for c in pool[e]]
        single, r_single = min(singles, key=lambda cr: rms_of(cr[1][judge]))
        rms_pair, d, e, r_pair = best_pair(
            [(rms_of(r[judge]), d, e, r) for d in pool[PAIR[0]] for e in pool[PAIR[1]]
             for r in (heldout_of([*others, d, e]),)])
        rms_now = rms_of(heldout_of(out)[judge])
        # what is named may itself be a drift and an expansion on one sensor (forward
        # selection and refine choose each with the other in): best_pair's rule, not
        # the lower RMS alone, decides between it and a pair on two sensors
        one_sensor = (sorted(c.effect for c in on_axis) == sorted(PAIR)
                      and len({c.sensor for c in on_axis}) == 1
                      and not any("lagged" in c.extra for c in on_axis))
        if rms_pair >= rms_now * (1 + TIE if one_sensor else 1):
            continue
        touched = np.any(d.columns != 0, axis=1) | np.any(e.columns != 0, axis=1)
        z = significance(r_single, r_pair, order_judge, touched)
        # the gain over the readings that sense the axis: a drift of 1 µm/K beside a
        # large expansion moves only those, and over every reading of the campaign its
        # gain is diluted below what names any effect alone
        rows = judge & touched
        gain = (rms_of(r_single[rows]) - rms_of(r_pair[rows])) / rms_of(r_single[rows])
        fit = fit_of([*others, d, e])
        n = len(others)
        if z < Z_MIN or gain < MIN_GAIN or min(_t(fit, n), _t(fit, n + 1)) < T_MIN:
            continue
        # the pair takes the place of the axis's first thermal effect; the member that
        # explains more alone comes first
        pair = [d, e] if single.effect == PAIR[0] else [e, d]
        first = next(i for i, c in enumerate(out) if any(c is x for x in on_axis))
        kept = [c for c in out if not any(c is x for x in on_axis)]
        at = sum(1 for c in out[:first] if not any(c is x for x in on_axis))
        out = [*kept[:at], *pair, *kept[at:]]
    return out


def masked_pair(
    scored: list[Scored], heldout_of: Callable[[list[Candidate]], F64],
    judge: NDArray[np.bool_], order_judge: NDArray[np.intp], base: F64, rms_before: float,
    fit_of: Callable[[list[Candidate]], JointFit],
) -> tuple[Candidate, Candidate, F64] | None:
    """A drift and an expansion of one axis that pass the gates together against the
    rigid base when nothing passes alone, or None.

    Of opposite signs they cancel over the middle of the travel (a screw growing one
    way, the spindle's carrier the other): each alone then explains a small share of
    the readings and fails the gates, the two together explain most of it. The pair
    (the best of every drift and expansion sensor of an axis, over every axis) must
    pass what names any effect against ``base``, the rigid model's held-out residuals
    (gain ``MIN_GAIN`` of ``rms_before``, significance ``Z_MIN``, each coefficient
    ``T_MIN`` in the joint fit), and its weaker member those of :func:`same_axis_pairs`
    against the best single thermal effect of the axis.

    Returns
    -------
    tuple or None
        The member that explains more alone, the other, and the pair's held-out
        residuals (N,).
    """
    best: tuple[float, Candidate, Candidate, F64, Candidate, F64] | None = None
    for axis in sorted({s.candidate.axis for s in scored if s.candidate.effect in PAIR}):
        pool = {e: [s.candidate for s in scored
                    if s.candidate.effect == e and s.candidate.axis == axis
                    and not s.candidate.drop and "lagged" not in s.candidate.extra]
                for e in PAIR}
        if not pool[PAIR[0]] or not pool[PAIR[1]]:
            continue
        top = min((s for s in scored if s.candidate.effect in PAIR
                   and s.candidate.axis == axis and "lagged" not in s.candidate.extra),
                  key=lambda s: s.rms_after_um)
        rms, d, e, r = best_pair(
            [(rms_of(r[judge]), d, e, r) for d in pool[PAIR[0]] for e in pool[PAIR[1]]
             for r in (heldout_of([d, e]),)])
        if best is None or rms < best[0]:
            best = (rms, d, e, r, top.candidate, top.heldout)
    if best is None:
        return None
    rms_pair, d, e, r_pair, single, r_single = best
    touched = np.any(d.columns != 0, axis=1) | np.any(e.columns != 0, axis=1)
    if ((rms_before - rms_pair) / rms_before < MIN_GAIN
            or significance(base, r_pair, order_judge, touched) < Z_MIN):
        return None
    rows = judge & touched
    gain = (rms_of(r_single[rows]) - rms_of(r_pair[rows])) / rms_of(r_single[rows])
    if gain < MIN_GAIN or significance(r_single, r_pair, order_judge, touched) < Z_MIN:
        return None
    fit = fit_of([d, e])
    if min(_t(fit, 0), _t(fit, 1)) < T_MIN:
        return None
    return (d, e, r_pair) if single.effect == PAIR[0] else (e, d, r_pair)
