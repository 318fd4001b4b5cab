"""A SINUMERIK's interpolatory compensation (CEC) as its NC evaluates a loaded file.

The simulated NC takes the file the operator loads (``ednc export --format cec``: an MPF
part program or the ``%_N_NC_CEC_INI`` initialisation file) as text and evaluates it by
the function manual K3's rules (section 4.4, /work/shared/spec/controllers.md):

* table t: ``$AN_CEC_INPUT_AXIS[t]``, ``$AN_CEC_OUTPUT_AXIS[t]``, ``$AN_CEC_STEP[t]``,
  ``$AN_CEC_MIN[t]``, ``$AN_CEC_MAX[t]`` and the points ``$AN_CEC[t,N]`` at
  MIN + N·STEP; linear between points; before MIN point 0's value, after MAX the last
  point's (held); ``$AN_CEC_IS_MODULO[t]=1`` repeats the table over MIN..MAX;
* ``$AN_CEC_DIRECTION[t]``: 0 both directions of the input axis, 1 positive only, -1
  negative only;
* ``$AN_CEC_MULT_BY_TABLE[t]=n``: the table is multiplied by the table of number n
  (index n - 1) and the product is added to the output axis as an additional value (both
  tables are also summed as they are);
* the compensation of an axis is the sum of its tables and products.

Only what an NC loads is taken: the first line names the file (``%_N_..._MPF`` or
``_INI``), the last ends it (M30/M02 or M17), every line between is an assignment or a
comment; anything else raises ``ValueError``, as the NC would refuse to load it.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["CecTables"]

F64 = NDArray[np.float64]
_LINE = re.compile(r"^\$AN_CEC(_[A-Z_]+)?\[(\d+)(?:,(\d+))?\]=(\S+)$")
_AXIS = re.compile(r"^\(([A-Za-z][A-Za-z0-9_]*)\)$")


@dataclass
class _Table:
    inp: str = ""
    out: str = ""
    step: float = 0.0
    lo: float = 0.0
    hi: float = 0.0
    direction: int = 0
    mult: int = 0
    modulo: bool = False
    points: dict[int, float] = field(default_factory=dict)

    def values(self, q: F64) -> F64:
        """The table at input positions ``q`` (N,), interpolated and held at the ends."""
        n = max(self.points) + 1
        v = np.array([self.points.get(i, 0.0) for i in range(n)])
        if n == 1 or self.step <= 0:
            return np.full(q.shape, v[0])
        if self.modulo and self.hi > self.lo:
            q = self.lo + np.mod(q - self.lo, self.hi - self.lo)
        s = np.clip((q - self.lo) / self.step, 0.0, n - 1.0)
        i = np.minimum(np.floor(s).astype(np.int64), n - 2)
        t = s - i
        out: F64 = v[i] * (1.0 - t) + v[i + 1] * t
        return out


class CecTables:
    """The CEC tables of one loaded file.

    Parameters
    ----------
    text : str
        The file as loaded.
    axes : sequence of str
        The NC's machine axes in its order (``X``, ``Y``, ...).
    axis_names : mapping of str to str, optional
        The file's axis name of each machine axis (default: the name followed by 1,
        ``X1``, as ``ednc export`` writes them).

    Raises
    ------
    ValueError
        The file is not one the NC loads, or names an axis it does not have.
    """

    def __init__(self, text: str, axes: Sequence[str],
                 axis_names: Mapping[str, str] | None = None) -> None:
        names = {a.upper(): (axis_names or {}).get(a.upper(), f"{a.upper()}1") for a in axes}
        self.columns = {v: j for j, v in enumerate(names.values())}
        self.n_axes = len(axes)
        self.tables = self._parse(text)
        for t, tab in self.tables.items():
            for a in (tab.inp, tab.out):
                if a not in self.columns:
                    raise ValueError(f"table {t}: axis {a!r} is not one of the NC's "
                                     f"({' '.join(self.columns)})")
            if tab.mult and self.tables.get(tab.mult - 1) is None:
                raise ValueError(f"table {t}: multiplied by table number {tab.mult}, "
                                 "which the file does not hold")

    @staticmethod
    def _parse(text: str) -> dict[int, _Table]:
        lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
        if len(lines) < 2 or not lines[0].startswith("%_N_"):
            raise ValueError("not an NC file: the first line must be %_N_<name>_MPF/_INI")
        ini = lines[0].endswith("_INI")
        end = ("M17",) if ini else ("M30", "M02", "M2")
        if lines[-1] not in end:
            raise ValueError(f"the file ends with {lines[-1]!r}, not {' or '.join(end)}")
        tables: dict[int, _Table] = {}
        for ln in lines[1:-1]:
            if ln.startswith(";") or ln == "CHANDATA(1)":
                continue
            m = _LINE.match(ln)
            if m is None:
                raise ValueError(f"line {ln!r}: not a $AN_CEC assignment")
            var, t, point, value = m.group(1) or "", int(m.group(2)), m.group(3), m.group(4)
            tab = tables.setdefault(t, _Table())
            if var == "":
                if point is None:
                    raise ValueError(f"line {ln!r}: $AN_CEC needs [table,point]")
                tab.points[int(point)] = float(value)
            elif var in ("_INPUT_AXIS", "_OUTPUT_AXIS"):
                a = _AXIS.match(value)
                if a is None:
                    raise ValueError(f"line {ln!r}: an axis is written (NAME)")
                if var == "_INPUT_AXIS":
                    tab.inp = a.group(1)
                else:
                    tab.out = a.group(1)
            elif var == "_STEP":
                tab.step = float(value)
            elif var == "_MIN":
                tab.lo = float(value)
            elif var == "_MAX":
                tab.hi = float(value)
            elif var == "_DIRECTION":
                tab.direction = int(value)
            elif var == "_MULT_BY_TABLE":
                tab.mult = int(value)
            elif var == "_IS_MODULO":
                tab.modulo = int(value) == 1
            else:
                raise ValueError(f"line {ln!r}: ${var} is not a CEC variable")
        for t, tab in tables.items():
            if not (tab.inp and tab.out and tab.points):
                raise ValueError(f"table {t}: input axis, output axis and points are needed")
        return tables

    def compensation_mm(self, q: F64, direction: NDArray[np.integer] | None = None) -> F64:
        """The compensation per axis at machine positions ``q``, mm (degrees).

        Parameters
        ----------
        q : ndarray, shape (N, n_axes)
        direction : ndarray of int, shape (N, n_axes), optional
            Last direction of motion (+1 when omitted).

        Returns
        -------
        ndarray, shape (N, n_axes)
        """
        q = np.atleast_2d(np.asarray(q, dtype=float))
        d = np.ones(q.shape, dtype=np.int64) if direction is None else np.asarray(direction)
        out = np.zeros(q.shape)
        value = {t: tab.values(q[:, self.columns[tab.inp]]) for t, tab in self.tables.items()}
        for t, tab in self.tables.items():
            v = value[t]
            if tab.direction:
                v = np.where(d[:, self.columns[tab.inp]] == tab.direction, v, 0.0)
            col = self.columns[tab.out]
            out[:, col] += v
            if tab.mult:
                out[:, col] += v * value[tab.mult - 1]
        return out
