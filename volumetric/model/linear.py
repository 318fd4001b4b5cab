"""First-order (linear) form of the volumetric error, and the actuator Jacobian.

A small error motion (δ, ε) inserted at some point of the chain moves the tool tip by
``Rf (δ + ε × r)`` and turns it by ``Rf ε``, where ``Rf`` is the nominal rotation of the
chain up to that point and ``r`` the nominal tool tip seen from the point (the Abbe arm).
Summing these over every error gives the volumetric error to first order; it is linear in
the component errors, hence in their polynomial coefficients, which is what identification
needs. The insertion points follow the link table of :mod:`volumetric.model.kinematics`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.components import GeometricErrors, component_names, location_names
from volumetric.model.exact import VolumetricError
from volumetric.model.kinematics import (
    Link,
    _positions,
    _tool_vector,
    branch_links,
    link_component_errors,
)
from volumetric.model.machine import Machine
from volumetric.model.rigid import axis_angle_matrix, skew

F64 = NDArray[np.float64]
UM_PER_MM = 1e3
RAD_PER_URAD = 1e-6


@dataclass(frozen=True)
class Sensitivity:
    """How a group of errors moves the tool tip, point by point.

    Attributes
    ----------
    names : tuple of str
        ISO 230-1 names of the errors in the group.
    matrix : ndarray, shape (N, 6, k)
        (Δp in µm, Δω in µrad) per unit (µm or µrad) of each error.
    column : int or None
        For position-dependent errors, the column of q at which they are evaluated;
        None for location errors (constants).
    """

    names: tuple[str, ...]
    matrix: F64
    column: int | None


@dataclass(frozen=True)
class NominalChain:
    """Nominal frames along a branch, shape (N, ...) each.

    Attributes
    ----------
    links : list of Link
    r_pre : list of ndarray, each (N, 3, 3)
        Rotation of the frame before each link (workpiece frame = identity).
    rot : list of ndarray or None, each (N, 3, 3)
        The link's own nominal rotation (rotary links), else None.
    p_after : list of ndarray, each (N, 3)
        Nominal tool tip expressed in the frame after each link, mm.
    q : ndarray, shape (N, n_axes)
    """

    links: list[Link]
    r_pre: list[F64]
    rot: list[F64 | None]
    p_after: list[F64]
    q: F64


def nominal_chain(
    machine: Machine, q: ArrayLike, *, spindle: str | None = None, tool_mm: ArrayLike | None = None
) -> NominalChain:
    """Nominal frames of a branch at commanded positions (N, n_axes)."""
    qa = _positions(machine, q)
    n = qa.shape[0]
    branch = machine.branch(spindle)
    links = branch_links(machine, branch)
    rots: list[F64 | None] = []
    for link in links:
        if link.rotary:
            rots.append(axis_angle_matrix(link.direction, np.deg2rad(qa[:, link.column])))
        else:
            rots.append(None)
    r_pre: list[F64] = []
    r = np.broadcast_to(np.eye(3), (n, 3, 3))
    for rot in rots:
        r_pre.append(r)
        if rot is not None:
            r = r @ rot
    p_after: list[F64] = [np.empty(0)] * len(links)
    p = _tool_vector(branch, tool_mm, n)
    for i in range(len(links) - 1, -1, -1):
        p_after[i] = p
        p = _nominal_link(links[i], rots[i], qa, p)
    return NominalChain(links, r_pre, rots, p_after, qa)


def _nominal_link(link: Link, rot: F64 | None, q: F64, p: F64) -> F64:
    if rot is None:
        return p + q[:, link.column, None] * link.direction
    out: F64 = np.einsum("nij,nj->ni", rot, p - link.pivot) + link.pivot
    return out


def _insertion(rf: F64, r: F64, frame: F64) -> F64:
    """(N, 6, 6) map of an error (δ µm, ε µrad) in ``frame`` to (Δp µm, Δω µrad)."""
    n = r.shape[0]
    rff = rf @ frame
    out = np.zeros((n, 6, 6))
    out[:, :3, :3] = rff
    out[:, :3, 3:] = -(rf @ skew(r) @ frame) * (RAD_PER_URAD * UM_PER_MM)
    out[:, 3:, 3:] = rff
    return out


def sensitivities(
    machine: Machine, q: ArrayLike, *, spindle: str | None = None, tool_mm: ArrayLike | None = None
) -> list[Sensitivity]:
    """First-order sensitivities of the tool tip to every error of a branch.

    Parameters
    ----------
    machine : Machine
    q : array_like, shape (N, n_axes)
        Commanded positions, mm or degrees.
    spindle : str, optional
    tool_mm : float or array_like (N,), optional

    Returns
    -------
    list of Sensitivity
        One per axis for its six component errors (``column`` set), and one per axis
        that has location errors (``column`` None).
    """
    chain = nominal_chain(machine, q, spindle=spindle, tool_mm=tool_mm)
    loc_names = set(location_names(machine))
    out: list[Sensitivity] = []
    for i, link in enumerate(chain.links):
        rp, rot, pa = chain.r_pre[i], chain.rot[i], chain.p_after[i]
        qk = chain.q[:, link.column]
        k = link.axis.name
        if not link.rotary:
            r = pa if link.tool_side else pa + qk[:, None] * link.direction
            out.append(Sensitivity(component_names(link.axis), _insertion(rp, r, link.frame),
                                   link.column))
            names = tuple(n for n in (f"EA0{k}", f"EB0{k}", f"EC0{k}") if n in loc_names)
            if names:
                m = np.zeros((qk.shape[0], 6, len(names)))
                for j, name in enumerate(names):
                    e = link.frame @ np.eye(3)["ABC".index(name[1])]
                    # the line of motion turns by e: the move q·d gains q·(e × d)
                    m[:, :3, j] = (rp @ np.cross(e, link.direction)) * qk[:, None] * 1e-3
                out.append(Sensitivity(names, m, None))
            continue
        assert rot is not None
        c = link.pivot
        r_before = np.einsum("nij,nj->ni", rot, pa - c)  # tool seen from the pivot, base side
        r_after = pa - c  # tool seen from the pivot, in the turned frame
        rp_rot = rp @ rot
        if link.tool_side:  # E · M
            ins = _insertion(rp, r_before, link.frame)
        else:  # M · E
            ins = _insertion(rp_rot, r_after, link.frame)
        out.append(Sensitivity(component_names(link.axis), ins, link.column))
        names = tuple(n for n in (f"E{c_}0{k}" for c_ in "XYZABC") if n in loc_names)
        if names:
            plus = _insertion(rp, r_before, np.eye(3))
            minus = _insertion(rp_rot, r_after, np.eye(3))
            m = np.zeros((qk.shape[0], 6, len(names)))
            for j, name in enumerate(names):
                idx = "XYZABC".index(name[1])
                along = idx >= 3 and np.allclose(np.eye(3)[idx - 3], link.direction)
                if along:  # zero-position error: an extra turn about the axis
                    m[:, :, j] = minus[:, :, idx]
                else:  # L · M · L⁻¹
                    m[:, :, j] = plus[:, :, idx] - minus[:, :, idx]
            out.append(Sensitivity(names, m, None))
    return out


def linear_volumetric_error(
    machine: Machine,
    errors: GeometricErrors,
    q: ArrayLike,
    *,
    spindle: str | None = None,
    tool_mm: ArrayLike | None = None,
) -> VolumetricError:
    """The volumetric error to first order in the errors (see module docstring).

    Returns
    -------
    VolumetricError
        Position (µm) and orientation (µrad) errors, shape (N, 3) each.
    """
    errors.check(machine)
    qa = _positions(machine, q)
    total = np.zeros((qa.shape[0], 6))
    for s in sensitivities(machine, qa, spindle=spindle, tool_mm=tool_mm):
        if s.column is None:
            v = np.array([errors.location(n) for n in s.names])
            total += s.matrix @ v
        else:
            axis = machine.axes[s.column]
            v2 = link_component_errors(errors, axis, qa[:, s.column])
            total += np.einsum("nij,nj->ni", s.matrix, v2)
    return VolumetricError(total[:, :3], total[:, 3:])


def jacobian(
    machine: Machine, q: ArrayLike, *, spindle: str | None = None, tool_mm: ArrayLike | None = None
) -> F64:
    """Nominal Jacobian of the tool pose with respect to the commanded axes.

    Returns
    -------
    ndarray, shape (N, 6, n_axes)
        Rows: tool tip position (µm) and orientation (µrad) relative to the workpiece;
        columns: per mm of a linear axis or per degree of a rotary axis. Axes not in the
        branch have zero columns.
    """
    chain = nominal_chain(machine, q, spindle=spindle, tool_mm=tool_mm)
    n = chain.q.shape[0]
    jac = np.zeros((n, 6, len(machine.axes)))
    for i, link in enumerate(chain.links):
        rp, rot = chain.r_pre[i], chain.rot[i]
        if rot is None:
            jac[:, :3, link.column] = (rp @ link.direction) * UM_PER_MM
            continue
        arm = np.einsum("nij,nj->ni", rot, chain.p_after[i] - link.pivot)
        per_rad = np.cross(link.direction, arm)
        jac[:, :3, link.column] = np.einsum("nij,nj->ni", rp, per_rad) * UM_PER_MM * np.pi / 180
        jac[:, 3:, link.column] = (rp @ link.direction) * 1e6 * np.pi / 180
    return jac
