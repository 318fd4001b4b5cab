"""Component-error tables in CSV with ISO 230-1 column names, in and out.

Layout, one file per axis (so tables from laser software or a controller's pitch-error
compensation can be brought in axis by axis)::

    x_mm,EXX,EYX,EZX,EAX,EBX,ECX
    0,0.0,0.0,0.0,1.2,-3.4,0.5
    50,1.1,0.3,-0.2,1.3,-3.1,0.7

The first column is the axis position (``<axis>_mm`` for linear axes, ``<axis>_deg`` for
rotary ones); the others are any subset of that axis's six component errors (µm, µrad).
Position-independent errors go in one more file with the header ``name,value``
(``EC0Y,12.5``). Every cell must be a finite number; an error names file, line and column.
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


def position_column(axis: Axis) -> str:
    return f"{axis.key}_{'mm' if axis.kind == 'linear' else 'deg'}"


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
        w.writerow([position_column(axis), *names])
        values = [errors.components[n](q) for n in names]
        for i, qi in enumerate(q):
            w.writerow([f"{qi:.6g}", *(f"{v[i]:.6g}" for v in values)])
        out[axis.name] = buf.getvalue()
    if errors.locations:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["name", "value"])
        for name, value in sorted(errors.locations.items()):
            w.writerow([name, f"{value:.6g}"])
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
        if header == ["name", "value"]:
            for line, r in body:
                if len(r) != 2:
                    raise ComponentErrorSpecError(f"{source}:{line}: expected name,value")
                name = r[0].strip()
                if name not in allowed_locations:
                    raise ComponentErrorSpecError(
                        f"{source}:{line}: {name!r} is not a location error of this machine "
                        f"({sorted(allowed_locations)})"
                    )
                locs[name] = _number(r[1].strip(), f"{source}:{line} column value")
            continue
        axis = by_column.get(header[0])
        if axis is None:
            raise ComponentErrorSpecError(
                f"{source}: first column {header[0]!r} is not an axis position column of "
                f"this machine ({sorted(by_column)})"
            )
        valid = set(component_names(axis))
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
                data[k, j] = _number(cell.strip(), f"{source}:{line} column {header[j]}")
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
