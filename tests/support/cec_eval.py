"""An evaluator of SINUMERIK CEC files written from the K3 function manual's rules alone.

It reads the file's text (never the exporter's objects) and computes the compensation the
control would add per axis:

* a table t is given by ``$AN_CEC_INPUT_AXIS[t]``, ``$AN_CEC_OUTPUT_AXIS[t]``,
  ``$AN_CEC_STEP[t]``, ``$AN_CEC_MIN[t]``, ``$AN_CEC_MAX[t]`` and the points
  ``$AN_CEC[t,N]`` at MIN + N·STEP, the last at MAX; between points linear interpolation;
  below MIN point 0's value, above MAX the last point's (K3 4.4, "Table parameters");
* ``$AN_CEC_IS_MODULO[t]=1``: the table repeats, MAX followed by MIN;
* ``$AN_CEC_DIRECTION[t]``: 0 both directions of the input axis, 1 positive only, -1
  negative only;
* ``$AN_CEC_MULT_BY_TABLE[t]=n``: table t times the table of *number* n (index n - 1),
  which must have the same output (compensation) axis; the product is added to the
  output's total, as an additional value: both tables are summed as well;
* the total per output axis is the sum of its tables plus the products.

The file must also have the structure an NC loads: ``%_N_..._MPF`` (or ``_INI`` with
``CHANDATA``), and end with M30/M02 (MPF) or M17 (INI). Violations raise ``ValueError``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]
_ASSIGN = re.compile(r"^\$(AN_CEC(?:_[A-Z_]+)?)\[(\d+)(?:,(\d+))?\]=(.+)$")


@dataclass
class Table:
    index: int
    input: str = ""
    output: str = ""
    step: float = float("nan")
    lo: float = float("nan")
    hi: float = float("nan")
    direction: int = 0
    mult: int = 0
    modulo: bool = False
    points: dict[int, float] = field(default_factory=dict)

    def values(self) -> F64:
        n = len(self.points)
        if sorted(self.points) != list(range(n)):
            raise ValueError(f"table {self.index}: points are not 0..{n - 1}")
        return np.array([self.points[i] for i in range(n)])

    def at(self, q: F64) -> F64:
        v = self.values()
        n = v.size
        if not (self.step > 0 and abs(self.lo + self.step * (n - 1) - self.hi) < 1e-9):
            raise ValueError(f"table {self.index}: MIN + STEP·(points - 1) != MAX "
                             f"({self.lo} + {self.step}·{n - 1} vs {self.hi})")
        q = np.asarray(q, dtype=float)
        if self.modulo:
            q = self.lo + np.mod(q - self.lo, self.hi - self.lo)
        else:
            q = np.clip(q, self.lo, self.hi)
        s = (q - self.lo) / self.step
        i = np.clip(np.floor(s).astype(int), 0, n - 2) if n > 1 else np.zeros_like(s, int)
        if n == 1:
            return np.full(q.shape, v[0])
        t = s - i
        out: F64 = v[i] * (1 - t) + v[i + 1] * t
        return out


def parse(text: str) -> dict[int, Table]:
    """The tables of a CEC file, checked for the structure an NC loads."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    if not lines or not lines[0].startswith("%_N_"):
        raise ValueError("first line must be %_N_<name>_MPF or _INI")
    ini = lines[0].endswith("_INI")
    if not ini and not lines[0].endswith("_MPF"):
        raise ValueError(f"{lines[0]!r}: neither an MPF nor an INI name")
    last = lines[-1]
    if (ini and last != "M17") or (not ini and last not in ("M30", "M02", "M2")):
        raise ValueError(f"ends with {last!r}: an {'INI' if ini else 'MPF'} ends with "
                         f"{'M17' if ini else 'M30'}")
    if ini and "CHANDATA(1)" not in lines[:3]:
        raise ValueError("an INI with $AN_CEC needs CHANDATA(1)")
    tables: dict[int, Table] = {}
    for ln in lines[1:-1]:
        if ln.startswith(";") or ln.startswith("CHANDATA"):
            continue
        m = _ASSIGN.match(ln)
        if not m:
            raise ValueError(f"line {ln!r} is not a $AN_CEC assignment or a comment")
        var, t, n, value = m.group(1), int(m.group(2)), m.group(3), m.group(4)
        tab = tables.setdefault(t, Table(t))
        if var == "AN_CEC":
            if n is None:
                raise ValueError(f"{ln!r}: $AN_CEC needs [table,point]")
            tab.points[int(n)] = float(value)
        elif var in ("AN_CEC_INPUT_AXIS", "AN_CEC_OUTPUT_AXIS"):
            am = re.fullmatch(r"\(([A-Za-z][A-Za-z0-9_]*)\)", value)
            if not am:
                raise ValueError(f"{ln!r}: an axis is written (NAME)")
            if var == "AN_CEC_INPUT_AXIS":
                tab.input = am.group(1)
            else:
                tab.output = am.group(1)
        elif var == "AN_CEC_STEP":
            tab.step = float(value)
        elif var == "AN_CEC_MIN":
            tab.lo = float(value)
        elif var == "AN_CEC_MAX":
            tab.hi = float(value)
        elif var == "AN_CEC_DIRECTION":
            tab.direction = int(value)
            if tab.direction not in (-1, 0, 1):
                raise ValueError(f"{ln!r}: direction is -1, 0 or 1")
        elif var == "AN_CEC_MULT_BY_TABLE":
            tab.mult = int(value)
        elif var == "AN_CEC_IS_MODULO":
            tab.modulo = int(value) == 1
        else:
            raise ValueError(f"{ln!r}: unknown variable ${var}")
    for t in tables.values():
        if not t.input or not t.output or not t.points:
            raise ValueError(f"table {t.index}: input, output and points are required")
        if t.mult:
            other = tables.get(t.mult - 1)
            if other is None:
                raise ValueError(f"table {t.index}: multiplied by table number {t.mult}, "
                                 f"index {t.mult - 1}, which is not in the file")
            if other.output != t.output:
                raise ValueError(f"table {t.index}: factor table {t.mult - 1} has another "
                                 "compensation axis")
    return tables


def compensation(tables: dict[int, Table], axes: dict[str, int], q: F64,
                 direction: F64 | None = None) -> F64:
    """Total compensation per axis (N, n_axes), mm or degrees, at positions q.

    Parameters
    ----------
    axes : mapping of the file's axis names to columns of q
    direction : ndarray (N, n_axes) of +1/-1, optional (positive when omitted)
    """
    out = np.zeros_like(q, dtype=float)
    dirs = np.ones_like(q) if direction is None else direction
    value = {i: t.at(q[:, axes[t.input]]) for i, t in tables.items()}
    for i, t in tables.items():
        on = np.ones(q.shape[0], bool) if t.direction == 0 else (
            dirs[:, axes[t.input]] == t.direction)
        v = np.where(on, value[i], 0.0)
        out[:, axes[t.output]] += v
        if t.mult:
            out[:, axes[t.output]] += v * value[t.mult - 1]
    return out
