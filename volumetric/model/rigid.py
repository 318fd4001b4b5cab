"""Small vectorised rigid-body helpers over arrays of points, shape (N, 3).

Rotations are given as rotation vectors (axis times angle, rad). ``rotate`` is exact: for
the small angles of component errors it evaluates the Rodrigues coefficients by their
series, whose truncation error is below double precision for |θ| < 1e-2 rad, and by the
closed form otherwise.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

F64 = NDArray[np.float64]

_SERIES_LIMIT = 1e-2  # rad; beyond it the closed form is used (see module docstring)


def cross(a: F64, b: F64) -> F64:
    """Row-wise cross product of (N, 3) (or broadcastable (3,)) arrays."""
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    bx, by, bz = b[..., 0], b[..., 1], b[..., 2]
    return np.stack((ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx), axis=-1)


def rodrigues_coefficients(w: F64) -> tuple[F64, F64]:
    """``sin θ / θ`` and ``(1 - cos θ) / θ²`` for rotation vectors w, shape (N, 3)."""
    t2 = np.einsum("...i,...i->...", w, w)
    if np.all(t2 < _SERIES_LIMIT**2):
        a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0)
        b = 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0)
        return a, b
    t = np.sqrt(t2)
    safe = np.where(t2 > 0, t, 1.0)
    a = np.where(t2 > 0, np.sin(safe) / safe, 1.0)
    b = np.where(t2 > 0, (1.0 - np.cos(safe)) / (safe * safe), 0.5)
    return a, b


def rotate(w: F64, v: F64) -> F64:
    """Rotate vectors v (N, 3) by rotation vectors w (N, 3) or (3,): exact Rodrigues."""
    a, b = rodrigues_coefficients(w)
    wv = cross(w, v)
    return v + a[..., None] * wv + b[..., None] * cross(w, wv)


def rotation_matrix(w: F64) -> F64:
    """Rotation matrices (N, 3, 3) of rotation vectors (N, 3)."""
    a, b = rodrigues_coefficients(w)
    k = skew(w)
    eye = np.broadcast_to(np.eye(3), k.shape)
    out: F64 = eye + a[..., None, None] * k + b[..., None, None] * (k @ k)
    return out


def axis_angle_matrix(axis: F64, theta: F64) -> F64:
    """Rotation matrices (N, 3, 3) about a fixed unit axis (3,) by angles θ (N,), rad."""
    k = skew(np.asarray(axis, dtype=float))
    s = np.sin(theta)[:, None, None]
    c = np.cos(theta)[:, None, None]
    out: F64 = np.eye(3) + s * k + (1.0 - c) * (k @ k)
    return out


def skew(w: F64) -> F64:
    """Skew matrices [w]× of shape (..., 3, 3) such that [w]× v = w × v."""
    z = np.zeros(w.shape[:-1])
    wx, wy, wz = w[..., 0], w[..., 1], w[..., 2]
    return np.stack(
        (
            np.stack((z, -wz, wy), axis=-1),
            np.stack((wz, z, -wx), axis=-1),
            np.stack((-wy, wx, z), axis=-1),
        ),
        axis=-2,
    )


def rotation_vector(r: F64) -> F64:
    """Rotation vectors (N, 3) of rotation matrices (N, 3, 3): the exact logarithm."""
    v = np.stack((r[:, 2, 1] - r[:, 1, 2], r[:, 0, 2] - r[:, 2, 0], r[:, 1, 0] - r[:, 0, 1]), -1)
    s = 0.5 * np.linalg.norm(v, axis=1)  # sin θ
    c = np.clip(0.5 * (np.trace(r, axis1=1, axis2=2) - 1.0), -1.0, 1.0)  # cos θ
    theta = np.arctan2(s, c)
    # θ / (2 sin θ) → 1/2 as θ → 0; the series is exact to double precision below 1e-4.
    small = theta < 1e-4
    safe = np.where(small, 1.0, s)
    factor = np.where(small, 0.5 * (1.0 + theta * theta / 6.0), theta / (2.0 * safe))
    out: F64 = v * factor[:, None]
    return out


def frame_from_z(direction: F64) -> F64:
    """The smallest rotation (3, 3) taking the base z axis onto a unit ``direction``.

    Used for the own frame of a tilted spindle axis: for a direction in the y-z plane,
    tilted by θ, it is the rotation about x by θ, so x stays x and y turns into y1.
    """
    d = np.asarray(direction, dtype=float)
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, d)
    s = float(np.linalg.norm(axis))
    c = float(d @ z)
    if s < 1e-15:
        flip: F64 = np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
        return flip
    theta = float(np.arctan2(s, c))
    out: F64 = axis_angle_matrix(axis / s, np.array([theta]))[0]
    return out
