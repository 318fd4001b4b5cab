"""Reading the files the commands take, each problem one :class:`~ednc.cli.UserError`
that names the file (and the line, column or entry the core names)."""

from __future__ import annotations

import json
import math
from pathlib import Path

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
