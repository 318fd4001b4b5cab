"""Reading the files the commands take, each problem one :class:`~ednc.cli.UserError`
that names the file (and the line, column or entry the core names)."""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ednc.cli import UserError
from volumetric.errors import ComponentErrorSpecError, MachineSpecError
from volumetric.measure.measurement import MeasurementFormatError, Measurements, read_measurements
from volumetric.measure.plausible import measurement_warnings, rotary_mismatch
from volumetric.model.machine import Machine, description_warnings, load_machine
from volumetric.model.model import MachineModel
from volumetric.model.modelcheck import check_model
from volumetric.plausible.files import decode_text, wrong_file


def warn(text: str) -> None:
    """One warning line on stderr: plausible input that looks like a unit slip all the
    same (:mod:`volumetric.plausible`); the command goes on."""
    print(f"ednc: warning: {text.strip()}".replace("\n", " "), file=sys.stderr)


def checked(value: float, problem: str | None) -> float:
    """``value``, or a UserError with ``problem`` (a plausibility refusal)."""
    if problem is not None:
        raise UserError(problem)
    return value


def parse_number(text: str, where: str) -> float:
    """A finite number from a cell or an option; ``where`` names it in the error."""
    try:
        v = float(text)
    except ValueError:
        raise UserError(f"{where}: {text.strip()!r} is not a number") from None
    if not math.isfinite(v):
        raise UserError(f"{where}: must be finite")
    return v


def int_option(value: int, name: str, lo: int, hi: int | None = None,
               meaning: str = "") -> int:
    """``value`` when within [lo, hi], else a UserError naming the option."""
    if value < lo or (hi is not None and value > hi):
        where = f">= {lo}" if hi is None else f"within [{lo}, {hi}]"
        raise UserError(f"{name} {value}: must be {where}{meaning}")
    return value


def float_option(value: float, name: str, lo: float, hi: float, *, lo_open: bool = False,
                 unit: str = "") -> float:
    """``value`` when finite and within the range (lo excluded with ``lo_open``)."""
    low_ok = value > lo if lo_open else value >= lo
    if not (math.isfinite(value) and low_ok and value <= hi):
        bracket = "(" if lo_open else "["
        raise UserError(f"{name} {value:g}: must be within {bracket}{lo:g}, {hi:g}]{unit}")
    return value


def check_output(path: Path | None, option: str, *, directory: bool = False) -> None:
    """Refuse an output path that cannot be written, before any work is done (a fit of a
    big file should not end in 'no such directory'). ``directory``: the path is a directory
    to create (``--report``)."""
    if path is None:
        return
    parent = path.parent if not directory or not path.exists() else path
    if directory and path.exists() and not path.is_dir():
        raise UserError(f"{option} {path}: exists and is not a directory")
    if not directory and path.is_dir():
        raise UserError(f"{option} {path}: is a directory; give a file name")
    if directory and not path.exists():
        # created with its parents by the command: the nearest existing one must be writable
        parent = path.parent
        while not parent.exists() and parent != parent.parent:
            parent = parent.parent
    elif not parent.exists():
        raise UserError(f"{option} {path}: the directory {parent} does not exist")
    if not parent.is_dir():
        raise UserError(f"{option} {path}: {parent} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UserError(f"{option} {path}: cannot write in {parent} (permission denied)")
    if path.exists() and not directory and not os.access(path, os.W_OK):
        raise UserError(f"{option} {path}: the file exists and cannot be written")


def _plain(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def dump_json(value: Any, indent: int | None = None) -> str:
    """JSON text that any parser reads: a non-finite float (which ``json.dumps`` writes as
    ``Infinity``/``NaN``, not JSON) is written as null, numpy scalars as numbers."""
    return json.dumps(_plain(value), indent=indent, allow_nan=False)


def read_machine(path: Path) -> Machine:
    """A machine description (formats.md §1), with ``pivots_mm`` wherever a table's rotary
    axis needs it (:func:`volumetric.model.machine.missing_pivots`)."""
    try:
        machine = load_machine(path, require_pivots=True)
    except MachineSpecError as exc:
        raise UserError(str(exc)) from None
    for w in description_warnings(machine):
        warn(f"{path}: {w}")
    return machine


def read_data(path: Path) -> Measurements:
    """A measurement CSV (formats.md §2)."""
    try:
        m = read_measurements(path)
    except MeasurementFormatError as exc:
        raise UserError(str(exc)) from exc
    except UnicodeDecodeError as exc:
        raise UserError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start}); save "
                        "it as UTF-8") from exc
    except OSError as exc:
        raise UserError(f"cannot read {path}: {exc.strerror or exc}") from exc
    for w in measurement_warnings(m, str(path)):
        warn(w)
    return m


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
        if self.rows_seen == 0:
            self.check_axes(m)
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


    def check_axes(self, m: Measurements) -> None:
        """The readings' rotary columns match the machine's rotary axes
        (:func:`volumetric.measure.plausible.rotary_mismatch`)."""
        problem = rotary_mismatch(m.has_rotary, m.q[:, 3:], {a.name for _, a in self.axes})
        if problem is not None:
            raise UserError(f"{self.path}: {problem}")


def read_model(path: Path, machine: Machine | None = None) -> MachineModel:
    """What ``ednc fit`` (or ``diagnose --out``) wrote, checked against ``machine``."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise UserError(f"{path}: cannot read ({exc.strerror or exc})") from None
    other = wrong_file(raw[:4096], str(path), "model")
    if other is not None:
        raise UserError(other)
    try:
        data = json.loads(decode_text(raw, str(path)))
    except json.JSONDecodeError as exc:
        raise UserError(f"{path}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except ValueError as exc:
        raise UserError(str(exc)) from None
    except RecursionError:
        raise UserError(f"{path}: nested too deeply to be a model") from None
    try:
        model = check_model(data)
        if machine is not None:
            if model.machine and model.machine != machine.name:
                # each machine has its own errors: another's model compensates errors this
                # one does not have (a model without a name, written by hand, is taken)
                raise UserError(
                    f"{path}: the model is of machine {model.machine!r}, the description of "
                    f"{machine.name!r}; fit this machine's own readings (or correct the "
                    "'machine' entry if it is the same machine renamed)")
            check_model(data, machine)
    except ComponentErrorSpecError as exc:
        raise UserError(f"{path}: {exc}") from None
    return model
