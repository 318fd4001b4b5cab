"""Machines and errors for the kinematics tests: small machine builders, random component
errors and positions, and ``naive_pose``, the per-point 4x4 product the vectorised exact
error is checked against (also the baseline of ``benchmarks/volumetric_throughput.py``)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from volumetric.model.components import (
    GeometricErrors,
    Polynomial,
    Table,
    component_names,
    location_names,
)
from volumetric.model.machine import Machine, parse_machine

TRAVEL = {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}


def machine(chain: str, **extra: object) -> Machine:
    spec: dict[str, object] = {"name": "m", "chain": chain, "travel_mm": TRAVEL,
                               "tool_length_mm": 100.0}
    spec.update(extra)
    return parse_machine(spec)


def arch(theta1_deg: float = 0.0, theta2_deg: float = 30.0) -> Machine:
    """The arch-type two-spindle machine of the first seed: x on the workpiece, y shared,
    z1 and z2 tilted by θ1, θ2 in the y-z plane."""
    def d(th: float) -> list[float]:
        t = np.deg2rad(th)
        return [0.0, float(-np.sin(t)), float(np.cos(t))]
    return parse_machine({
        "name": "arch", "chain": "w X b Y t",
        "travel_mm": {"x": [10, 500], "y": [10, 290], "z1": [-300, -10], "z2": [-300, -10]},
        "spindles": [
            {"name": "S1", "axis": "Z1", "direction": d(theta1_deg), "tool_length_mm": 50.0},
            {"name": "S2", "axis": "Z2", "direction": d(theta2_deg), "tool_length_mm": 50.0},
        ],
    })


def random_errors(m: Machine, rng: np.random.Generator, size: float) -> GeometricErrors:
    comps: dict[str, Polynomial | Table] = {}
    for a in m.axes:
        span = a.travel[1] - a.travel[0]
        for n in component_names(a):
            comps[n] = Polynomial(tuple(rng.normal(0, size, 4)), a.travel[0], span)
    locs = {n: float(rng.normal(0, 2 * size)) for n in location_names(m)}
    return GeometricErrors(comps, locs)


def random_q(m: Machine, rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    return np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in m.axes])


def _h(r: NDArray[np.float64], t: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.eye(4)
    out[:3, :3] = r
    out[:3, 3] = t
    return out


def _trans(t: NDArray[np.float64]) -> NDArray[np.float64]:
    return _h(np.eye(3), t)


def naive_pose(
    m: Machine, e: GeometricErrors | None, q: NDArray[np.float64], spindle: str | None = None
) -> NDArray[np.float64]:
    branch = m.branch(spindle)
    t_total = np.eye(4)
    for a in branch.links:
        qk = q[m.axis_names.index(a.name)]
        d = np.array(a.direction)
        if a.name in ("X", "Y", "Z", "A", "B", "C"):
            frame = np.eye(3)
        else:
            frame, _ = Rotation.align_vectors([d], [[0.0, 0.0, 1.0]])
            frame = frame.as_matrix()
        comp = np.zeros(6)
        loc_ang = np.zeros(3)
        loc_off = np.zeros(3)
        if e is not None:
            comp = np.array([e.components[n](np.array([qk]))[0] if n in e.components else 0.0
                             for n in component_names(a)])
            loc_ang = np.array([e.location(f"E{c}0{a.name}") for c in "ABC"]) * 1e-6
            loc_off = np.array([e.location(f"E{c}0{a.name}") for c in "XYZ"]) * 1e-3
        err = _h(Rotation.from_rotvec(frame @ comp[3:] * 1e-6).as_matrix(),
                 frame @ comp[:3] * 1e-3)
        if a.kind == "linear":
            tilted = Rotation.from_rotvec(frame @ loc_ang).apply(d)
            move = _trans(qk * tilted)
            link = move @ err if a.side == "tool" else err @ move
        else:
            c = np.array(a.pivot_mm)
            zero = float(loc_ang @ d)
            tilt = loc_ang - zero * d
            rot = _trans(c) @ _h(Rotation.from_rotvec(d * (np.deg2rad(qk) + zero)).as_matrix(),
                                 np.zeros(3)) @ _trans(-c)
            loc = _trans(c + loc_off) @ _h(Rotation.from_rotvec(tilt).as_matrix(),
                                           np.zeros(3)) @ _trans(-c)
            move = loc @ rot @ np.linalg.inv(loc)
            err_p = _trans(c) @ err @ _trans(-c)
            link = err_p @ move if a.side == "tool" else move @ err_p
        t_total = t_total @ link
    tool = _h(np.eye(3), branch.tool_length_mm * np.array(branch.tool_direction))
    return t_total @ tool
