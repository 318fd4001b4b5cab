"""Builders and checks for the property tests of the numeric core
(``tests/test_properties_core.py``).

Each check raises ``AssertionError`` with the figures when its property does not hold, so a
test can also show that the check fails on a deliberately wrong input.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from machine_sim.lookup import GridMap
from protocol.codes import MapEncoding
from protocol.mapformat import ErrorMapPayload
from volumetric.identify.fit import FitResult
from volumetric.measure.measurement import Measurements
from volumetric.model.components import Component, GeometricErrors, Polynomial
from volumetric.model.exact import VolumetricError, volumetric_error
from volumetric.model.linear import linear_volumetric_error
from volumetric.model.machine import Machine, parse_machine

F64 = NDArray[np.float64]
FirstOrder = Callable[[Machine, GeometricErrors, F64, str | None], VolumetricError]
"""A first-order model: (machine, errors, positions (N, n_axes), spindle) -> error."""

THREE_AXIS_CHAINS = ("w X Y b Z t", "w Y b X Z t", "w X b Y Z t", "w b X Y Z t")
FIVE_AXIS_CHAINS = ("w C A X b Y Z t", "w A C b X Y Z t", "w C B b X Y Z t",
                    "w X Y b Z A C t", "w b X Y Z B C t", "w C b X Y Z A t")
LINEAR_TRAVEL = {"x": [0.0, 500.0], "y": [0.0, 300.0], "z": [-300.0, 0.0]}
TILT_TRAVEL = [-90.0, 30.0]  # a swivel axis (A or B) of a trunnion or a head, degrees


def make_machine(chain: str, pivots: Mapping[str, Sequence[float]] | None = None,
                 tool_length_mm: float = 100.0) -> Machine:
    """A machine of ``chain`` on :data:`LINEAR_TRAVEL`; A and B swivel over
    :data:`TILT_TRAVEL`, C turns a full turn (the default rotary travel)."""
    travel: dict[str, list[float]] = dict(LINEAR_TRAVEL)
    for tilt in ("A", "B"):
        if tilt in chain.split():
            travel[tilt.lower()] = list(TILT_TRAVEL)
    rotary = {t for t in chain.split() if t in ("A", "B", "C")}
    return parse_machine({
        "name": "prop", "chain": chain, "travel_mm": travel, "tool_length_mm": tool_length_mm,
        "pivots_mm": {k: list(v) for k, v in (pivots or {}).items() if k in rotary},
    })


def scaled(errors: GeometricErrors, factor: float) -> GeometricErrors:
    """Every component and location error times ``factor`` (polynomial components)."""
    comps: dict[str, Component] = {}
    for name, c in errors.components.items():
        assert isinstance(c, Polynomial), f"{name}: scaled() takes polynomial components"
        comps[name] = Polynomial(tuple(factor * v for v in c.coefficients), c.origin, c.scale)
    return GeometricErrors(comps, {k: factor * v for k, v in errors.locations.items()})


def _rms(a: F64) -> float:
    return float(np.sqrt(np.mean(np.sum(a * a, axis=1))))


@dataclass(frozen=True)
class Gap:
    """Exact minus first-order volumetric error over a set of points (RMS of the norms).

    Attributes
    ----------
    position_um, orientation_urad : float
        RMS gap of the tool tip position (µm) and orientation (µrad).
    error_um, error_urad : float
        RMS of the exact error itself, same units.
    """

    position_um: float
    orientation_urad: float
    error_um: float
    error_urad: float


def linear_model(machine: Machine, errors: GeometricErrors, q: F64, spindle: str | None
                 ) -> VolumetricError:
    """The project's first-order model, :func:`linear_volumetric_error`."""
    return linear_volumetric_error(machine, errors, q, spindle=spindle)


def first_order_gap(machine: Machine, errors: GeometricErrors, q: F64,
                    first_order: FirstOrder = linear_model, spindle: str | None = None
                    ) -> Gap:
    """The gap between :func:`volumetric_error` and a first-order model at positions q."""
    ex = volumetric_error(machine, errors, q, spindle=spindle)
    li = first_order(machine, errors, q, spindle)
    assert ex.orientation_urad is not None and li.orientation_urad is not None
    return Gap(_rms(ex.position_um - li.position_um),
               _rms(ex.orientation_urad - li.orientation_urad),
               _rms(ex.position_um), _rms(ex.orientation_urad))


SECOND_ORDER_RATIO = (3.5, 4.5)
"""Halving every error divides a purely second-order gap by 4; third-order terms (relative
size ~1e-4 at these error sizes) and rounding (~1e-10 µm) stay far inside this band, a
first-order discrepancy (ratio 2) far outside."""
RELATIVE_GAP_PER_URAD = 1e-4
"""Second order over first order is of the order of the angular errors in rad (an angle
times an error): the gap may be at most this fraction of the error per µrad (or µm) of
coefficient size; measured up to about 1.1e-5 on these machines (a factor 9 of margin)."""


def assert_second_order(machine: Machine, errors: GeometricErrors, q: F64, size: float,
                        first_order: FirstOrder = linear_model,
                        spindle: str | None = None) -> None:
    """The first-order model errs by a second-order amount: halving all errors divides
    the gap by about 4, and the gap is small against the error (``size``: the typical
    coefficient, µm or µrad)."""
    full = first_order_gap(machine, errors, q, first_order, spindle)
    half = first_order_gap(machine, scaled(errors, 0.5), q, first_order, spindle)
    lo, hi = SECOND_ORDER_RATIO
    for what, a, b, err in (("position", full.position_um, half.position_um, full.error_um),
                            ("orientation", full.orientation_urad, half.orientation_urad,
                             full.error_urad)):
        assert b > 0.0, f"{what}: no gap at all at half size (the check sees nothing)"
        ratio = a / b
        assert lo <= ratio <= hi, (f"{machine.chain}: {what} gap {a:.3g} -> {b:.3g} when "
                                   f"the errors halve (ratio {ratio:.3f}, want {lo}-{hi})")
        assert a <= RELATIVE_GAP_PER_URAD * size * err, (
            f"{machine.chain}: {what} gap {a:.3g} against an error of {err:.3g}")


@dataclass(frozen=True)
class Layout:
    """Where and how a simulated campaign reads: positions in ``machine.axes`` order
    (N, n_axes), tool lengths (N,) mm, unit directions (N, 3), angle readings (N,)."""

    q: F64
    tool_mm: F64
    u: F64
    is_angle: NDArray[np.bool_]


def random_layout(machine: Machine, rng: np.random.Generator, n: int,
                  tools: tuple[float, ...] = (0.0, 150.0), angle_share: float = 0.25
                  ) -> Layout:
    """Readings at random positions and directions, with two tools and some angle readings
    (what separates the angular errors from the straightnesses)."""
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in machine.axes])
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    return Layout(q, rng.choice(np.array(tools), n), u, rng.random(n) < angle_share)


def simulated_readings(machine: Machine, layout: Layout, geometry: GeometricErrors,
                       offset_um: F64, noise_um: float, noise_urad: float,
                       rng: np.random.Generator) -> Measurements:
    """Readings of the exact volumetric error projected on each direction (plus the
    readings' zero ``offset_um`` (3,) for displacements), with Gaussian noise of standard
    deviation ``noise_um`` (displacements) and ``noise_urad`` (angles)."""
    n = layout.q.shape[0]
    ve = volumetric_error(machine, geometry, layout.q, tool_mm=layout.tool_mm)
    assert ve.orientation_urad is not None
    value = np.where(layout.is_angle,
                     np.einsum("ni,ni->n", layout.u, ve.orientation_urad)
                     + rng.normal(0.0, noise_urad, n),
                     np.einsum("ni,ni->n", layout.u, ve.position_um + offset_um)
                     + rng.normal(0.0, noise_um, n))
    q6 = np.zeros((n, 6))  # the file's x y z a b c columns
    for j, a in enumerate(machine.axes):
        q6[:, "XYZABC".index(a.name)] = layout.q[:, j]
    return Measurements(test=np.array(["random"] * n), run=np.zeros(n, np.int64),
                        time_s=np.arange(n, dtype=float), q=q6,
                        direction=np.zeros((n, 3), np.int8), tool_mm=layout.tool_mm,
                        is_angle=layout.is_angle, u=layout.u, value=value)


def normalised_errors(result: FitResult, truth: Mapping[str, float]) -> F64:
    """(estimate - truth) / stated standard uncertainty of every identified parameter."""
    return np.array([(v - truth[p.name]) / s
                     for p, v, s in zip(result.params, result.values, result.std, strict=True)])


MAX_SIGMAS = 5.0
"""No identified parameter further than this from the truth, in its stated uncertainties:
over some 100 parameters times 25 examples, |z| > 5 has a chance of about 1e-3."""
RMS_Z = (0.3, 3.0)
"""The RMS of the normalised errors: about 1 when the stated uncertainties are right; below
0.3 they are absurdly large, above 3 absurdly small."""


def assert_recovered(z: F64) -> None:
    """The identified parameters lie within their stated uncertainties of the truth."""
    worst = float(np.abs(z).max())
    rms = float(np.sqrt(np.mean(z * z)))
    assert worst <= MAX_SIGMAS, f"a parameter is {worst:.1f} σ from the truth"
    assert RMS_Z[0] <= rms <= RMS_Z[1], (f"RMS of (estimate - truth)/σ is {rms:.2f}, want "
                                         f"{RMS_Z[0]}-{RMS_Z[1]}")


def node_points(machine: Machine, payload: ErrorMapPayload) -> tuple[F64, F64]:
    """Every node of a grid payload: its grid coordinates (N, D), as the machine looks it
    up, and the machine coordinates (N, n_axes) it stands for (axes outside the grid at
    mid-travel, where the map takes their correction)."""
    mesh = np.meshgrid(*[g.start + g.step * np.arange(g.count) for g in payload.grid],
                       indexing="ij")
    grid = np.column_stack([m.ravel() for m in mesh])
    q = np.tile(0.5 * (machine.travel_lo + machine.travel_hi), (grid.shape[0], 1))
    for j, g in enumerate(payload.grid):
        q[:, machine.axis_names.index(g.name.upper())] = grid[:, j]
    return grid, q


def encoding_rounding(payload: ErrorMapPayload, exact: F64) -> F64:
    """Largest difference, mm or degrees, between a value and what the encoding carries:
    half an increment (int32 counts), half a float32 spacing at the value (float32)."""
    if payload.encoding is MapEncoding.INT32_INCREMENTS:
        return np.full(exact.shape, 0.5 * payload.increment_mm)
    spacing = np.spacing(np.abs(exact).astype(np.float32)).astype(np.float64)
    return 0.5 * spacing


def assert_nodes_match(machine: Machine, payload: ErrorMapPayload, exact: F64,
                       slack: float = 1e-12) -> None:
    """The machine's lookup at the payload's nodes returns ``exact`` (N, n_axes), the
    solver's corrections there, within the encoding's rounding (plus ``slack`` for the
    arithmetic of the lookup, mm)."""
    g = GridMap.from_payload(payload)
    grid, _ = node_points(machine, payload)
    got = g.lookup(grid)
    want = exact[:, [machine.axis_names.index(o) for o in g.outputs]]
    excess = np.abs(got - want) - encoding_rounding(payload, want)
    worst = float(excess.max())
    assert worst <= slack, (f"node value off the solver's correction by {worst:.3g} mm "
                            f"beyond the {payload.encoding.name} rounding")
