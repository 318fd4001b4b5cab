"""Siemens CEC tables ("sag compensation, multi-dimensional") that carry a model's errors.

How the control combines the tables (SINUMERIK function manual *Extended Functions*, K3
"Compensations", section 4.4.4 "Sag compensation / interpolatory compensation", system
variables ``$AN_CEC...``; checked against the 03/2013 edition, 6FC5397-1BP40-3BA1):

* table ``t`` adds to its output (compensation) axis ``$AN_CEC_OUTPUT_AXIS[t]`` a value
  interpolated linearly in the position of its input (basic) axis
  ``$AN_CEC_INPUT_AXIS[t]`` between the points ``$AN_CEC[t,N]`` at
  ``$AN_CEC_MIN[t] + N·$AN_CEC_STEP[t]``, up to ``$AN_CEC_MAX[t]``; below MIN the value of
  point 0 holds, above MAX that of the last point, unless ``$AN_CEC_IS_MODULO[t]=1``, when
  the table repeats with period MAX - MIN;
* ``$AN_CEC_DIRECTION[t]``: 0 both traversing directions of the input axis, 1 only the
  positive, -1 only the negative one;
* ``$AN_CEC_MULT_BY_TABLE[t] = n`` (n ≠ 0): the values of table t are multiplied by those
  of the table of *number* n, where table number = table index + 1 (so index n - 1), a
  table of the same compensation axis; "the product is added as an additional compensation
  value to the total compensation value". Table t and table n - 1 are still summed
  themselves: this export keeps every table enabled (SD41300 ``$SN_CEC_TABLE_ENABLE[t]=1``)
  and cancels their own values inside other tables of the same input and output, so the
  file means the same whether or not a reader thinks a factor table is also summed only
  when enabled;
* the total per output axis is the sum over its enabled tables plus the products;
  MD32710 ``$MA_CEC_ENABLE[axis]`` enables that sum, SD41300 each table.

Units: values in mm (degrees onto a rotary axis), positions mm or degrees; a product of
two values is read as mm.

The export (:func:`cec_export`): the model's shares (:mod:`volumetric.compensate.cec_plan`)
become one 1-D table per (input, output) pair, one factor table per (input, arm, output)
product and one two-point arm table per (arm, output), as many as the control allows,
chosen by tool-tip effect: a product needs its factor, its arm and the 1-D tables of its
input and its arm (which cancel their own values). Backlash doubles the axis's own table
into a positive- and a negative-direction table (``$AN_CEC_DIRECTION``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.cec_plan import CecPlan, Fn, Piece, plan_cec
from volumetric.compensate.cec_select import carried_sum, group_shares, select_groups
from volumetric.model.components import GeometricErrors
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
CONTROLS: dict[str, tuple[int, int]] = {"828d": (8, 200), "840d": (62, 2000)}
"""Tables and points per table: an 828D has eight tables of 200 points once the option is
enabled, fixed (K3 4.4.4.3); an 840D sl as many as MD18342 ``$MN_MM_CEC_MAX_POINTS[t]``
reserves, here at most 62 tables of 2,000 points."""
_DENSE = 2001
_STEPS = (0.01, 0.02, 0.025, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 2.5, 5.0, 10.0, 20.0,
          25.0, 50.0, 100.0, 200.0, 250.0, 500.0, 1000.0)


@dataclass(frozen=True)
class CecTable:
    """One CEC table as written.

    Attributes
    ----------
    input, output : str
        Machine axis names of the model (``X``, ``C``).
    start, step : float
        ``$AN_CEC_MIN`` and ``$AN_CEC_STEP``, mm or degrees.
    values : ndarray, shape (n,)
        ``$AN_CEC[t, 0..n-1]``, mm (degrees onto a rotary axis; factor and arm tables:
        see ``role``).
    role : {"table", "factor", "arm"}
    covers : tuple of str
        The errors it carries.
    direction : {0, 1, -1}
    modulo : bool
    mult_by : int or None
        Position (in the export's list) of the arm table a factor is multiplied by.
    interp_um : float
        Largest difference between the table and the function it samples, at the tool tip
        (µm; for a factor, times the longest arm).
    """

    input: str
    output: str
    start: float
    step: float
    values: F64
    role: str
    covers: tuple[str, ...]
    direction: int = 0
    modulo: bool = False
    mult_by: int | None = None
    interp_um: float = 0.0

    @property
    def stop(self) -> float:
        return self.start + self.step * (self.values.size - 1)

    def __call__(self, q: F64) -> F64:
        """The value at input positions by the control's rules (clamped or modulo)."""
        q = np.asarray(q, dtype=float)
        pos = self.start + self.step * np.arange(self.values.size)
        if self.modulo:
            q = self.start + np.mod(q - self.start, self.stop - self.start)
        out: F64 = np.interp(q, pos, self.values)
        return out


@dataclass(frozen=True)
class LeftOut:
    """An error the file does not carry (or carries only in part), with its cost.

    Attributes
    ----------
    error : str
    effect_um : float or None
        Largest tool-tip displacement it causes (or leaves), µm; None where it depends on
        something else (a thermal term's on the temperatures; the reason says how).
    reason : str
    """

    error: str
    effect_um: float | None
    reason: str

    def to_json(self) -> dict[str, object]:
        eff = None if self.effect_um is None else round(self.effect_um, 4)
        return {"error": self.error, "effect_um": eff, "reason": self.reason}


@dataclass(frozen=True)
class CecExport:
    """The tables, in writing order (index = first table number + position), and what
    they leave."""

    tables: tuple[CecTable, ...]
    left_out: tuple[LeftOut, ...]
    control: str
    max_tables: int
    max_points: int
    tool_mm: float
    affine_um: float
    positioning: bool = True
    backlash_um: Mapping[str, float] = field(default_factory=dict)


@dataclass
class _Group:
    key: str
    needs: tuple[str, ...]
    effect_um: float
    label: str


def _round_step(span: float, candidates: tuple[float, ...]) -> list[float]:
    return [s for s in candidates if s <= span + 1e-12]


def _sample(fn_total: Fn, lo: float, hi: float, *, modulo: bool, tol: float,
            max_points: int, weight: float) -> tuple[float, float, F64, float]:
    """Round step, start, values and interpolation error (× weight, µm) of a function
    over [lo, hi]: the largest step of the 1-2-2.5-5 series (dividing 360 for a modulo
    table) whose error stays under ``tol``, within ``max_points``."""
    span = hi - lo
    dense = np.linspace(lo, hi, _DENSE)
    want = fn_total(dense)
    steps = _round_step(span, _STEPS)
    if modulo:
        steps = [s for s in steps if abs(span / s - round(span / s)) < 1e-9]
    best: tuple[float, float, F64, float] | None = None
    for step in sorted(steps, reverse=True):
        n = math.ceil(span / step - 1e-9) + 1
        if n > max_points:
            break
        start = lo if modulo else math.floor(lo / step + 1e-9) * step
        n = math.ceil((hi - start) / step - 1e-9) + 1
        if n > max_points:
            break
        pos: F64 = start + step * np.arange(n, dtype=np.float64)
        vals = _r6(fn_total(pos))  # as the file writes
        err = float(np.abs(np.interp(dense, pos, vals) - want).max()) * weight
        best = (start, step, vals, err)
        if err <= tol:
            return best
    if best is None:  # even two points exceed the table's size: two points at the ends
        vals = _r6(fn_total(np.array([lo, hi])))
        err = float(np.abs(np.interp(dense, [lo, hi], vals) - want).max()) * weight
        return lo, span, vals, err
    return best


def _r6(v: F64) -> F64:
    """Rounded to the 6 decimals the file writes."""
    return np.asarray(np.round(np.asarray(v, dtype=np.float64), 6), dtype=np.float64)


def _const(c: float) -> Fn:
    return lambda q: np.full(np.shape(q), c)


def _arm_cancel(c: float, s: float) -> Fn:
    return lambda q: -(np.asarray(q, dtype=np.float64) - c) / s


def _sum(pieces: list[Piece], extra: Fn | None = None) -> Fn:
    def f(q: F64) -> F64:
        out = np.zeros(np.shape(q))
        for p in pieces:
            out = out + p.fn(np.asarray(q, dtype=float))
        if extra is not None:
            out = out + extra(np.asarray(q, dtype=float))
        return out
    return f


def _scale_of(half: float) -> float:
    """Arm scale S, a power of ten: the arm table holds ``(q - c)/S``, at most 0.5 mm
    here, and the factor ``S·F``. Both are also summed on their own and cancelled in the
    1-D tables of the same input and output; the arm is linear, so its cancellation is
    exact, and a small S keeps the factor's own value (and its interpolation error,
    which enters unmultiplied) small."""
    return float(10.0 ** math.ceil(math.log10(max(half, 1e-9) / 0.5)))


def cec_export(machine: Machine, geometry: GeometricErrors, *, tool_mm: float,
               control: str = "840d", max_tables: int | None = None,
               max_points: int | None = None, tolerance_um: float = 0.5,
               positioning: bool = True, backlash_um: Mapping[str, float] | None = None,
               fold_at: Mapping[str, float] | None = None,
               plan: CecPlan | None = None) -> CecExport:
    """The CEC tables of a model's geometry, within a control's limits.

    Parameters
    ----------
    machine : Machine
    geometry : GeometricErrors
        µm and µrad (periodic terms folded in by the caller).
    tool_mm : float
        Tool length the Abbe arms are taken with, mm.
    control : {"828d", "840d"}
        Gives the default table count and points per table (:data:`CONTROLS`).
    max_tables, max_points : int, optional
        Override the control's.
    tolerance_um : float
        Budget of each table's interpolation error at the tool tip, µm (split over the
        tables of an output axis).
    positioning : bool
        False leaves EXX, ..., ECC to the leadscrew tables (named in ``left_out``).
    backlash_um : mapping of axis name (``X``) to reversal µm, optional
    fold_at : mapping of axis name to position, optional
        Where an arm along that axis is taken for a product that is not written
        (:func:`~volumetric.compensate.cec_plan.plan_cec`).
    """
    tables_cap, points_cap = CONTROLS[control]
    max_tables = tables_cap if max_tables is None else max_tables
    max_points = points_cap if max_points is None else max_points
    backlash = {k.upper(): v for k, v in (backlash_um or {}).items() if v}
    plan = plan or plan_cec(machine, geometry, tool_mm, positioning=positioning,
                           fold_at=fold_at)
    lin = plan.linear
    travel = {a.name: a.travel for a in machine.axes}
    half = {k: 0.5 * (travel[k][1] - travel[k][0]) for k in lin}
    left: list[LeftOut] = [LeftOut(n, e, r) for n, e, r in plan.left]
    if plan.affine_um > tolerance_um:
        turning = [a.name for a in machine.axes if a.kind == "rotary" and a.side == "tool"]
        left.append(LeftOut(
            "Abbe terms whose arm turns" + (f" with {', '.join(turning)}" if turning else ""),
            plan.affine_um,
            "a product holds an arm linear in one axis; the tables carry the best affine "
            "part of these arms, this much is left (5-axis transformation data)"))

    dense = {a.name: np.linspace(a.travel[0], a.travel[1], 513) for a in machine.axes}
    groups: list[_Group] = []
    for (k, d), pieces in plan.one_d.items():
        v = _sum(pieces)(dense[k])
        scale = 1e3 if machine.axis(d).kind == "linear" else _rotary_um(machine, d)
        groups.append(_Group(f"1d:{k}:{d}", (f"1d:{k}:{d}",),
                             float(np.abs(v).max()) * scale, _names(pieces) + f" (input {k}"
                             f", output {d})"))
    scales: dict[tuple[str, str, str], float] = {}
    for (k, m, d), pieces in plan.factors.items():
        fmax = float(np.abs(_sum(pieces)(dense[k])).max())
        scales[(k, m, d)] = _scale_of(half[m])
        groups.append(_Group(f"prod:{k}:{m}:{d}",
                             (f"1d:{k}:{d}", f"1d:{m}:{d}", f"arm:{m}:{d}",
                              f"prod:{k}:{m}:{d}"),
                             fmax * half[m] * 1e3,
                             f"{_names(pieces)} × arm {m.lower()} (output {d})"))
    for k, b in backlash.items():
        if k in lin:
            groups.append(_Group(f"dir:{k}", (f"1d:{k}:{k}", f"dir:{k}"), abs(b) / 2,
                                 f"backlash {k} ({b:g} µm reversal)"))
        else:
            left.append(LeftOut(f"backlash {k}", abs(b) / 2,
                                "a rotary axis's reversal: the control's backlash "
                                "compensation (MD32450 $MA_BACKLASH), not CEC"))
    for d, c in plan.constants.items():
        groups.append(_Group(f"const:{d}", (f"const:{d}",), abs(c) * 1e3,
                             f"constant along {d}"))

    shares, total = group_shares(plan, backlash)
    needs = {g.key: g.needs for g in groups if not g.key.startswith("const:")}
    chosen = select_groups(needs, shares, total, max_tables)
    for g in groups:
        if g.key.startswith("const:") or set(g.needs) <= chosen:
            continue
        left.append(LeftOut(g.label, g.effect_um,
                            f"over the {max_tables} tables of the {control}: the tables "
                            "chosen lower the tool-tip error more per table"))
    for g in groups:
        if g.key.startswith("const:"):
            d = g.key.split(":")[1]
            if not any(n.startswith("1d:") and n.endswith(f":{d}") for n in chosen):
                left.append(LeftOut(g.label, g.effect_um, "no table onto this axis"))
    # what is not carried is centred somewhere over the workspace; a constant rides free
    # on any table onto the axis, so the file carries the centre of its range too
    rest = total - carried_sum(chosen, shares, total)
    mid = 0.5 * (rest.max(axis=0) + rest.min(axis=0))
    means = {d: float(mid[i]) for i, d in enumerate(plan.linear) if abs(mid[i]) * 1e3 > 1e-3}
    if fold_at:  # the user asked for the tables to be exact at a working height instead
        means = {}
    return _build(machine, plan, chosen, scales, backlash, control, max_tables, max_points,
                  tolerance_um, positioning, left, means)


def _rotary_um(machine: Machine, axis: str) -> float:
    """µm at the tool tip per degree of a rotary axis: its reach over the linear travels."""
    reach = math.sqrt(sum((a.travel[1] - a.travel[0]) ** 2 for a in machine.axes
                          if a.kind == "linear"))
    return reach * 1e3 * math.pi / 180.0


def _names(pieces: list[Piece]) -> str:
    seen: list[str] = []
    for p in pieces:
        if p.error not in seen:
            seen.append(p.error)
    return "+".join(seen)


def _build(machine: Machine, plan: CecPlan, chosen: set[str],
           scales: dict[tuple[str, str, str], float], backlash: Mapping[str, float],
           control: str, max_tables: int, max_points: int, tolerance_um: float,
           positioning: bool, left: list[LeftOut],
           means: Mapping[str, float] | None = None) -> CecExport:
    travel = {a.name: a.travel for a in machine.axes}
    centre = plan.centre
    one_d = {(k, d): list(p) for (k, d), p in plan.one_d.items()}
    # every table onto output d shares the tolerance
    per_output: dict[str, int] = {}
    for n in chosen:
        parts = n.split(":")
        per_output[parts[-1]] = per_output.get(parts[-1], 0) + 1
    # cancellations: a factor's own value S·F in its input's table, an arm's own value
    # (q - c)/S in its arm's table
    arms: dict[tuple[str, str], float] = {}
    for n in sorted(chosen):
        if not n.startswith("prod:"):
            continue
        _, k, m, d = n.split(":")
        s = scales[(k, m, d)]
        pieces = plan.factors[(k, m, d)]
        one_d.setdefault((k, d), []).append(
            Piece(f"(cancels factor {k}×{m})", _neg_scaled(_sum(pieces), s)))
        arms.setdefault((m, d), s)
    for (m, d), s in arms.items():
        c = centre[m]
        one_d.setdefault((m, d), []).append(
            Piece(f"(cancels arm {m})", _arm_cancel(c, s)))
    constants = dict(plan.constants)
    for d, c in (means or {}).items():
        constants[d] = constants.get(d, 0.0) + c
    for d, c in constants.items():
        target = next((kd for kd in sorted(one_d) if kd[1] == d and f"1d:{kd[0]}:{d}" in chosen),
                      None)
        if target is not None:
            one_d[target].append(Piece(f"(constant {d})", _const(c)))
    tables: list[CecTable] = []
    index: dict[tuple[str, str], int] = {}
    for key in sorted(k for k in chosen if k.startswith("1d:")):
        _, k, d = key.split(":")
        pieces = one_d.get((k, d), [])
        ax = machine.axis(k)
        rotary_out = machine.axis(d).kind == "rotary"
        weight = _rotary_um(machine, d) if rotary_out else 1e3
        modulo = ax.kind == "rotary" and ax.travel[1] - ax.travel[0] >= 360.0 - 1e-9
        tol = tolerance_um / max(per_output.get(d, 1), 1)
        lo, hi = travel[k]
        if modulo:
            hi = lo + 360.0
        covers = tuple(dict.fromkeys(p.error for p in pieces if not p.error.startswith("(")))
        dirs = [(1, backlash[k] / 2e3), (-1, -backlash[k] / 2e3)] if (
            f"dir:{k}" in chosen and k == d) else [(0, 0.0)]
        for direction, shift in dirs:
            f = _sum(pieces, _const(shift) if shift else None)
            start, step, vals, err = _sample(f, lo, hi, modulo=modulo, tol=tol,
                                             max_points=max_points, weight=weight)
            extra = (f"backlash {k}",) if direction else ()
            tables.append(CecTable(k, d, start, step, vals, "table", covers + extra,
                                   direction, modulo, None, err))
            if err > tol:
                left.append(LeftOut(f"{'+'.join(covers) or 'table'} (input {k}, output {d})",
                                    err, f"{vals.size} points at step {step:g} leave this "
                                         "much between the points"))
        index[(k, d)] = len(tables) - 1
    arm_index: dict[tuple[str, str], int] = {}
    for (m, d), s in sorted(arms.items()):
        lo, hi = travel[m]
        c = centre[m]
        vals = _r6(np.array([(lo - c) / s, (hi - c) / s]))
        arm_index[(m, d)] = len(tables)
        tables.append(CecTable(m, d, lo, hi - lo, vals, "arm", (f"arm {m} / {s:g}",)))
    for key in sorted(k for k in chosen if k.startswith("prod:")):
        _, k, m, d = key.split(":")
        s = scales[(k, m, d)]
        pieces = plan.factors[(k, m, d)]
        lo, hi = travel[k]
        longest = max(abs(travel[m][0] - centre[m]), abs(travel[m][1] - centre[m])) / s
        tol = tolerance_um / max(per_output.get(d, 1), 1)
        start, step, vals, err = _sample(_pos_scaled(_sum(pieces), s), lo, hi, modulo=False,
                                         tol=tol, max_points=max_points,
                                         weight=1e3 * (1.0 + longest))
        tables.append(CecTable(k, d, start, step, vals, "factor",
                               tuple(p.error for p in pieces), 0, False,
                               arm_index[(m, d)], err))
        if err > tol:
            left.append(LeftOut(f"{_names(pieces)} × arm {m.lower()}", err,
                                f"{vals.size} points at step {step:g} leave this much"))
    return CecExport(tuple(tables), tuple(left), control, max_tables, max_points,
                     plan.tool_mm, plan.affine_um, positioning, dict(backlash))


def _neg_scaled(f: Fn, s: float) -> Fn:
    return lambda q: -s * f(q)


def _pos_scaled(f: Fn, s: float) -> Fn:
    return lambda q: s * f(q)


def apply_tables(export: CecExport, machine: Machine, q: F64,
                 direction: F64 | None = None) -> F64:
    """Corrections (N, n_axes), mm or degrees, the control adds by the rules of the module
    docstring: every table summed onto its output, plus each factor times its arm.

    ``direction`` (N, n_axes) holds each axis's traversing direction (+1 or -1); without
    it, direction-dependent tables count as the positive direction.
    """
    col = {a.name: i for i, a in enumerate(machine.axes)}
    dq = np.zeros_like(q, dtype=float)
    vals = [t(q[:, col[t.input]]) for t in export.tables]
    for i, t in enumerate(export.tables):
        v = vals[i]
        if t.direction:
            d = direction[:, col[t.input]] if direction is not None else np.ones(q.shape[0])
            v = np.where(d == t.direction, v, 0.0)
        dq[:, col[t.output]] += v
        if t.mult_by is not None:
            dq[:, col[t.output]] += v * vals[t.mult_by]
    return dq


__all__ = ["CONTROLS", "CecExport", "CecTable", "LeftOut", "apply_tables", "cec_export"]
