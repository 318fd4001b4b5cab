"""What a model's errors ask of Siemens CEC tables: 1-D shares and first-order products.

A CEC table adds a function of one axis (its input) to one axis (its output), and a table
multiplied by another (``$AN_CEC_MULT_BY_TABLE``) adds the product of two such functions
(SINUMERIK function manual K3, section 4.4.4; see :mod:`volumetric.compensate.cec`). This
module splits the linear axes' corrections of a model into exactly those shapes.

To first order the tool-tip error is ``e_tip(q) = Σ_c P_c(q) e_c(q_K)``, summed over the
errors ``c`` (a component error of axis K, or a constant location error), with ``P_c`` the
model's own first-order sensitivity (:func:`volumetric.model.linear.sensitivities`). The
linear axes cancel it with ``dq = -J⁺ e_tip``, ``J`` the nominal Jacobian of the linear
axes (:func:`volumetric.model.linear.jacobian`; ``dq = -e_tip`` on a 3-axis machine). So
each error asks for ``e_c(q_K) S_c(q)`` with ``S_c = -J⁺ P_c`` (mm per µm or per µrad).

For an error of a linear axis ``S_c`` is affine in the linear axes' positions: a
displacement error moves the tool by itself, an angular one by the angle times the Abbe
arm, the tool tip seen from the carriage, which moves with the other axes and holds the
tool length. ``S_c = s_0 + Σ_m s_m q_m`` is fitted per output axis d on sample points and
gives three shapes:

* ``e_c(q_K) (s_0 + s_K q_K)``: a function of K alone, a 1-D table input K, output d;
* ``e_c(q_K) s_m q_m`` for another axis m: a *product*, a factor table input K times an
  arm table input m, both output d;
* a location error (constant ``e``): ``e s_m q_m`` per axis m, 1-D tables again.

The fit is checked, not assumed: :func:`plan_cec` reports how far the shapes are from the
model's own first-order correction (``affine_um``), which is zero to rounding on machines
whose linear axes carry no rotary axis on the tool side, and what remains where the arm
turns with a head. Rotary axes: the angular positioning error of a rotary axis (``ECC``
on C) is a 1-D table of that axis onto itself (degrees); every other rotary error moves the
tool through the rotation and belongs in the 5-axis transformation data; it is named with
its tool-tip effect.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from volumetric.model.components import Component, GeometricErrors, component_names
from volumetric.model.linear import jacobian, sensitivities
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
Fn = Callable[[F64], F64]
DEG_PER_URAD = 180.0 / np.pi * 1e-6
_NEGLIGIBLE_UM = 1e-4  # a share moving the tool by less than this is not written


@dataclass(frozen=True)
class Piece:
    """One error's share of a CEC function.

    Attributes
    ----------
    error : str
        The ISO 230-1 name it carries (``EBY``, ``EC0Y``, ``backlash X``).
    fn : callable
        Values at input positions (N,) → (N,): mm (or degrees for a rotary output) for a
        1-D share, mm per mm of arm for a factor.
    """

    error: str
    fn: Fn


@dataclass
class CecPlan:
    """The shares of a model's corrections, keyed by the table shape they need.

    Attributes
    ----------
    one_d : dict of (input, output) to list of Piece
        1-D shares, mm (degrees onto a rotary axis).
    factors : dict of (input K, arm m, output d) to list of Piece
        Factors of products: the correction is ``Σ fn(q_K) · (q_m - centre_m)``, mm per mm
        (the arm's centre is moved into the 1-D shares).
    constants : dict of output to float
        Constant corrections, mm.
    left : list of (name, tool-tip effect µm, reason)
        Errors CEC cannot carry.
    affine_um : float
        Largest tool-tip distance between the shapes (exact functions, no sampling) and
        the model's first-order correction, µm, over the check points.
    """

    machine: Machine
    geometry: GeometricErrors
    tool_mm: float
    linear: tuple[str, ...]
    centre: dict[str, float]
    one_d: dict[tuple[str, str], list[Piece]] = field(default_factory=dict)
    factors: dict[tuple[str, str, str], list[Piece]] = field(default_factory=dict)
    constants: dict[str, float] = field(default_factory=dict)
    left: list[tuple[str, float, str]] = field(default_factory=list)
    affine_um: float = 0.0


def sample_points(machine: Machine, n: int, seed: int = 0) -> F64:
    """Uniform random commanded positions over the travel, shape (n, n_axes)."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in machine.axes])


def linear_axes(machine: Machine) -> tuple[str, ...]:
    return tuple(a.name for a in machine.axes if a.kind == "linear")


def correction_sensitivity(machine: Machine, q: F64, tool_mm: float
                           ) -> tuple[dict[str, tuple[F64, F64]], F64]:
    """Per error name: (``S`` (N, n_linear) mm per unit, ``P`` (N, 3) µm per unit); and
    ``G = J⁺`` (N, n_linear, 3) mm per µm (see module docstring)."""
    cols = [i for i, a in enumerate(machine.axes) if a.kind == "linear"]
    jac = jacobian(machine, q, tool_mm=tool_mm)[:, :3, :][:, :, cols]
    g: F64 = np.asarray(np.linalg.pinv(jac), dtype=np.float64)
    out: dict[str, tuple[F64, F64]] = {}
    for s in sensitivities(machine, q, tool_mm=tool_mm):
        p = s.matrix[:, :3, :]
        corr = -np.einsum("nij,njk->nik", g, p)
        for j, name in enumerate(s.names):
            out[name] = (corr[:, :, j], p[:, :, j])
    return out, g


def _times(f: Component, a: float, b: float) -> Fn:
    """``q ↦ f(q)·(a + b q)`` (µm or µrad times mm per unit → mm)."""
    return lambda q: np.asarray(f(q), dtype=float) * (a + b * q)


def _scaled(f: Component, k: float) -> Fn:
    return lambda q: np.asarray(f(q), dtype=float) * k


def _linear(k: float) -> Fn:
    return lambda q: k * np.asarray(q, dtype=float)


def plan_cec(machine: Machine, geometry: GeometricErrors, tool_mm: float, *,
             positioning: bool = True, fold_at: Mapping[str, float] | None = None,
             n_fit: int = 600, seed: int = 0) -> CecPlan:
    """The shares of :class:`CecPlan` for a model's geometry.

    Parameters
    ----------
    machine : Machine
        Single tool tip (the first branch is used).
    geometry : GeometricErrors
        µm and µrad, as the model holds them (terms folded in by the caller).
    tool_mm : float
        Tool length the Abbe arms are taken with, mm.
    positioning : bool
        False leaves the positioning errors of each axis (EXX, ..., ECC) to the
        leadscrew (LEC) tables: they are named in ``left`` instead.
    fold_at : mapping of axis name to position, optional
        Where an Abbe arm along that axis is taken when its product is not written (the
        working height for Z, ``--work-z``): the product's share at that position is in
        the 1-D table of its factor's axis. Default: the middle of the axis's travel.
    n_fit : int
        Random points the affine shapes are fitted on (a second set checks them).
    """
    lin = linear_axes(machine)
    q = sample_points(machine, n_fit, seed)
    sens, _ = correction_sensitivity(machine, q, tool_mm)
    col = {a.name: i for i, a in enumerate(machine.axes)}
    lin_cols = [col[k] for k in lin]
    design = np.column_stack([np.ones(q.shape[0]), q[:, lin_cols]])
    half = {k: 0.5 * (machine.axis(k).travel[1] - machine.axis(k).travel[0]) for k in lin}
    centre = {k: 0.5 * (machine.axis(k).travel[0] + machine.axis(k).travel[1]) for k in lin}
    centre.update({k.upper(): float(v) for k, v in (fold_at or {}).items()
                   if k.upper() in centre})
    plan = CecPlan(machine, geometry, tool_mm, lin, centre)
    coefs: dict[str, F64] = {}

    def add(key: tuple[str, str], piece: Piece) -> None:
        plan.one_d.setdefault(key, []).append(piece)

    for axis in machine.axes:
        for name in component_names(axis):
            f = geometry.components.get(name)
            if f is None or name not in sens:
                continue
            s_corr, p = sens[name]
            lo, hi = axis.travel
            qk = np.linspace(lo, hi, 257)
            size = float(np.abs(f(qk)).max())
            if size == 0.0:
                continue
            own = name[1] == axis.name or (axis.kind == "rotary" and name[1] == axis.name)
            if own and not positioning:
                plan.left.append((name, _effect(p, f(q[:, col[axis.name]])),
                                  "left to the leadscrew (LEC) tables (--lec)"))
                continue
            if axis.kind == "rotary":
                if own:  # the rotary axis turns back by its own angular error
                    add((axis.name, axis.name), Piece(name, _scaled(f, -DEG_PER_URAD)))
                else:
                    plan.left.append((name, _effect(p, f(q[:, col[axis.name]])),
                                      "moves the tool through the rotation: 5-axis "
                                      "transformation data, not a CEC table"))
                continue
            coef = _fit(design, s_corr)
            coefs[name] = coef
            kk = lin.index(axis.name)
            for d_i, d in enumerate(lin):
                s0, sk = float(coef[0, d_i]), float(coef[1 + kk, d_i])
                if size * (abs(s0) + abs(sk) * _reach(axis.travel)) * 1e3 > _NEGLIGIBLE_UM:
                    add((axis.name, d), Piece(name, _times(f, s0, sk)))
                for m_i, m in enumerate(lin):
                    sm = float(coef[1 + m_i, d_i])
                    if m == axis.name or size * abs(sm) * half[m] * 1e3 <= _NEGLIGIBLE_UM:
                        continue
                    plan.factors.setdefault((axis.name, m, d), []).append(
                        Piece(name, _scaled(f, sm)))
                    # the factor multiplies (q_m - centre): the centre's share is 1-D
                    add((axis.name, d), Piece(name, _scaled(f, sm * centre[m])))
    for name, value in sorted(geometry.locations.items()):
        if value == 0.0 or name not in sens:
            continue
        s_corr, p = sens[name]
        axis = machine.axis(name[3:])
        if axis.kind == "rotary":
            plan.left.append((name, _effect(p, np.full(q.shape[0], value)),
                              "location of a rotary axis: 5-axis transformation data "
                              "(kinematic chain, measured e.g. with CYCLE996)"))
            continue
        coef = _fit(design, s_corr)
        coefs[name] = coef
        for d_i, d in enumerate(lin):
            if abs(coef[0, d_i] * value) * 1e3 > _NEGLIGIBLE_UM:
                plan.constants[d] = plan.constants.get(d, 0.0) + float(coef[0, d_i] * value)
            for m_i, m in enumerate(lin):
                sm = float(coef[1 + m_i, d_i]) * value
                if abs(sm) * _reach(machine.axis(m).travel) * 1e3 > _NEGLIGIBLE_UM:
                    add((m, d), Piece(name, _linear(sm)))
    plan.affine_um = _check(plan, coefs, seed + 1)
    _out_of_reach(plan, q, sens, coefs)
    return plan


def _fit(design: F64, target: F64) -> F64:
    """Least-squares coefficients (1 + n_linear, n_linear) of the affine shape."""
    coef, *_ = np.linalg.lstsq(design, target, rcond=None)
    return np.asarray(coef, dtype=np.float64)


def _out_of_reach(plan: CecPlan, q: F64, sens: dict[str, tuple[F64, F64]],
                  coefs: dict[str, F64]) -> None:
    """Name the part of each carried error that moves the tool where no linear axis of
    the machine moves it (a machine without a Z axis cannot correct an error along z)."""
    m = plan.machine
    cols = [i for i, a in enumerate(m.axes) if a.kind == "linear"]
    jac = jacobian(m, q, tool_mm=plan.tool_mm)[:, :3, :][:, :, cols]  # µm per mm
    col = {a.name: i for i, a in enumerate(m.axes)}
    for name in coefs:
        s_corr, p = sens[name]
        rest = p + np.einsum("nij,nj->ni", jac, s_corr)  # (I - J J⁺) P, µm per unit
        if name in plan.geometry.components:
            e = np.asarray(plan.geometry.components[name](q[:, col[name[2:]]]), dtype=float)
        else:
            e = np.full(q.shape[0], plan.geometry.locations[name])
        size = float(np.linalg.norm(rest * e[:, None], axis=1).max())
        if size > 10 * _NEGLIGIBLE_UM:
            plan.left.append((name, size, "moves the tool where no linear axis of this "
                                          "machine moves it: no table can correct that part"))


def _reach(travel: tuple[float, float]) -> float:
    return max(abs(travel[0]), abs(travel[1]), 1.0)


def _effect(p: F64, e: F64) -> float:
    """Largest tool-tip displacement ``|P e|`` over the points, µm."""
    return float(np.linalg.norm(p * np.asarray(e, dtype=float)[:, None], axis=1).max())


def _check(plan: CecPlan, coefs: dict[str, F64], seed: int) -> float:
    """Tool-tip distance (µm) between the affine shapes and ``-J⁺ P e`` on fresh points,
    for the errors the shapes carry."""
    m = plan.machine
    q = sample_points(m, 400, seed)
    sens, _ = correction_sensitivity(m, q, plan.tool_mm)
    col = {a.name: i for i, a in enumerate(m.axes)}
    lin_q = q[:, [col[k] for k in plan.linear]]
    design = np.column_stack([np.ones(q.shape[0]), lin_q])
    worst = np.zeros((q.shape[0], len(plan.linear)))
    for name, coef in coefs.items():
        s_corr, _ = sens[name]
        if name in plan.geometry.components:
            e = np.asarray(plan.geometry.components[name](q[:, col[name[2:]]]), dtype=float)
        else:
            e = np.full(q.shape[0], plan.geometry.locations[name])
        worst += (design @ coef - s_corr) * e[:, None]
    return float(np.linalg.norm(worst, axis=1).max() * 1e3)


__all__ = ["DEG_PER_URAD", "CecPlan", "Piece", "correction_sensitivity", "linear_axes",
           "plan_cec", "sample_points"]
