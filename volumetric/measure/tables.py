"""Component-error tables in CSV with ISO 230-1 column names, in and out.

Layout, one file per axis (so tables from laser software or a controller's pitch-error
compensation can be brought in axis by axis)::

    x_mm,EXX_um,EYX_um,EZX_um,EAX_urad,EBX_urad,ECX_urad
    0,0.0,0.0,0.0,1.2,-3.4,0.5
    50,1.1,0.3,-0.2,1.3,-3.1,0.7

The first column is the axis position (``<axis>_mm`` for linear axes, ``<axis>_deg`` for
rotary ones); the others are any subset of that axis's six component errors, each named
by its ISO 230-1 name and its unit: ``_um`` for the translational ones (``EXX``, ``EYX``,
``EZX``: second letter X, Y or Z), ``_urad`` for the angular ones (``EAX``, ``EBX``,
``ECX``). The bare ISO name (``EXX``) is read too, in the same units, as laser software
and the files of earlier versions write it; a suffix that contradicts the name's unit
(``EAX_um``) is refused. Position-independent errors go in one more file,
``name,value,unit`` (``EC0Y,12.5,urad``; ``name,value`` is read too). Every cell must be a
finite number; an error names file, line and column.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import (
    Component,
    GeometricErrors,
    Table,
    component_names,
    location_names,
)
from volumetric.model.machine import Axis, Machine

UNITS = {"um": "µm", "urad": "µrad"}


def position_column(axis: Axis) -> str:
    return f"{axis.key}_{'mm' if axis.kind == 'linear' else 'deg'}"


def unit_of(name: str) -> str:
    """``um`` or ``urad``: ISO 230-1 names say it by their second letter (EXX, EX0C: a
    displacement along X; EAX, EC0Y: a rotation about A's axis x)."""
    return "um" if name[1] in "XYZ" else "urad"


def error_column(name: str) -> str:
    """The header of a component error's column: its ISO 230-1 name and its unit."""
    return f"{name}_{unit_of(name)}"


def _split_unit(column: str, source: str) -> str:
    """The ISO 230-1 name of a column header (``EXX_um`` or ``EXX``); a unit suffix that
    contradicts the name is refused rather than read in the wrong unit."""
    name, _, unit = column.rpartition("_")
    if not name or unit not in UNITS:
        return column
    if unit != unit_of(name):
        want = unit_of(name)
        raise ComponentErrorSpecError(
            f"{source}: column {column!r}: {name} is in {UNITS[want]} ({name}_{want}), "
            f"not {UNITS[unit]}")
    return name


def export_tables(
    machine: Machine, errors: GeometricErrors, *, points: int = 21
) -> dict[str, str]:
    """CSV text per axis (keyed ``X``, ``Y``, ...) plus ``locations``.

    Components are sampled at ``points`` equally spaced positions over the travel.
    """
    out: dict[str, str] = {}
    for axis in machine.axes:
        names = [n for n in component_names(axis) if n in errors.components]
        if not names:
            continue
        q = np.linspace(axis.travel[0], axis.travel[1], points)
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([position_column(axis), *map(error_column, names)])
        values = [errors.components[n](q) for n in names]
        for i, qi in enumerate(q):
            w.writerow([f"{qi:.6g}", *(f"{v[i]:.6g}" for v in values)])
        out[axis.name] = buf.getvalue()
    if errors.locations:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["name", "value", "unit"])
        for name, value in sorted(errors.locations.items()):
            w.writerow([name, f"{value:.6g}", unit_of(name)])
        out["locations"] = buf.getvalue()
    return out


def _number(cell: str, where: str) -> float:
    try:
        v = float(cell)
    except ValueError:
        raise ComponentErrorSpecError(f"{where}: {cell!r} is not a number") from None
    if not math.isfinite(v):
        raise ComponentErrorSpecError(f"{where}: {cell!r} is not a finite number")
    return v


def import_tables(machine: Machine, files: Iterable[tuple[str, str]]) -> GeometricErrors:
    """Component and location errors from CSV texts.

    Parameters
    ----------
    machine : Machine
    files : iterable of (source name, CSV text)

    Raises
    ------
    ComponentErrorSpecError
        Naming the file, line and column of the first problem.
    """
    comps: dict[str, Component] = {}
    locs: dict[str, float] = {}
    by_column = {position_column(a): a for a in machine.axes}
    allowed_locations = set(location_names(machine))
    for source, text in files:
        rows = list(csv.reader(io.StringIO(text)))
        if not rows or not rows[0]:
            raise ComponentErrorSpecError(f"{source}: empty file")
        header = [h.strip() for h in rows[0]]
        body = [(i + 2, r) for i, r in enumerate(rows[1:]) if any(c.strip() for c in r)]
        if header in (["name", "value"], ["name", "value", "unit"]):
            for line, r in body:
                if len(r) != len(header):
                    raise ComponentErrorSpecError(
                        f"{source}:{line}: expected {','.join(header)}")
                name = r[0].strip()
                if name not in allowed_locations:
                    raise ComponentErrorSpecError(
                        f"{source}:{line}: {name!r} is not a location error of this machine "
                        f"({sorted(allowed_locations)})"
                    )
                if len(r) == 3 and r[2].strip() != unit_of(name):
                    raise ComponentErrorSpecError(
                        f"{source}:{line} column unit: {name} is in {unit_of(name)}, "
                        f"not {r[2].strip()!r}")
                locs[name] = _number(r[1].strip(), f"{source}:{line} column value")
            continue
        axis = by_column.get(header[0])
        if axis is None:
            raise ComponentErrorSpecError(
                f"{source}: first column {header[0]!r} is not an axis position column of "
                f"this machine ({sorted(by_column)})"
            )
        valid = set(component_names(axis))
        written = header  # for messages: the column as the file names it
        header = [header[0], *(_split_unit(col, source) for col in header[1:])]
        for col in header[1:]:
            if col not in valid:
                raise ComponentErrorSpecError(
                    f"{source}: column {col!r} is not a component error of axis {axis.name} "
                    f"({sorted(valid)})"
                )
        if len(set(header)) != len(header):
            raise ComponentErrorSpecError(f"{source}: a column appears twice in {header}")
        if not body:
            raise ComponentErrorSpecError(f"{source}: no rows")
        data = np.empty((len(body), len(header)))
        for k, (line, r) in enumerate(body):
            if len(r) != len(header):
                raise ComponentErrorSpecError(
                    f"{source}:{line}: {len(r)} cells, the header has {len(header)}"
                )
            for j, cell in enumerate(r):
                data[k, j] = _number(cell.strip(), f"{source}:{line} column {written[j]}")
        try:
            for j, col in enumerate(header[1:], start=1):
                comps[col] = Table(tuple(data[:, 0]), tuple(data[:, j]))
        except ComponentErrorSpecError as exc:
            raise ComponentErrorSpecError(f"{source}: {exc}") from None
    errors = GeometricErrors(comps, locs)
    errors.check(machine)
    return errors


def read_table_files(paths: Iterable[Path]) -> list[tuple[str, str]]:
    """(name, text) of each file, with a clear error for unreadable ones."""
    out = []
    for p in paths:
        try:
            out.append((str(p), Path(p).read_text()))
        except OSError as exc:
            raise ComponentErrorSpecError(f"{p}: cannot read ({exc.strerror})") from None
    return out


def write_tables(tables: Mapping[str, str], directory: Path) -> list[Path]:
    directory.mkdir(parents=True, exist_ok=True)
    written = []
    for key, text in tables.items():
        p = directory / f"{key}.csv"
        p.write_text(text)
        written.append(p)
    return written
