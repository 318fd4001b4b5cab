"""What a controller's cycle latency costs a position-dependent compensation in motion,
and how to remove it.

A PLC that looks the compensation up at the position it reads applies the value a few
cycles later, when the axes have moved on: at feed v along a compensation gradient ∇c the
applied value lags by about ``∇c · v · latency``. This module replays a part program's
trajectory (:func:`machine_sim.program.execute`, :meth:`Trajectory.at`) cycle by cycle
through such a loop and measures, per cycle, the tool-tip distance between what the loop
applies and what the NC should apply in that cycle (the compensation at that cycle's own
set point), for three ways of looking up:

``naive``
    the value for the cycle in which it takes effect is looked up at the set point of the
    cycle in which the PLC read the position, ``delay_cycles`` earlier (what the paper's
    PLC loop and this project's simulated controllers do);
``setpoint``
    looked up at the interpolator's set point of the cycles in which the value will be in
    effect (the middle of them, when a value holds for several NC cycles, which halves the
    worst error over the hold); an NC exposes its interpolator's coming set points, so the
    PLC can read them instead of the actual position;
``feedforward``
    the naive value plus a velocity feed-forward term: the change of the compensation
    between the last two lookups, extrapolated over the latency (``Δc / Δt · lead``), from
    positions the PLC already has. Exact on straight moves at constant feed; it overshoots
    for a few cycles at corners.

Timing (:class:`LoopTiming`): a value computed in update ``j`` reads the set point of
cycle ``u_j = j · update_cycles``, takes effect in cycle ``u_j + delay_cycles`` and holds
until the next one takes effect. Tool-tip distances use the nominal kinematics
(:func:`volumetric.model.kinematics.tool_pose`), so a rotary axis's angular lag counts with
its lever arm. Rate limits (MD32760, the Fanuc ladder's step limit) are not modelled:
at these feeds the compensation changes by well under a µm per cycle.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine

from .program import Trajectory

__all__ = ["FANUC", "LOOKUPS", "SIEMENS", "LatencyResult", "Lookup", "LoopTiming",
           "applied_corrections", "extra_error"]

F64 = NDArray[np.float64]
Lookup = Literal["naive", "setpoint", "feedforward"]
LOOKUPS: tuple[Lookup, ...] = ("naive", "setpoint", "feedforward")
Correction = Callable[[F64], F64]
"""Compensation per axis (N, n_axes), mm or degrees, at set points (N, n_axes)."""


@dataclass(frozen=True)
class LoopTiming:
    """When a looked-up compensation takes effect.

    Attributes
    ----------
    cycle_s : float
        The NC cycle in which values take effect (and the error is measured), s.
    update_cycles : int
        A new value every this many cycles.
    delay_cycles : int
        From the cycle whose set point a lookup reads to the first cycle the value is in
        effect.
    """

    cycle_s: float
    update_cycles: int
    delay_cycles: int

    def __post_init__(self) -> None:
        if not (self.cycle_s > 0 and self.update_cycles >= 1 and self.delay_cycles >= 0):
            raise ValueError(f"bad loop timing {self}")

    @property
    def lead_s(self) -> float:
        """From the position a naive lookup reads to the middle of the cycles its value
        is in effect, s: what the set-point lookup and the feed-forward make up for."""
        return (self.delay_cycles + (self.update_cycles - 1) / 2.0) * self.cycle_s


FANUC = LoopTiming(cycle_s=0.008, update_cycles=1, delay_cycles=2)
"""8 ms ladder scan: the scan reads the machine position, writes the EMZPS shift to R at
its end, and the NC takes it over with the next scan: the value acts 16 ms after the
position it was looked up at."""

SIEMENS = LoopTiming(cycle_s=0.004, update_cycles=2, delay_cycles=3)
"""4 ms interpolation cycle, PLC every 2 of them (``SiemensConfig.plc_every``): the PLC
reads the position, writes SD43900 at the end of its 8 ms cycle, the NC applies it from the
next IPO cycle: 12 ms after the position read, held for two IPO cycles."""


@dataclass(frozen=True)
class LatencyResult:
    """Per-cycle extra tool-tip error of one lookup.

    Attributes
    ----------
    time_s : ndarray (M,)
        Cycle times, s (cycles before the first value takes effect are left out).
    extra_um : ndarray (M,)
        Tool-tip distance between the applied and the right compensation, µm.
    """

    time_s: F64
    extra_um: F64

    @property
    def worst_um(self) -> float:
        return float(np.max(self.extra_um, initial=0.0))

    @property
    def rms_um(self) -> float:
        return float(np.sqrt(np.mean(self.extra_um ** 2))) if self.extra_um.size else 0.0


def applied_corrections(correction: Correction, trajectory: Trajectory, timing: LoopTiming,
                        lookup: Lookup) -> tuple[F64, F64, F64, F64]:
    """Replay the loop over the trajectory.

    Returns
    -------
    times : ndarray (M,)
        Cycle times from the first cycle with a value in effect, s.
    setpoints : ndarray (M, n_axes)
    applied : ndarray (M, n_axes)
        What the loop applies in each cycle, mm or degrees.
    right : ndarray (M, n_axes)
        The compensation at each cycle's own set point.
    """
    T, h, d = timing.cycle_s, timing.update_cycles, timing.delay_cycles
    n = int(np.ceil(float(trajectory.knots_s[-1]) / T)) + 1
    times: F64 = np.arange(n, dtype=np.float64) * T
    q = trajectory.at(times)
    right = correction(q)
    reads = np.arange(0, n, h)                      # u_j: cycles whose set point is read
    match lookup:
        case "naive":
            values = right[reads]
        case "setpoint":
            at = (reads + d + (h - 1) / 2.0) * T    # middle of the cycles it is in effect
            values = correction(trajectory.at(at))
        case "feedforward":
            now = right[reads]
            before = np.vstack([now[:1], now[:-1]])  # the previous lookup (none: no rate)
            values = now + (now - before) * (timing.lead_s / (h * T))
        case _:
            raise ValueError(f"unknown lookup {lookup!r}")
    # cycle i runs the value of the last update j with u_j + d <= i
    cycles = np.arange(n)
    j = (cycles - d) // h
    live = j >= 0
    applied = values[np.clip(j, 0, len(values) - 1)]
    return (np.asarray(times[live], dtype=np.float64), q[live], applied[live], right[live])


def extra_error(machine: Machine, correction: Correction, trajectory: Trajectory,
                timing: LoopTiming, lookup: Lookup) -> LatencyResult:
    """The extra tool-tip error each cycle of ``trajectory`` gets from the loop's latency
    with the given lookup (module docstring)."""
    times, q, applied, right = applied_corrections(correction, trajectory, timing, lookup)
    p_applied, _ = tool_pose(machine, q + applied, orientation=False)
    p_right, _ = tool_pose(machine, q + right, orientation=False)
    extra: F64 = np.linalg.norm(p_applied - p_right, axis=1) * 1000.0
    return LatencyResult(times, extra)
