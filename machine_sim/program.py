"""A motion executor for simple part programs: rapid and linear moves, dwell, spindle.

A program is a sequence of instructions; executing it gives a time-stamped trajectory
(positions at segment ends, straight lines in between), the spindle speed over time, and
a mark at each :class:`Measure` with the time, position and each axis's last direction of
motion (what the measurement CSV's ``dir_*`` columns hold and backlash depends on).

Timing: a move takes ``overhead_s`` (acceleration and settling) plus its length over the
speed: rapids run every axis at its rapid rate together (the slowest axis sets the time),
linear moves run the Euclidean length of the linear axes at the feed (rotary-only moves:
degrees at the feed read as deg/min). A :class:`Measure` waits ``settle_s`` (the
instrument averages) and reads at the end of it. Targets outside an axis's travel are an
error naming the instruction, not a clamp.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.machine import Machine

__all__ = [
    "Dwell",
    "Instruction",
    "Linear",
    "MachineState",
    "Mark",
    "Measure",
    "MotionLimits",
    "Program",
    "ProgramError",
    "Rapid",
    "SpindleOff",
    "SpindleOn",
    "Trajectory",
    "concatenate",
    "execute",
]

F64 = NDArray[np.float64]
TRAVEL_TOL = 1e-6  # mm or degrees: targets computed by float arithmetic may touch the ends


class ProgramError(ValueError):
    """A program the machine cannot run; the text names the instruction and the axis."""


@dataclass(frozen=True)
class Rapid:
    """Move at rapid rate; ``target`` by axis key (``{"x": 100.0}``), others stay."""

    target: Mapping[str, float]


@dataclass(frozen=True)
class Linear:
    """Move in a straight line at ``feed_mm_min``; ``target`` by axis key."""

    target: Mapping[str, float]
    feed_mm_min: float


@dataclass(frozen=True)
class Dwell:
    """Wait ``seconds``."""

    seconds: float


@dataclass(frozen=True)
class SpindleOn:
    """Run the spindle at ``rpm``."""

    rpm: float


@dataclass(frozen=True)
class SpindleOff:
    """Stop the spindle."""


@dataclass(frozen=True)
class Measure:
    """Take one instrument reading here after ``settle_s``.

    Attributes
    ----------
    test : str
        CSV ``test`` label.
    run : int
        CSV ``run``.
    quantity : {"displacement", "angle"}
    u : tuple of 3 float
        Sensing direction (displacement) or rotation axis (angle), unit length.
    settle_s : float
    tool_mm : float or None
        Length of the tool (or the reflector's offset from the gauge line); None for the
        branch's default.
    spindle : str or None
        Tool branch on a multi-spindle machine.
    """

    test: str
    run: int
    quantity: Literal["displacement", "angle"]
    u: tuple[float, float, float]
    settle_s: float = 2.0
    tool_mm: float | None = None
    spindle: str | None = None


Instruction = Rapid | Linear | Dwell | SpindleOn | SpindleOff | Measure
Program = Sequence[Instruction]


@dataclass(frozen=True)
class MotionLimits:
    """Rates of the simulated machine."""

    rapid_mm_min: float = 15000.0
    rapid_deg_min: float = 3600.0
    overhead_s: float = 0.4


@dataclass(frozen=True)
class MachineState:
    """Where the machine is: time (s), positions (n_axes,), last directions, spindle."""

    time_s: float
    q: F64
    direction: NDArray[np.int8]
    spindle_rpm: float = 0.0

    @staticmethod
    def home(machine: Machine, q: Mapping[str, float] | None = None) -> MachineState:
        """At time 0, at the start of every travel (or ``q``), no direction yet."""
        pos = machine.travel_lo.copy()
        for i, a in enumerate(machine.axes):
            if a.kind == "rotary":
                pos[i] = 0.0
        for key, v in (q or {}).items():
            pos[machine.axis_names.index(machine.axis(key).name)] = float(v)
        return MachineState(0.0, pos, np.zeros(len(machine.axes), dtype=np.int8))


@dataclass(frozen=True)
class Mark:
    """A reading taken during execution."""

    time_s: float
    q: F64
    direction: NDArray[np.int8]
    spindle_rpm: float
    measure: Measure


@dataclass(frozen=True)
class Trajectory:
    """Piecewise-linear motion over time.

    Attributes
    ----------
    knots_s : ndarray, shape (K,)
        Segment boundaries, s, non-decreasing.
    q : ndarray, shape (K, n_axes)
        Positions at the knots, mm or degrees.
    rpm : ndarray, shape (K,)
        Spindle speed held from each knot to the next.
    marks : tuple of Mark
    final : MachineState
    """

    knots_s: F64
    q: F64
    rpm: F64
    marks: tuple[Mark, ...]
    final: MachineState

    def at(self, times_s: ArrayLike) -> F64:
        """The interpolator's set points at ``times_s`` (M,): positions (M, n_axes), mm or
        degrees, linear between knots (held before the first and after the last).

        Two knots at one time (a spindle command) carry the same position, so the
        interpolation is well defined there.
        """
        t = np.asarray(times_s, dtype=float)
        out = np.empty((t.shape[0], self.q.shape[1]))
        for j in range(self.q.shape[1]):
            out[:, j] = np.interp(t, self.knots_s, self.q[:, j])
        return out

    def loads(self, grid_s: F64, machine: Machine) -> tuple[F64, dict[str, F64]]:
        """Mean spindle speed (rpm) and axis speeds (m/min, by axis key) over grid steps.

        Step m runs from ``grid_s[m]`` to ``grid_s[m + 1]``; the last value repeats the one
        before it. Exact for piecewise-constant spindle speed and linear motion.
        """
        dt = np.diff(self.knots_s)
        revs = np.concatenate([[0.0], np.cumsum(self.rpm[:-1] * dt / 60.0)])
        dist = np.vstack([np.zeros(self.q.shape[1]),
                          np.cumsum(np.abs(np.diff(self.q, axis=0)), axis=0)])

        def mean_rate(cum: F64) -> F64:
            c = np.interp(grid_s, self.knots_s, cum)
            r = np.diff(c) / np.diff(grid_s)
            return np.append(r, r[-1] if r.size else 0.0)

        rpm = mean_rate(revs) * 60.0
        speeds = {a.key: mean_rate(dist[:, j]) * 60.0 / 1000.0
                  for j, a in enumerate(machine.axes)}
        return rpm, speeds


@dataclass
class _Builder:
    knots: list[float] = field(default_factory=list)
    q: list[F64] = field(default_factory=list)
    rpm: list[float] = field(default_factory=list)
    marks: list[Mark] = field(default_factory=list)

    def add(self, state: MachineState) -> None:
        self.knots.append(state.time_s)
        self.q.append(state.q.copy())
        self.rpm.append(state.spindle_rpm)


def _target(machine: Machine, state: MachineState, target: Mapping[str, float],
            where: str) -> F64:
    q = state.q.copy()
    for key, v in target.items():
        try:
            axis = machine.axis(key)
        except KeyError as exc:
            raise ProgramError(f"{where}: {exc.args[0]}") from None
        j = machine.axis_names.index(axis.name)
        value = float(v)
        lo, hi = axis.travel
        if not np.isfinite(value) or value < lo - TRAVEL_TOL or value > hi + TRAVEL_TOL:
            raise ProgramError(f"{where}: axis {axis.name} target {value!r} is outside its "
                               f"travel [{lo}, {hi}]")
        q[j] = min(max(value, lo), hi)
    return q


def execute(
    machine: Machine,
    program: Program,
    *,
    start: MachineState | None = None,
    limits: MotionLimits | None = None,
) -> Trajectory:
    """Run a program and record its motion.

    Parameters
    ----------
    machine : Machine
    program : sequence of Instruction
    start : MachineState, optional
        Where the machine is when the program starts (``MachineState.home`` by default);
        pass the previous trajectory's ``final`` to chain programs.
    limits : MotionLimits, optional

    Returns
    -------
    Trajectory

    Raises
    ------
    ProgramError
        An unknown axis, a target outside the travel, a non-positive feed, a negative
        dwell, a negative spindle speed, an unknown instruction.
    """
    lim = limits or MotionLimits()
    state = start or MachineState.home(machine)
    rotary = np.array([a.kind == "rotary" for a in machine.axes])
    b = _Builder()
    b.add(state)
    for i, ins in enumerate(program):
        where = f"instruction {i} ({type(ins).__name__})"
        match ins:
            case Rapid(target=target):
                q = _target(machine, state, target, where)
                delta = np.abs(q - state.q)
                rate = np.where(rotary, lim.rapid_deg_min, lim.rapid_mm_min) / 60.0
                state = _move(state, q, float(np.max(delta / rate, initial=0.0)), lim)
            case Linear(target=target, feed_mm_min=feed):
                if not (np.isfinite(feed) and feed > 0):
                    raise ProgramError(f"{where}: feed must be > 0 mm/min, got {feed!r}")
                q = _target(machine, state, target, where)
                delta = q - state.q
                length = float(np.linalg.norm(delta[~rotary]))
                if length == 0.0:
                    length = float(np.linalg.norm(delta[rotary]))
                state = _move(state, q, length / (feed / 60.0), lim)
            case Dwell(seconds=s):
                if not (np.isfinite(s) and s >= 0):
                    raise ProgramError(f"{where}: dwell must be >= 0 s, got {s!r}")
                state = replace(state, time_s=state.time_s + s)
            case SpindleOn(rpm=rpm):
                if not (np.isfinite(rpm) and rpm >= 0):
                    raise ProgramError(f"{where}: spindle speed must be >= 0, got {rpm!r}")
                b.add(state)
                state = replace(state, spindle_rpm=float(rpm))
            case SpindleOff():
                b.add(state)
                state = replace(state, spindle_rpm=0.0)
            case Measure(settle_s=s):
                if not (np.isfinite(s) and s >= 0):
                    raise ProgramError(f"{where}: settle_s must be >= 0, got {s!r}")
                u = np.asarray(ins.u, dtype=float)
                if u.shape != (3,) or abs(float(np.linalg.norm(u)) - 1.0) > 1e-9:
                    raise ProgramError(f"{where}: u = {ins.u!r} is not a unit vector")
                state = replace(state, time_s=state.time_s + s)
                b.marks.append(Mark(state.time_s, state.q.copy(), state.direction.copy(),
                                    state.spindle_rpm, ins))
            case _:
                raise ProgramError(f"{where}: not an instruction this executor knows")
        b.add(state)
    return Trajectory(np.array(b.knots), np.array(b.q), np.array(b.rpm), tuple(b.marks), state)


def _move(state: MachineState, q: F64, seconds: float, lim: MotionLimits) -> MachineState:
    delta = q - state.q
    moved = np.abs(delta) > 1e-12
    if not np.any(moved):
        return state
    direction = np.where(moved, np.sign(delta), state.direction).astype(np.int8)
    return MachineState(state.time_s + seconds + lim.overhead_s, q, direction,
                        state.spindle_rpm)


def concatenate(parts: Sequence[Trajectory]) -> Trajectory:
    """Trajectories run one after the other (each starting at the previous ``final``)."""
    if not parts:
        raise ValueError("concatenate needs at least one trajectory")
    return Trajectory(
        np.concatenate([p.knots_s for p in parts]),
        np.vstack([p.q for p in parts]),
        np.concatenate([p.rpm for p in parts]),
        tuple(m for p in parts for m in p.marks),
        parts[-1].final,
    )
