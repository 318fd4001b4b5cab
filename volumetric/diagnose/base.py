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
from volumetric.identify.design import build_design
from volumetric.identify.fit import FitError, FitResult, fit, model_from_parameters
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
