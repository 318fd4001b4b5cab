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
rotary positioning            ``C-positioning``      angle about the rotary axis
R-test (ISO 10791-6)          ``C-rtest-1``          displacement along x, y and z of a ball
============================  =====================  =========================================

The R-test holds the tool tip on a ball fixed to the workpiece while the rotary axis
turns (the linear axes follow, as with RTCP: :func:`hold_tool_at`), and three sensors read
the ball's displacement along x, y and z of the workpiece frame at every angle. Balls at
two positions separate the rotary axis's location errors from its motion errors.

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

Diagonal targets and directions come from :mod:`volumetric.verify.iso230_6`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.model.kinematics import tool_pose
from volumetric.model.linear import jacobian
from volumetric.model.machine import Axis, Machine
from volumetric.model.rigid import frame_from_z
from volumetric.verify.iso230_6 import diagonal_targets, diagonal_unit_vectors

from .program import Instruction, Linear, Measure, Program, Rapid

__all__ = [
    "RTestSetup",
    "RTestSetupError",
    "angular_test",
    "axis_frame",
    "default_line",
    "diagonal_test",
    "hold_tool_at",
    "positioning_test",
    "rotary_positioning_test",
    "rtest",
    "rtest_balls",
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

    Targets and the laser direction come from :func:`volumetric.verify.iso230_6.diagonal_targets`
    and :func:`~volumetric.verify.iso230_6.diagonal_unit_vectors`; every run goes start to end
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


def hold_tool_at(machine: Machine, point: F64, fixed: Mapping[str, float], *,
                 spindle: str | None = None, tool_mm: float | None = None) -> dict[str, float]:
    """Linear axis positions that put the nominal tool tip at ``point`` (workpiece frame).

    With the rotary (and any other ``fixed``) axes given, the tool tip is an affine
    function of the base linear axes X, Y, Z, so one solve of the nominal Jacobian is
    exact.

    Raises
    ------
    ValueError
        The machine lacks a base linear axis, or a solution lies outside the travel.
    """
    names = [k for k in ("X", "Y", "Z") if k in machine.axis_names]
    if len(names) != 3:
        raise ValueError(f"machine {machine.name!r} needs X, Y and Z to hold the tool at a "
                         "point")
    q = np.zeros(len(machine.axes))
    for i, a in enumerate(machine.axes):
        lo, hi = a.travel
        q[i] = 0.0 if a.kind == "rotary" and lo <= 0 <= hi else lo
    for key, v in fixed.items():
        q[machine.axis_names.index(machine.axis(key).name)] = float(v)
    cols = [machine.axis_names.index(k) for k in names]
    p0, _ = tool_pose(machine, q[None, :], None, spindle=spindle, tool_mm=tool_mm,
                      orientation=False)
    full = jacobian(machine, q[None, :], spindle=spindle, tool_mm=tool_mm)[0]
    jac = full[:3][:, cols] * 1e-3  # µm per mm → mm per mm
    q[cols] += np.linalg.solve(jac, np.asarray(point, dtype=float) - p0[0])
    out = {}
    for j in cols:
        a = machine.axes[j]
        lo, hi = a.travel
        if not lo - 1e-6 <= q[j] <= hi + 1e-6:
            raise ValueError(f"holding the tool at {np.round(point, 3).tolist()} needs "
                             f"{a.name} = {q[j]:.3f}, outside its travel [{lo}, {hi}]")
        out[a.key] = float(min(max(q[j], lo), hi))
    return out


def _rotary_targets(axis: Axis, count: int, span_deg: float | None = None) -> F64:
    """Angles over the travel (a full turn without repeating its end), or within
    ±span_deg of the travel's angle nearest 0 when given."""
    lo, hi = axis.travel
    if span_deg is not None:
        # Around 0 when the travel holds it (the usual set-up angle), else around the end
        # nearest 0: a travel of [-120, -60] must not get the empty window [-30, 30].
        centre = min(max(0.0, lo), hi)
        lo, hi = max(lo, centre - span_deg), min(hi, centre + span_deg)
        return np.linspace(lo, hi, count)
    if hi - lo >= 360.0 - 1e-9:  # a full turn: the last target would repeat the first
        return np.linspace(lo, lo + 360.0, count + 1)[:-1]
    margin = 0.05 * (hi - lo)
    return np.linspace(lo + margin, hi - margin, count)


def rotary_positioning_test(
    machine: Machine, axis: str, *, targets: int = 12, runs: int = 2,
    line: Mapping[str, float] | None = None, settle_s: float = 3.0,
    feed_deg_min: float = 1800.0, overrun_deg: float = 3.0,
) -> Program:
    """Angular positioning of a rotary axis (ISO 230-2 for rotary axes, with an indexing
    table or autocollimator): ``<AX>-positioning``, quantity ``angle`` about the axis."""
    ax = machine.axis(axis)
    if ax.kind != "rotary":
        raise ValueError(f"axis {ax.name} is linear; use positioning_test")
    setup = default_line(machine, [ax.name]) if line is None else dict(line)
    t = _rotary_targets(ax, targets)[:, None]
    lo, hi = np.array([ax.travel[0]]), np.array([ax.travel[1]])
    prog: list[Instruction] = []
    d = ax.direction
    for run in range(1, runs + 1):
        reads = [Measure(f"{ax.name}-positioning", run, "angle", (d[0], d[1], d[2]),
                         settle_s)] * t.shape[0]
        prog += _cycle(t, [ax.key], lo, hi, setup, reads, np.array([overrun_deg]),
                       feed_deg_min)
    return prog


def rtest(
    machine: Machine, axis: str, ball_mm: Sequence[float] | F64, *, label: str | None = None,
    targets: int = 12, angles_deg: Sequence[float] | F64 | None = None, runs: int = 1,
    line: Mapping[str, float] | None = None,
    tool_mm: float | None = None, spindle: str | None = None, settle_s: float = 3.0,
    feed_mm_min: float = 2000.0,
) -> Program:
    """R-test of a rotary axis with the ball at ``ball_mm`` (workpiece frame, mm).

    At every angle (``targets`` over the travel, or ``angles_deg``; bidirectional: up
    through them, then down) the linear axes put the nominal tool tip on the ball
    (:func:`hold_tool_at`) and three readings follow: displacement along x, y and z.
    Label ``<AX>-rtest`` unless given.

    Raises
    ------
    ValueError
        A rotary position at which the ball is out of the linear axes' reach.
    """
    ax = machine.axis(axis)
    if ax.kind != "rotary":
        raise ValueError(f"axis {ax.name} is linear; the R-test turns a rotary axis")
    name = label or f"{ax.name}-rtest"
    setup = default_line(machine, [ax.name, "X", "Y", "Z"]) if line is None else dict(line)
    ball = np.asarray(ball_mm, dtype=float)
    angles = (_rotary_targets(ax, targets) if angles_deg is None
              else np.asarray(angles_deg, dtype=float))
    holds = [hold_tool_at(machine, ball, {**setup, ax.key: float(a)}, spindle=spindle,
                          tool_mm=tool_mm) for a in angles]
    prog: list[Instruction] = [Rapid({**setup, **holds[0], ax.key: float(angles[0])})]
    for run in range(1, runs + 1):
        for i in [*range(len(angles)), *range(len(angles) - 2, -1, -1)]:
            prog.append(Linear({**holds[i], ax.key: float(angles[i])}, feed_mm_min))
            for j, u in enumerate(((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))):
                # three sensors read at once: only the first waits for the settling
                prog.append(Measure(name, run, "displacement", u, settle_s if j == 0 else 0.0,
                                    tool_mm, spindle))
    return prog


class RTestSetupError(ValueError):
    """No R-test set-up fits the machine's travels (the message says which axis)."""


@dataclass(frozen=True)
class RTestSetup:
    """Where an R-test's ball sits (workpiece frame, mm), the tool length probing it
    (None: the branch's) and the rotary positions visited (degrees)."""

    ball_mm: F64
    tool_mm: float | None
    angles_deg: F64


def rtest_balls(machine: Machine, axis: str, *, targets: int = 12) -> list[RTestSetup]:
    """Two R-test set-ups the machine can reach.

    A rotary axis that carries the workpiece gets two balls on opposite sides of its axis
    at different heights, near the tool tip's mid-travel position; one that carries the
    tool gets one ball at that position, probed with two tool lengths. Radii shrink from
    150 mm, and angle ranges from the full travel to ±60° and ±30°, until every position
    is within reach of the linear axes; for a workpiece axis the pair of balls also turns
    about the axis in 30° steps, and when no opposite pair fits (an axis at the edge of
    the linear travel) both balls go on one side, the second at half the radius.

    Raises
    ------
    RTestSetupError
        Nothing down to 10 mm and ±30° fits the travels.
    """
    ax = machine.axis(axis)
    d = np.asarray(ax.direction, dtype=float)
    e1 = np.cross(d, [0.0, 0.0, 1.0] if abs(d[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    branch = machine.branch(None)
    mid = default_line(machine, [ax.name], fraction=0.5)
    q = np.array([0.0 if a.kind == "rotary" else mid.get(a.key, 0.0) for a in machine.axes])
    tip = tool_pose(machine, q[None, :], None, orientation=False)[0][0]
    c = np.asarray(ax.pivot_mm, dtype=float)
    foot = c + float((tip - c) @ d) * d  # the point of the axis nearest the mid tool tip
    spans: list[float | None] = [None, 60.0, 30.0]
    # Passes: the opposite pair as it always was (so every machine that had a set-up keeps
    # it, and its campaign), then that pair turned about the axis in 30° steps, then, for
    # an axis at the edge of the linear travel, both balls on one side (the second at half
    # the radius and raised, so radial and axial errors still separate).
    passes: list[list[tuple[int, float]]] = [[(0, -1.0)]]
    if ax.side == "workpiece":
        passes += [[(t, -1.0) for t in range(30, 180, 30)],
                   [(t, 0.5) for t in range(0, 360, 30)]]
    for turns in passes:
        for span in spans:
            angles = _rotary_targets(ax, targets, span)
            for radius in (150.0, 100.0, 50.0, 25.0, 10.0):
                for turn, second in turns:
                    if ax.side == "workpiece":
                        phi = np.radians(turn)
                        e = np.cos(phi) * e1 + np.sin(phi) * e2
                        setups = [RTestSetup(foot + radius * e, None, angles),
                                  RTestSetup(foot + second * radius * e + 0.5 * radius * d,
                                             None, angles)]
                    else:
                        setups = [RTestSetup(tip, None, angles),
                                  RTestSetup(tip - radius * np.asarray(branch.tool_direction),
                                             branch.tool_length_mm + radius, angles)]
                    if _reachable(machine, setups, mid, ax.key):
                        return setups
    lo, hi = ax.travel
    raise RTestSetupError(
        f"no R-test set-up for axis {ax.name} of {machine.name}: no pair of balls 10-150 mm "
        f"from the axis stays within the linear travels over ±30° of its travel "
        f"[{lo:g}, {hi:g}]°; check the axis's pivot (pivots_mm) against the linear travels")


def _reachable(machine: Machine, setups: list[RTestSetup], mid: Mapping[str, float],
               key: str) -> bool:
    """Whether the linear axes can hold the tool on every ball at every angle."""
    try:
        for st in setups:
            for a in st.angles_deg:
                hold_tool_at(machine, st.ball_mm, {**mid, key: float(a)}, tool_mm=st.tool_mm)
    except ValueError:
        return False
    return True
