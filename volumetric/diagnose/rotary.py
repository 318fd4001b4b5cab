"""Rotary-axis candidates of the diagnosis (step 3 of :mod:`volumetric.diagnose`): a cyclic
error of many per turn beyond the base's harmonics (``rotary_periodic``) and a rotary
axis's reversal error (``rotary_backlash``), one of each per rotary axis.

The base model already carries, on every rotary axis of at least half a turn, the
harmonics ``ednc fit`` gives it (up to ``MAX_ORDER_FOURIER`` = 4 per turn over a full
turn, fewer over less, :func:`~volumetric.identify.design.fourier_order`: the error
motions of the bearing and the axis's own smooth errors). A gear, a worm or a bearing of
many teeth or balls adds a cyclic error of N per turn beyond those: the candidate is the
harmonic of order N on each of the axis's six components (radial, axial, two tilts,
indexing), the order taken from a least-squares periodogram of the base residual (every
training reading the components touch, angles too, weighted as the fit weighs them) over
the orders the readings resolve: from ``MAX_ORDER_FOURIER + 1`` (on every axis: on a
part turn the orders up to 4 are the smooth errors the rigid model describes) up to the
Nyquist limit of the finest angular step at which one test reads the axis
(:func:`order_limit`: an R-test every 2.5° resolves up to 71 per turn, every 5° up to
35; the standard campaign's R-tests at 12 angles, 30° apart, resolve 5), at most
:data:`MAX_ORDER`.

A reversal error of a rotary axis (the lost motion of a worm, a clamped table that
settles) is ``-(B/2)·d`` on the axis's own angle, ``d`` the direction the axis last moved
(the readings' ``dir_<axis>`` column), ``B`` in µrad: the same sign convention as a
linear axis's backlash (the axis lags behind the command by half the reversal).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.design import (
    MAX_ORDER_FOURIER,
    Param,
    axis_positions,
    branch_rows,
    fourier_axis,
    fourier_order,
)
from volumetric.measure.measurement import Measurements
from volumetric.model.components import Fourier, GeometricErrors, add_components
from volumetric.model.linear import sensitivities
from volumetric.model.machine import Axis, Machine

F64 = NDArray[np.float64]
MAX_ORDER = 90
"""Highest order per turn the cyclic candidate searches (a worm of 90 teeth)."""


def component_sensitivity(machine: Machine, m: Measurements, axis: Axis
                          ) -> tuple[list[str], F64]:
    """What each reading senses of 1 µm or µrad of each of ``axis``'s six component errors
    (first-order chain, as the base design's columns), shape (N, 6), with their ISO names
    (``EXC`` ... ``ECC``)."""
    j_axis = machine.axes.index(axis)
    q = axis_positions(machine, m)
    out = np.zeros((len(m), 6))
    names: list[str] = []
    for bname, rows in branch_rows(machine, m).items():
        if rows.size == 0:
            continue
        ang = m.is_angle[rows]
        u = m.u[rows]
        for s in sensitivities(machine, q[rows], spindle=bname, tool_mm=m.tool_mm[rows]):
            if s.column != j_axis:
                continue
            out[rows] = np.where(ang[:, None],
                                 np.einsum("ni,nik->nk", u, s.matrix[:, 3:, :]),
                                 np.einsum("ni,nik->nk", u, s.matrix[:, :3, :]))
            names = list(s.names)
    return names, out


def _turning(angles: F64, tests: NDArray[np.str_]) -> NDArray[np.bool_]:
    """The readings of the tests that read the axis at 5 or more angles."""
    out = np.zeros(len(angles), dtype=bool)
    for label in np.unique(tests):
        rows = tests == label
        if np.unique(np.round(angles[rows], 4)).size >= 5:
            out |= rows
    return out


def angular_step(angles: F64, tests: NDArray[np.str_]) -> float:
    """The finest angular step (degrees) at which one test reads the axis: per test, the
    median gap between its distinct angles (tests at fewer than 5 angles do not count);
    the smallest over the tests, inf when none counts. Steps of different tests do not
    mix: a 30° R-test beside one every 2.5° would leave gaps of a fraction of a degree
    that resolve nothing."""
    best = math.inf
    for label in np.unique(tests):
        a = np.unique(np.round(angles[tests == label], 4))
        if a.size >= 5:
            best = min(best, float(np.median(np.diff(a))))
    return best


def order_limit(step_deg: float) -> int:
    """Highest order per turn that angles ``step_deg`` apart resolve (below their Nyquist
    order ``180 / step``), at most :data:`MAX_ORDER`."""
    if not math.isfinite(step_deg) or step_deg <= 0:
        return 0
    return min(MAX_ORDER, math.ceil(180.0 / step_deg - 1e-9) - 1)


def _harmonic_columns(sens: F64, theta: F64, order: int) -> F64:
    """``sens_j cos(Nθ)``, ``sens_j sin(Nθ)`` for each sensed component j, shape (N, 2k)."""
    c, s = np.cos(order * theta), np.sin(order * theta)
    return np.column_stack([sens * c[:, None], sens * s[:, None]])


def _without(a: F64, nuisance: F64, rows: NDArray[np.bool_]) -> F64:
    """``a`` (N, k) less its least-squares projection on ``nuisance`` (N, j) fitted on
    ``rows``."""
    if nuisance.shape[1] == 0:
        return a
    coef, *_ = np.linalg.lstsq(nuisance[rows], a[rows], rcond=1e-10)
    out: F64 = a - nuisance @ coef
    return out


def _basis_of(a: F64) -> F64:
    """An orthonormal basis (n, r) of the columns of ``a`` (n, j): the left singular
    vectors above 1e-8 of the largest singular value."""
    if a.shape[1] == 0:
        return a
    u, sv, _ = np.linalg.svd(a, full_matrices=False)
    out: F64 = u[:, sv > 1e-8 * max(float(sv.max(initial=0.0)), 1e-300)]
    return out


def best_order(sens: F64, theta: F64, resid: F64, rows: NDArray[np.bool_], lo: int,
               hi: int, nuisance: F64 | None = None, w: F64 | None = None) -> int:
    """The order N in ``lo .. hi`` whose harmonics on the sensed components explain most of
    ``resid`` on ``rows`` beside ``nuisance`` (N, j), the base design and what else the
    candidate is taken clear of: the weighted squared norm of the residual's projection on
    each order's 2k columns made orthogonal to ``nuisance`` (the gain of adding that order
    to the base, not of fitting the residual alone: over part of a turn the base takes a
    share of a 6-per-turn error, and what it leaves can look more like 7).

    Parameters
    ----------
    sens : ndarray, shape (N, k)
        What each reading senses of each of the axis's k sensed components (µm per µm or
        µrad, µrad per µrad on an angle reading).
    theta : ndarray, shape (N,)
        The axis's angle at each reading, rad.
    resid : ndarray, shape (N,)
        The residual of the model the order is judged beside, µm or µrad.
    rows : ndarray of bool, shape (N,)
        The readings judged (training readings the components touch, either kind).
    lo, hi : int
        The orders searched, per turn.
    nuisance : ndarray, shape (N, j), optional
    w : ndarray, shape (N,), optional
        The fit's weight of each reading (1/µm² or 1/µrad²); 1 when not given.

    Returns
    -------
    int
        The order of largest gain, ties to the lower.

    Notes
    -----
    The gain is the drop of the weighted residual sum of squares that the order's
    columns make beside the base, so the order is the one whose joint fit with the base
    fits best, the same least squares the effect is then estimated by
    (:func:`~volumetric.diagnose.estimate.estimate_effect`): every reading it weighs
    counts here with its weight. On a part-turn axis this is what separates orders: the
    R-tests of a tool-side A read ±60°, over which 6 and 7 per turn differ by a third of
    a cycle and the base's harmonics 1-4 take most of either, while A's positioning test
    reads its indexing over ±99°.
    """
    sw = np.ones(int(rows.sum())) if w is None else np.sqrt(w[rows])
    s, t, r = sens[rows], theta[rows], resid[rows] * sw
    q = (None if nuisance is None or nuisance.shape[1] == 0
         else _basis_of(nuisance[rows] * sw[:, None]))
    best, best_pw = lo, -1.0
    for n in range(lo, hi + 1):
        a = _harmonic_columns(s, t, n) * sw[:, None]
        if q is not None:
            a = a - q @ (q.T @ a)
        g = a.T @ a
        b = a.T @ r
        lam, vec = np.linalg.eigh(g)
        keep = lam > 1e-10 * max(float(lam.max(initial=0.0)), 1e-300)
        z = vec[:, keep].T @ b
        pw = float(np.sum(z * z / lam[keep]))
        if pw > best_pw:
            best, best_pw = n, pw
    return best


def rotary_candidates(machine: Machine, m: Measurements, resid: F64, train: NDArray[np.bool_],
                      missing: dict[str, str], a0: F64 | None = None, w: F64 | None = None,
                      ) -> list[tuple[str, str, F64, dict[str, Any]]]:
    """The rotary candidates for these readings as (effect, axis key, columns, extra), and
    what cannot be assessed in ``missing``.

    Parameters
    ----------
    machine : Machine
    m : Measurements
    resid : ndarray, shape (N,)
        The base model's residual (fitted on the training readings).
    train : ndarray of bool, shape (N,)
    missing : dict
        Filled with ``rotary_periodic <axis>`` / ``rotary_backlash <axis>`` reasons.
    a0 : ndarray, shape (N, P), optional
        The base design: each order's gain is judged beside it (:func:`best_order`).
    w : ndarray, shape (N,), optional
        The base fit's weight of each reading (1/µm², 1/µrad²): given, the order is judged
        on every training reading the axis's components touch, angles too, each with its
        weight (the least squares the effect is estimated by); not given, on the
        displacement readings alone, unweighted.
    """
    out: list[tuple[str, str, F64, dict[str, Any]]] = []
    q = axis_positions(machine, m)
    for axis in machine.axes:
        if axis.kind != "rotary":
            continue
        names, sens = component_sensitivity(machine, m, axis)
        disp = ~m.is_angle
        # a component the readings hardly sense is left out (a tool-side C turns the
        # tool about its own axis: no tool-tip reading sees its indexing error, whose
        # estimate would be noise over nothing): its sensitivity's RMS over the
        # displacement readings of the tests that turn the axis (where its harmonics vary)
        # under 1e-3 of the largest (µm per µm, or per µrad: a lever of 1 mm)
        qa = q[:, machine.axes.index(axis)]
        turning = disp & _turning(qa, m.test)
        level = (np.sqrt(np.mean(sens[turning] ** 2, axis=0)) if turning.any()
                 else np.zeros(sens.shape[1]))
        sensed_cols = np.flatnonzero(level > 1e-3 * max(float(level.max(initial=0.0)), 1e-300))
        rows = np.any(np.abs(sens[:, sensed_cols]) > 1e-9, axis=1) & disp
        if sensed_cols.size == 0 or not rows.any():
            missing[f"rotary_periodic {axis.key}"] = f"no reading senses axis {axis.name}"
            continue
        sens = sens[:, sensed_cols]
        comps = [names[i] for i in sensed_cols]
        theta = np.deg2rad(qa)
        key = f"rotary_periodic {axis.key}"
        if not fourier_axis(axis):
            missing[key] = (f"axis {axis.name} travels {axis.travel[1] - axis.travel[0]:g}°: "
                            "too little of a turn for cyclic errors")
        else:
            sel = rows & train
            step = angular_step(qa[sel], m.test[sel])
            lo, hi = MAX_ORDER_FOURIER + 1, order_limit(step)
            if hi < lo:
                missing[key] = (f"axis {axis.name} is read every {step:.3g}°, which resolves "
                                f"{max(hi, 0)} per turn at most; the base carries up to "
                                f"{lo - 1} (an R-test every 2.5° resolves up to 71)")
            else:
                # on a part turn the base carries fewer orders than the truth may have
                # (fourier_order): the orders between are the smooth errors of the axis,
                # not a cyclic error of many per turn, yet over a part turn they leak
                # into higher harmonics; the candidate and the periodogram see only what
                # those orders cannot explain
                low = [_harmonic_columns(sens, theta, k)
                       for k in range(fourier_order(axis) + 1, MAX_ORDER_FOURIER + 1)]
                nuisance = np.column_stack(low) if low else np.zeros((len(m), 0))
                clean = _without(resid[:, None], nuisance, sel)[:, 0]
                beside = nuisance if a0 is None else np.column_stack((a0, nuisance))
                # the order judged as it is then estimated: on an axis of part of a turn
                # the R-tests may read less of it (a tool-side A: ±60°) than the
                # positioning test reads its indexing (±99°), and only the wider reach
                # tells orders a third of a cycle apart over the narrower one
                judged = (sel if w is None else
                          train & np.any(np.abs(sens) > 1e-9, axis=1))
                n = best_order(sens, theta, clean, judged, lo, hi, beside, w)
                params = [Param(f"{c}[{2 * n - 1}]", c, 2 * n - 1, _unit(c), "fourier")
                          for c in comps]
                params += [Param(f"{c}[{2 * n}]", c, 2 * n, _unit(c), "fourier")
                           for c in comps]
                out.append(("rotary_periodic", axis.key,
                            _without(_harmonic_columns(sens, theta, n), nuisance, sel),
                            {"params": params, "order": n, "order_limit": hi,
                             "step_deg": step}))
        direction = m.extra.get(f"dir_{axis.key}")
        own = names.index(f"E{axis.name}{axis.name}") if names else -1
        bkey = f"rotary_backlash {axis.key}"
        if direction is None or direction.dtype.kind not in "fiu" or own < 0:
            missing[bkey] = f"no dir_{axis.key} column: the approach direction of {axis.name}"
            continue
        d = np.asarray(direction, dtype=float)
        full = component_sensitivity(machine, m, axis)[1][:, own]
        if np.unique(d[rows & (d != 0) & (np.abs(full) > 1e-9)]).size < 2:
            missing[bkey] = f"one approach direction only of {axis.name}"
            continue
        out.append(("rotary_backlash", axis.key, (-0.5 * full * d)[:, None], {}))
    return out


def _unit(component: str) -> str:
    return "urad" if component[1] in "ABC" else "um"


def harmonic_estimate(params: list[Param], coef: F64) -> dict[str, tuple[float, float]]:
    """The harmonic's (cos, sin) coefficients by component, µm or µrad."""
    out: dict[str, list[float]] = {}
    for p, v in zip(params, coef, strict=True):
        out.setdefault(p.component, [0.0, 0.0])[0 if p.degree % 2 else 1] = float(v)
    return {c: (v[0], v[1]) for c, v in out.items()}


def with_harmonics(geometry: GeometricErrors, order: int,
                   harmonics: dict[str, tuple[float, float]]) -> GeometricErrors:
    """``geometry`` with the harmonic of ``order`` per turn added to each component of
    ``harmonics`` ((cos, sin) coefficients by ISO name)."""
    comps = dict(geometry.components)
    zeros = (0.0,) * (order - 1)
    for name, (a, b) in harmonics.items():
        comps[name] = add_components(comps.get(name), Fourier(0.0, (*zeros, a), (*zeros, b)))
    return GeometricErrors(comps, geometry.locations)


def rotary_again(machine: Machine, m: Measurements, c: Any, resid: F64,
                 train: NDArray[np.bool_], a0: F64, w: F64 | None = None) -> Any:
    """The ``rotary_periodic`` candidate of ``c``'s axis with its order found again from
    ``resid`` (the residual of the model with the effects found so far) beside ``a0``
    (that model's design) with the readings' weights ``w``, or None when there is
    none."""
    for effect, key, cols, extra in rotary_candidates(machine, m, resid, train, {}, a0, w):
        if effect == "rotary_periodic" and key == c.axis:
            return type(c)(effect, key, None, cols, extra)
    return None
