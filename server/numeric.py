"""Where the service calls the numeric core (:mod:`volumetric`), in one place.

The core is the authority on what a machine description, a measurement CSV or a model may
hold; the API uses the same readers as the offline commands, so it rejects exactly what
they reject, with the same messages. Everything here is synchronous and may take a while
(a fit): async callers use :func:`asyncio.to_thread`.
"""

from __future__ import annotations

import io
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from volumetric.diagnose.diagnosis import DiagnosisError, diagnose
from volumetric.errors import MachineSpecError
from volumetric.identify.fit import FitError, fit
from volumetric.measure.measurement import MeasurementFormatError, Measurements, read_measurements
from volumetric.measure.plausible import measurement_warnings, rotary_mismatch
from volumetric.model.machine import missing_pivots, parse_machine
from volumetric.model.model import FORMAT as MODEL_FORMAT
from volumetric.model.modelcheck import check_model as check_model_content
from volumetric.verify.iso230_6 import DiagonalTestError, diagonal_ranges, improvement

__all__ = [
    "ACCEPTANCE",
    "MODEL_FORMAT",
    "MeasurementError",
    "ModelError",
    "VerificationError",
    "check_machine_description",
    "check_model",
    "count_measurement_rows",
    "diagnose_sets",
    "fit_model",
    "measurement_check",
    "verify_diagonals",
]

ACCEPTANCE = 0.70
"""A compensation passes the body-diagonal verification when it removes at least 70 % of the
largest diagonal range (the EDNC paper's acceptance, ISO 230-6 diagonals)."""


class MeasurementError(ValueError):
    """A measurement CSV the core refuses; the message names the line and column."""


class ModelError(ValueError):
    """A model the core cannot read or fit; the message says what and where."""


class VerificationError(ValueError):
    """Readings that are not a body-diagonal test the core can evaluate."""


def check_machine_description(spec: dict[str, Any]) -> None:
    """Raise ValueError (the core's message) when the description cannot be a machine.

    ``spec`` is the description as JSON (formats.md §1), already type-checked by the
    pydantic schema; this adds the core's kinematic checks (chain syntax, a travel for
    every linear axis, unit spindle directions, ...).
    """
    try:
        problem = missing_pivots(spec, parse_machine(spec))  # as `ednc` reads a description
    except MachineSpecError as exc:
        raise ValueError(str(exc)) from None
    if problem is not None:
        raise ValueError(problem)


def _read(text: str, source: str) -> Measurements:
    stream = io.StringIO(text)
    stream.name = source  # read_measurements names its errors by the stream's name
    try:
        return read_measurements(stream)
    except MeasurementFormatError as exc:
        raise MeasurementError(str(exc)) from None


def count_measurement_rows(text: str, source: str,
                           description: dict[str, Any] | None = None) -> int:
    """Validate a measurement CSV (formats.md §2) and return its number of readings
    (:func:`measurement_check` without the warnings)."""
    return measurement_check(text, source, description)[0]


def measurement_check(text: str, source: str, description: dict[str, Any] | None = None
                      ) -> tuple[int, list[str]]:
    """Validate a measurement CSV (formats.md §2); its number of readings, and what in
    them looks like a unit slip all the same (readings of 0.01 "µm" that are mm:
    :func:`volumetric.measure.plausible.measurement_warnings`).

    Parameters
    ----------
    text
        The whole file, decoded.
    source
        What to call it in error messages (the upload's file name).
    description
        The machine's description: its rotary axes must match the readings' columns.

    Raises
    ------
    MeasurementError
        With the core's message naming the line and column.
    """
    m = _read(text, source)
    if description is not None:
        # the check `ednc fit` and `diagnose` make: a five-axis machine's readings have its
        # rotary columns (a description the API stored always parses)
        rotary = {a.name for a in parse_machine(description).axes if a.name in ("A", "B", "C")}
        problem = rotary_mismatch(m.has_rotary, m.q[:, 3:], rotary)
        if problem is not None:
            raise MeasurementError(f"{source}: {problem}")
    return len(m), measurement_warnings(m, source)


def check_model(body: dict[str, Any], description: dict[str, Any]) -> None:
    """Raise :class:`ModelError` unless ``body`` is a model (``MachineModel.to_json``) whose
    error names all belong to the machine described by ``description``."""
    # the check `ednc predict`, `compensate` and `map` make of a model file (format, at
    # least one error, finite terms on the machine's axes, the machine's error names)
    try:
        check_model_content(body, parse_machine(description))
    except (ValueError, TypeError, KeyError) as exc:
        raise ModelError(str(exc)) from None


def _readings(sets: Sequence[tuple[str, str]]) -> Measurements:
    parts = [_read(text, name) for name, text in sets]
    try:
        return Measurements.concat(parts)
    except ValueError as exc:
        raise ModelError(f"the sets do not combine: {exc}") from None


def plain_json(value: Any) -> Any:
    """``value`` with numpy scalars made Python numbers and non-finite floats made None.

    The core's JSON is meant for ``json.dumps``; a database JSON column and strict clients
    also refuse NaN and numpy integers.
    """
    if isinstance(value, dict):
        return {str(k): plain_json(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain_json(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def fit_model(
    description: dict[str, Any], sets: Sequence[tuple[str, str]], *, select: bool = True
) -> dict[str, Any]:
    """Identify a machine's rigid model from stored measurement sets.

    Parameters
    ----------
    description
        The machine description (formats.md §1).
    sets
        ``(name, csv_text)`` of each measurement set, used together.
    select
        Choose polynomial degrees from the data (BIC) rather than using the maxima.

    Returns
    -------
    dict
        The model as JSON (``MachineModel.to_json``), fit statistics under ``info``.

    Raises
    ------
    MeasurementError, ModelError
        Unreadable sets; sets that do not combine or observe too little to fit.
    """
    machine = parse_machine(description)
    readings = _readings(sets)
    try:
        result = fit(machine, readings, select=select)
    except FitError as exc:
        raise ModelError(str(exc)) from None
    body: dict[str, Any] = plain_json(result.model.to_json())
    return body


def diagnose_sets(
    description: dict[str, Any], sets: Sequence[tuple[str, str]], *,
    holdout_after: float | None = None,
) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """Diagnose what the rigid model misses in stored measurement sets (``ednc diagnose``).

    Returns
    -------
    result : dict
        The diagnosis JSON (formats.md §3 and the core's extensions).
    model : dict or None
        The model extended by the named effect, or None when the effect is ``none``.

    Raises
    ------
    MeasurementError, ModelError
        Unreadable sets, or readings that cannot support a diagnosis (the core's message).
    """
    machine = parse_machine(description)
    readings = _readings(sets)
    try:
        found = diagnose(machine, readings, holdout_after=holdout_after)
    except DiagnosisError as exc:
        raise ModelError(str(exc)) from None
    model = None if found.effect == "none" else plain_json(found.model.to_json())
    return plain_json(found.to_json()), model


def verify_diagonals(
    before: tuple[str, str], after: tuple[str, str] | None, *, target_tol_mm: float = 1e-3
) -> dict[str, Any]:
    """Evaluate ISO 230-6 body-diagonal tests, and the gain of a compensation.

    Parameters
    ----------
    before, after
        ``(set name, csv_text)`` of the diagonal tests without and with compensation;
        ``after`` may be None (ranges only).
    target_tol_mm
        Commanded points closer than this along a diagonal are one target (mm).

    Returns
    -------
    dict
        ``ranges_before_um`` (and with ``after``: ``ranges_after_um``, ``improvement`` per
        diagonal and ``overall``, ``accepted`` = overall >= :data:`ACCEPTANCE`).

    Raises
    ------
    MeasurementError, VerificationError
    """
    try:
        ranges_before = diagonal_ranges(_read(before[1], before[0]),
                                        target_tol_mm=target_tol_mm)
        report: dict[str, Any] = {"standard": "ISO 230-6 body diagonals",
                                  "before_set": before[0], "ranges_before_um": ranges_before}
        if after is not None:
            ranges_after = diagonal_ranges(_read(after[1], after[0]),
                                           target_tol_mm=target_tol_mm)
            gain = improvement(ranges_before, ranges_after)
            report |= {"after_set": after[0], "ranges_after_um": ranges_after,
                       "improvement": gain, "acceptance": ACCEPTANCE,
                       "accepted": gain["overall"] >= ACCEPTANCE}
    except DiagonalTestError as exc:
        raise VerificationError(str(exc)) from None
    return report
