"""The ``factored`` map kind: sums of products of 1-D tables, for endpoints that can only
look tables up, multiply and add in fixed point (a Fanuc PMC ladder has no trigonometry).

What the machine evaluates. A map has *fields* ``F_f(q)``: the correction of every axis
(fields ``0 .. K-1``, machine axis order, mm or degrees) and, for a machine with rotary
axes, the *sensitivities* ``S_lr`` (one field per linear axis ``l`` and rotary axis ``r``,
mm per degree): how much linear axis ``l`` must move so that the tool tip stays where it
is when rotary axis ``r`` moves by one degree. Each field is a sum of terms, each term one
1-D table of one axis times a product of up to four *basis* tables (each a 1-D table of one
axis, shared by all terms)::

    F_f(q) = Σ_{t: field t = f} T_t(q_{axis t}) · Π_{b ∈ factors t} B_b(q_{axis b})

Every table is linearly interpolated on a uniform grid of its axis (held at the ends),
its nodes a power of two counts apart, and its values are int16 times a power of two
(:mod:`volumetric.compensate.factoredtables`). So the ladder's loop is shifts, lookups,
multiplies and adds in integers; no trigonometry: the trigonometric shapes the chain needs
come as basis tables (``cos θ``, ``sin θ``, ``cos 2θ``, ``sin 2θ`` of each rotary axis on
8.192° nodes, :data:`~volumetric.compensate.factoredfit.BASIS_STEP_DEG`) and the linear
positions as two-node basis tables (an affine function is interpolated exactly).

Why this structure. To first order in the errors, the weighted compensation of a chain
with orthogonal nominal axes is: per rotary axis a function of that axis times trigonometric
functions of the other rotary axes times an affine function of the linear positions (the
rotary axes' errors and location errors, seen from the workpiece); per linear axis a
function of that axis (its component errors) times trigonometric functions (up to the
second harmonic: a rotary correction's lever arm turns with the same rotation that makes
the correction) times an affine function of the other linear positions (an angular error's
lever). The builder offers every such term and fits them by linear least squares over
random samples of the exact corrections (:mod:`volumetric.compensate.solver`; the unknowns
are the term tables' values, the basis tables are fixed), choosing them one table at a
time (:func:`volumetric.compensate.factoredfit.select`): of the ~265 candidates per field of a
5-axis machine a few dozen carry the corrections. The table spacing starts at 32.768 mm
on a linear axis and 8.192° on a rotary axis (at 0.001 mm and 0.001°), and it halves and
the selection's budget shrinks while the check below finds the tolerance missed.

Quantisation-aware corrections (issue 11, item 2). The controller rounds every correction
to whole increments (0.001 mm, 0.001°). Rounding a rotary correction by up to half an
increment moves the tool tip by 0.0005° × the lever (up to ~5 µm at 500 mm); so the
endpoint rounds the rotary corrections first, each down or up, and lets the linear axes
absorb what that leaves: ``lin_l += Σ_r S_lr · (rounded_r - F_r)``, then rounds the linear
ones. Of the 2^R down/up choices it keeps the one whose linear rounding residual is
smallest (sum of squares: with orthogonal linear axes that is the tool tip's displacement).
The error as sent then approaches the linear rounding (at most √3/2 increment), not
0.0005° × the lever. :meth:`FactoredMap.applied` is the center's reference of that rule
in the endpoint's integer arithmetic; the machine has its own (:mod:`machine_sim.ladder`),
pinned to this one by tests, and every as-sent figure is computed with it.

Thermal terms (``thermal_in_map``) travel as with grid maps of format version 3: the map is
built at their reference temperatures and the endpoint adds ``-ΔE`` of each (constant plus
slope times the axis position) to its axis's correction before rounding.

Units: positions mm or degrees; correction fields mm or degrees; sensitivity fields mm per
degree; tool-tip errors µm.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.factoredfit import Layout, layout, select, shift_for
from volumetric.compensate.factoredtables import (
    MAX_FACTORS,
    AxisGrid,
    FactoredMap,
    Table1D,
    Term,
    counts_per_unit,
    fixed_point,
    payload_bytes,
)
from volumetric.compensate.maps import (
    DEFAULT_INCREMENT,
    DEFAULT_LIMIT_DEG,
    DEFAULT_LIMIT_MM,
    MAX_MAP_BYTES,
    Controller,
    MapBuildError,
    MapProblem,
    MapReport,
    MapTooLargeError,
    check_parameters,
    geometry_of,
    reversal_of,
)
from volumetric.compensate.solver import Weights
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
BUDGET_SHARE = 0.2
"""Terms are added to a field until its worst error on the fit samples is at most this
share of the tolerance asked at the tool tip (halved in every further round), or until
more tables stop paying. The linear axes' own rounding is up to 0.87 increment and
dominates what is sent: at 0.1 the tables chased 0.1 µm for an as-sent figure of 0.72 µm
(5-axis, 17.4 kB in format version 4); at 0.2 ten 5-axis maps came out at 0.70-0.86 µm
as sent, 5.1-7.6 kB (4.2-6.3 kB with 8.192° basis tables); at 0.3 one in ten missed
1.0 µm (1.04) after its round."""
MIN_BUDGET_UM = 0.01
"""The smallest per-field budget, µm: below it tables only chase the fit's noise."""
_MAX_ROUNDS = 5


def sensitivities(prob: MapProblem, q: F64) -> F64:
    """Linear-axis motion (mm) that keeps the tool tips where they are per degree of each
    rotary axis: ``-pinv(J_lin) J_rot`` of the stacked position rows of every tool tip,
    (N, L·R), linear axis slowest."""
    m = prob.machine
    lin = [i for i, a in enumerate(m.axes) if a.kind != "rotary"]
    rot = [i for i, a in enumerate(m.axes) if a.kind == "rotary"]
    if not lin or not rot:
        return np.zeros((q.shape[0], 0))
    blocks = []
    for br in m.branches:
        tool = None if prob.tool_mm is None else prob.tool_mm.get(br.name)
        blocks.append(jacobian(m, q, spindle=br.name, tool_mm=tool)[:, :3])
    j = np.concatenate(blocks, axis=1)  # (N, 3B, n_axes)
    s = -np.linalg.pinv(j[:, :, lin]) @ j[:, :, rot]  # (N, L, R)
    out: F64 = s.reshape(q.shape[0], -1)
    return out


def build_factored_map(
    machine: Machine,
    model: MachineModel,
    temperatures: Mapping[str, float] | None = None,
    *,
    tolerance_um: float = 1.0,
    controller: Controller | None = None,
    increment: float = DEFAULT_INCREMENT,
    limit_mm: float = DEFAULT_LIMIT_MM,
    limit_deg: float = DEFAULT_LIMIT_DEG,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    version: int = 1,
    valid_s: int = 0,
    check_points: int = 8192,
    seed: int = 0,
    max_bytes: int = MAX_MAP_BYTES,
    thermal_in_map: bool = True,
    over_tolerance_ok: bool = False,
) -> FactoredMap:
    """The factored map of a machine (module docstring).

    Parameters
    ----------
    machine, model, temperatures
        As for :func:`volumetric.compensate.gridmap.build_map`.
    tolerance_um : float
        Largest tool-tip error *as sent* (rounded by the endpoint's rule) allowed on the
        independent check, µm. A tolerance below what whole increments can carry
        (:func:`as_sent_floor_um`: the linear axes' own rounding plus 0.1 µm) is raised to
        it, and the report says so in its ``tolerance_um``: a grid's tolerance is its
        interpolation before rounding, so the center may ask 0.5 µm of every kind.
    controller : {"fanuc"}, optional
        Factored maps are for endpoints that round to ``increment``.
    increment : float
        mm (degrees) per count.
    limit_mm, limit_deg, weights, tool_mm, version, valid_s, seed, max_bytes
        As for :func:`~volumetric.compensate.gridmap.build_map`.
    check_points : int
        Size of the independent random check set over the whole travel.
    thermal_in_map : bool
        Carry the model's thermal terms for the endpoint to apply.
    over_tolerance_ok : bool
        Return the map of the last refinement even when it misses the tolerance (its
        report says by how much); the caller decides (``ednc map
        --allow-over-tolerance``).

    Raises
    ------
    MapBuildError
        Bad parameters, a non-Fanuc controller, or the tolerance missed after the last
        refinement unless ``over_tolerance_ok`` (:class:`MapTooLargeError` when the map
        would outgrow ``max_bytes``).
    """
    t0 = time.perf_counter()
    ctrl = check_parameters(machine, model, tolerance_um, controller, increment, limit_mm,
                            limit_deg, check_points)
    if ctrl != "fanuc":
        raise MapBuildError("factored maps are for endpoints that round to whole "
                            "increments (Fanuc); this machine's controller is " + ctrl)
    n_lin = sum(a.kind != "rotary" for a in machine.axes)
    # the tables aim at the tolerance asked (a tenth of it per field), the check at what
    # whole increments can carry: a map asked for 0.1 µm is then the increment's rounding
    # and little else, as a grid built to 0.1 µm is
    budget_um = max(BUDGET_SHARE * tolerance_um, MIN_BUDGET_UM)
    tolerance_um = max(tolerance_um, as_sent_floor_um(n_lin, increment))
    names = machine.axis_names
    thermal = tuple(t for t in model.terms if isinstance(t, ThermalTerm)) if thermal_in_map \
        else ()
    static, temps = model, dict(temperatures or {})
    if thermal:
        for th in thermal:
            if th.axis.upper() not in names:
                raise MapBuildError(f"thermal term on axis {th.axis}: machine "
                                    f"{machine.name!r} has {' '.join(names)}")
        static = MachineModel(model.machine, model.geometry,
                              tuple(t for t in model.terms if not isinstance(t, ThermalTerm)),
                              model.info)
        temps = {t.sensor: t.t_ref_C for t in thermal} | temps
    geometry = geometry_of(static, temps)
    geometry.check(machine)
    w = Weights.default(machine) if weights is None else weights
    prob = MapProblem(machine, geometry, w, tool_mm, machine.travel_lo, machine.travel_hi)
    full = prob if not thermal else MapProblem(machine, geometry_of(model, temps), w,
                                               tool_mm, prob.lo, prob.hi)
    k = len(names)
    rotary = tuple(a.kind == "rotary" for a in machine.axes)
    n_rot = sum(rotary)
    backlash = np.array([model.reversal_um().get(a.key, 0.0) * 1e-3 for a in machine.axes])
    limits = np.array([limit_deg if r else limit_mm for r in rotary])

    rng = np.random.default_rng(seed)
    span = prob.hi - prob.lo
    n_fit = 8192 if n_rot else 4096
    q_fit = _fit_points(prob.lo, span, rng, n_fit)
    targets = np.hstack([prob.exact(q_fit) + 0.5 * backlash, sensitivities(prob, q_fit)])
    check_rng = np.random.default_rng([seed, 1])
    q_dec = prob.lo + span * rng.random((check_points // 2, k))
    exact_dec = full.exact(q_dec)
    q_chk = prob.lo + span * check_rng.random((check_points, k))
    exact_chk = full.exact(q_chk)
    lever_mm = _lever_mm(machine)
    # µm at the tool tip per unit of each field: 1e3 per mm; a degree of rotation over
    # the longest lever; a sensitivity times the largest rotary residual (1 increment)
    tip_scale = np.array([lever_mm * math.pi / 180 * 1e3 if r else 1e3 for r in rotary]
                         + [increment * 1e3] * (targets.shape[1] - k))

    per_unit = counts_per_unit(increment)
    # node spacing a power of two counts (the endpoint's index is a shift): about 40 mm
    # (at least 4 intervals over the travel) and 7.5° to start, halved in every further
    # round down to about 2° on a rotary axis
    shifts = [shift_for(7.5 * per_unit) if r else
              shift_for(float(s) / max(4, min(32, math.ceil(float(s) / 40.0))) * per_unit)
              for r, s in zip(rotary, span, strict=True)]
    min_rot_shift = shift_for(2.0 * per_unit)
    q_fit_c = q_fit * per_unit
    harmonics = 2
    rounds = 0
    last = math.inf
    while True:
        rounds += 1
        lay = layout(machine, per_unit, shifts, harmonics)
        a = lay.design(q_fit_c)
        kept = select(lay, a, targets, tip_scale, budget_um)
        fm = _assemble(machine, version, lay, kept, increment, limits, backlash, model,
                       temps, valid_s, thermal)
        if fm.nbytes > max_bytes:
            raise MapTooLargeError(f"machine {machine.name!r}: a factored map of "
                                   f"{fm.nbytes} bytes is over the {max_bytes}-byte limit")
        worst_dec = _sent_error(full, fm, q_dec, exact_dec, backlash, temps)
        if worst_dec <= tolerance_um or rounds >= _MAX_ROUNDS or \
                (worst_dec >= last and rounds % 2 == 1):
            break
        last = worst_dec
        # a miss: first the same spacing with a tighter budget (more terms, few bytes);
        # then halve the spacing (about twice the values)
        if rounds % 2 == 0:
            shifts = [max(min_rot_shift, k - 1) if r else max(0, k - 1)
                      for r, k in zip(rotary, shifts, strict=True)]
            # about twice the unknowns: twice the fit samples, or the finer tables
            # overfit between them (a 5-axis map went 0.57 -> 1.07 µm unrounded with
            # the same 8,192)
            more = _fit_points(prob.lo, span, rng, q_fit.shape[0])
            q_fit = np.vstack([q_fit, more])
            targets = np.vstack([targets, np.hstack([prob.exact(more) + 0.5 * backlash,
                                                     sensitivities(prob, more)])])
            q_fit_c = q_fit * per_unit
        else:
            budget_um /= 2
            # the decision set found what the fit samples did not show: fit it too, and
            # decide the next round on a fresh one (the final check stays unseen)
            q_fit = np.vstack([q_fit, q_dec])
            targets = np.vstack([targets, np.hstack([
                prob.exact(q_dec) + 0.5 * backlash, sensitivities(prob, q_dec)])])
            q_fit_c = q_fit * per_unit
            q_dec = prob.lo + span * rng.random((check_points // 2, k))
            exact_dec = full.exact(q_dec)
            last = math.inf
    worst_sent = _sent_error(full, fm, q_chk, exact_chk, backlash, temps)
    approx = fm.corrections(q_chk, temps) - 0.5 * backlash - exact_chk
    worst_interp = float(full.tip_um(q_chk, approx).max())
    if worst_sent > tolerance_um and not over_tolerance_ok:
        raise MapBuildError(f"machine {machine.name!r}: the factored map reaches "
                            f"{worst_sent:.3f} µm as sent, over {tolerance_um} µm (linear "
                            f"rounding alone is up to {0.87 * increment * 1e3:.2f} µm)")
    report = MapReport(
        nodes=fm.entries, bytes=fm.nbytes, tolerance_um=tolerance_um,
        worst_interpolation_um=worst_interp, worst_error_um=worst_sent,
        check_points=check_points, clamped_nodes=0, rounds=rounds,
        build_s=time.perf_counter() - t0, kind="factored",
    )
    return dataclasses.replace(fm, report=report)


EDGE_SHARE = 0.25
"""Of the fit samples, this share has each coordinate at an end of its travel with
probability 1/3 (the rest uniform): the errors' curvature and the products of several
axes' shapes are largest at the ends, where uniform samples are thin in five dimensions
(a 5-axis map missed 1 µm at A's end of travel with uniform samples alone)."""


def _fit_points(lo: F64, span: F64, rng: np.random.Generator, n: int) -> F64:
    """``n`` fit positions (n, K): uniform over the travel, :data:`EDGE_SHARE` of them
    pushed to the ends coordinate by coordinate."""
    q: F64 = lo + span * rng.random((n, lo.size))
    m = int(EDGE_SHARE * n)
    pick = rng.random((m, lo.size))
    q[:m] = np.where(pick < 1 / 6, lo, np.where(pick < 1 / 3, lo + span, q[:m]))
    return q


def as_sent_floor_um(linear_axes: int, increment: float) -> float:
    """The smallest as-sent tolerance a factored map is built for, µm: half an increment on
    each of ``linear_axes`` orthogonal axes (``√L/2`` increments, what rounding alone can
    leave, 0.87 µm at 0.001 mm on three axes) plus 0.1 µm for the tables themselves."""
    return 0.5 * math.sqrt(max(linear_axes, 1)) * increment * 1e3 + 0.1


def _lever_mm(machine: Machine) -> float:
    """The longest lever a rotary correction can have: workspace diagonal plus tool and
    pivot offsets, mm."""
    diag = float(np.linalg.norm([a.travel[1] - a.travel[0] for a in machine.axes
                                 if a.kind != "rotary"]))
    pivots = [float(np.linalg.norm(a.pivot_mm)) for a in machine.axes if a.kind == "rotary"]
    tools = [float(br.tool_length_mm) for br in machine.branches]
    return diag + max(pivots, default=0.0) + max(tools, default=0.0)


def _assemble(machine: Machine, version: int, lay: Layout, kept: list[tuple[int, int, F64]],
              increment: float, limits: F64, backlash: F64, model: MachineModel,
              temps: Mapping[str, float], valid_s: int,
              thermal: tuple[ThermalTerm, ...]) -> FactoredMap:
    # only the basis tables some kept term uses travel; renumber them
    used = sorted({b for _, c, _v in kept for b in lay.candidates[c][1]})
    renum = {b: i for i, b in enumerate(used)}
    k = len(machine.axes)
    per_unit = counts_per_unit(increment)
    terms = []
    for f, c, values in kept:
        axis, factors, _ = lay.candidates[c]
        g = lay.grids[axis]
        # corrections were fitted in mm (degrees): the tables hold counts; a sensitivity
        # (mm per degree) is counts per count at equal increments
        v, e = fixed_point(values * per_unit if f < k else values)
        terms.append(Term(f, Table1D(axis, g.start, g.shift, v, e),
                          tuple(renum[b] for b in factors)))
    lim = tuple(max(1, round(float(v) * per_unit)) / per_unit for v in limits)
    return FactoredMap(
        machine=machine.name, version=version, controller="fanuc",
        axes=machine.axis_names, rotary=tuple(a.kind == "rotary" for a in machine.axes),
        increment=increment, limits=lim,
        reversal=reversal_of(machine, model, increment), grids=tuple(lay.grids),
        bases=tuple(lay.bases[b] for b in used), terms=tuple(terms),
        temperatures=dict(temps), valid_s=valid_s, thermal=thermal,
    )


def _sent_error(full: MapProblem, fm: FactoredMap, q: F64, exact: F64, backlash: F64,
                temps: Mapping[str, float]) -> float:
    """Worst tool-tip error (µm) of the map as the endpoint applies it, against the exact
    model (with its thermal terms at ``temps``); the positive-approach shift of a lagging
    axis is not an error."""
    applied = fm.applied(q, temps)
    return float(full.tip_um(q, applied - 0.5 * backlash - exact).max())


__all__ = [
    "MAX_FACTORS",
    "AxisGrid",
    "FactoredMap",
    "Table1D",
    "Term",
    "as_sent_floor_um",
    "build_factored_map",
    "fixed_point",
    "payload_bytes",
    "sensitivities",
]
