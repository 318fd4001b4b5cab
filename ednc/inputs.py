"""Reading the files the commands take, each problem one :class:`~ednc.cli.UserError`
that names the file (and the line, column or entry the core names)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ednc.cli import UserError
from volumetric.errors import ComponentErrorSpecError, MachineSpecError
from volumetric.measure.measurement import MeasurementFormatError, Measurements, read_measurements
from volumetric.model.machine import Machine, load_machine
from volumetric.model.model import MachineModel


def parse_number(text: str, where: str) -> float:
    """A finite number from a cell or an option; ``where`` names it in the error."""
    try:
        v = float(text)
    except ValueError:
        raise UserError(f"{where}: {text.strip()!r} is not a number") from None
    if not math.isfinite(v):
        raise UserError(f"{where}: must be finite")
    return v


def read_machine(path: Path) -> Machine:
    """A machine description (formats.md §1)."""
    try:
        return load_machine(path)
    except MachineSpecError as exc:
        raise UserError(str(exc)) from None


def read_data(path: Path) -> Measurements:
    """A measurement CSV (formats.md §2)."""
    try:
        return read_measurements(path)
    except (MeasurementFormatError, UnicodeDecodeError) as exc:
        raise UserError(str(exc)) from exc
    except OSError as exc:
        raise UserError(f"cannot read {path}: {exc.strerror or exc}") from exc


_STANDARD_AXES = ("X", "Y", "Z", "A", "B", "C")


class ReadingsTravel:
    """Checks readings against the machine's travel, block after block.

    The model is fitted as polynomials over the travel; a reading far outside it (a wrong
    column, a typo, another machine's file) would bend every polynomial to reach it. The
    file's line of the first offending reading is named (the header is line 1, readings
    follow one per line, as formats.md §2 writes them).
    """

    def __init__(self, machine: Machine, path: Path) -> None:
        self.path = path
        self.axes = [(j, a) for j, a in enumerate(machine.axes) if a.name in _STANDARD_AXES]
        self.rows_seen = 0

    def check(self, m: Measurements) -> Measurements:
        """``m`` unchanged, or a UserError naming the line, axis, value and travel."""
        for _, axis in self.axes:
            column = m.q[:, _STANDARD_AXES.index(axis.name)]
            lo, hi = axis.travel
            margin = 1e-6 * max(hi - lo, 1.0)
            outside = np.flatnonzero((column < lo - margin) | (column > hi + margin))
            if outside.size:
                i = int(outside[0])
                unit = "°" if axis.kind == "rotary" else " mm"
                raise UserError(
                    f"{self.path} line {self.rows_seen + i + 2}: {axis.key} = {column[i]:g}{unit} "
                    f"is outside the travel [{lo:g}, {hi:g}] of axis {axis.name} "
                    f"({outside.size} such readings in this block); check the file and the "
                    "description (--allow-outside-travel to use them anyway)")
        self.rows_seen += len(m)
        return m


def read_model(path: Path, machine: Machine | None = None) -> MachineModel:
    """What ``ednc fit`` (or ``diagnose --out``) wrote, checked against ``machine``."""
    try:
        data = json.loads(path.read_text())
    except OSError as exc:
        raise UserError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except json.JSONDecodeError as exc:
        raise UserError(f"{path}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except UnicodeDecodeError:
        raise UserError(f"{path}: not a text file") from None
    try:
        model = MachineModel.from_json(data)
        if machine is not None:
            if model.machine and model.machine != machine.name:
                # each machine has its own errors: another's model compensates errors this
                # one does not have (a model without a name, written by hand, is taken)
                raise UserError(
                    f"{path}: the model is of machine {model.machine!r}, the description of "
                    f"{machine.name!r}; fit this machine's own readings (or correct the "
                    "'machine' entry if it is the same machine renamed)")
            model.geometry.check(machine)
    except ComponentErrorSpecError as exc:
        raise UserError(f"{path}: {exc}") from None
    return model
