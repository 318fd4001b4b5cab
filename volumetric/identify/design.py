"""The identification problem's design matrix: one row per reading, one column per parameter.

Every reading is one linear observation of the model's parameters: a displacement reads
``u · Δp`` and an angle ``u · Δω`` (:mod:`volumetric.model.linear`), and every error is a sum of
basis functions times coefficients. The parameters are

* the coefficients of each component error in Legendre polynomials of its axis position
  normalised to [-1, 1] over the travel; per component the lowest degree follows a
  convention that removes what is structurally the same as another parameter: no
  constant in any displacement component (it is the tool-tip offset below), no slope in
  a straightness that a squareness of the same axis already describes (EXY's slope is
  EC0Y, EXZ's is EB0Z, EYZ's is EA0Z), no constant in a rotary axis's components (those
  are its location errors). What the readings at hand cannot separate beyond that is
  found by the fit's null-space analysis, not assumed;
* for a rotary axis whose travel spans at least half a turn, its component errors in a
  Fourier basis of the angle instead (``cos kθ``, ``sin kθ``, k = 1 .. K, no constant:
  that is the location error; K = ``MAX_ORDER_FOURIER`` over any such travel,
  :func:`fourier_order`): the error motions of a rotary table (eccentricity,
  wobble, a cyclic indexing error) repeat every turn, which a low-degree polynomial over
  ±180° cannot follow. Orders are chosen like degrees (a parameter's ``degree`` counts
  the basis functions: ``2k - 1`` for ``cos kθ``, ``2k`` for ``sin kθ``); axes of short
  travel (a swivel head's ±30°) keep polynomials;
* the location errors of :func:`volumetric.model.components.location_names`;
* a constant offset of each tool tip relative to the workpiece (``OFFSET_X`` ...), for
  readings whose zero is not the machine's reference.

The matrix is in the readings' units: µm per µm or µrad of a parameter.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import legendre
from numpy.typing import NDArray

from volumetric.measure.measurement import Measurements
from volumetric.model.components import DIRECTIONS, Fourier, Polynomial, location_names
from volumetric.model.linear import sensitivities
from volumetric.model.machine import Axis, Machine

F64 = NDArray[np.float64]
MAX_DEGREE_LINEAR = 6
MAX_DEGREE_ANGULAR = 4
MAX_DEGREE_ROTARY = 3
MAX_ORDER_FOURIER = 4
"""Highest harmonic per turn of a full-turn rotary axis's components (9 basis functions
need at least 9 distinct angles; the standard campaign's R-tests visit 12)."""
PERIODIC_SPAN_DEG = 180.0
"""Rotary travel from which components take the Fourier basis: over a shorter one the
first harmonics are as smooth as a cubic and no better determined."""


@dataclass(frozen=True)
class Param:
    """One column of the design matrix.

    Attributes
    ----------
    name : str
        ``EXX[2]`` (degree-2 coefficient of EXX), ``EC0Y`` or ``OFFSET_X``.
    component : str
        The ISO name the parameter belongs to (``EXX``, ``EC0Y``) or ``OFFSET``.
    degree : int
        Polynomial degree (-1 for constants that are not coefficients); for the Fourier
        basis the index of the basis function (``2k - 1``: ``cos kθ``, ``2k``: ``sin kθ``).
    unit : str
        ``"um"`` or ``"urad"``.
    basis : {"legendre", "fourier"}
        The basis the coefficient belongs to.
    """

    name: str
    component: str
    degree: int
    unit: str
    basis: str = "legendre"


def fourier_axis(axis: Axis) -> bool:
    """True for a rotary axis whose components take the Fourier basis (travel of at least
    ``PERIODIC_SPAN_DEG``)."""
    return axis.kind == "rotary" and axis.travel[1] - axis.travel[0] >= PERIODIC_SPAN_DEG


FourierChoice = bool | frozenset[str]
"""Which rotary axes take the Fourier basis: True every one of long travel, False none, a
set of axis names those of them (the diagnosis tries one axis at a time)."""


def uses_fourier(axis: Axis, fourier: FourierChoice) -> bool:
    """Whether ``axis``'s components are in the Fourier basis under the choice ``fourier``."""
    if not fourier_axis(axis):
        return False
    return fourier if isinstance(fourier, bool) else axis.name in fourier


def fourier_order(axis: Axis) -> int:
    """Highest harmonic per turn the axis's components carry: ``MAX_ORDER_FOURIER`` over
    any travel of at least ``PERIODIC_SPAN_DEG`` (the axes that take the Fourier basis).

    Over half a turn the travel sees two periods of the fourth harmonic, and BIC with the
    fit's null-space analysis keeps only the orders the readings determine. Fewer (one per
    quarter turn, 2 over ±110°, as before) left a tilting axis's third and fourth
    harmonics, which a trunnion's bearings do have, to the residual, where they leaked
    into every higher harmonic the diagnosis looks at (``ednc diagnose``'s base is this
    model)."""
    span = axis.travel[1] - axis.travel[0]
    return MAX_ORDER_FOURIER if span >= PERIODIC_SPAN_DEG else max(1, int(span // 90.0))


def min_degree(machine: Machine, axis: Axis, direction: str) -> int:
    """The lowest polynomial degree a component carries (see module docstring)."""
    if axis.kind == "rotary":
        return 1
    if direction in ("A", "B", "C"):
        return 0
    # a tilt of the line of motion about base axis a moves the tool along e_a × d
    e = np.eye(3)["XYZ".index(direction)]
    d = np.asarray(axis.direction)
    locs = set(location_names(machine))
    for k, a in enumerate("ABC"):
        if f"E{a}0{axis.name}" in locs:
            shift = np.cross(np.eye(3)[k], d)
            if axis.name not in ("X", "Y", "Z"):  # spindle axes tilt in their own frame
                continue
            if abs(float(shift @ e)) > 0.5:
                return 2
    return 1


def max_degree(axis: Axis, direction: str, fourier: FourierChoice = True) -> int:
    if uses_fourier(axis, fourier):
        return 2 * fourier_order(axis)
    if axis.kind == "rotary":
        return MAX_DEGREE_ROTARY
    return MAX_DEGREE_ANGULAR if direction in ("A", "B", "C") else MAX_DEGREE_LINEAR


def axis_positions(machine: Machine, m: Measurements) -> F64:
    """Commanded positions (N, n_axes) of the readings in ``machine.axes`` order.

    An axis without a standard column (a spindle axis ``Z1``) reads its own extra column
    ``z1_mm`` when the file has one, else ``z_mm``: the position of the reading's own
    spindle axis (other spindle axes are irrelevant to that row).
    """
    cols = {"X": 0, "Y": 1, "Z": 2, "A": 3, "B": 4, "C": 5}
    q = np.zeros((len(m), len(machine.axes)))
    for j, a in enumerate(machine.axes):
        own = m.extra.get(f"{a.key}_mm")
        if a.name not in cols and own is not None and own.dtype.kind == "f":
            q[:, j] = own
        else:
            q[:, j] = m.q[:, cols.get(a.name, 2)]
    return q


def branch_rows(machine: Machine, m: Measurements) -> dict[str, NDArray[np.intp]]:
    """Row indices per tool branch (spindle)."""
    names = [b.name for b in machine.branches]
    if m.spindle is None or len(names) == 1:
        return {names[0]: np.arange(len(m))}
    out: dict[str, NDArray[np.intp]] = {}
    unknown = sorted(set(m.spindle.tolist()) - set(names))
    if unknown:
        raise ValueError(f"readings name spindles {unknown}; the machine has {names}")
    for n in names:
        out[n] = np.flatnonzero(m.spindle == n)
    return out


@dataclass(frozen=True)
class Design:
    """The full design matrix at the maximal degrees.

    Attributes
    ----------
    matrix : ndarray, shape (N, P)
    params : list of Param
    """

    matrix: F64
    params: list[Param]

    def columns(self, names: list[str]) -> NDArray[np.intp]:
        index = {p.name: i for i, p in enumerate(self.params)}
        return np.array([index[n] for n in names], dtype=np.intp)


def _basis(q: F64, axis: Axis, degrees: range, fourier: FourierChoice) -> F64:
    if uses_fourier(axis, fourier):
        return fourier_basis(q, degrees)
    lo, hi = axis.travel
    s = (2.0 * q - lo - hi) / (hi - lo)
    vander = np.asarray(legendre.legvander(s, max(degrees.stop - 1, 0)), dtype=np.float64)
    out: F64 = vander[:, degrees.start : degrees.stop]
    return out


def fourier_basis(q: F64, degrees: range) -> F64:
    """Fourier basis functions ``degrees`` (1: cos θ, 2: sin θ, 3: cos 2θ ...) at angles q.

    Parameters
    ----------
    q : ndarray, shape (N,)
        Angles, degrees.
    degrees : range
        Basis indices, starting at 1 or more.

    Returns
    -------
    ndarray, shape (N, len(degrees))
    """
    theta = np.deg2rad(q)
    cols = []
    for j in degrees:
        k = (j + 1) // 2
        cols.append(np.cos(k * theta) if j % 2 else np.sin(k * theta))
    return np.column_stack(cols) if cols else np.zeros((q.shape[0], 0))


def _branch_params(machine: Machine, branch: str, *, degrees: Mapping[str, int] | None,
                   offsets: bool, fourier: FourierChoice) -> list[Param]:
    """The parameters the readings of one tool branch observe, in design order.

    The layout depends on the machine alone, so it is read from the sensitivities at one
    dummy position (their names and columns, not their values).
    """
    q = np.zeros((1, len(machine.axes)))
    out: list[Param] = []
    for s in sensitivities(machine, q, spindle=branch, tool_mm=np.zeros(1)):
        if s.column is None:
            out += [Param(name, name, -1, "urad" if name[1] in "ABC" else "um")
                    for name in s.names]
            continue
        axis = machine.axes[s.column]
        for j, name in enumerate(s.names):
            direction = DIRECTIONS[j]
            lo = min_degree(machine, axis, direction)
            hi = max_degree(axis, direction, fourier)
            if degrees is not None:
                hi = min(hi, degrees.get(name, hi))
            unit = "urad" if direction in "ABC" else "um"
            kind = "fourier" if uses_fourier(axis, fourier) else "legendre"
            out += [Param(f"{name}[{k}]", name, k, unit, kind) for k in range(lo, hi + 1)]
    if offsets:
        for c in "XYZ":
            name = "OFFSET_" + c if len(machine.branches) == 1 else f"OFFSET_{c}_{branch}"
            out.append(Param(name, "OFFSET", -1, "um"))
    return out


def design_params(
    machine: Machine,
    *,
    degrees: Mapping[str, int] | None = None,
    offsets: bool = True,
    fourier: FourierChoice = True,
    branches: Sequence[str] | None = None,
) -> list[Param]:
    """The columns of :func:`build_design`, in its order, for readings of ``branches``
    (tool branch names; all of the machine's by default).

    A parameter shared by several branches (a component of the common chain) appears once,
    where its first branch puts it. Fixing the layout first lets a design be built block
    by block (:func:`build_design` with ``params``) with the same columns in every block.
    """
    names = [b.name for b in machine.branches] if branches is None else list(branches)
    seen: dict[str, Param] = {}
    for b in names:
        for p in _branch_params(machine, b, degrees=degrees, offsets=offsets, fourier=fourier):
            seen.setdefault(p.name, p)
    return list(seen.values())


def build_design(
    machine: Machine,
    m: Measurements,
    *,
    degrees: Mapping[str, int] | None = None,
    offsets: bool = True,
    fourier: FourierChoice = True,
    params: Sequence[Param] | None = None,
) -> Design:
    """Design matrix of the rigid model for the readings.

    Parameters
    ----------
    machine : Machine
    m : Measurements
    degrees : mapping of str to int, optional
        Highest degree per component (ISO name); the module's maxima otherwise.
    offsets : bool
        Include the tool-tip offset parameters.
    fourier : bool or frozenset of str
        Rotary axes of long travel in the Fourier basis (module docstring): all (True),
        none (False: polynomials everywhere, the smooth model the diagnosis extends) or
        those named.
    params : sequence of Param, optional
        The columns, as :func:`design_params` lists them for the same ``degrees``,
        ``offsets`` and ``fourier``: every block of a file then gets the same columns.
        A subset of them builds only those columns. By default, the columns of the tool
        branches these readings belong to.

    Returns
    -------
    Design
        ``matrix`` of shape (N, P), µm or µrad of the reading per unit of each parameter.
    """
    q = axis_positions(machine, m)
    n = len(m)
    rows_of = branch_rows(machine, m)
    if params is None:
        params = design_params(machine, degrees=degrees, offsets=offsets, fourier=fourier,
                               branches=[b for b, r in rows_of.items() if r.size])
    index = {p.name: i for i, p in enumerate(params)}
    # column-major: the design is filled and read a column at a time
    matrix = np.zeros((n, len(params)), order="F")

    def add(name: str, rows: NDArray[np.intp], values: F64) -> None:
        j = index.get(name)
        if j is None:
            return  # a column left out of ``params`` on purpose
        if rows.size == n:
            matrix[:, j] += values
        else:
            matrix[rows, j] += values

    for bname, rows in rows_of.items():
        if rows.size == 0:
            continue
        ang = m.is_angle[rows]
        u = m.u[rows]
        tool = m.tool_mm[rows]
        for s in sensitivities(machine, q[rows], spindle=bname, tool_mm=tool):
            # project the (Δp, Δω) rows of the sensitivity on each reading's direction
            proj = np.where(
                ang[:, None],
                np.einsum("ni,nik->nk", u, s.matrix[:, 3:, :]),
                np.einsum("ni,nik->nk", u, s.matrix[:, :3, :]),
            )
            if s.column is None:
                for j, name in enumerate(s.names):
                    add(name, rows, proj[:, j])
                continue
            axis = machine.axes[s.column]
            for j, name in enumerate(s.names):
                direction = DIRECTIONS[j]
                lo = min_degree(machine, axis, direction)
                hi = max_degree(axis, direction, fourier)
                if degrees is not None:
                    hi = min(hi, degrees.get(name, hi))
                if hi < lo:
                    continue
                basis = _basis(q[rows, s.column], axis, range(lo, hi + 1), fourier)
                for k in range(lo, hi + 1):
                    add(f"{name}[{k}]", rows, proj[:, j] * basis[:, k - lo])
        if offsets:
            for i, c in enumerate("XYZ"):
                name = "OFFSET_" + c if len(machine.branches) == 1 else f"OFFSET_{c}_{bname}"
                add(name, rows, np.where(ang, 0.0, u[:, i]))
    return Design(matrix, list(params))


def component_polynomial(axis: Axis, coefficients: Mapping[int, float]) -> Polynomial:
    """Legendre coefficients by degree → a :class:`Polynomial` in the normalised position.

    The returned polynomial has ``origin`` at mid-travel and ``scale`` half the travel, so
    its coefficients stay of the size of the error itself (µm or µrad).
    """
    lo, hi = axis.travel
    deg = max(coefficients) if coefficients else 0
    c = np.zeros(deg + 1)
    for k, v in coefficients.items():
        c[k] = v
    mono = legendre.leg2poly(c)
    return Polynomial(tuple(float(x) for x in mono), 0.5 * (lo + hi), 0.5 * (hi - lo))


def component_fourier(coefficients: Mapping[int, float]) -> Fourier:
    """Fourier basis coefficients by index (see :func:`fourier_basis`) → a :class:`Fourier`."""
    order = (max(coefficients) + 1) // 2 if coefficients else 0
    cos = [0.0] * order
    sin = [0.0] * order
    for j, v in coefficients.items():
        k = (j + 1) // 2
        if j % 2:
            cos[k - 1] = float(v)
        else:
            sin[k - 1] = float(v)
    return Fourier(0.0, tuple(cos), tuple(sin))


__all__ = [
    "Design",
    "Param",
    "axis_positions",
    "branch_rows",
    "build_design",
    "component_fourier",
    "component_polynomial",
    "design_params",
    "fourier_axis",
    "fourier_basis",
    "location_names",
    "max_degree",
    "min_degree",
    "uses_fourier",
]
