"""Where the service's edge calls the numeric core's validators, in one place.

The core (:mod:`volumetric`) is the authority on what a machine description or a
measurement CSV may hold; the API uses the same readers as the offline commands, so it
rejects exactly what they reject, with the same messages.
"""

from __future__ import annotations

import io
from typing import Any

from volumetric.errors import MachineSpecError
from volumetric.machine import parse_machine
from volumetric.measurement import MeasurementFormatError, read_measurements


class MeasurementError(ValueError):
    """A measurement CSV the core refuses; the message names the line and column."""


def check_machine_description(spec: dict[str, Any]) -> None:
    """Raise ValueError (the core's message) when the description cannot be a machine.

    ``spec`` is the description as JSON (formats.md §1), already type-checked by the
    pydantic schema; this adds the core's kinematic checks (chain syntax, a travel for
    every linear axis, unit spindle directions, ...).
    """
    try:
        parse_machine(spec)
    except MachineSpecError as exc:
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
    stream = io.StringIO(text)
    stream.name = source  # read_measurements names its errors by the stream's name
    try:
        return len(read_measurements(stream))
    except MeasurementFormatError as exc:
        raise MeasurementError(str(exc)) from None
