"""Deviation along each body diagonal (ISO 230-6), for the verification plots (pure, numpy).

:func:`volumetric.verify.iso230_6.diagonal_ranges` reduces each diagonal to its range; the plot
needs what the range is taken over: at each target point along the diagonal, the mean
reading over all runs and approach directions, signed along the diagonal's direction
from its first to its last commanded point. The range of a profile here is the range the
report states (the tests check that), so the plot and the number cannot disagree.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.measurement import Measurements
from volumetric.verify.iso230_2 import PositioningTestError, cluster_targets
from volumetric.verify.iso230_6 import DiagonalTestError

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Profile:
    """One diagonal's deviation profile.

    Attributes
    ----------
    along_mm : ndarray, shape (m,)
        Distance of each target from the first one along the diagonal (mm), ascending.
    mean_um : ndarray, shape (m,)
        Mean reading at each target (µm), positive along the diagonal's run direction.
    """

    along_mm: FloatArray
    mean_um: FloatArray

    @property
    def range_um(self) -> float:
        """Largest minus smallest mean (µm): the ISO 230-6 diagonal range."""
        return float(self.mean_um.max() - self.mean_um.min())


def diagonal_profiles(m: Measurements, *, target_tol_mm: float = 1e-3) -> dict[str, Profile]:
    """Profiles of every ``diag-*`` test in the readings.

    Parameters
    ----------
    m : Measurements
        Readings; only rows whose test label starts with ``diag-`` are used.
    target_tol_mm : float
        Commanded points closer than this along the diagonal (mm) are one target.

    Returns
    -------
    dict of str to Profile
        Test label to profile, in order of first appearance.

    Raises
    ------
    DiagonalTestError
        No diagonal readings, or fewer than two targets on a diagonal. (Readings that the
        report's evaluation refuses never reach here: the report was made from them.)
    """
    labels = [str(t) for t in dict.fromkeys(m.test.tolist()) if str(t).startswith("diag-")]
    if not labels:
        raise DiagonalTestError("no body-diagonal readings (test labels 'diag-...')")
    out: dict[str, Profile] = {}
    for label in labels:
        d = m.select((m.test == label) & ~m.is_angle)
        if len(d) == 0:
            raise DiagonalTestError(f"{label}: no displacement readings")
        xyz = d.xyz
        # Direction from the first commanded point to the farthest one: the run direction,
        # so that "along" starts at 0 at the start corner.
        offsets = xyz - xyz[0]
        far = int(np.argmax(np.linalg.norm(offsets, axis=1)))
        length = float(np.linalg.norm(offsets[far]))
        if length <= target_tol_mm:
            raise DiagonalTestError(f"{label}: only one target point")
        direction = offsets[far] / length
        along = offsets @ direction
        try:
            targets, which = cluster_targets(along, target_tol_mm, f"positions along {label}")
        except PositioningTestError as exc:
            raise DiagonalTestError(f"{label}: {exc}") from exc
        signed = d.value * np.sign(d.u @ direction)
        means = np.bincount(which, weights=signed) / np.bincount(which)
        start = targets.min()
        out[label] = Profile(along_mm=targets - start, mean_um=means)
    return out
