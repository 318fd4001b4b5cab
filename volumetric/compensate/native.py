"""Compensation in controllers' native formats, for machines without our endpoint.

Two exports of a :class:`~volumetric.compensate.tablesmap.TablesMap`:

* **ISO 230-1 component tables** (CSV, one file per axis, the layout of
  :mod:`volumetric.measure.tables`, as volumetric compensations of the ISG/Beckhoff kind
  read them): every component table of the map at the union of its nodes, so that linear
  interpolation of the file reproduces the map's tables exactly; plus the location errors.
  Such a controller evaluates the chain itself: nothing is lost.
* **Siemens CEC** (``$AN_CEC`` blocks in an MPF part program): CEC tables are 1-D, one
  input axis and one output axis each, and add their value to the output axis's position.
  What a 1-D table can hold of a machine's errors:

  - straightness and positioning of a linear axis: ``E<c><K>(k)`` moves the tool along c as
    a function of K alone, corrected by a table input K, output c, values ``-E`` (mm);
  - squareness: a linear function of the leaning axis's position (input Y, output X for
    ``EC0Y``; input Z, outputs X and Y for ``EB0Z`` and ``EA0Z``);
  - angular positioning of a rotary axis (``ECC`` on C): input C, output C.

  What it cannot hold: roll, pitch and yaw of the linear axes (their effect at the tool is
  the angle times an arm that depends on the *other* axes' positions and on the tool
  length: a product, not a 1-D table), every other error of rotary axes (radial and axial
  motions and tilts act through the chain's rotation), and thermal terms. The export lists
  those with their largest size so the user sees what stays uncompensated; the ``tables``
  map kind (the chain evaluated in the endpoint) compensates them all.

Corrections for a 3-axis machine are ``dq = -e(q)`` to first order, which the CEC tables
above sum up to; table values are in mm (degrees for a rotary axis), positions likewise.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.tablesmap import TablesMap
from volumetric.measure.tables import position_column
from volumetric.model.components import is_angular, parse_name
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
CEC_MAX_POINTS = 200
"""Points per CEC table on an 828D (8 tables of 200 points); an 840D allows more."""
_MM_PER_UM = 1e-3
_MM_PER_UM_MM = 1e-6  # µrad × mm → mm


@dataclass(frozen=True)
class CecTable:
    """One 1-D CEC table: ``values`` (mm or degrees) added to ``output`` as a function of
    ``input``'s position at ``start + i·step``."""

    input: str
    output: str
    start: float
    step: float
    values: F64
    covers: str
    """The errors the table compensates, e.g. ``"EYX"`` or ``"EC0Y"``."""


@dataclass(frozen=True)
class CecExport:
    tables: tuple[CecTable, ...]
    left_out: tuple[tuple[str, float], ...]
    """Errors no 1-D table holds, with their largest absolute value (µm or µrad)."""


def _resample(name: str, t: TablesMap, lo: float, hi: float, points: int) -> tuple[F64, F64]:
    q = np.linspace(lo, hi, points)
    comp = next(s for s in t.tables if s.name == name).component()
    return q, np.asarray(comp(q), dtype=float)


def cec_tables(t: TablesMap, *, max_points: int = CEC_MAX_POINTS) -> CecExport:
    """The CEC tables of a map (see module docstring for what they cover).

    Parameters
    ----------
    t : TablesMap
    max_points : int
        Points per table; a map table with more nodes is resampled uniformly.
    """
    m: Machine = t.machine
    linear = {a.name for a in m.axes if a.kind == "linear"}
    out: list[CecTable] = []
    left: list[tuple[str, float]] = []
    for s in t.tables:
        p = parse_name(s.name)
        axis = m.axis(p.axis)
        size = float(np.abs(s.values).max())
        if axis.kind == "linear" and p.direction in linear and not is_angular(s.name):
            lo, hi = axis.travel
            n = min(max_points, max(2, s.values.size))
            q, v = _resample(s.name, t, lo, hi, n)
            out.append(CecTable(axis.name, p.direction, float(lo), float(q[1] - q[0]),
                                -v * _MM_PER_UM, s.name))
        elif axis.kind == "rotary" and p.direction == axis.name:
            lo, hi = axis.travel
            n = min(max_points, max(2, s.values.size))
            q, v = _resample(s.name, t, lo, hi, n)
            # µrad → degrees
            out.append(CecTable(axis.name, axis.name, float(lo), float(q[1] - q[0]),
                                -np.degrees(v * 1e-6), s.name))
        else:
            left.append((s.name, size))
    # squareness: the tool moves by -EC0Y·y in x, +EB0Z·z in x, -EA0Z·z in y
    lean = {"EC0Y": ("Y", "X", -1.0), "EB0Z": ("Z", "X", 1.0), "EA0Z": ("Z", "Y", -1.0)}
    for name, value in sorted(t.locations.items()):
        if name in lean and lean[name][0] in linear and lean[name][1] in linear:
            src, dst, sign = lean[name]
            lo, hi = m.axis(src).travel
            q = np.array([lo, hi], dtype=float)
            out.append(CecTable(src, dst, float(lo), float(hi - lo),
                                -sign * value * q * _MM_PER_UM_MM, name))
        else:
            left.append((name, abs(value)))
    left += [(f"{th.kind} {th.axis} ({th.sensor})", abs(th.coefficient)) for th in t.thermal]
    return CecExport(tuple(out), tuple(left))


def cec_mpf(t: TablesMap, *, max_points: int = CEC_MAX_POINTS) -> str:
    """The CEC tables as an MPF part program (``$AN_CEC`` system variables).

    Axis identifiers are written ``X1``, ``Y1``, ``Z1``, ``A1``, ``B1``, ``C1`` (the usual
    machine axis names of MD10000); rename them to the machine's own before loading.
    Activation (``$MA_CEC_ENABLE``, ``$SN_CEC_TABLE_ENABLE``, NEWCONF) is left to the
    commissioning engineer, as the manufacturer's documentation prescribes.
    """
    e = cec_tables(t, max_points=max_points)
    lines = [f"; CEC compensation tables of {t.machine.name}, map version {t.version}",
             "; values: corrections in mm (degrees for rotary axes) = -error",
             f"; {len(e.tables)} tables"]
    for name, size in e.left_out:
        lines.append(f"; not expressible as a 1-D table, left uncompensated: {name} "
                     f"(up to {size:.3g} µm or µrad)")
    for i, c in enumerate(e.tables):
        lines += [
            f"; table {i}: {c.covers}, input {c.input}, output {c.output}",
            f"$AN_CEC_INPUT_AXIS[{i}]=({c.input}1)",
            f"$AN_CEC_OUTPUT_AXIS[{i}]=({c.output}1)",
            f"$AN_CEC_STEP[{i}]={c.step:.6f}",
            f"$AN_CEC_MIN[{i}]={c.start:.6f}",
            f"$AN_CEC_MAX[{i}]={c.start + c.step * (c.values.size - 1):.6f}",
        ]
        lines += [f"$AN_CEC[{i},{n}]={v:.6f}" for n, v in enumerate(c.values)]
    lines.append("M17")
    return "\n".join(lines) + "\n"


def iso230_1_tables(t: TablesMap) -> dict[str, str]:
    """ISO 230-1 CSV text per axis (keyed by axis name) plus ``locations``: each axis's
    component tables at the union of their nodes (linear interpolation of the file gives
    back the map's tables exactly), in µm and µrad."""
    out: dict[str, str] = {}
    for axis in t.machine.axes:
        mine = [s for s in t.tables if parse_name(s.name).axis == axis.name]
        if not mine:
            continue
        nodes = np.unique(np.concatenate(
            [s.start + s.step * np.arange(s.values.size) if s.values.size > 1
             else np.array(axis.travel, dtype=float) for s in mine]))
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([position_column(axis), *(s.name for s in mine)])
        cols = [np.asarray(s.component()(nodes), dtype=float) for s in mine]
        for i, qi in enumerate(nodes):
            w.writerow([f"{qi:.9g}", *(f"{c[i]:.9g}" for c in cols)])
        out[axis.name] = buf.getvalue()
    if t.locations:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["name", "value"])
        for name, value in sorted(t.locations.items()):
            w.writerow([name, f"{value:.9g}"])
        out["locations"] = buf.getvalue()
    return out


__all__ = ["CEC_MAX_POINTS", "CecExport", "CecTable", "cec_mpf", "cec_tables",
           "iso230_1_tables"]
