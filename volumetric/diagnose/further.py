"""Further effects of the diagnosis (step 6 of :mod:`volumetric.diagnose`): forward
selection of a second and third effect against the model with those already named, the
thermal and time effects chosen again with every other effect in (:func:`refine`), and
each named thermal effect's ``alternatives``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate, periodic_again
from volumetric.diagnose.estimate import estimate_effect
from volumetric.diagnose.gates import (
    MAX_EFFECTS,
    MIN_GAIN,
    T_MIN,
    THERMAL_FAMILY,
    TIE,
    Z_MIN,
    Scored,
    prefer_physical,
    significance,
)
from volumetric.diagnose.joint import PAIR, JointFit, joint_fit, same_axis_pairs
from volumetric.diagnose.rotary import rotary_again, with_harmonics
from volumetric.diagnose.splits import Judge, combined, known_sum, rms_of, solve_normal
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, Term

F64 = NDArray[np.float64]


def list_alternatives(
    chosen: list[Candidate], effects: list[dict[str, Any]], details: dict[str, Any],
    scored: list[Scored], judge: NDArray[np.bool_],
    heldout_of: Callable[[list[Candidate]], F64],
) -> None:
    """Each named thermal effect's ``alternatives`` in its ``effects`` entry: the other
    sensors of its effect and axis whose held-out RMS, with every other named effect in
    the model, is within ``TIE`` of its own. Screw sensors that follow the same shop air
    differ by tenths of a kelvin over a campaign; with a second effect beside a small
    drift the data may not tell them apart, and the entry says so instead of leaving
    the user to trust a coin toss. With one effect this is the top level's list; with
    several, the top level's list is the first entry's (all others in)."""
    if len(chosen) == 1:
        if "alternatives" in details and effects and effects[0]["effect"] == chosen[0].effect:
            effects[0]["alternatives"] = details["alternatives"]
        return
    for i, c_i in enumerate(chosen):
        if c_i.sensor is None or c_i.drop or "lagged" in c_i.extra:
            continue
        others = [c for j, c in enumerate(chosen) if j != i]
        own = rms_of(heldout_of([*others, c_i])[judge])
        alt = sorted({s.candidate.sensor for s in scored
                      if (s.candidate.effect, s.candidate.axis) == (c_i.effect, c_i.axis)
                      and s.candidate.sensor not in (None, c_i.sensor)
                      and not s.candidate.drop and "lagged" not in s.candidate.extra
                      and rms_of(heldout_of([*others, s.candidate])[judge]) <= own * (1 + TIE)}
                     - {None})
        entry = next((e for e in effects
                      if (e["effect"], e["axis"], e["sensor"]) == (c_i.effect, c_i.axis,
                                                                   c_i.sensor)), None)
        if entry is None:
            continue
        if alt:
            entry["alternatives"] = alt
        if entry is effects[0]:
            if alt:
                details["alternatives"] = alt
            else:
                details.pop("alternatives", None)


def refine(machine: Machine, m: Measurements, chosen: list[Candidate], scored: list[Scored],
            a0: F64, y: F64, w: F64, train: NDArray[np.bool_], judge: NDArray[np.bool_],
            heldout_of: Callable[[list[Candidate]], F64]) -> list[Candidate]:
    """Each thermal or time effect of ``chosen`` chosen again among the thermal and time
    candidates of its axis, with every other chosen effect in the model (forward selection
    picked it before the others were in, when a backlash or a drift on the same axis
    still distorted the comparison of sensors that move alike); each periodic error's
    period found again from the residual of the model with the others in (the base
    residual it was first taken from still held them, and a drift of several µm moves
    the periodogram's peak)."""
    out = list(chosen)
    for i, c_i in enumerate(out):
        if c_i.effect == "periodic":
            others = [c for j, c in enumerate(out) if j != i]
            base = combined(a0, others)
            y_o = y - known_sum(len(y), others)
            x = solve_normal(base[train].T @ (base[train] * w[train, None]),
                            (base[train] * w[train, None]).T @ y_o[train])
            again = periodic_again(machine, m, c_i, y_o - base @ x, train)
            if again is not None:
                r_old = heldout_of([*others, c_i])
                r_new = heldout_of([*others, again])
                if rms_of(r_new[judge]) < rms_of(r_old[judge]):
                    out[i] = again
            continue
        if c_i.effect not in THERMAL_FAMILY or c_i.drop or "lagged" in c_i.extra:
            continue
        others = [c for j, c in enumerate(out) if j != i]
        taken = {(c.effect, c.axis) for c in others}
        tried = []
        for s in scored:
            c = s.candidate
            if (c.effect in THERMAL_FAMILY and c.axis == c_i.axis and not c.drop
                    and "lagged" not in c.extra and (c.effect, c.axis) not in taken):
                r = heldout_of([*others, c])
                tried.append(Scored(c, r, rms_of(r[judge]), 0.0, 0.0))
        if tried:
            tried.sort(key=lambda t: t.rms_after_um)
            out[i] = prefer_physical(tried).candidate
    return out


def next_effect(
    machine: Machine, m: Measurements, a0: F64, w: F64, y: F64, train: NDArray[np.bool_],
    judge: NDArray[np.bool_], order_judge: NDArray[np.intp],
    heldout_of: Callable[[list[Candidate]], F64], scored: list[Scored],
    chosen: list[Candidate],
    current: Scored,
) -> tuple[Scored, dict[str, Any], Term | None] | None:
    """The strongest further effect given those ``chosen``, or None when none passes.

    Candidates of an effect and axis already chosen (other sensors of the same drift),
    lagged refinements and a second replacing candidate are not tried; the gain is
    measured against the held-out residuals of the model with the chosen effects.
    """
    taken = {(c.effect, c.axis) for c in chosen}
    replacing = any(c.drop for c in chosen)
    rms0 = rms_of(current.heldout[judge])
    base = combined(a0, chosen)
    y = y - known_sum(len(y), chosen)  # what the chosen effects' fitted columns and base face
    tried: list[Scored] = []
    # a periodic error's period taken again from the residual of the model with the
    # effects found so far: the base residual it came from still held them (a drift of
    # several µm moves the periodogram's peak off a 1 µm pitch error)
    x_now = solve_normal(base[train].T @ (base[train] * w[train, None]),
                        (base[train] * w[train, None]).T @ y[train])
    resid_now = y - base @ x_now
    for s in scored:
        c = s.candidate
        if (c.effect, c.axis) in taken or "lagged" in c.extra or (c.drop and replacing):
            continue
        if c.effect == "periodic":
            c = periodic_again(machine, m, c, resid_now, train) or c
        elif c.effect == "rotary_periodic":
            # a cyclic error's order, too, from the residual of the model with the effects
            # found so far (a 4 µm pitch error distorts the periodogram of a 1 µm one)
            c = rotary_again(machine, m, c, resid_now, train, base, w) or c
        r = heldout_of([*chosen, c])
        rms = rms_of(r[judge])
        tried.append(Scored(c, r, rms, 0.0, (rms0 - rms) / rms0))
    if not tried:
        return None
    tried.sort(key=lambda t: t.rms_after_um)
    pick = prefer_physical(tried)
    z = significance(current.heldout, pick.heldout, order_judge,
                      np.any(pick.candidate.columns != 0, axis=1))
    best = Scored(pick.candidate, pick.heldout, pick.rms_after_um, z, pick.gain)
    if best.z < Z_MIN or best.gain < MIN_GAIN:
        return None
    est, term, _ = estimate_effect(machine, m, base, w, y, train, best.candidate)
    if est.pop("_t") < T_MIN:
        return None
    return best, est, term



@dataclass
class Named:
    """The effects named so far, in the order named.

    Attributes
    ----------
    chosen : list of Candidate
    effects : list of dict
        Their ``effects`` entries (effect, axis, sensor, estimate, rms_after_um).
    terms : list of Term or None
        Each one's model term (None for an effect the model carries otherwise).
    model : MachineModel
        The saved model with all of them.
    current : Scored
        The last one's held-out figures (the model with every named effect).
    joint : ndarray or None
        The base parameters of the fit with every named effect in, when the same-axis
        pairs (:mod:`volumetric.diagnose.joint`) changed what was named: the saved model's
        rigid part and offsets are then taken from it.
    """

    chosen: list[Candidate]
    effects: list[dict[str, Any]]
    terms: list[Term | None]
    model: MachineModel
    current: Scored
    joint: F64 | None = None


def add_further(machine: Machine, m: Measurements, judge: Judge, scored: list[Scored],
                named: Named) -> Named:
    """Further effects beside the first (forward selection, each judged against the model
    with the effects already found and held to the same three tests), the thermal and time
    effects and periods chosen again with all of them in (:func:`refine`), and every
    estimate again with every other effect in the model."""
    sp, a0, w, y = judge.split, judge.a0, judge.w, judge.y
    train, jm = sp.train, sp.judge
    chosen, effects, effect_terms = named.chosen, named.effects, named.terms
    model, current = named.model, named.current
    while len(chosen) < MAX_EFFECTS:
        nxt = next_effect(machine, m, a0, w, y, train, jm, sp.order_judge, judge.of,
                          scored, chosen, current)
        if nxt is None:
            break
        found, est2, term2 = nxt
        chosen.append(found.candidate)
        current = found
        effects.append({"effect": found.candidate.effect, "axis": found.candidate.axis,
                        "sensor": found.candidate.sensor, "estimate": est2,
                        "rms_after_um": round(found.rms_after_um, 4)})
        effect_terms.append(term2)
        if term2 is not None:
            model = model.with_terms(term2)
        harmonics = est2.pop("_harmonics", None)
        if harmonics is not None:
            # a rotary axis's cyclic error: its harmonic joins the axis's components
            model = MachineModel(model.machine,
                                 with_harmonics(model.geometry, est2["order"], harmonics),
                                 model.terms, model.info)
    if len(chosen) > 1:
        swapped = refine(machine, m, chosen, scored, a0, y, w, train, jm, judge.of)
        if any(a is not b for a, b in zip(swapped, chosen, strict=True)):
            # a sensor (or time) chosen before another effect on its axis was in the model
            # gives way to the alias that explains more with all the effects in; a period
            # taken from a residual that still held a drift, to the one without it
            chosen = swapped
            for i, c_i in enumerate(chosen):
                r_i = judge.of(chosen[: i + 1])
                effects[i].update(effect=c_i.effect, axis=c_i.axis, sensor=c_i.sensor,
                                  rms_after_um=round(rms_of(r_i[jm]), 4))
            current = Scored(chosen[-1], r_i, rms_of(r_i[jm]), current.z, current.gain)
    joint: F64 | None = None
    if any(c.effect in PAIR for c in chosen):
        # a drift and an expansion of one axis judged as a pair (volumetric.diagnose.joint)
        def fit_of(cands: list[Candidate]) -> JointFit:
            return joint_fit(a0, w, y, train, cands)
        paired = same_axis_pairs(chosen, scored, judge.of, jm, sp.order_judge, fit_of)
        if len(paired) != len(chosen) or any(
                a is not b for a, b in zip(paired, chosen, strict=True)):
            old = {id(c): (e, t) for c, e, t in zip(chosen, effects, effect_terms, strict=True)}
            chosen = paired
            effects, effect_terms = [], []
            for i, c_i in enumerate(chosen):
                e_i, t_i = old.get(id(c_i), ({}, None))
                r_i = judge.of(chosen[: i + 1])
                effects.append({**e_i, "effect": c_i.effect, "axis": c_i.axis,
                                "sensor": c_i.sensor, "estimate": e_i.get("estimate", {}),
                                "rms_after_um": round(rms_of(r_i[jm]), 4)})
                effect_terms.append(t_i)
            current = Scored(chosen[-1], r_i, rms_of(r_i[jm]), current.z, current.gain)
            # the rigid part and offsets of the fit with every effect in: the first
            # effect's own fit (a lagged drift's offsets with its level) no longer holds
            # (a thermal model saved as the combination of its models is fitted as saved)
            joint = joint_fit(a0, w, y, train,
                              [c.extra["saved"].candidate if "saved" in c.extra else c
                               for c in chosen]).x
    if len(chosen) > 1:
        # each estimate again with every other effect in the model: effects on one axis
        # (a drift and an expansion) share variance that the first fit gave to one alone
        for i, c_i in enumerate(chosen):
            if c_i.drop or "lagged" in c_i.extra:
                continue  # a replacing or dynamic model keeps its own fit
            rest = [c for j, c in enumerate(chosen) if j != i]
            est_i, term_i, _ = estimate_effect(machine, m, combined(a0, rest), w,
                                               y - known_sum(len(y), rest), train, c_i)
            est_i.pop("_t")
            est_i.pop("_harmonics", None)  # the model keeps the harmonic first fitted
            effects[i]["estimate"] = est_i
            effect_terms[i] = term_i
        with_correlations(chosen, effects, joint_fit(a0, w, y, train, chosen))
        model = MachineModel(model.machine, model.geometry,
                             tuple(t for t in effect_terms if t is not None), model.info)
    return Named(chosen, effects, effect_terms, model, current, joint)


def with_correlations(chosen: list[Candidate], effects: list[dict[str, Any]],
                      fit: JointFit) -> None:
    """Each entry of a drift or an expansion that shares its axis with the other gains
    ``correlation``: for every such effect of its axis, the correlation between the two
    estimates in the joint fit (near -1: the readings trade one for the other)."""
    for i, c_i in enumerate(chosen):
        if c_i.effect not in PAIR or i not in fit.slices:
            continue
        corr = [{"effect": c_j.effect, "axis": c_j.axis, "sensor": c_j.sensor,
                 "r": round(fit.correlation(i, j), 3)}
                for j, c_j in enumerate(chosen)
                if j != i and j in fit.slices and c_j.effect in PAIR
                and c_j.axis == c_i.axis and c_j.effect != c_i.effect]
        if corr:
            effects[i]["correlation"] = corr
