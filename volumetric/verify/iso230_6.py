"""ISO 230-6 body-diagonal displacement test: target points, evaluation, before/after gain.

The four body diagonals of the x, y, z working volume are named after the direction each
axis moves when the diagonal is run from its start corner to its end corner: P = positive,
N = negative. With travel [lo, hi] per axis (shrunk by ``margin_mm`` at both ends):

====== ==================== ====================
label  start corner          end corner
====== ==================== ====================
PPP    (x_lo, y_lo, z_lo)    (x_hi, y_hi, z_hi)
NPP    (x_hi, y_lo, z_lo)    (x_lo, y_hi, z_hi)
PNP    (x_lo, y_hi, z_lo)    (x_hi, y_lo, z_hi)
PPN    (x_lo, y_lo, z_hi)    (x_hi, y_hi, z_lo)
====== ==================== ====================

Every function here keys diagonals by their measurement test label, ``diag-PPP`` etc., so a
simulator can write ``test = label`` and the evaluation reads it back unchanged.

The evaluated figure per diagonal is the diagonal displacement error range: at each target
point, the mean reading over all runs and both approach directions; the range is max - min
of those means (µm). The EDNC paper's acceptance of a compensation (at least 70 % better on
the diagonals) is :func:`improvement` of the ranges before and after.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.measurement import U_NORM_TOL, Measurements
from volumetric.verify.iso230_2 import PositioningTestError, cluster_targets

__all__ = [
    "DIAGONALS",
    "DiagonalTestError",
    "diagonal_ranges",
    "diagonal_targets",
    "diagonal_unit_vectors",
    "improvement",
]

FloatArray = NDArray[np.float64]

DIAGONALS: dict[str, tuple[int, int, int]] = {
    "diag-PPP": (1, 1, 1),
    "diag-NPP": (-1, 1, 1),
    "diag-PNP": (1, -1, 1),
    "diag-PPN": (1, 1, -1),
}
"""Test label to the direction (+1 or -1) each of x, y, z moves from start to end."""


class DiagonalTestError(ValueError):
    """Travel or readings that do not make a body-diagonal test."""


def _corners(travel: Mapping[str, tuple[float, float]], margin_mm: float
             ) -> dict[str, tuple[FloatArray, FloatArray]]:
    """Start and end corner (mm, shape (3,)) of each diagonal."""
    if not margin_mm >= 0:  # also refuses NaN
        raise DiagonalTestError(f"margin_mm must not be negative, got {margin_mm:g}")
    lo = np.empty(3)
    hi = np.empty(3)
    for j, axis in enumerate("xyz"):
        if axis not in travel:
            raise DiagonalTestError(f"travel has no {axis} axis (it has {sorted(travel)})")
        a, b = (float(v) for v in travel[axis])
        if not (np.isfinite(a) and np.isfinite(b)) or b <= a:
            raise DiagonalTestError(f"travel of {axis} must be [min, max] with min < max, "
                                    f"got [{a:g}, {b:g}]")
        if b - a <= 2.0 * margin_mm:
            raise DiagonalTestError(f"travel of {axis} ({b - a:g} mm) leaves nothing inside "
                                    f"a margin of {margin_mm:g} mm at each end")
        lo[j], hi[j] = a + margin_mm, b - margin_mm
    out: dict[str, tuple[FloatArray, FloatArray]] = {}
    for label, signs in DIAGONALS.items():
        s = np.asarray(signs) > 0
        out[label] = (np.where(s, lo, hi), np.where(s, hi, lo))
    return out


def diagonal_targets(travel: Mapping[str, tuple[float, float]], n_points: int = 20,
                     margin_mm: float = 10.0) -> dict[str, FloatArray]:
    """Equally spaced target points along the four body diagonals.

    Parameters
    ----------
    travel : mapping of ``x``, ``y``, ``z`` to (min, max)
        Axis travel (mm), as ``travel_mm`` of the machine description.
    n_points : int
        Target points per diagonal, start and end corners included (at least 2).
    margin_mm : float
        Distance kept from each end of every axis's travel (mm), clear of the limits.

    Returns
    -------
    dict of str to ndarray, shape (n_points, 3)
        Commanded x, y, z (mm) from the start corner to the end corner, keyed
        ``diag-PPP``, ``diag-NPP``, ``diag-PNP``, ``diag-PPN``.

    Raises
    ------
    DiagonalTestError
        Missing axis, empty or inverted travel, a margin that leaves no travel, or fewer
        than 2 points.
    """
    if n_points < 2:
        raise DiagonalTestError(f"a diagonal needs at least 2 points, got {n_points}")
    t = np.linspace(0.0, 1.0, n_points)[:, None]
    return {label: start + t * (end - start)
            for label, (start, end) in _corners(travel, margin_mm).items()}


def diagonal_unit_vectors(travel: Mapping[str, tuple[float, float]], margin_mm: float = 10.0
                          ) -> dict[str, FloatArray]:
    """Unit vector from start to end corner of each diagonal, shape (3,): the laser's u.

    Same parameters and errors as :func:`diagonal_targets`.
    """
    out: dict[str, FloatArray] = {}
    for label, (start, end) in _corners(travel, margin_mm).items():
        d = end - start
        out[label] = d / np.linalg.norm(d)
    return out


def diagonal_ranges(m: Measurements, *, target_tol_mm: float = 1e-3) -> dict[str, float]:
    """Diagonal displacement error range (µm) of every ``diag-*`` test in the readings.

    Rows whose test label does not start with ``diag-`` are ignored. For each diagonal the
    commanded points must lie on one line (within ``target_tol_mm``); targets are the
    distinct positions along it; each reading is signed along the diagonal (``u`` must be
    parallel or antiparallel to it); the range is max - min over targets of the mean
    reading over all runs and approach directions.

    Parameters
    ----------
    m : Measurements
        Readings; displacement rows only for ``diag-*`` tests.
    target_tol_mm : float
        Commanded points closer than this along the diagonal (mm) are one target.

    Returns
    -------
    dict of str to float
        Test label to range (µm), in order of first appearance.

    Raises
    ------
    DiagonalTestError
        No ``diag-*`` rows, angle readings, points off a line, fewer than 2 targets, or a
        sensing direction not along the diagonal.
    """
    labels = [str(t) for t in dict.fromkeys(m.test.tolist()) if str(t).startswith("diag-")]
    if not labels:
        raise DiagonalTestError("no body-diagonal readings (test labels 'diag-...')")
    return {label: _range_of(m.select(m.test == label), label, target_tol_mm)
            for label in labels}


def _range_of(d: Measurements, label: str, tol: float) -> float:
    if d.is_angle.any():
        raise DiagonalTestError(f"{label}: {int(d.is_angle.sum())} angle reading(s); a "
                                "diagonal test reads displacements along the diagonal")
    xyz = d.xyz
    centre = xyz.mean(axis=0)
    _, sv, vt = np.linalg.svd(xyz - centre, full_matrices=False)
    direction = vt[0]
    along = (xyz - centre) @ direction
    if sv[0] <= tol:
        raise DiagonalTestError(f"{label}: only one target point")
    off_line = np.linalg.norm(xyz - centre - along[:, None] * direction, axis=1)
    if off_line.max() > tol:
        i = int(np.argmax(off_line))
        raise DiagonalTestError(
            f"{label}: the commanded points do not lie on one line (point "
            f"{tuple(np.round(xyz[i], 6).tolist())} is {off_line[i]:.3g} mm off it)")
    cosine = d.u @ direction
    bad = np.flatnonzero(np.abs(cosine) < 1.0 - U_NORM_TOL)
    if bad.size:
        i = int(bad[0])
        raise DiagonalTestError(
            f"{label}: the reading at {tuple(np.round(xyz[i], 6).tolist())} (run {d.run[i]}) "
            f"senses along u = {tuple(d.u[i].tolist())}, not along the diagonal "
            f"{tuple(np.round(direction, 6).tolist())}")
    try:
        targets, which = cluster_targets(along, tol, f"positions along {label}")
    except PositioningTestError as exc:
        raise DiagonalTestError(f"{label}: {exc}") from exc
    if targets.size < 2:
        raise DiagonalTestError(f"{label}: only one target point")
    signed = d.value * np.sign(cosine)
    means = np.bincount(which, weights=signed) / np.bincount(which)
    return float(means.max() - means.min())


def improvement(before: Mapping[str, float], after: Mapping[str, float]) -> dict[str, float]:
    """Relative reduction of the diagonal ranges: (before - after) / before.

    Parameters
    ----------
    before, after : mapping of str to float
        Ranges (µm) per test label, as from :func:`diagonal_ranges`, with the same labels.

    Returns
    -------
    dict of str to float
        Per label the fraction removed (0.7 = 70 % better, negative = worse), and
        ``overall``: the reduction of the largest range, 1 - max(after) / max(before), the
        worst diagonal deciding as it does for the working volume's accuracy.

    Raises
    ------
    DiagonalTestError
        Different labels, no labels, or a range before that is not positive.
    """
    if set(before) != set(after):
        raise DiagonalTestError(f"before has diagonals {sorted(before)}, after has "
                                f"{sorted(after)}")
    if not before:
        raise DiagonalTestError("no diagonals to compare")
    out: dict[str, float] = {}
    for label, b in before.items():
        if not b > 0:
            raise DiagonalTestError(f"{label}: range before is {b:g} µm; a reduction needs "
                                    "a positive range to start from")
        out[label] = (b - after[label]) / b
    out["overall"] = 1.0 - max(after.values()) / max(before.values())
    return out
