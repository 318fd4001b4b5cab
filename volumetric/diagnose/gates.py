"""Ranking and gates of the diagnosis (step 4 of :mod:`volumetric.diagnose`): the
figures a candidate is scored by and the three tests it must pass to be named.

A candidate is named when it reduces the held-out RMS of all displacement readings by at
least ``MIN_GAIN``, its chunk-mean gain over the readings it touches stands ``Z_MIN``
standard errors clear (:func:`significance`), and its coefficient ``T_MIN`` standard
uncertainties clear of zero (:func:`volumetric.diagnose.estimate.estimate_effect`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.splits import rms_of

F64 = NDArray[np.float64]


Z_MIN = 1.0
"""Significance of the held-out gain, in standard errors of the chunk-mean gain."""
MIN_GAIN = 0.05
"""Smallest relative reduction of the held-out RMS that names an effect."""
T_MIN = 5.0
"""Coefficient over its standard uncertainty that a named effect must reach."""
N_CHUNKS = 30
TIE = 0.05
"""Relative held-out RMS within which another sensor is reported as an alternative."""

MAX_EFFECTS = 3
"""Most effects one diagnosis names (forward selection)."""

@dataclass(frozen=True)
class Scored:
    candidate: Candidate
    heldout: F64  # (N,) held-out residuals
    rms_after_um: float
    z: float
    gain: float


def significance(base: F64, cand: F64, order: NDArray[np.intp], touched: NDArray[np.bool_]
                  ) -> float:
    """Chunk-mean gain of squared held-out errors over its standard error.

    ``order`` lists the judged readings in time order; only those the candidate touches
    count, so an effect confined to one axis is not diluted by the others' readings.
    """
    rows = order[touched[order]]
    gain = (base * base - cand * cand)[rows]
    chunks = np.array_split(gain, min(N_CHUNKS, max(gain.size // 5, 2)))
    sums = np.array([c.mean() for c in chunks if c.size])
    if sums.size < 2:
        return 0.0
    se = float(sums.std(ddof=1) / math.sqrt(sums.size))
    return float(sums.mean() / se) if se > 0 else (math.inf if sums.mean() > 0 else 0.0)


THERMAL_FAMILY = ("thermal_drift", "thermal_expansion", "time_drift")
"""Effects that follow a slow signal (a sensor or the clock): over one campaign several of
them can look alike, so which one is named is settled with every other effect in."""
TIME_TIE = 0.02
"""A time drift is named over a thermal candidate of its axis only when it explains the
held-out readings more than this much better: a slowly warming structure and the clock
are aliases over one campaign, and the sensor is the physical cause that can be
compensated."""


def prefer_physical(ranked: list[Scored]) -> Scored:
    """The first of ``ranked`` (sorted by held-out RMS), unless it is a time drift and a
    thermal candidate of the same axis is within ``TIME_TIE`` of it."""
    top = ranked[0]
    if top.candidate.effect != "time_drift":
        return top
    for s in ranked[1:]:
        if s.rms_after_um > top.rms_after_um * (1 + TIME_TIE):
            break
        c = s.candidate
        if (c.effect in THERMAL_FAMILY[:2] and c.axis == top.candidate.axis
                and "lagged" not in c.extra):
            return s
    return top



def score(c: Candidate, r: F64, base: F64, rms_before: float, judge: NDArray[np.bool_],
          order_judge: NDArray[np.intp]) -> Scored:
    """Candidate ``c`` scored by its held-out residuals ``r`` against the base's ``base``
    (shape (N,) each): held-out RMS of the judged readings, significance of the gain
    over the readings it touches, relative gain."""
    rms = rms_of(r[judge])
    z = significance(base, r, order_judge, np.any(c.columns != 0, axis=1))
    return Scored(c, r, rms, z, (rms_before - rms) / rms_before)


def passes(s: Scored) -> bool:
    """True when ``s`` passes the gain and significance gates (the T gate is the
    estimate's)."""
    return s.z >= Z_MIN and s.gain >= MIN_GAIN
