"""The diagnosis's base model (step 1 of :mod:`volumetric.diagnose`): the rigid model
identified on the training readings, and identified again with the named effects taken
out (:func:`base_without`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.estimate import offsets_of
from volumetric.diagnose.splits import combined, known_sum, rms_of, solve_normal
from volumetric.identify.design import Param, build_design
from volumetric.identify.fit import (
    FitError,
    FitResult,
    fit,
    model_from_parameters,
    select_degrees,
)
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]


REFITS = 2
"""Most times the rigid model's degrees are chosen again with the named effects taken out
(:func:`base_without`); each time the diagnosis runs again on the new base."""

def base_without(
    machine: Machine, m: Measurements, train: NDArray[np.bool_], a0: F64, w: F64,
    chosen: list[Candidate], base_fit: FitResult,
) -> FitResult | None:
    """The rigid model identified again on the training readings minus the named effects,
    or None when it keeps the same parameters.

    The base's degrees are chosen by BIC on readings that still hold the effects: a
    12 µm backlash or a drift of several µm is residual variance no polynomial
    explains, so the criterion takes the higher degrees' gain for noise and keeps
    components too smooth. Their leftover shape then decides between candidates that
    differ by less (screw sensors that follow the same shop air: a wrong one that fits
    a straightness component's leftover wins). The effects' fitted contribution (joint
    fit with the base, training readings) is taken out, the degrees chosen again, and
    the parameters' values fitted on the readings as they are (the effects beside them
    are the diagnosis's job).

    Parameters
    ----------
    machine : Machine
    m : Measurements
    train : ndarray of bool, shape (N,)
    a0 : ndarray, shape (N, P)
        The current base design.
    w : ndarray, shape (N,)
        Weights of the readings.
    chosen : list of Candidate
        The effects named.
    base_fit : FitResult
        The current base.

    Returns
    -------
    FitResult or None
    """
    extra = [c for c in chosen if not c.drop and not c.fixed]
    k = sum(c.columns.shape[1] for c in extra)
    known = known_sum(len(m), chosen)
    if k == 0 and not known.any():
        return None
    a = combined(a0, chosen)
    y = m.value - known
    x = solve_normal(a[train].T @ (a[train] * w[train, None]),
                    (a[train] * w[train, None]).T @ y[train])
    effect = known + (np.column_stack([c.columns for c in extra]) @ x[a.shape[1] - k:]
                      if k else 0.0)
    trained = m.select(train)
    cleaned = replace(trained, value=trained.value - effect[train])
    try:
        again = fit(machine, cleaned)
        # over a full turn the harmonics are orthogonal: only a part turn needs this;
        # beside other effects (a reversal error of the same axis) the pruned base left
        # room for a cyclic error nothing had (benchmarks/diagnosis_five_axis.py seeds 67
        # and 125), so only cyclic errors alone
        part = {f"E{c}{a.name}" for e in extra if e.effect == "rotary_periodic"
                for a in (machine.axis(e.axis),) if a.travel[1] - a.travel[0] < 360.0
                for c in "XYZABC"}
        if part and all(c.effect == "rotary_periodic" for c in chosen):
            again = _pruned(machine, m, train, w, chosen, again, known, part)
    except FitError:
        return None
    if [p.name for p in again.params] == [p.name for p in base_fit.params]:
        return None
    # the values on the readings as they are, with the weights found without the effects
    design = build_design(machine, trained)
    at = design.matrix[:, design.columns([p.name for p in again.params])]
    wt = again.weights
    values = solve_normal(at.T @ (at * wt[:, None]), (at * wt[:, None]).T @ trained.value)
    resid = trained.value - at @ values
    rms = {label: rms_of(resid[sel]) for label, sel in
           (("displacement_um", ~trained.is_angle), ("angle_urad", trained.is_angle))
           if sel.any()}
    info = {**again.model.info, "rms": rms, "offsets_um": offsets_of(again.params, values),
            "parameters": [{**p, "value": float(v)} for p, v in
                           zip(again.model.info["parameters"], values, strict=True)]}
    model = MachineModel(machine.name, model_from_parameters(machine, again.params,
                                                             values).geometry, (), info)
    return replace(again, values=values, model=model, rms=rms,
                               residual=resid)



def _pruned(machine: Machine, m: Measurements, train: NDArray[np.bool_], w: F64,
            chosen: list[Candidate], again: FitResult, known: F64,
            capped: set[str]) -> FitResult:
    """``again`` (the base chosen without the named effects) less the harmonics of the
    components ``capped`` (a part-turn axis's) that BIC drops with the effects' columns
    beside the base's, rather than on the readings once the effects' estimate is taken
    off.

    A cyclic error of N per turn on an axis of part of a turn (A read over ±99° of its
    ±110°) is not orthogonal to the axis's harmonics 1 to 4 there. Taken off the
    readings as estimated beside a base with all four on every component, it leaves its
    estimation error behind, along those harmonics: BIC on the cleaned readings kept
    third and fourth harmonics A does not have, which cancel over the readings but not
    over A's last 11° (2.1 µm at the tool tip). Beside the effect's own columns they gain
    only noise. Only parameters are dropped: which of two confounded ones the fit kept
    stays its choice (another choice extrapolates differently beyond the readings).
    """
    extra = [c for c in chosen if not c.drop and not c.fixed]
    cols = np.column_stack([c.columns for c in extra])
    design = build_design(machine, m)
    k = cols.shape[1]
    pool = again.params
    a = np.column_stack((design.matrix[:, design.columns([p.name for p in pool])], cols))
    params = [*(p if p.component in capped else replace(p, degree=-1) for p in pool),
              *(Param(f"effect[{i}]", f"effect {i}", -1, "um") for i in range(k))]
    at, wt, yt = a[train], w[train], (m.value - known)[train]
    g = at.T @ (at * wt[:, None])
    b = (at * wt[:, None]).T @ yt
    sel = select_degrees(params, g, b, float(np.sum(wt * yt * yt)), int(train.sum()),
                         np.arange(len(params), dtype=np.intp))
    keep = sorted(int(j) for j in sel if j < len(pool))
    if len(keep) == len(pool):
        return again
    kept = [pool[j] for j in keep]
    names = {p.name for p in kept}
    info = {**again.model.info,
            "parameters": [q for q in again.model.info["parameters"] if q["name"] in names]}
    deg: dict[str, int] = {}
    for p in kept:
        if p.degree >= 0:
            deg[p.component] = max(deg.get(p.component, 0), p.degree)
    return replace(again, params=kept, values=again.values[keep], std=again.std[keep],
                   degrees=deg, model=replace(again.model, geometry=model_from_parameters(
                       machine, kept, again.values[keep]).geometry, info=info))


def base_design(machine: Machine, m: Measurements, train: NDArray[np.bool_],
                base: FitResult | None) -> tuple[FitResult, F64, F64]:
    """The base model fitted on the training readings (``base`` when given), its design
    over every reading and the readings' weights.

    Returns
    -------
    base_fit : FitResult
    a0 : ndarray, shape (N, P)
        The base's columns (its identifiable parameters) over all readings.
    w : ndarray, shape (N,)
        The weight of each reading (the fit's displacement or angle weight).

    Raises
    ------
    FitError
        The rigid model cannot be identified.
    """
    # the model `ednc fit` gives by default (harmonics on every rotary axis of at least
    # half a turn, orders by BIC): an effect is what goes beyond it
    base_fit = base if base is not None else fit(machine, m.select(train))
    design = build_design(machine, m)
    a0 = design.matrix[:, design.columns([p.name for p in base_fit.params])]
    trained = m.select(train)
    wd = base_fit.weights[~trained.is_angle]
    wa = base_fit.weights[trained.is_angle]
    w = np.where(m.is_angle, float(wa[0]) if wa.size else 1.0, float(wd[0]) if wd.size else 1.0)
    return base_fit, a0, w
