"""A random but realistic true geometry for a simulated machine.

The control center never sees this: it has to identify it from simulated measurements.
Sizes follow what uncompensated machining centres of 0.3 to 1 m travel show (ISO 230-1
examples, manufacturers' acceptance sheets), at ``scale = 1``:

==========================  ===============================================  ===========
error                       shape                                            size
==========================  ===============================================  ===========
positioning ``EXX``         s·(c1 + c2·s + c3·s² + c4·s³), zero at start      ≤ ~30 µm
straightness ``EYX``        s·(1 - s)·(b0 + b1·s): zero at both ends (the     ≤ ~5 µm
                            end-point reference line; its slope is squareness)
roll, pitch, yaw ``EAX``    s·(a1 + a2·s + a3·s²), zero at start              ≤ ~40 µrad
squareness ``EC0Y`` ...     constant                                         ≤ ~40 µrad
rotary radial/axial         harmonics 2..4 of the angle                      ≤ ~3 µm
rotary tilt (wobble)        harmonics 2..3 of the angle                      ≤ ~15 µrad
rotary angular positioning  harmonics 1..3 of the angle                      ≤ ~30 µrad
rotary location errors      constants (offsets µm, tilts and zero µrad)      ≤ ~30 µm/µrad
==========================  ===============================================  ===========

``s = (q - q_min) / (q_max - q_min)`` is the normalised position of a linear axis. All
linear-axis components are zero at the start of travel (the usual reference of a laser
measurement); rotary components are zero at 0°. With ``form="table"`` each linear-axis
component is tabulated densely (every ~1 % of travel) and gains a gentle curvature that no
low-order polynomial holds exactly (a half-to-one-and-a-half wave over the travel of up to
10 % of the component's size), which is closer to a real machine.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.model.components import (
    Component,
    Fourier,
    GeometricErrors,
    Polynomial,
    Table,
    add_components,
    location_names,
)
from volumetric.model.machine import Axis, Machine

__all__ = ["cyclic_error", "random_geometry", "rotary_error_motions"]

F64 = NDArray[np.float64]

# Sizes at scale 1 (µm for displacements, µrad for angles); see the module table.
POSITIONING_UM = 20.0
STRAIGHTNESS_UM = 4.0
ANGULAR_URAD = 25.0
SQUARENESS_URAD = 40.0
ROTARY_RADIAL_UM = 2.0
ROTARY_WOBBLE_URAD = 10.0
ROTARY_INDEX_URAD = 20.0
ROTARY_OFFSET_UM = 20.0
ROTARY_TILT_URAD = 30.0
TABLE_NODES = 101


def random_geometry(
    machine: Machine,
    rng: np.random.Generator,
    *,
    scale: float = 1.0,
    form: Literal["polynomial", "table"] = "polynomial",
) -> GeometricErrors:
    """A smooth, realistic true geometry for every axis of ``machine``.

    Parameters
    ----------
    machine : Machine
    rng : numpy.random.Generator
        The only source of randomness: the same generator state gives the same geometry.
    scale : float
        Multiplies every error (0 gives a perfect machine).
    form : {"polynomial", "table"}
        Linear-axis components as exact low-order polynomials, or as dense tables of the
        same polynomials plus a gentle curvature (see the module docstring).

    Returns
    -------
    GeometricErrors
        Every component error of every axis (µm, µrad) and every location error of
        :func:`volumetric.model.components.location_names`.
    """
    if not np.isfinite(scale) or scale < 0:
        raise ValueError(f"scale must be a finite number >= 0, got {scale!r}")
    if form not in ("polynomial", "table"):
        raise ValueError(f"form must be 'polynomial' or 'table', got {form!r}")
    components: dict[str, Component] = {}
    for axis in machine.axes:
        if axis.kind == "linear":
            components.update(_linear_axis(axis, rng, scale, form))
        else:
            components.update(_rotary_axis(axis, rng, scale))
    locations: dict[str, float] = {}
    for name in location_names(machine):
        axis_name = name[3:]
        rotary = machine.axis(axis_name).kind == "rotary"
        if rotary and name[1] in "XYZ":
            size = ROTARY_OFFSET_UM
        elif rotary:
            size = ROTARY_TILT_URAD
        else:
            size = SQUARENESS_URAD
        locations[name] = float(rng.uniform(-1.0, 1.0) * size * scale)
    return GeometricErrors(components, locations)


def _linear_axis(
    axis: Axis, rng: np.random.Generator, scale: float, form: str
) -> dict[str, Component]:
    lo, hi = axis.travel
    span = hi - lo
    own = "XYZ"[_own_index(axis)]
    out: dict[str, Component] = {}
    for c in "XYZABC":
        if c in "XYZ" and c == own:
            # s·(c1 + c2 s + c3 s² + c4 s³): a scale error with gentle curvature
            k = rng.uniform(-1.0, 1.0, 4) * np.array([1.0, 0.35, 0.2, 0.1]) * POSITIONING_UM
            coeffs = (0.0, *k)
        elif c in "XYZ":
            # s(1 - s)(b0 + b1 s) = b0 s + (b1 - b0) s² - b1 s³: a bow, zero at both ends
            b0, b1 = rng.uniform(-1.0, 1.0, 2) * 4.0 * STRAIGHTNESS_UM * np.array([1.0, 0.7])
            coeffs = (0.0, b0, b1 - b0, -b1)
        else:
            a = rng.uniform(-1.0, 1.0, 3) * np.array([1.0, 0.5, 0.3]) * ANGULAR_URAD
            coeffs = (0.0, *a)
        poly = Polynomial(tuple(float(v * scale) for v in coeffs), lo, span)
        name = f"E{c}{axis.name}"
        if form == "polynomial":
            out[name] = poly
            continue
        q = np.linspace(lo, hi, TABLE_NODES)
        s = (q - lo) / span
        size = float(np.max(np.abs(poly(q)))) if span > 0 else 0.0
        waves = rng.uniform(0.5, 1.5)
        phase = rng.uniform(0.0, 2 * np.pi)
        # sin(φ + 2π w s) - sin(φ) keeps the component zero at the start of travel
        bend = 0.1 * size * (np.sin(phase + 2 * np.pi * waves * s) - np.sin(phase))
        if c in "XYZ" and c != own:
            bend = bend - s * bend[-1]  # straightness stays zero at the far end too
        out[name] = Table(tuple(q.tolist()), tuple((poly(q) + bend).tolist()))
    return out


def _own_index(axis: Axis) -> int:
    """Index (0, 1, 2 for x, y, z) of the error direction that is the axis's own motion.

    Base axes move along x, y or z; a spindle axis's own frame has its motion along z1.
    """
    if axis.name in ("X", "Y", "Z"):
        return "XYZ".index(axis.name)
    return 2


def _rotary_axis(axis: Axis, rng: np.random.Generator, scale: float) -> dict[str, Component]:
    lo, hi = axis.travel
    # Tabulate over the travel (at least a full turn so the table covers any command);
    # every 5° is dense enough for harmonics up to the 4th.
    lo_t, hi_t = min(lo, -180.0), max(hi, 180.0)
    q = np.linspace(lo_t, hi_t, round((hi_t - lo_t) / 5.0) + 1)
    theta = np.deg2rad(q)
    own = axis.name  # the rotation's own direction letter: A, B or C
    out: dict[str, Component] = {}
    for c in "XYZABC":
        harmonics: tuple[int, ...]
        if c in "XYZ":
            harmonics, size = (2, 3, 4), ROTARY_RADIAL_UM
        elif c == own:
            harmonics, size = (1, 2, 3), ROTARY_INDEX_URAD
        else:
            harmonics, size = (2, 3), ROTARY_WOBBLE_URAD
        v = np.zeros_like(theta)
        for k in harmonics:
            amp = rng.uniform(-1.0, 1.0) * size / k
            ph = rng.uniform(0.0, 2 * np.pi)
            v += amp * (np.sin(k * theta + ph) - np.sin(ph))  # zero at 0°
        out[f"E{c}{axis.name}"] = Table(tuple(q.tolist()), tuple((v * scale).tolist()))
    return out


# Once- and twice-per-turn error motions of a rotary table (ISO 230-7 sizes): a radial
# eccentricity of the bearing, an axial runout, a wobble of the axis and a cyclic indexing
# error of the worm or encoder, each the amplitude range of the first harmonic (µm, µrad);
# the second harmonic is up to half as large.
ROTARY_PERIODIC_RADIAL_UM = (4.0, 12.0)
ROTARY_PERIODIC_AXIAL_UM = (1.5, 5.0)
ROTARY_PERIODIC_WOBBLE_URAD = (15.0, 40.0)
ROTARY_PERIODIC_INDEX_URAD = (20.0, 60.0)


def rotary_error_motions(
    machine: Machine, rng: np.random.Generator, *, orders: tuple[int, ...] = (1, 2),
    scale: float = 1.0,
) -> dict[str, Component]:
    """Periodic error motions of every rotary axis: harmonics ``orders`` per turn.

    Each component of a rotary axis becomes ``Σ_k A_k (sin(kθ + φ_k) − sin φ_k)`` (zero
    at 0°), tabulated every 2.5° over the travel (at least a full turn), with ``A_1``
    drawn from the ranges above and ``A_k`` up to ``A_1 / k`` for k > 1. The radial
    components are those perpendicular to the axis, the axial one along it, the wobble
    the two tilts and the indexing error the rotation about the axis itself.

    Parameters
    ----------
    machine : Machine
    rng : numpy.random.Generator
    orders : tuple of int
        Harmonics per turn present (1: eccentricity, wobble; 2: an elliptic bearing ...).
    scale : float
        Multiplies every amplitude.

    Returns
    -------
    dict of str to Table
        Component errors by ISO name (``EXC`` ...), to replace a geometry's own.
    """
    out: dict[str, Component] = {}
    for axis in machine.axes:
        if axis.kind != "rotary":
            continue
        lo, hi = axis.travel
        lo_t, hi_t = min(lo, -180.0), max(hi, 180.0)
        q = np.linspace(lo_t, hi_t, round((hi_t - lo_t) / 2.5) + 1)
        theta = np.deg2rad(q)
        own = axis.name
        own_linear = {"A": "X", "B": "Y", "C": "Z"}[own]
        for c in "XYZABC":
            if c == own:
                size = ROTARY_PERIODIC_INDEX_URAD
            elif c == own_linear:
                size = ROTARY_PERIODIC_AXIAL_UM
            elif c in "XYZ":
                size = ROTARY_PERIODIC_RADIAL_UM
            else:
                size = ROTARY_PERIODIC_WOBBLE_URAD
            v = np.zeros_like(theta)
            for k in orders:
                amp = rng.uniform(*size) / (1.0 if k == 1 else rng.uniform(k, 2.0 * k))
                ph = rng.uniform(0.0, 2 * np.pi)
                v += amp * (np.sin(k * theta + ph) - np.sin(ph))
            out[f"E{c}{axis.name}"] = Table(tuple(q.tolist()), tuple((v * scale).tolist()))
    return out


def cyclic_error(
    machine: Machine, geometry: GeometricErrors, axis: str, order: int, radial_um: float,
    angular_urad: float, rng: np.random.Generator,
) -> GeometricErrors:
    """``geometry`` with a cyclic error of ``order`` per turn added to a rotary axis's
    components (a gear, a worm or a bearing of that many teeth or balls), exactly (a
    :class:`~volumetric.model.components.Fourier` term, not a table).

    The indexing component (the rotation about the axis itself, ``ECC`` for C) gets
    ``angular_urad``; each radial component (perpendicular to the axis) ``radial_um``
    times a random factor in [0.5, 1]; the axial one and the two tilts a random fraction
    (0.1 to 0.4) of the radial size (µm) and of ``angular_urad`` (µrad). Phases are
    random.

    Parameters
    ----------
    machine : Machine
    geometry : GeometricErrors
    axis : str
        A rotary axis (name or key).
    order : int
        Cycles per turn (>= 1).
    radial_um, angular_urad : float
        Amplitudes (>= 0).
    rng : numpy.random.Generator
    """
    ax = machine.axis(axis)
    if ax.kind != "rotary":
        raise ValueError(f"axis {ax.name} is linear; a cyclic error per turn needs a rotary axis")
    if order < 1 or radial_um < 0 or angular_urad < 0:
        raise ValueError(f"order must be >= 1 and amplitudes >= 0, got {order}, {radial_um}, "
                         f"{angular_urad}")
    own = ax.name
    own_linear = {"A": "X", "B": "Y", "C": "Z"}[own]
    comps = dict(geometry.components)
    zeros = (0.0,) * (order - 1)
    for c in "XYZABC":
        if c == own:
            amp = angular_urad
        elif c == own_linear:
            amp = radial_um * float(rng.uniform(0.1, 0.4))
        elif c in "XYZ":
            amp = radial_um * float(rng.uniform(0.5, 1.0))
        else:
            amp = angular_urad * float(rng.uniform(0.1, 0.4))
        ph = float(rng.uniform(0.0, 2 * np.pi))
        term = Fourier(0.0, (*zeros, amp * float(np.sin(ph))), (*zeros, amp * float(np.cos(ph))))
        name = f"E{c}{own}"
        comps[name] = add_components(comps.get(name), term)
    return GeometricErrors(comps, geometry.locations)
