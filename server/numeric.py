"""Where the service calls the numeric core (:mod:`volumetric`), in one place.

The core's validators are the authority on what a machine description or a measurement CSV
may hold; the service uses them at its edge so that the API rejects exactly what the
offline commands reject. They are looked up at call time and used when present, so the
service also runs (with its own, lighter checks) while the core is being written.
"""

from __future__ import annotations

import csv
import importlib
import io
from types import ModuleType
from typing import Any


class MeasurementError(ValueError):
    """A measurement CSV the core refuses; the message names the line and column."""


def _core(module: str) -> ModuleType | None:
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name != module:  # the module exists but is broken: do not hide that
            raise
        return None


def check_machine_description(spec: dict[str, Any]) -> None:
    """Raise ValueError (the core's message) when the description cannot be a machine.

    ``spec`` is the description as JSON (formats.md §1), already type-checked by the
    pydantic schema; this adds the core's kinematic checks (chain syntax, a travel for
    every linear axis, unit spindle directions, ...).
    """
    core = _core("volumetric.machine")
    if core is None:
        return
    spec_error: type[Exception] = core.MachineSpecError
    try:
        core.parse_machine(spec)
    except spec_error as exc:
        raise ValueError(str(exc)) from None


def count_measurement_rows(text: str, source: str) -> int:
    """Validate a measurement CSV (formats.md §2) and return its number of readings.

    Parameters
    ----------
    text
        The whole file, decoded.
    source
        What to call it in error messages (the upload's file name).

    Raises
    ------
    MeasurementError
        With the core's message naming the line and column.
    """
    core = _core("volumetric.measurement")
    if core is not None:
        stream = io.StringIO(text)
        stream.name = source  # read_measurements names its errors by the stream's name
        format_error: type[Exception] = core.MeasurementFormatError
        try:
            return len(core.read_measurements(stream))
        except format_error as exc:
            raise MeasurementError(str(exc)) from None
    # Without the core: at least a header and one reading of the same width.
    rows = [row for row in csv.reader(io.StringIO(text)) if row]
    if len(rows) < 2:
        raise MeasurementError(f"{source}: needs a header line and at least one reading")
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != len(rows[0]):
            raise MeasurementError(
                f"{source}, line {i}: row has {len(row)} cells, the header has {len(rows[0])}"
            )
    return len(rows) - 1
