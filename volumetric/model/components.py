"""Component errors with ISO 230-1 names, and the functions that describe them.

Names
-----
``E<c><K>`` is the error of axis ``K`` in direction / about axis ``<c>`` as a function of
K's own position: for X, ``EXX`` (positioning), ``EYX`` and ``EZX`` (straightness),
``EAX`` (roll), ``EBX`` (pitch), ``ECX`` (yaw); the same six for every axis, rotary axes
included (``EXC``, ``EYC`` radial, ``EZC`` axial, ``EAC``, ``EBC`` tilt, ``ECC`` angular
positioning of C). Spindle axes of multi-spindle machines (``Z1``) use their own frame:
``EXZ1``, ``EYZ1``, ``EZZ1`` along x, y1, z1 where z1 is the spindle axis direction and
y1 the base y turned with it.

``E<c>0<K>`` are the position-independent (location) errors:

* linear axes: the orientation of the line of motion. X is the reference; Y has ``EC0Y``
  (squareness to X); Z has ``EA0Z`` (to Y) and ``EB0Z`` (to X). A spindle axis ``Z1`` has
  ``EA0Z1`` and ``EB0Z1`` in its own frame.
* rotary axes: offsets and tilts of the rotation axis and its zero: for C, ``EX0C``,
  ``EY0C`` (µm), ``EA0C``, ``EB0C`` (µrad) and ``EC0C`` (zero position, µrad); likewise
  ``EY0A, EZ0A, EB0A, EC0A, EA0A`` for A and ``EX0B, EZ0B, EA0B, EC0B, EB0B`` for B.

Units and signs
---------------
Linear errors are in µm, angular errors in µrad; positions in mm (linear axes) or degrees
(rotary axes). A component error is the error of the *tool relative to the workpiece*
caused by that axis, whichever side of the base the axis is on, so a laser positioning
run on X reads ``EXX`` directly: ``EXX(x) = +5`` means the tool stands 5 µm further along
+x than commanded. Angular errors follow the right-hand rule about the base axes.
A location error of a linear axis is a right-hand rotation of its line of motion: with
``EC0Y > 0`` the Y axis leans towards -x (a +y move carries the tool by ``-EC0Y·y``
in x, i.e. the angle between +X and +Y exceeds 90°); with ``EB0Z > 0`` a +z move carries
the tool by ``+EB0Z·z`` in x; with ``EA0Z > 0`` by ``-EA0Z·z`` in y.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.machine import Axis, Machine

DIRECTIONS = ("X", "Y", "Z", "A", "B", "C")
_NAME = re.compile(r"^E([XYZABC])(0?)([XYZABC][0-9]*)$")

# Location errors per rotary axis: (two offsets ⟂ axis, two tilts ⟂ axis, zero position).
_ROTARY_LOCATIONS = {
    "A": ("Y", "Z", "B", "C", "A"),
    "B": ("X", "Z", "A", "C", "B"),
    "C": ("X", "Y", "A", "B", "C"),
}


@dataclass(frozen=True)
class Polynomial:
    """A component error as a polynomial in the normalised axis position.

    ``e(q) = sum_k c_k s**k`` with ``s = (q - origin) / scale``.

    Attributes
    ----------
    coefficients : tuple of float
        ``c_0 .. c_d`` in µm or µrad.
    origin, scale : float
        mm or degrees. The defaults give a plain polynomial in q.
    """

    coefficients: tuple[float, ...]
    origin: float = 0.0
    scale: float = 1.0

    def __post_init__(self) -> None:
        if not all(math.isfinite(c) for c in self.coefficients):
            raise ComponentErrorSpecError(f"polynomial coefficients must be finite: {self}")
        if not (math.isfinite(self.scale) and self.scale != 0 and math.isfinite(self.origin)):
            raise ComponentErrorSpecError(
                f"polynomial needs finite origin and non-zero scale: {self}"
            )

    def __call__(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        s = (np.asarray(q, dtype=float) - self.origin) / self.scale
        out = np.zeros_like(s)
        for c in reversed(self.coefficients):  # Horner
            out = out * s + c
        return out

    def to_json(self) -> dict[str, Any]:
        return {
            "type": "polynomial",
            "coefficients": list(self.coefficients),
            "origin": self.origin,
            "scale": self.scale,
        }


@dataclass(frozen=True)
class Table:
    """A component error tabulated at positions, linearly interpolated.

    Outside the table the end values hold (a controller's pitch-error table does the same).

    Attributes
    ----------
    positions : tuple of float
        Strictly increasing, mm or degrees.
    values : tuple of float
        µm or µrad at those positions.
    """

    positions: tuple[float, ...]
    values: tuple[float, ...]
    _p: NDArray[np.float64] = field(init=False, repr=False, compare=False)
    _v: NDArray[np.float64] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        p = np.asarray(self.positions, dtype=float)
        v = np.asarray(self.values, dtype=float)
        if p.ndim != 1 or p.shape != v.shape or p.size < 1:
            raise ComponentErrorSpecError("table needs as many values as positions (at least one)")
        bad = np.flatnonzero(~np.isfinite(p) | ~np.isfinite(v))
        if bad.size:
            i = int(bad[0])
            raise ComponentErrorSpecError(
                f"table entry {i}: position {float(p[i])}, value {float(v[i])} is not a finite "
                "number"
            )
        if np.any(np.diff(p) <= 0):
            i = int(np.flatnonzero(np.diff(p) <= 0)[0])
            raise ComponentErrorSpecError(
                f"table positions must increase strictly: {p[i]} then {p[i + 1]} at entry {i + 1}"
            )
        object.__setattr__(self, "_p", p)
        object.__setattr__(self, "_v", v)

    def __call__(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        out: NDArray[np.float64] = np.interp(np.asarray(q, dtype=float), self._p, self._v)
        return out

    def to_json(self) -> dict[str, Any]:
        return {"type": "table", "positions": list(self.positions), "values": list(self.values)}


@dataclass(frozen=True)
class Sinusoid:
    """A cyclic component error: ``a·sin(2π q / period + phase)``.

    Attributes
    ----------
    amplitude : float
        µm or µrad.
    period : float
        mm or degrees.
    phase : float
        rad.
    """

    amplitude: float
    period: float
    phase: float = 0.0

    def __post_init__(self) -> None:
        if not all(math.isfinite(v) for v in (self.amplitude, self.period, self.phase)):
            raise ComponentErrorSpecError(f"sinusoid parameters must be finite: {self}")
        if self.period <= 0:
            raise ComponentErrorSpecError(f"sinusoid period must be positive: {self}")

    def __call__(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        qa = np.asarray(q, dtype=float)
        phase = 2 * np.pi * qa / self.period + self.phase
        out: NDArray[np.float64] = self.amplitude * np.sin(phase)
        return out

    def to_json(self) -> dict[str, Any]:
        return {"type": "sinusoid", "amplitude": self.amplitude, "period": self.period,
                "phase": self.phase}


@dataclass(frozen=True)
class Fourier:
    """A component error periodic in a rotary axis's angle (once, twice ... per turn).

    ``e(q) = a0 + sum_k (a_k cos(k θ) + b_k sin(k θ))`` with ``θ = q·π/180`` (q in
    degrees), ``k = 1 .. len(cos)``. The error motions of a rotary table over a full turn
    (eccentricity and wobble once per turn, an elliptic bearing twice, a cyclic indexing
    error of the worm or encoder) are sums of such harmonics: a low-degree polynomial in
    the angle cannot follow them over ±180° and, unlike this basis, does not return to
    its value after a turn.

    Attributes
    ----------
    a0 : float
        Constant, µm or µrad.
    cos, sin : tuple of float
        ``a_1 .. a_K`` and ``b_1 .. b_K``, µm or µrad (the same length).
    """

    a0: float
    cos: tuple[float, ...]
    sin: tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.cos) != len(self.sin):
            raise ComponentErrorSpecError(
                f"fourier needs as many sine as cosine coefficients: {self}")
        if not all(math.isfinite(c) for c in (self.a0, *self.cos, *self.sin)):
            raise ComponentErrorSpecError(f"fourier coefficients must be finite: {self}")

    def __call__(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        theta = np.deg2rad(np.asarray(q, dtype=float))
        out: NDArray[np.float64] = np.full_like(theta, self.a0)
        for k, (a, b) in enumerate(zip(self.cos, self.sin, strict=True), start=1):
            out = out + a * np.cos(k * theta) + b * np.sin(k * theta)
        return out

    def harmonic(self, k: int) -> float:
        """Amplitude of the k-per-turn harmonic, ``hypot(a_k, b_k)`` (0 beyond K)."""
        if not 1 <= k <= len(self.cos):
            return 0.0
        return math.hypot(self.cos[k - 1], self.sin[k - 1])

    def to_json(self) -> dict[str, Any]:
        return {"type": "fourier", "a0": self.a0, "cos": list(self.cos),
                "sin": list(self.sin)}


@dataclass(frozen=True)
class Sum:
    """The sum of several component functions (a base fit plus model extensions)."""

    terms: tuple[Polynomial | Table | Sinusoid | Fourier, ...]

    def __call__(self, q: NDArray[np.float64]) -> NDArray[np.float64]:
        out = np.zeros(np.shape(q))
        for t in self.terms:
            out = out + t(q)
        return out

    def to_json(self) -> dict[str, Any]:
        return {"type": "sum", "terms": [t.to_json() for t in self.terms]}


Component = Polynomial | Table | Sinusoid | Fourier | Sum


def add_components(a: Component | None, b: Component) -> Component:
    """``a + b`` as one component (``b`` when ``a`` is None)."""
    if a is None:
        return b
    left = a.terms if isinstance(a, Sum) else (a,)
    right = b.terms if isinstance(b, Sum) else (b,)
    return Sum((*left, *right))


def component_from_json(spec: Any) -> Component:
    """One component function from its JSON form (see the ``to_json`` methods)."""
    if not isinstance(spec, Mapping):
        raise ComponentErrorSpecError("expected an object with a 'type'")
    kind = spec.get("type", "polynomial")
    if kind == "polynomial":
        return Polynomial(
            tuple(float(c) for c in spec["coefficients"]),
            float(spec.get("origin", 0.0)),
            float(spec.get("scale", 1.0)),
        )
    if kind == "table":
        return Table(
            tuple(float(c) for c in spec["positions"]),
            tuple(float(c) for c in spec["values"]),
        )
    if kind == "sinusoid":
        return Sinusoid(float(spec["amplitude"]), float(spec["period"]),
                        float(spec.get("phase", 0.0)))
    if kind == "fourier":
        return Fourier(float(spec.get("a0", 0.0)), tuple(float(c) for c in spec["cos"]),
                       tuple(float(c) for c in spec["sin"]))
    if kind == "sum":
        terms = []
        for t in spec["terms"]:
            c = component_from_json(t)
            if isinstance(c, Sum):
                raise ComponentErrorSpecError("a sum cannot contain a sum")
            terms.append(c)
        return Sum(tuple(terms))
    raise ComponentErrorSpecError(
        f"type {kind!r} is not 'polynomial', 'table', 'sinusoid', 'fourier' or 'sum'"
    )


@dataclass(frozen=True)
class ParsedName:
    """An ISO 230-1 error name taken apart: ``EC0Y`` → ('C', True, 'Y')."""

    direction: str
    location: bool
    axis: str


def parse_name(name: str) -> ParsedName:
    """Split an ISO 230-1 component or location error name.

    Raises
    ------
    ComponentErrorSpecError
        When ``name`` is not of the form ``E<c><axis>`` or ``E<c>0<axis>``.
    """
    m = _NAME.match(name)
    if not m:
        raise ComponentErrorSpecError(
            f"{name!r} is not an ISO 230-1 error name such as 'EXX', 'EBY' or 'EC0Y'"
        )
    return ParsedName(m.group(1), m.group(2) == "0", m.group(3))


def component_names(axis: Axis) -> tuple[str, ...]:
    """The six position-dependent component errors of an axis, in (X, Y, Z, A, B, C) order."""
    return tuple(f"E{c}{axis.name}" for c in DIRECTIONS)


def location_names(machine: Machine) -> tuple[str, ...]:
    """The position-independent errors the machine has (see module docstring)."""
    names: list[str] = []
    base_linear = [n for n in ("X", "Y", "Z") if n in machine.axis_names]
    # The first base linear axis is the reference; the second leans towards the first
    # (one squareness), the third has two.
    for i, k in enumerate(base_linear):
        if i == 0:
            continue
        others = [c for c in ("X", "Y", "Z") if c != k]
        if i == 1:
            first = base_linear[0]
            about = next(c for c in ("X", "Y", "Z") if c not in (k, first))
            names.append(f"E{_angle_of(about)}0{k}")
        else:
            names.extend(f"E{_angle_of(c)}0{k}" for c in others)
    for a in machine.axes:
        if a.kind == "rotary":
            off1, off2, t1, t2, zero = _ROTARY_LOCATIONS[a.name]
            names += [f"E{off1}0{a.name}", f"E{off2}0{a.name}"]
            names += [f"E{t1}0{a.name}", f"E{t2}0{a.name}", f"E{zero}0{a.name}"]
        elif a.name not in ("X", "Y", "Z"):  # spindle axis: two tilts in its own frame
            names += [f"EA0{a.name}", f"EB0{a.name}"]
    return tuple(names)


def _angle_of(linear: str) -> str:
    return {"X": "A", "Y": "B", "Z": "C"}[linear]


def is_angular(name: str) -> bool:
    """True for errors in µrad (rotations and tilts), False for µm (displacements)."""
    p = parse_name(name)
    return p.direction in ("A", "B", "C")


@dataclass(frozen=True)
class GeometricErrors:
    """The component and location errors of one machine.

    Attributes
    ----------
    components : mapping of str to Polynomial or Table
        Position-dependent errors by ISO name; missing ones are zero.
    locations : mapping of str to float
        Position-independent errors by ISO name, µm or µrad; missing ones are zero.
    """

    components: Mapping[str, Component] = field(default_factory=dict)
    locations: Mapping[str, float] = field(default_factory=dict)

    def check(self, machine: Machine) -> None:
        """Raise if a name does not belong to this machine."""
        axes = set(machine.axis_names)
        for name in self.components:
            p = parse_name(name)
            if p.location:
                raise ComponentErrorSpecError(
                    f"{name} is a position-independent (location) error: give it under "
                    "'locations' as a number, not as a function"
                )
            if p.axis not in axes:
                raise ComponentErrorSpecError(
                    f"component error {name}: machine {machine.name!r} has no axis {p.axis} "
                    f"(its axes are {' '.join(machine.axis_names)})"
                )
        allowed = set(location_names(machine))
        for name, value in self.locations.items():
            p = parse_name(name)
            if not p.location:
                raise ComponentErrorSpecError(
                    f"{name} is position-dependent: give it under 'components'"
                )
            if p.axis not in axes:
                raise ComponentErrorSpecError(
                    f"location error {name}: machine {machine.name!r} has no axis {p.axis}"
                )
            if name not in allowed:
                raise ComponentErrorSpecError(
                    f"location error {name} is not one of this machine's: {sorted(allowed)}"
                )
            if not math.isfinite(value):
                raise ComponentErrorSpecError(f"location error {name} = {value!r} is not finite")

    def link_errors(
        self, axis: Axis, q: ArrayLike
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """Translation (mm) and rotation (rad) error vectors of one axis at positions q.

        Returns ``None`` when the axis has no component errors, otherwise two arrays of
        shape (N, 3) in the axis's own frame.
        """
        names = component_names(axis)
        if not any(n in self.components for n in names):
            return None
        qa = np.asarray(q, dtype=float)
        out = np.zeros((qa.shape[0], 6))
        for j, n in enumerate(names):
            f = self.components.get(n)
            if f is not None:
                out[:, j] = f(qa)
        return out[:, :3] * 1e-3, out[:, 3:] * 1e-6

    def location(self, name: str) -> float:
        """A location error in its unit (µm or µrad); zero when absent."""
        return float(self.locations.get(name, 0.0))

    def to_json(self) -> dict[str, Any]:
        return {
            "components": {k: v.to_json() for k, v in sorted(self.components.items())},
            "locations": dict(sorted(self.locations.items())),
        }

    @staticmethod
    def from_json(data: Mapping[str, Any]) -> GeometricErrors:
        """Inverse of :meth:`to_json`; errors name the entry."""
        if not isinstance(data, Mapping):
            raise ComponentErrorSpecError("expected an object with 'components' and 'locations'")
        for key in ("components", "locations"):
            if not isinstance(data.get(key, {}), Mapping):
                raise ComponentErrorSpecError(f"{key}: expected an object keyed by ISO names")
        comps: dict[str, Component] = {}
        for name, spec in dict(data.get("components", {})).items():
            parse_name(name)
            try:
                comps[name] = component_from_json(spec)
            except KeyError as exc:
                raise ComponentErrorSpecError(f"components.{name}: missing {exc}") from None
            except ComponentErrorSpecError as exc:
                raise ComponentErrorSpecError(f"components.{name}: {exc}") from None
            except (TypeError, ValueError) as exc:
                raise ComponentErrorSpecError(f"components.{name}: {exc}") from None
        locs: dict[str, float] = {}
        for name, value in dict(data.get("locations", {})).items():
            parse_name(name)
            try:
                locs[name] = float(value)
            except (TypeError, ValueError):
                raise ComponentErrorSpecError(
                    f"locations.{name}: {value!r} is not a number"
                ) from None
        return GeometricErrors(comps, locs)
