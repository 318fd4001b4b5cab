"""The diagnosis's entry point, :func:`diagnose`: the steps of :mod:`volumetric.diagnose`
(the procedure is documented there) run in order on one campaign's readings.

The names other code imports from here (the splits, the gates, the answer) are re-exported
from the modules that hold them.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.base import REFITS, base_design, base_without
from volumetric.diagnose.candidates import Candidate, candidates
from volumetric.diagnose.combination import component_name
from volumetric.diagnose.estimate import estimate_effect, offsets_of
from volumetric.diagnose.further import Named, add_further, list_alternatives
from volumetric.diagnose.gates import (
    MAX_EFFECTS,
    MIN_GAIN,
    T_MIN,
    TIE,
    Z_MIN,
    Scored,
    prefer_physical,
    score,
)
from volumetric.diagnose.joint import JointFit, joint_fit, masked_pair
from volumetric.diagnose.lagged import (
    MAP_THERMAL_RECORDS,
    SELECTED_TERMS,
    lagged_model,
    lagged_scored,
    named_thermal,
)
from volumetric.diagnose.result import Diagnosis, DiagnosisError
from volumetric.diagnose.rotary import with_harmonics
from volumetric.diagnose.splits import (
    FIRST_JUDGED,
    FORWARD_BLOCKS,
    K_FOLDS,
    BaseGrams,
    Judge,
    block_table,
    choose_split,
    combined,
    fold_fits,
    fold_labels,
    forward_blocks,
    forward_residuals,
    heldout_per_fold,
    heldout_residuals,
    rms_of,
    solve_normal,
    time_ordered,
)
from volumetric.diagnose.unexplained import (
    residual_structure,
    unexplained_entry,
    with_unexplained,
)
from volumetric.identify.fit import FitError, FitResult, model_from_parameters
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, Term

__all__ = [
    "FIRST_JUDGED", "FORWARD_BLOCKS", "K_FOLDS", "MAP_THERMAL_RECORDS", "MAX_EFFECTS",
    "MIN_GAIN", "MIN_READINGS", "REFITS", "SELECTED_TERMS", "TIE", "T_MIN", "Z_MIN",
    "BaseGrams", "Diagnosis", "DiagnosisError", "Scored", "base_without", "diagnose",
    "fold_fits", "fold_labels", "forward_blocks", "forward_residuals", "heldout_per_fold",
    "heldout_residuals", "time_ordered",
]

MIN_READINGS = 50
F64 = NDArray[np.float64]


def diagnose(
    machine: Machine,
    m: Measurements,
    *,
    holdout_after: float | None = None,
    base: FitResult | None = None,
    refits: int = REFITS,
) -> Diagnosis:
    """Find what the rigid model misses (see :mod:`volumetric.diagnose`).

    Parameters
    ----------
    machine : Machine
    m : Measurements
    holdout_after : float, optional
        Judge on readings with ``time_s >= holdout_after`` after fitting on the earlier
        ones, instead of the default folds.
    base : FitResult, optional
        The rigid model to extend (its parameters and weights; fitted on the training
        readings, polynomials on every axis). By default identified here by BIC.
    refits : int
        How many times the rigid model's degrees may be chosen again on the readings with
        the named effects taken out (step 1; :func:`base_without`), the diagnosis then
        run again on that base. 0 keeps the first choice.

    Raises
    ------
    DiagnosisError
        Too few readings, or no displacement readings.
    """
    return _diagnose(machine, m, holdout_after, base, refits)


def _diagnose(machine: Machine, m: Measurements, holdout_after: float | None,
              base: FitResult | None, refits: int) -> Diagnosis:
    """:func:`diagnose` on the base ``base`` (identified here when None)."""
    if len(m) < MIN_READINGS:
        raise DiagnosisError(f"too few readings for a diagnosis: {len(m)} (need at least "
                             f"{MIN_READINGS})")
    if not (~m.is_angle).any():
        raise DiagnosisError("no displacement readings: the diagnosis judges displacements")
    # step 2: the split
    try:
        sp = choose_split(m, holdout_after)
    except ValueError as exc:
        raise DiagnosisError(str(exc)) from None
    train, judged = sp.train, sp.judge
    # step 1: the base
    try:
        base_fit, a0, w = base_design(machine, m, train, base)
    except FitError as exc:
        raise DiagnosisError(f"the rigid model cannot be identified: {exc}") from None
    y = m.value
    judge = Judge(sp, a0, y, w)
    base_heldout = judge.heldout(a0)
    rms_before = judge.rms(base_heldout)
    full_base_resid = y - a0 @ solve_normal(a0[train].T @ (a0[train] * w[train, None]),
                                            (a0[train] * w[train, None]).T @ y[train])
    # step 3: the candidates, each scored on the split
    cands, missing = candidates(machine, m, full_base_resid, train, a0, w)
    scored = [score(c, judge.of([c]), base_heldout, rms_before, judged, sp.order_judge)
              for c in cands]
    # a dynamic (lagged) refinement of the best thermal drift
    dyn = lagged_scored(m, scored, judge, full_base_resid, base_heldout, rms_before)
    if dyn is not None:
        scored.append(dyn)
    scored.sort(key=lambda s: s.rms_after_um)
    table = [{"effect": s.candidate.effect, "axis": s.candidate.axis,
              "sensor": s.candidate.sensor, "rms_after_um": round(s.rms_after_um, 4),
              "gain": round(s.gain, 4), "z": round(s.z, 2),
              **({"model": "lagged"} if "lagged" in s.candidate.extra else {})}
             for s in scored]
    details: dict[str, Any] = {"n_readings": len(m), "folds": len(sp.fold_ids),
                               "split": sp.name}
    if sp.name == "forward":
        details["blocks"] = block_table(sp.folds, judged, base_heldout, sp.fold_ids)
    # step 4: ranking and gates
    pick = prefer_physical(scored) if scored else None
    best = named_thermal(pick, dyn, scored, sp.order_judge,
                         decided=sp.name in ("forward", "chronological"))
    if best is not None:
        static = best.candidate
        if "lagged" in static.extra:
            static = min((s for s in scored if s.candidate.effect == "thermal_drift"
                          and "lagged" not in s.candidate.extra), key=lambda s: s.rms_after_um
                         ).candidate
        # step 5: the estimate
        estimate, term, joint = estimate_effect(machine, m, a0, w, y, train, static)
        details["t"] = round(estimate.pop("_t"), 2)
        if details["t"] < T_MIN:
            best = None
    first_pair = None
    if best is None:
        # a drift and an expansion of one axis that cancel alone and pass together
        def fit_of(cands: list[Candidate]) -> JointFit:
            return joint_fit(a0, w, y, train, cands)
        first_pair = masked_pair(scored, judge.of, judged, sp.order_judge, base_heldout,
                                 rms_before, fit_of)
    if best is None and first_pair is None:
        none_model = MachineModel(machine.name, base_fit.model.geometry, (),
                                  {**base_fit.model.info,
                                   "offsets_um": offsets_of(base_fit.params, base_fit.values)})
        details["effects"] = []
        left = residual_structure(machine, m, base_heldout, judged, base_fit.degrees)
        if left:
            # structure no candidate explains: say so rather than "none"
            entry = unexplained_entry(left, [], rms_before)
            details["effects"] = [entry]
            return Diagnosis("unexplained", entry["axis"], entry["sensor"], entry["estimate"],
                             rms_before, rms_before, table, missing, none_model, details,
                             base_heldout, base_heldout, judged)
        return Diagnosis("none", None, None, {}, rms_before, rms_before, table, missing,
                         none_model, details, base_heldout, base_heldout, judged)
    if first_pair is not None:
        named0 = pair_named(machine, m, judge, first_pair, base_fit)
        details["t"] = round(named0.effects[0]["estimate"].pop("_t"), 2)
    else:
        assert best is not None
        named0 = first_named(machine, m, judge, scored, best, static, estimate, term, joint,
                             base_fit, details)
    # step 6: further effects
    named = add_further(machine, m, judge, scored, named0)
    chosen, effects, current = named.chosen, named.effects, named.current
    if named.joint is not None and not any(c.drop or c.effect == "rotary_periodic"
                                           for c in chosen):
        # a drift and an expansion of one axis were judged as a pair: the rigid part and
        # offsets of the fit with every effect in (a lagged drift's, replaced, no longer
        # hold; a cyclic error's harmonic is the first fit's, kept); a term's own
        # reference centres it on the training readings
        p = len(base_fit.params)
        named = replace(named, model=MachineModel(
            named.model.machine,
            model_from_parameters(machine, base_fit.params, named.joint[:p]).geometry,
            named.model.terms,
            {**base_fit.model.info, "extended_with": chosen[0].effect,
             "offsets_um": offsets_of(base_fit.params, named.joint[:p])}))
    # step 7: unexplained structure
    left = residual_structure(machine, m, current.heldout, judged, base_fit.degrees)
    if left:
        effects = with_unexplained(effects, left, rms_before, current.rms_after_um)
    first = effects[0]
    effect, axis, sensor, estimate = (first["effect"], first["axis"], first["sensor"],
                                      first["estimate"])
    details["effects"] = effects
    if sp.name == "forward":
        details["blocks"] = block_table(sp.folds, judged, base_heldout, sp.fold_ids,
                                        current.heldout)
    if refits > 0:
        # step 1 again: the base's degrees were chosen with these effects still in the
        # readings, which made them look like noise: chosen again without them, and
        # everything judged again on that base when it differs
        again = base_without(machine, m, train, a0, w, chosen, base_fit)
        if again is not None:
            return _diagnose(machine, m, holdout_after, again, refits - 1)
    list_alternatives(chosen, effects, details, scored, judged, judge.of)
    return Diagnosis(effect, axis, sensor, estimate, rms_before, current.rms_after_um, table,
                     missing, named.model, details, base_heldout, current.heldout, judged)


def first_named(machine: Machine, m: Measurements, judge: Judge, scored: list[Scored],
                best: Scored, static: Candidate, estimate: dict[str, Any], term: Term | None,
                joint: F64, base_fit: FitResult, details: dict[str, Any]) -> Named:
    """The first effect named (step 5): its entry, and the saved model with it (a lagged
    drift's dynamic term, or the effect's term with the rigid part of their joint fit,
    ``joint``); the top level's ``alternatives`` into ``details``."""
    c = best.candidate
    # the combination of the thermal models saved in place of the one chosen
    # (volumetric.diagnose.lagged.saved_instead): everything here is judged by the chosen
    # one's figures, and only the saved model (and its description) is the combination's
    comb: Scored | None = c.extra.get("saved")
    kept = comb.candidate if comb is not None else c
    if "lagged" in c.extra:
        # the static family names the effect; the dynamic model is its refinement
        estimate["dynamic"] = dict(kept.extra.get("description", {}))
        if comb is not None:
            # both figures, each named, so that the entry's rms_after_um (the chosen
            # model's, which the gates used) is not read as the saved model's
            estimate["dynamic"]["combination"] = {
                **estimate["dynamic"].get("combination", {}),
                "saved_rms_after_um": round(comb.rms_after_um, 4),
                "chosen": component_name(c),
                "chosen_rms_after_um": round(best.rms_after_um, 4)}
    effect, axis, sensor = static.effect, static.axis, static.sensor
    if "lagged" in c.extra:
        # the dynamic model behind the figure is what is saved: its lags with their time
        # constants and end states, and the offsets of the same joint fit
        model = lagged_model(machine, m, judge, kept, base_fit, estimate)
    else:
        # the rigid part refitted together with the effect, so it no longer carries a
        # share of it (a drift seen as straightness, a backlash as positioning error)
        geometry = model_from_parameters(machine, base_fit.params, joint).geometry
        harmonics = estimate.pop("_harmonics", None)
        if harmonics is not None:
            # a cyclic error of a rotary axis: its harmonic joins the axis's components
            geometry = with_harmonics(geometry, estimate["order"], harmonics)
        model = MachineModel(machine.name, geometry, (term,) if term is not None else (),
                             {**base_fit.model.info, "extended_with": effect,
                              "offsets_um": offsets_of(base_fit.params, joint)})
    alternatives = sorted({s.candidate.sensor for s in scored
                           if s.candidate.effect == effect and s.candidate.axis == axis
                           and s.candidate.sensor not in (None, sensor)
                           and s.rms_after_um <= best.rms_after_um * (1 + TIE)} - {None})
    if alternatives:
        details["alternatives"] = alternatives
    first_terms: list[Term | None] = [model.terms[0] if model.terms else None]
    return Named([best.candidate],
                 [{"effect": effect, "axis": axis, "sensor": sensor, "estimate": estimate,
                   "rms_after_um": round(best.rms_after_um, 4)}],
                 first_terms, model, best)


def pair_named(machine: Machine, m: Measurements, judge: Judge,
               pair: tuple[Candidate, Candidate, F64], base_fit: FitResult) -> Named:
    """A drift and an expansion of one axis named together first
    (:func:`~volumetric.diagnose.joint.masked_pair`): their entries, each estimated
    with the other in the model, and the saved model with both terms and the rigid part
    of their joint fit. The first entry's estimate keeps ``_t``."""
    first, second, r_pair = pair
    sp, a0, w, y = judge.split, judge.a0, judge.w, judge.y
    entries: list[dict[str, Any]] = []
    terms: list[Term | None] = []
    for c, other in ((first, second), (second, first)):
        est, term, _ = estimate_effect(machine, m, combined(a0, [other]), w, y, sp.train, c)
        if c is second:
            est.pop("_t")
        entries.append({"effect": c.effect, "axis": c.axis, "sensor": c.sensor,
                        "estimate": est})
        terms.append(term)
    entries[0]["rms_after_um"] = round(judge.rms(judge.of([first])), 4)
    entries[1]["rms_after_um"] = round(judge.rms(r_pair), 4)
    x = joint_fit(a0, w, y, sp.train, [first, second]).x[: len(base_fit.params)]
    model = MachineModel(machine.name,
                         model_from_parameters(machine, base_fit.params, x).geometry,
                         tuple(t for t in terms if t is not None),
                         {**base_fit.model.info, "extended_with": first.effect,
                          "offsets_um": offsets_of(base_fit.params, x)})
    rms = rms_of(r_pair[sp.judge])
    return Named([first, second], entries, terms, model,
                 Scored(second, r_pair, rms, 0.0, 0.0))
