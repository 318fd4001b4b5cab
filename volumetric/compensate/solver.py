"""Actuator corrections that minimise the weighted tool-tip errors of every tool of a machine.

One solver serves every machine: a 3-axis mill, a 5-axis machine and a multi-spindle
machine whose spindles share axes (the first seed, Ahn, Min and Pasek 2006). The tool tips
(branches) are stacked: for each branch ``b`` the Jacobian ``J_b`` (:func:`jacobian`, rows
µm and µrad, columns per mm or per degree) and the error ``e_b``. The corrections solve the
weighted least-squares problem of the seed's Eq. 24a,

    dq = -(Jᵀ W J)⁺ Jᵀ W e                                  (Eq. 24a, C_ref = -P)

with ``W`` diagonal (three position weights per tool tip, Eq. 24b, and optionally three
orientation weights). ``J`` may be rank deficient (an axis whose tool tip has zero weight
is unobservable): the solve is the minimum-norm one, through an SVD of the weighted,
column-normalised ``W½ J`` in which singular values below ``rcond · σ_max`` count as zero, so
an unobservable axis gets 0, never NaN.

The error depends on position, and what matters is the error at the *compensated* command
``q + dq``. The residual is therefore evaluated exactly, ``r(dq) = pose_actual(q + dq) -
pose_nominal(q)``, and the correction refined by ``dq ← dq - G r(dq)`` (``G`` the weighted
pseudo-inverse above) until the step is below a tolerance; two or three steps suffice,
since ``e`` changes by far less than a µm over a correction of tens of µm. For a 3-axis
machine this is ``dq = -e(q + dq)``.

Units: corrections in mm (linear axes) or degrees (rotary axes); errors and residuals in µm
(position) and µrad (orientation); weights per µm² and per µrad².
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.components import GeometricErrors
from volumetric.model.kinematics import _positions, tool_pose
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.rigid import rotation_vector

F64 = NDArray[np.float64]
UM_PER_MM = 1e3
URAD_PER_RAD = 1e6
DEFAULT_RCOND = 1e-9
"""Relative rank tolerance: singular values of the column-normalised weighted Jacobian below
``rcond · σ_max`` are treated as zero. Columns are normalised to unit length first, so a
well-posed machine has singular values of order 1 and a genuinely unobservable direction
exactly 0; 1e-9 separates the two with margin on both sides."""
DEFAULT_STEP_TOL = 1e-7
"""Stop refining when no correction changes by more than this (mm or degrees): 0.1 nm."""
BLOCK = 16384  # points per batched SVD: bounds the (BLOCK, R, n) temporaries


class CompensationError(ValueError):
    """Input the solver cannot use (weights of the wrong length, negative, ...)."""


@dataclass(frozen=True)
class Weights:
    """Diagonal of ``W`` (Eq. 24b), per tool tip.

    Attributes
    ----------
    position : ndarray, shape (n_branches, 3)
        Weights of the x, y, z position errors of each tool tip, per µm².
    orientation : ndarray, shape (n_branches, 3)
        Weights of the orientation errors about x, y, z, per µrad²; zero to leave the
        orientation out.
    """

    position: F64
    orientation: F64

    def __post_init__(self) -> None:
        for name, w in (("position", self.position), ("orientation", self.orientation)):
            if w.ndim != 2 or w.shape[1] != 3:
                raise CompensationError(f"{name} weights must have shape (n_spindles, 3)")
            if not np.all(np.isfinite(w)) or np.any(w < 0):
                raise CompensationError(f"{name} weights must be finite and >= 0, got {w}")
        if self.position.shape != self.orientation.shape:
            raise CompensationError("position and orientation weights differ in shape")
        if not np.any(self.position > 0) and not np.any(self.orientation > 0):
            raise CompensationError("all weights are zero: nothing to compensate")

    @property
    def uses_orientation(self) -> bool:
        return bool(np.any(self.orientation > 0))

    @staticmethod
    def default(machine: Machine) -> Weights:
        """Every position error weighs 1; orientation errors weigh 1 per µrad² when the
        machine has rotary axes (which can correct them), else 0."""
        b = len(machine.branches)
        rotary = any(a.kind == "rotary" for a in machine.axes)
        return Weights(np.ones((b, 3)), np.full((b, 3), 1.0 if rotary else 0.0))

    @staticmethod
    def parse(machine: Machine, values: Sequence[float]) -> Weights:
        """Weights from a flat list, tool tip by tool tip in ``machine.branches`` order.

        ``3·B`` values are position weights (x, y, z per tool tip: ``1,1,1,10,10,10`` on a
        two-spindle machine weighs spindle 2 ten times); ``6·B`` values are position then
        orientation weights per tool tip (``px py pz ox oy oz`` for each).

        Raises
        ------
        CompensationError
            On any other length, a non-finite or negative value, or all zeros.
        """
        b = len(machine.branches)
        w = np.asarray(list(values), dtype=float)
        names = " ".join(br.name for br in machine.branches)
        if w.ndim != 1 or w.size not in (3 * b, 6 * b):
            raise CompensationError(
                f"weights: machine {machine.name!r} has {b} tool tip(s) ({names}); give "
                f"{3 * b} values (x, y, z per tool tip) or {6 * b} (x, y, z, a, b, c per "
                f"tool tip), got {w.size}"
            )
        bad = np.flatnonzero(~np.isfinite(w) | (w < 0))
        if bad.size:
            i = int(bad[0])
            raise CompensationError(f"weights: value {i + 1} ({w[i]}) must be finite and >= 0")
        if w.size == 3 * b:
            return Weights(w.reshape(b, 3), np.zeros((b, 3)))
        w6 = w.reshape(b, 6)
        return Weights(w6[:, :3].copy(), w6[:, 3:].copy())


@dataclass(frozen=True)
class Compensation:
    """The result of :func:`compensate` at N commanded positions.

    Attributes
    ----------
    axes : tuple of str
        Machine axes, the columns of ``q`` and ``dq``.
    branches : tuple of str
        Tool tips, the first index of the error arrays.
    q : ndarray, shape (N, n_axes)
        Commanded positions, mm or degrees.
    dq : ndarray, shape (N, n_axes)
        Corrections to add to the commands, mm or degrees.
    error_um, residual_um : ndarray, shape (n_branches, N, 3)
        Tool tip position error before (at q) and after (at q + dq) compensation, µm.
    error_urad, residual_urad : ndarray, shape (n_branches, N, 3), or None
        The same for the orientation, µrad (None when orientation was not weighed).
    rank : ndarray of int, shape (N,)
        Rank of the weighted Jacobian at each point.
    iterations : int
        Refinement steps taken.
    step : float
        The largest correction change of the last step, mm or degrees.
    converged : bool
        Whether ``step`` fell below the tolerance; the result is falsy otherwise.
    message : str
    """

    axes: tuple[str, ...]
    branches: tuple[str, ...]
    q: F64
    dq: F64
    error_um: F64
    residual_um: F64
    error_urad: F64 | None
    residual_urad: F64 | None
    rank: NDArray[np.int64]
    iterations: int
    step: float
    converged: bool
    message: str

    def __bool__(self) -> bool:
        return self.converged

    def max_error_um(self) -> F64:
        """Largest |error| per tool tip and direction before compensation, shape (B, 3)."""
        out: F64 = np.abs(self.error_um).max(axis=1)
        return out

    def max_residual_um(self) -> F64:
        """Largest |residual| per tool tip and direction after compensation, shape (B, 3)."""
        out: F64 = np.abs(self.residual_um).max(axis=1)
        return out


def weighted_pinv(
    machine: Machine,
    q: F64,
    weights: Weights,
    *,
    tool_mm: Mapping[str, float] | None = None,
    rcond: float = DEFAULT_RCOND,
) -> tuple[F64, NDArray[np.int64], F64]:
    """The weighted pseudo-inverse ``G`` with ``dq = -G e`` (Eq. 24a), point by point.

    Parameters
    ----------
    machine : Machine
    q : ndarray, shape (N, n_axes)
        Commanded positions, mm or degrees.
    weights : Weights
    tool_mm : mapping of spindle name to float, optional
        Tool lengths, mm; each branch's default otherwise.
    rcond : float
        Relative rank tolerance (see :data:`DEFAULT_RCOND`).

    Returns
    -------
    g : ndarray, shape (N, n_axes, R)
        Maps the stacked error (R rows: per branch 3 position rows in µm, then 3
        orientation rows in µrad if orientation is weighed) to corrections.
    rank : ndarray of int, shape (N,)
    jac : ndarray, shape (N, R, n_axes)
        The stacked (unweighted) Jacobian.
    """
    n = q.shape[0]
    # Linear axes only: the Jacobian is the same everywhere, so one point serves all.
    constant = not any(a.kind == "rotary" for a in machine.axes)
    qj = q[:1] if constant else q
    jac = _stacked_jacobian(machine, qj, weights.uses_orientation, tool_mm)
    sw = np.sqrt(_row_weights(weights))
    a = jac * sw[None, :, None]
    # Normalise the columns (per mm and per degree differ by orders of magnitude) so that
    # the rank tolerance and the minimum norm treat every axis alike.
    norms = np.linalg.norm(a, axis=1)  # (n, n_axes)
    scale = np.where(norms > 0, norms, 1.0)
    a = a / scale[:, None, :]
    g = np.empty((qj.shape[0], a.shape[2], a.shape[1]))
    rank = np.empty(qj.shape[0], dtype=np.int64)
    for start in range(0, qj.shape[0], BLOCK):
        sl = slice(start, start + BLOCK)
        u, s, vt = np.linalg.svd(a[sl], full_matrices=False)
        keep = s > rcond * s[:, :1]
        inv = np.where(keep, 1.0 / np.where(keep, s, 1.0), 0.0)
        rank[sl] = keep.sum(axis=1)
        g[sl] = np.einsum("nji,nj,nkj->nik", vt, inv, u)
    g = g / scale[:, :, None] * sw[None, None, :]
    if constant:
        return (np.broadcast_to(g, (n, *g.shape[1:])), np.broadcast_to(rank, (n,)),
                np.broadcast_to(jac, (n, *jac.shape[1:])))
    return g, rank, jac


def _row_weights(weights: Weights) -> F64:
    rows = [weights.position] + ([weights.orientation] if weights.uses_orientation else [])
    out: F64 = np.concatenate(rows, axis=1).reshape(-1)
    return out


def _stacked_jacobian(
    machine: Machine, q: F64, orientation: bool, tool_mm: Mapping[str, float] | None
) -> F64:
    blocks = []
    for br in machine.branches:
        j = jacobian(machine, q, spindle=br.name, tool_mm=_tool(tool_mm, br.name))
        blocks.append(j if orientation else j[:, :3])
    return np.concatenate(blocks, axis=1)


def _tool(tool_mm: Mapping[str, float] | None, name: str) -> float | None:
    return None if tool_mm is None else tool_mm.get(name)


def compensate(
    machine: Machine,
    errors: GeometricErrors,
    q: ArrayLike,
    *,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    rcond: float = DEFAULT_RCOND,
    step_tol: float = DEFAULT_STEP_TOL,
    max_iterations: int = 6,
) -> Compensation:
    """Corrections of every machine axis that minimise the weighted tool-tip errors.

    Parameters
    ----------
    machine : Machine
    errors : GeometricErrors
        The machine's geometry (e.g. ``MachineModel.geometry_at(temperatures)``).
    q : array_like, shape (N, n_axes)
        Commanded positions, mm or degrees, in ``machine.axes`` order.
    weights : Weights, optional
        :meth:`Weights.default` when omitted.
    tool_mm : mapping of spindle name to float, optional
        Tool lengths, mm; each branch's default otherwise.
    rcond : float
        Relative rank tolerance of the solve.
    step_tol : float
        Stop when no correction changes by more than this, mm or degrees.
    max_iterations : int
        At most this many refinement steps (the first solve counts as one).

    Returns
    -------
    Compensation
        Falsy, with a message, if the refinement did not settle within ``max_iterations``.

    Raises
    ------
    ValueError
        On positions of the wrong shape or not finite, or errors that do not belong to
        the machine (:class:`~volumetric.errors.ComponentErrorSpecError`).
    """
    qa = _positions(machine, q)
    solver = _Solver(machine, errors, qa, weights, tool_mm, rcond)
    dq, iterations, step, converged, message = solver.run(step_tol, max_iterations)
    res_p, res_o = solver.residual(dq)
    return Compensation(
        axes=machine.axis_names,
        branches=tuple(br.name for br in machine.branches),
        q=qa, dq=dq,
        error_um=solver.error_p, residual_um=res_p,
        error_urad=solver.error_o, residual_urad=res_o,
        rank=np.asarray(solver.rank, dtype=np.int64),
        iterations=iterations, step=step, converged=converged, message=message,
    )


def corrections(
    machine: Machine,
    errors: GeometricErrors,
    q: ArrayLike,
    *,
    weights: Weights | None = None,
    tool_mm: Mapping[str, float] | None = None,
    rcond: float = DEFAULT_RCOND,
    step_tol: float = DEFAULT_STEP_TOL,
    max_iterations: int = 6,
) -> F64:
    """Only the corrections of :func:`compensate`, shape (N, n_axes), mm or degrees.

    Skips the final residual evaluation (one exact pose per tool tip fewer), for callers
    that evaluate many points, such as map builders.

    Raises
    ------
    CompensationError
        When the refinement does not settle (the message says how far it got).
    """
    solver = _Solver(machine, errors, _positions(machine, q), weights, tool_mm, rcond)
    dq, _, _, converged, message = solver.run(step_tol, max_iterations)
    if not converged:
        raise CompensationError(f"machine {machine.name!r}: {message}")
    return dq


class _Solver:
    """The iteration of the module docstring over one set of points."""

    def __init__(self, machine: Machine, errors: GeometricErrors, qa: F64,
                 weights: Weights | None, tool_mm: Mapping[str, float] | None,
                 rcond: float) -> None:
        w = Weights.default(machine) if weights is None else weights
        if w.position.shape[0] != len(machine.branches):
            raise CompensationError(
                f"weights are for {w.position.shape[0]} tool tips, machine {machine.name!r} "
                f"has {len(machine.branches)}"
            )
        errors.check(machine)
        self.machine, self.errors, self.qa, self.tool_mm = machine, errors, qa, tool_mm
        self.orient = w.uses_orientation
        self.g, self.rank, _ = weighted_pinv(machine, qa, w, tool_mm=tool_mm, rcond=rcond)
        self.nominal = [
            tool_pose(machine, qa, None, spindle=br.name, tool_mm=_tool(tool_mm, br.name),
                      orientation=self.orient)
            for br in machine.branches
        ]
        self.error_p, self.error_o = self.residual(np.zeros_like(qa))

    def residual(self, dq: F64) -> tuple[F64, F64 | None]:
        """Exact tool-tip error at ``q + dq`` against the nominal pose at ``q``:
        position (B, N, 3) µm and orientation (B, N, 3) µrad or None."""
        pos, ori = [], []
        for br, (p_nom, r_nom) in zip(self.machine.branches, self.nominal, strict=True):
            p, r = tool_pose(self.machine, self.qa + dq, self.errors, spindle=br.name,
                             tool_mm=_tool(self.tool_mm, br.name), orientation=self.orient)
            pos.append((p - p_nom) * UM_PER_MM)
            if r is not None and r_nom is not None:
                ori.append(rotation_vector(r @ np.swapaxes(r_nom, 1, 2)) * URAD_PER_RAD)
        return np.stack(pos), (np.stack(ori) if self.orient else None)

    def _stacked(self, pos: F64, ori: F64 | None) -> F64:
        # (B, N, 3) [+ (B, N, 3)] → (N, R) in the row order of the Jacobian
        parts = [pos] if ori is None else [pos, ori]
        out: F64 = np.concatenate(parts, axis=2).transpose(1, 0, 2).reshape(self.qa.shape[0], -1)
        return out

    def run(self, step_tol: float, max_iterations: int) -> tuple[F64, int, float, bool, str]:
        if max_iterations < 1:
            raise CompensationError("max_iterations must be at least 1")
        dq = np.zeros_like(self.qa)
        res_p, res_o = self.error_p, self.error_o
        step = math.inf
        iterations = 0
        while True:
            delta = -np.einsum("nij,nj->ni", self.g, self._stacked(res_p, res_o))
            dq = dq + delta
            step = float(np.abs(delta).max()) if delta.size else 0.0
            iterations += 1
            if step <= step_tol or iterations >= max_iterations:
                break
            res_p, res_o = self.residual(dq)
        converged = step <= step_tol
        message = (f"converged in {iterations} steps (last step {step:.2e})" if converged else
                   f"not converged: last step {step:.2e} > {step_tol:.0e} after {iterations} "
                   "steps; the errors may be too large for a small-correction solve")
        return dq, iterations, step, converged, message


__all__ = [
    "Compensation",
    "CompensationError",
    "Weights",
    "compensate",
    "corrections",
    "weighted_pinv",
]
