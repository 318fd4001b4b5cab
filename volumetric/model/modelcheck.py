"""The one check of a saved model (what ``ednc fit --out`` or ``ednc diagnose --out``
writes) before anything computes with it: the offline commands and the service's model
upload call :func:`check_model` alike, so they refuse exactly the same files.

A model must say it is one (``"format": "ednc-model/1"``), hold at least one error (an
empty object compensates nothing, yet predicted an RMS "as if real"), name only errors of
the machine it is applied to, and carry finite numbers in every term on axes the machine
has.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.machine import Machine
from volumetric.model.model import FORMAT, MachineModel
from volumetric.plausible.angles import ANGLE
from volumetric.plausible.displacements import DISPLACEMENT
from volumetric.plausible.limit import Limit

__all__ = ["ModelContentError", "check_model"]


class ModelContentError(ComponentErrorSpecError):
    """A model file that is not a model, or not one of this machine."""


def check_model(data: Any, machine: Machine | None = None) -> MachineModel:
    """The model ``data`` holds, checked (against ``machine`` when given).

    Parameters
    ----------
    data : object
        The parsed JSON.
    machine : Machine, optional
        The machine the model is to be applied to.

    Raises
    ------
    ModelContentError
        Not an object, another format, no error at all, a term with a non-finite number or
        on an axis the machine lacks, an error name of another machine (the message names
        the entry). A model of another machine *name* is the caller's to judge (the
        message differs between a file and an upload).
    """
    if not isinstance(data, Mapping):
        raise ModelContentError(f"a model is a JSON object (as 'ednc fit --out' writes), "
                                f"not {type(data).__name__}")
    if data.get("format") != FORMAT:
        raise ModelContentError(f"format: expected {FORMAT!r} (what 'ednc fit --out' "
                                f"writes), got {data.get('format')!r}")
    try:
        model = MachineModel.from_json(data)
    except ComponentErrorSpecError as exc:
        raise ModelContentError(str(exc)) from None
    # from_json names the entry for the shapes it expects; these are the shapes it does
    # not (a list where an object belongs)
    except (ValueError, TypeError, KeyError, AttributeError) as exc:
        raise ModelContentError(f"not a model: {exc}") from None
    if not (model.geometry.components or model.geometry.locations or model.terms):
        raise ModelContentError("the model holds no error (no components, locations or "
                                "terms): it would compensate nothing")
    keys = None if machine is None else {a.key for a in machine.axes}
    for i, term in enumerate(model.terms):
        kind = getattr(term, "kind", None) or type(term).__name__
        for f in fields(term):
            value = getattr(term, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                raise ModelContentError(f"terms[{i}] ({kind}): {f.name} = {value} is not "
                                        "finite")
            # sizes (µm, µrad, mm, °C, µm/K) far beyond a machine's; times (``*_s``) are
            # campaign seconds and may be large
            if (isinstance(value, float) and not f.name.endswith("_s")
                    and abs(value) > MAX_TERM_VALUE):
                raise ModelContentError(f"terms[{i}] ({kind}): {f.name} = {value:g} is "
                                        f"beyond ±{MAX_TERM_VALUE:g}; check the unit")
        axis = str(term.axis).lower()
        if keys is not None and axis not in keys:
            assert machine is not None
            raise ModelContentError(f"terms[{i}] ({kind}): machine {machine.name!r} has no "
                                    f"axis {axis!r} (its axes are {' '.join(sorted(keys))})")
    for name, value in model.geometry.locations.items():
        limit = limit_of(name)
        if not (math.isfinite(value) and abs(value) <= limit.hi):
            raise ModelContentError(f"locations.{name} = {value:g}: a location error is "
                                    f"within ±{limit.hi:g} {limit.unit}")
    if machine is not None:
        try:
            model.geometry.check(machine)
        except ComponentErrorSpecError as exc:
            raise ModelContentError(str(exc)) from None
        _check_sizes(model, machine)
    return model


MAX_TERM_VALUE = 1e9
"""Largest |number| of a term's size fields: past it arithmetic on it overflows or the
model is a unit slip."""
MAX_ERROR = ANGLE.hi
"""Largest |error| a model may give anywhere on its machine's travel: 10 mm of a
displacement (µm), 0.1 rad of an angle (µrad), the limits every entry point shares
(:mod:`volumetric.plausible`; :func:`limit_of`). Far beyond any machine tool, far below
what turns the kinematics' sines and squares into NaN (a location of 1e300 µrad did)."""


def limit_of(name: str) -> Limit:
    """The limit of an ISO 230-1 error by its name: ``E<direction>...`` is a displacement
    (µm) for a direction X, Y or Z, an angle (µrad) for A, B or C."""
    return DISPLACEMENT if name[1:2] in ("X", "Y", "Z") else ANGLE


def _check_sizes(model: MachineModel, machine: Machine) -> None:
    """Every component error finite and within :data:`MAX_ERROR` over its axis's travel
    (sampled at 65 points, ends included)."""
    travel = {a.name: a.travel for a in machine.axes}
    with np.errstate(all="ignore"):
        for name, component in model.geometry.components.items():
            axis = name[2:] if len(name) > 2 else ""
            lo, hi = travel.get(axis, (0.0, 1.0))
            values = np.asarray(component(np.linspace(lo, hi, 65)), dtype=np.float64)
            worst = float(np.max(np.abs(values))) if values.size else 0.0
            limit = limit_of(name)
            if not (math.isfinite(worst) and worst <= limit.hi):
                raise ModelContentError(
                    f"components.{name} reaches {worst:g} {limit.unit} on the travel "
                    f"[{lo:g}, {hi:g}]; a component error is within ±{limit.hi:g} "
                    f"{limit.unit}; check the unit")
