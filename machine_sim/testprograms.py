"""The standard measurement test programs, as part programs with readings.

Every function returns one :data:`~machine_sim.program.Program` whose :class:`Measure`
instructions carry the CSV labels:

============================  =====================  =========================================
test                          label                  reading
============================  =====================  =========================================
laser positioning (ISO 230-2)  ``X-positioning``      displacement along the axis
straightness                  ``X-straightness-Y``   displacement along the sensed direction
angular                       ``X-angular-B``        angle about B's axis (y): X's pitch
body diagonal (ISO 230-6)     ``diag-PPP``           displacement along the diagonal
============================  =====================  =========================================

Angular labels name the rotation axis: for X, ``-A`` is roll, ``-B`` pitch, ``-C`` yaw;
for Y, ``-B`` roll, ``-A`` pitch, ``-C`` yaw; for Z, ``-C`` roll and ``-A``/``-B`` the two
tilts. A spindle axis such as ``Z1`` uses its own frame: ``Z1-straightness-Y1`` senses
along y1 (the base y turned with the spindle).

Set-ups are those of a real laser measurement: the beam lies on a line *offset* from the
axis line (the other axes stand at ``line`` positions, by default the middle of their
travel) and the reflector sits at ``tool_mm`` below the gauge line, so Abbe offsets
couple the angular errors into every reading. Each run is an ISO 230-2 linear cycle:
every target approached from below (through an overrun below the first target), then every
target approached from above (through an overrun past the last). Positioning targets can
carry ISO 230-2's random offsets so periodic errors are not sampled at one phase.

Diagonal targets and directions come from :mod:`volumetric.iso230_6`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.iso230_6 import diagonal_targets, diagonal_unit_vectors
from volumetric.machine import Axis, Machine
from volumetric.rigid import frame_from_z

from .program import Instruction, Linear, Measure, Program, Rapid

__all__ = [
    "angular_test",
    "axis_frame",
    "default_line",
    "diagonal_test",
    "positioning_test",
    "straightness_test",
    "targets_along",
]

F64 = NDArray[np.float64]
OWN = {"X": 0, "Y": 1, "Z": 2}


def axis_frame(axis: Axis) -> F64:
    """Columns: the axis's own x, y, z error directions in the base frame, shape (3, 3).

    Identity for base axes; for a spindle axis the rotation taking z onto its direction.
    """
    if axis.name in ("X", "Y", "Z", "A", "B", "C"):
        return np.eye(3)
    return frame_from_z(np.asarray(axis.direction, dtype=float))


def _own_index(axis: Axis) -> int:
    return OWN.get(axis.name, 2)


def default_line(machine: Machine, moving: Sequence[str], *, fraction: float = 0.5
                 ) -> dict[str, float]:
    """Positions of the axes that do not move: ``fraction`` of their travel, rotary at 0."""
    out: dict[str, float] = {}
    names = {machine.axis(m).name for m in moving}
    for a in machine.axes:
        if a.name in names:
            continue
        lo, hi = a.travel
        out[a.key] = 0.0 if a.kind == "rotary" and lo <= 0 <= hi else lo + fraction * (hi - lo)
    return out


def targets_along(axis: Axis, count: int, *, margin_mm: float | None = None,
                  rng: np.random.Generator | None = None) -> F64:
    """``count`` targets spread over the travel, optionally with ISO 230-2 random offsets.

    The first and last targets stay ``margin_mm`` (default 2 % of travel, at least 2 mm)
    inside the travel so both approach directions fit an overrun. With ``rng`` every
    interior target moves by up to ±30 % of the spacing.
    """
    if count < 2:
        raise ValueError(f"a test needs at least 2 targets, got {count}")
    lo, hi = axis.travel
    span = hi - lo
    m = max(0.02 * span, 2.0) if margin_mm is None else margin_mm
    if span <= 2 * m:
        raise ValueError(f"axis {axis.name}: travel {span:g} mm leaves nothing inside a "
                         f"margin of {m:g} mm")
    t = np.linspace(lo + m, hi - m, count)
    if rng is not None and count > 2:
        step = (t[-1] - t[0]) / (count - 1)
        t[1:-1] += rng.uniform(-0.3, 0.3, count - 2) * step
    return t


def _cycle(points: F64, keys: Sequence[str], lows: F64, highs: F64, line: Mapping[str, float],
           make: Sequence[Measure], overrun: F64, feed: float) -> list[Instruction]:
    """One ISO 230-2 linear cycle over ``points`` (n, k) for axes ``keys``.

    ``make[i]`` is the reading to take at point i on the way up (its twin on the way down
    is the same). ``overrun`` (k,) is the overrun distance (mm) per axis, signed along the
    forward direction of travel.
    """
    first = np.clip(points[0] - overrun, lows, highs)
    last = np.clip(points[-1] + overrun, lows, highs)
    prog: list[Instruction] = [Rapid({**line, **dict(zip(keys, first.tolist(), strict=True))})]
    for i in range(points.shape[0]):
        prog.append(Linear(dict(zip(keys, points[i].tolist(), strict=True)), feed))
        prog.append(make[i])
    prog.append(Linear(dict(zip(keys, last.tolist(), strict=True)), feed))
    for i in range(points.shape[0] - 1, -1, -1):
        prog.append(Linear(dict(zip(keys, points[i].tolist(), strict=True)), feed))
        prog.append(make[i])
    return prog


def _single_axis_test(
    machine: Machine, axis_name: str, label: str, quantity: Literal["displacement", "angle"],
    u: F64, targets: F64, runs: int, line: Mapping[str, float] | None,
    tool_mm: float | None, spindle: str | None, overrun_mm: float, settle_s: float,
    feed_mm_min: float,
) -> Program:
    axis = machine.axis(axis_name)
    if axis.kind != "linear":
        raise ValueError(f"axis {axis.name} is rotary; these tests run linear axes")
    if runs < 1:
        raise ValueError(f"runs must be >= 1, got {runs}")
    branch = spindle
    if branch is None and axis.name not in ("X", "Y", "Z"):
        branch = next(b.name for b in machine.branches if axis in b.links)
    setup = default_line(machine, [axis.name]) if line is None else dict(line)
    uu = (float(u[0]), float(u[1]), float(u[2]))
    pts = np.asarray(targets, dtype=float)[:, None]
    lo, hi = np.array([axis.travel[0]]), np.array([axis.travel[1]])
    prog: list[Instruction] = []
    for run in range(1, runs + 1):
        reads = [Measure(label, run, quantity, uu, settle_s, tool_mm, branch)] * pts.shape[0]
        prog += _cycle(pts, [axis.key], lo, hi, setup, reads, np.array([overrun_mm]),
                       feed_mm_min)
    return prog


def positioning_test(
    machine: Machine, axis: str, *, targets: int | Sequence[float] | F64 = 21, runs: int = 5,
    line: Mapping[str, float] | None = None, tool_mm: float | None = None,
    spindle: str | None = None, overrun_mm: float = 3.0, settle_s: float = 4.0,
    feed_mm_min: float = 3000.0, rng: np.random.Generator | None = None,
    label: str | None = None,
) -> Program:
    """ISO 230-2 bidirectional positioning of a linear axis: ``<AX>-positioning``.

    Parameters
    ----------
    machine : Machine
    axis : str
        Axis name or key.
    targets : int or sequence of float
        Number of targets (spread by :func:`targets_along`, with random offsets when
        ``rng`` is given) or the target positions themselves (mm).
    runs : int
        Bidirectional cycles (ISO 230-2 asks for 5).
    line : mapping, optional
        Positions of the other axes (mm, degrees); :func:`default_line` by default.
    tool_mm : float, optional
        Reflector offset below the gauge line; the branch's tool length by default.
    spindle : str, optional
        Tool branch (multi-spindle machines; a spindle axis picks its own branch).
    overrun_mm, settle_s, feed_mm_min : float
    label : str, optional
        Test label; ``<AX>-positioning`` by default.
    """
    ax = machine.axis(axis)
    t = targets_along(ax, targets, rng=rng) if isinstance(targets, int) else np.asarray(
        targets, dtype=float)
    u = axis_frame(ax)[:, _own_index(ax)]
    return _single_axis_test(machine, ax.name, label or f"{ax.name}-positioning",
                             "displacement", u, t, runs, line, tool_mm, spindle,
                             overrun_mm, settle_s, feed_mm_min)


def straightness_test(
    machine: Machine, axis: str, sense: str, *, targets: int | Sequence[float] | F64 = 21,
    runs: int = 2, line: Mapping[str, float] | None = None, tool_mm: float | None = None,
    spindle: str | None = None, overrun_mm: float = 3.0, settle_s: float = 3.0,
    feed_mm_min: float = 3000.0,
) -> Program:
    """Straightness of ``axis`` sensed along ``sense`` (``"Y"``; ``"Y1"`` for a spindle
    axis's own y): ``<AX>-straightness-<SENSE>``. Same parameters as
    :func:`positioning_test`."""
    ax = machine.axis(axis)
    letter = sense[:1].upper()
    if letter not in OWN or OWN[letter] == _own_index(ax):
        raise ValueError(f"straightness of {ax.name} needs a sense across it, got {sense!r}")
    u = axis_frame(ax)[:, OWN[letter]]
    t = targets_along(ax, targets) if isinstance(targets, int) else np.asarray(targets, float)
    return _single_axis_test(machine, ax.name, f"{ax.name}-straightness-{sense.upper()}",
                             "displacement", u, t, runs, line, tool_mm, spindle,
                             overrun_mm, settle_s, feed_mm_min)


def angular_test(
    machine: Machine, axis: str, about: str, *, targets: int | Sequence[float] | F64 = 21,
    runs: int = 2, line: Mapping[str, float] | None = None, tool_mm: float | None = None,
    spindle: str | None = None, overrun_mm: float = 3.0, settle_s: float = 3.0,
    feed_mm_min: float = 3000.0,
) -> Program:
    """Angular error of ``axis`` about ``about`` (``"A"``, ``"B"``, ``"C"``: rotation about
    the own x, y, z): ``<AX>-angular-<ABOUT>``, quantity ``angle``. Same parameters as
    :func:`positioning_test`."""
    ax = machine.axis(axis)
    letter = about.upper()
    if letter not in ("A", "B", "C"):
        raise ValueError(f"angular test: about must be A, B or C, got {about!r}")
    u = axis_frame(ax)[:, "ABC".index(letter)]
    t = targets_along(ax, targets) if isinstance(targets, int) else np.asarray(targets, float)
    return _single_axis_test(machine, ax.name, f"{ax.name}-angular-{letter}", "angle", u, t,
                             runs, line, tool_mm, spindle, overrun_mm, settle_s, feed_mm_min)


def diagonal_test(
    machine: Machine, label: str, *, points: int = 21, runs: int = 3,
    margin_mm: float = 10.0, line: Mapping[str, float] | None = None,
    tool_mm: float | None = None, spindle: str | None = None, overrun_mm: float = 3.0,
    settle_s: float = 4.0, feed_mm_min: float = 3000.0,
) -> Program:
    """ISO 230-6 body diagonal ``label`` (``diag-PPP``, ``diag-NPP``, ``diag-PNP``,
    ``diag-PPN``): all three base axes move together; readings along the diagonal.

    Targets and the laser direction come from :func:`volumetric.iso230_6.diagonal_targets`
    and :func:`~volumetric.iso230_6.diagonal_unit_vectors`; every run goes start to end
    then back, through overruns along the diagonal.
    """
    missing = [k for k in ("X", "Y", "Z") if k not in machine.axis_names]
    if missing:
        raise ValueError(f"machine {machine.name!r} has no {'/'.join(missing)} axis for a "
                         "body diagonal")
    travel = {k.lower(): machine.axis(k).travel for k in ("X", "Y", "Z")}
    all_targets = diagonal_targets(travel, points, margin_mm)
    if label not in all_targets:
        raise ValueError(f"unknown diagonal {label!r}; expected one of {sorted(all_targets)}")
    pts = all_targets[label]
    u = diagonal_unit_vectors(travel, margin_mm)[label]
    lows = np.array([travel[k][0] for k in "xyz"])
    highs = np.array([travel[k][1] for k in "xyz"])
    setup = default_line(machine, ["X", "Y", "Z"]) if line is None else dict(line)
    uu = (float(u[0]), float(u[1]), float(u[2]))
    prog: list[Instruction] = []
    for run in range(1, runs + 1):
        reads = [Measure(label, run, "displacement", uu, settle_s, tool_mm, spindle)]
        prog += _cycle(pts, ["x", "y", "z"], lows, highs, setup, reads * pts.shape[0],
                       overrun_mm * u, feed_mm_min)
    return prog
