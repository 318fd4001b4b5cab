"""Volumetric error: the tool tip's position and orientation error relative to the workpiece.

The relative transform from workpiece to tool is the product of one link per axis, in
chain order (``b`` dropped), times the tool offset. With the conventions of
:mod:`volumetric.model.machine` and :mod:`volumetric.model.components`, each link is

===============  ==================  =================================================
axis             workpiece side      tool side
===============  ==================  =================================================
linear           ``E · T(q·d')``     ``T(q·d') · E``
rotary           ``L R(q) L⁻¹ · E``  ``E · L R(q) L⁻¹``
===============  ==================  =================================================

where ``T(q·d')`` translates along the (tilted) line of motion, ``R(q)`` turns by +q about
the axis through its pivot, ``L`` is the rotary axis's location error (offset and tilt
about the pivot; its zero error adds to q), and ``E`` the axis's component errors as a
small rigid motion (rotation about the carriage origin, or the pivot for rotary axes).
For a linear axis ``E`` acts in the carriage frame, so the Abbe arm of an angular error
is the tool tip's position in that carriage; for a rotary axis ``E`` is expressed in the
non-rotating frame on the base side, as fixed sensors measure it (ISO 230-7).

Everything is exact rigid-body algebra over arrays of commanded positions (N, n_axes);
:mod:`volumetric.model.linear` holds the first-order form used for identification.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.components import GeometricErrors, component_names
from volumetric.model.machine import Axis, Machine, ToolBranch
from volumetric.model.rigid import (
    axis_angle_matrix,
    frame_from_z,
    rotate,
    rotation_matrix,
)

F64 = NDArray[np.float64]
CHUNK = 8192  # points per block: keeps the temporaries of one block in the CPU cache


@dataclass(frozen=True)
class Link:
    """One axis of a tool branch with the geometry the kinematics needs.

    Attributes
    ----------
    axis : Axis
    column : int
        The axis's column in the commanded-position array (``machine.axes`` order).
    frame : ndarray, shape (3, 3)
        Rotation from the axis's own error frame to the base frame (identity except for
        tilted spindle axes).
    direction : ndarray, shape (3,)
        Unit vector of the axis in the base frame.
    pivot : ndarray, shape (3,)
        A point on a rotary axis, mm.
    """

    axis: Axis
    column: int
    frame: F64
    direction: F64
    pivot: F64

    @property
    def rotary(self) -> bool:
        return self.axis.kind == "rotary"

    @property
    def tool_side(self) -> bool:
        return self.axis.side == "tool"


def branch_links(machine: Machine, branch: ToolBranch) -> list[Link]:
    """The links of one tool branch in chain order (workpiece to tool)."""
    links = []
    for a in branch.links:
        d = np.array(a.direction)
        frame = frame_from_z(d) if a.name not in ("X", "Y", "Z", "A", "B", "C") else np.eye(3)
        links.append(Link(a, machine.axis_names.index(a.name), frame, d, np.array(a.pivot_mm)))
    return links


@dataclass(frozen=True)
class LinkErrors:
    """The location errors of one link in base-frame vectors (mm, rad)."""

    tilt: F64  # linear: rotation of the line of motion; rotary: tilt of the axis
    offset: F64  # rotary: shift of the axis line, mm
    zero: float  # rotary: zero-position error, rad


def link_location_errors(link: Link, errors: GeometricErrors) -> LinkErrors:
    """Collect a link's location errors (see :mod:`volumetric.model.components`)."""
    k = link.axis.name
    ang = np.array([errors.location(f"E{c}0{k}") for c in "ABC"]) * 1e-6
    off = np.array([errors.location(f"E{c}0{k}") for c in "XYZ"]) * 1e-3
    if link.rotary:
        zero = float(ang @ link.direction)
        tilt = ang - zero * link.direction
        return LinkErrors(tilt, off, zero)
    return LinkErrors(link.frame @ ang, np.zeros(3), 0.0)


def _tool_vector(branch: ToolBranch, tool_mm: ArrayLike | None, n: int) -> F64:
    length = branch.tool_length_mm if tool_mm is None else tool_mm
    lengths = np.broadcast_to(np.asarray(length, dtype=float), (n,))
    out: F64 = lengths[:, None] * np.array(branch.tool_direction)
    return out


def _positions(machine: Machine, q: ArrayLike) -> F64:
    qa = np.asarray(q, dtype=float)
    if qa.ndim == 1:
        qa = qa[None, :]
    if qa.ndim != 2 or qa.shape[1] != len(machine.axes):
        raise ValueError(
            f"commanded positions must have shape (N, {len(machine.axes)}) for axes "
            f"{' '.join(machine.axis_names)}; got {qa.shape}"
        )
    if not np.all(np.isfinite(qa)):
        raise ValueError("commanded positions contain NaN or infinity")
    return qa


def tool_pose(
    machine: Machine,
    q: ArrayLike,
    errors: GeometricErrors | None = None,
    *,
    spindle: str | None = None,
    tool_mm: ArrayLike | None = None,
    orientation: bool = True,
) -> tuple[F64, F64 | None]:
    """Tool tip position and orientation relative to the workpiece, exact.

    Parameters
    ----------
    machine : Machine
    q : array_like, shape (N, n_axes)
        Commanded positions in ``machine.axes`` order, mm or degrees.
    errors : GeometricErrors, optional
        None for the nominal (error-free) machine.
    spindle : str, optional
        The tool branch (multi-spindle machines); the first one by default.
    tool_mm : float or array_like of shape (N,), optional
        Tool length; the branch's default when omitted.
    orientation : bool
        Also return the tool orientation.

    Returns
    -------
    p : ndarray, shape (N, 3)
        Tool tip in the workpiece frame, mm.
    r : ndarray, shape (N, 3, 3) or None
        Tool orientation in the workpiece frame.
    """
    qa = _positions(machine, q)
    branch = machine.branch(spindle)
    links = branch_links(machine, branch)
    tool = _tool_vector(branch, tool_mm, qa.shape[0])
    if errors is not None:
        errors.check(machine)
    p_out = np.empty((qa.shape[0], 3))
    r_out = np.empty((qa.shape[0], 3, 3)) if orientation else None
    for start in range(0, qa.shape[0], CHUNK):
        sl = slice(start, start + CHUNK)
        p, r = _pose_block(links, qa[sl], tool[sl], errors, orientation)
        p_out[sl] = p
        if r_out is not None and r is not None:
            r_out[sl] = r
    return p_out, r_out


def _pose_block(
    links: list[Link],
    q: F64,
    tool: F64,
    errors: GeometricErrors | None,
    orientation: bool,
) -> tuple[F64, F64 | None]:
    """Backward pass over the links: apply the rightmost transform first."""
    n = q.shape[0]
    p = tool.copy()
    r = np.broadcast_to(np.eye(3), (n, 3, 3)).copy() if orientation else None
    for link in reversed(links):
        qk = q[:, link.column]
        err = None
        loc = None
        if errors is not None:
            le = errors.link_errors(link.axis, qk)
            if le is not None:
                err = (le[0] @ link.frame.T, le[1] @ link.frame.T)
            loc = link_location_errors(link, errors)
        if link.rotary:
            if link.tool_side:  # E · L R L⁻¹ : motion first, then E
                p, r = _rotary_motion(link, qk, loc, p, r)
                p, r = _apply_error(err, link.pivot, p, r)
            else:  # L R L⁻¹ · E
                p, r = _apply_error(err, link.pivot, p, r)
                p, r = _rotary_motion(link, qk, loc, p, r)
        else:
            d = link.direction if loc is None else rotate(loc.tilt, link.direction)
            if link.tool_side:  # T · E
                p, r = _apply_error(err, None, p, r)
                p = p + qk[:, None] * d
            else:  # E · T
                p = p + qk[:, None] * d
                p, r = _apply_error(err, None, p, r)
    return p, r


def _apply_error(
    err: tuple[F64, F64] | None, pivot: F64 | None, p: F64, r: F64 | None
) -> tuple[F64, F64 | None]:
    if err is None:
        return p, r
    delta, eps = err
    p = rotate(eps, p) + delta if pivot is None else rotate(eps, p - pivot) + pivot + delta
    if r is not None:
        r = rotation_matrix(eps) @ r
    return p, r


def _rotary_motion(
    link: Link, qk: F64, loc: LinkErrors | None, p: F64, r: F64 | None
) -> tuple[F64, F64 | None]:
    theta = np.deg2rad(qk)
    c = link.pivot
    if loc is None:
        rot = axis_angle_matrix(link.direction, theta)
        p = np.einsum("nij,nj->ni", rot, p - c) + c
        return p, (rot @ r if r is not None else None)
    # L R(θ + zero) L⁻¹ with L a small rigid motion (tilt, offset) about the pivot.
    theta = theta + loc.zero
    tilt = np.broadcast_to(loc.tilt, p.shape)
    x = rotate(-tilt, p - c - loc.offset) + c  # L⁻¹
    rot = axis_angle_matrix(link.direction, theta)
    x = np.einsum("nij,nj->ni", rot, x - c) + c
    p = rotate(tilt, x - c) + c + loc.offset  # L
    if r is not None:
        rl = rotation_matrix(loc.tilt[None, :])[0]
        r = (rl @ rot @ rl.T) @ r
    return p, r


def link_component_errors(
    errors: GeometricErrors, axis: Axis, q: F64
) -> F64:
    """The six component errors of an axis at positions q, shape (N, 6), µm and µrad."""
    out = np.zeros((q.shape[0], 6))
    for j, name in enumerate(component_names(axis)):
        f = errors.components.get(name)
        if f is not None:
            out[:, j] = f(q)
    return out


__all__ = [
    "CHUNK",
    "Link",
    "LinkErrors",
    "branch_links",
    "link_component_errors",
    "link_location_errors",
    "tool_pose",
]
