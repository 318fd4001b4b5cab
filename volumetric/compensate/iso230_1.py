"""ISO 230-1 component-error tables a reader can trust, for controls that evaluate the
chain themselves (ISG/Beckhoff, a KinematicsComp-like import, a spreadsheet).

One CSV per axis (``X.csv`` ...) and ``locations.csv``, or all of them in one file as
blocks separated by a blank line; each file starts with a metadata block of ``#`` lines::

    # format: ednc ISO 230-1 component errors, version 2
    # machine: vmc-01; model: ednc-model/1 of 2026-11-27, fitted on 2886 readings
    # sign convention: error = actual - commanded tool position relative to the
    #   workpiece (ISO 230-1); angles right-handed about x, y, z; EXX = +5 means the
    #   tool stands 5 µm further along +x than commanded
    # tool length 100 mm; reference temperature 20 °C (thermal terms: not in the tables)
    # not identified (empty cells): EAZ_urad (not measured by the campaign)
    x_mm,EXX_um,EYX_um,EZX_um,EAX_urad,EBX_urad,ECX_urad
    0,0,0,0,,0,0
    10,0.42,...

Rows are at a regular step (``--step``, default a round number giving 20 to 50 rows, or
at most 1/20 of a ballscrew period the model holds),
from a multiple of the step at or below the travel's start to one at or above its end.
Every one of the axis's six component errors has its column, its unit in its header; a
column the model did not identify is present with empty cells and named in the metadata,
so that a reader tells zero from unknown. ``ednc tables import`` reads this layout and
the earlier ones (no metadata, bare names, one file per axis).
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.tables import error_column, import_tables, position_column, unit_of
from volumetric.model.components import GeometricErrors, Sinusoid, Sum, component_names
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Axis, Machine
from volumetric.model.model import MachineModel

F64 = NDArray[np.float64]
POINTS = 4000
FORMAT_LINE = "# format: ednc ISO 230-1 component errors, version 2"
SIGN_CONVENTION = (
    "error = actual minus commanded tool position relative to the workpiece (ISO 230-1), "
    "um and urad; angles right-handed about x, y, z; EXX = +5 um means the tool stands "
    "5 um further along +x than commanded; EC0Y > 0: Y leans towards -x")
_SERIES = (0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 2.5, 5.0, 10.0, 20.0, 25.0, 50.0, 100.0, 200.0)


@dataclass(frozen=True)
class IsoExport:
    """Texts keyed by file stem (``X``, ``locations``), and what the rows leave.

    Attributes
    ----------
    files : dict of str to str
    interp : dict of str to float
        Per component, the largest gap between the rows' linear interpolation and the
        model's function (µm or µrad).
    unidentified : tuple of str
    """

    files: dict[str, str]
    interp: dict[str, float]
    unidentified: tuple[str, ...]
    tool_tip_um: float = 0.0
    """Largest tool-tip distance between the model and the tables as a reader
    interpolates them, µm (random points over the travel, the export's tool length)."""

    def single(self) -> str:
        """All blocks in one text, separated by blank lines (metadata once)."""
        parts = []
        for i, text in enumerate(self.files.values()):
            lines = text.splitlines()
            if i:
                lines = [ln for ln in lines if not ln.startswith("#")]
            parts.append("\n".join(lines))
        return "\n\n".join(parts) + "\n"


def default_step(axis: Axis) -> float:
    """A round step giving 20 to 50 rows over the travel (dividing 360 for rotary axes)."""
    span = axis.travel[1] - axis.travel[0]
    for s in _SERIES:
        if axis.kind == "rotary" and abs(360.0 / s - round(360.0 / s)) > 1e-9:
            continue
        if span / s <= 50:
            return s
    return _SERIES[-1]


def _rows(axis: Axis, step: float) -> F64:
    lo, hi = axis.travel
    start = math.floor(lo / step + 1e-9) * step
    stop = math.ceil(hi / step - 1e-9) * step
    out: F64 = start + step * np.arange(round((stop - start) / step) + 1, dtype=np.float64)
    return out


def _periodic_step(geometry: GeometricErrors, axis: Axis) -> float:
    """A round step of at most 1/20 of the shortest period of a sinusoid in the axis's
    components (a ballscrew's pitch error), so that the rows follow it; inf without one."""
    periods = []
    for n in component_names(axis):
        f = geometry.components.get(n)
        parts = f.terms if isinstance(f, Sum) else (f,)
        periods += [p.period for p in parts if isinstance(p, Sinusoid)]
    if not periods:
        return math.inf
    fine = [s for s in _SERIES if s <= min(periods) / 20]
    return fine[-1] if fine else _SERIES[0]


def _num(v: float) -> str:
    s = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "", "-") else s


def unidentified_of(model: MachineModel) -> dict[str, str]:
    """Components the model says it did not identify, with the reason."""
    out: dict[str, str] = {}
    for name in model.info.get("not_measured", []) or []:
        if name not in model.geometry.components:
            out[str(name)] = "not measured by the campaign"
    return out


def iso230_1_export(machine: Machine, model: MachineModel, geometry: GeometricErrors, *,
                    step_mm: float | None = None, tool_mm: float,
                    thermal: list[tuple[str, str]] | None = None,
                    backlash_um: Mapping[str, float] | None = None,
                    source: str = "") -> IsoExport:
    """The files of the module docstring.

    Parameters
    ----------
    machine : Machine
    model : MachineModel
        For the metadata (version, date, readings, identified components).
    geometry : GeometricErrors
        What the tables hold (periodic terms folded in by the caller).
    step_mm : float, optional
        Row step of the linear axes (rotary axes: :func:`default_step`).
    tool_mm : float
    thermal : list of (term, what it does), optional
        Terms the tables do not hold (named in the metadata).
    backlash_um : mapping of axis to reversal, optional
        Named in the metadata (a direction-free table cannot hold it).
    source : str
        The model file and its date, for the metadata.
    """
    unknown = unidentified_of(model)
    info = model.info
    meta = [FORMAT_LINE,
            f"# machine: {machine.name}; chain: {machine.chain}",
            f"# model: {source + '; ' if source else ''}{info.get('format', 'ednc-model/1')}"
            + (f" of {info['date']}" if info.get("date") else "")
            + (f", fitted on {info['n_readings']} readings" if info.get("n_readings") else "")
            + (f", version {info['version']}" if info.get("version") else ""),
            f"# sign convention: {SIGN_CONVENTION}",
            f"# tool length: {tool_mm:g} mm (the tables do not depend on it)",
            "# reference temperature: 20 C (ISO 1); " + (
                "thermal terms NOT in the tables: " + "; ".join(f"{n}: {w}" for n, w in thermal)
                if thermal else "the model has no thermal terms")]
    if backlash_um:
        meta.append("# backlash NOT in the tables (direction-dependent): " + "; ".join(
            f"{k} reversal {v:g} um" for k, v in sorted(backlash_um.items())))
    if unknown:
        meta.append("# not identified (empty cells, unknown rather than zero): " + "; ".join(
            f"{error_column(n)} ({why})" for n, why in sorted(unknown.items())))
    meta.append("# rows: linear interpolation between rows; ends held beyond them")
    files: dict[str, str] = {}
    interp: dict[str, float] = {}
    for axis in machine.axes:
        step = default_step(axis) if (step_mm is None or axis.kind == "rotary") else step_mm
        if step_mm is None:
            step = min(step, _periodic_step(geometry, axis))
        q = _rows(axis, step)
        names = component_names(axis)
        if not any(n in geometry.components or n in unknown for n in names):
            continue
        dense = np.linspace(axis.travel[0], axis.travel[1], 2001)
        cols: list[list[str]] = []
        for n in names:
            f = geometry.components.get(n)
            if n in unknown:
                cols.append([""] * q.size)
                continue
            v = np.zeros(q.size) if f is None else np.asarray(f(q), dtype=float)
            cols.append([_num(x) for x in v])
            if f is not None:
                back = np.interp(dense, q, np.round(v, 6))
                interp[n] = float(np.abs(back - f(dense)).max())
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([position_column(axis), *map(error_column, names)])
        for i, qi in enumerate(q):
            w.writerow([_num(qi), *(c[i] for c in cols)])
        files[axis.name] = "\n".join(meta) + "\n" + buf.getvalue()
    if geometry.locations:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["name", "value", "unit"])
        for name, value in sorted(geometry.locations.items()):
            w.writerow([name, f"{value:.9g}", unit_of(name)])
        files["locations"] = "\n".join(meta) + "\n" + buf.getvalue()
    gap = rows_gap_um(machine, geometry, files, tool_mm)
    line = (f"# the rows reproduce the model within {gap:.3f} um at the tool tip "
            f"({POINTS} random points, {tool_mm:g} mm tool)")
    files = {k: v.replace("\n# rows:", f"\n{line}\n# rows:", 1) for k, v in files.items()}
    return IsoExport(files, interp, tuple(sorted(unknown)), gap)


def rows_gap_um(machine: Machine, geometry: GeometricErrors, files: Mapping[str, str],
                tool_mm: float) -> float:
    """Largest tool-tip distance (µm) between ``geometry`` and the files read back by
    :func:`volumetric.measure.tables.import_tables`, exact kinematics on both."""
    back = import_tables(machine, [(f"{k}.csv", v) for k, v in files.items()])
    rng = np.random.default_rng(230)
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], POINTS) for a in machine.axes])
    a = volumetric_error(machine, geometry, q, tool_mm=tool_mm, orientation=False)
    b = volumetric_error(machine, back, q, tool_mm=tool_mm, orientation=False)
    return float(np.linalg.norm(a.position_um - b.position_um, axis=1).max())


__all__ = ["FORMAT_LINE", "IsoExport", "default_step", "iso230_1_export", "unidentified_of"]
