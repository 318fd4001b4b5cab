"""Which SINUMERIK setting data to write, and when: the planner of the native link.

Pure (no I/O, no clock of its own): the caller gives the setting data it wants per axis
(:class:`~volumetric.compensate.tempcomp.AxisTempComp`, from the model's thermal terms at
the latest temperatures) and the time; :meth:`SdWritePlanner.due` answers the writes to
send now. The rules:

1. **Only changes.** A datum is written when it differs from what the NC holds (as last
   written or read back) by more than its resolution (:data:`RESOLUTION`: 0.01 µm for
   SD43900, 1e-9 mm/mm for SD43910, 1 µm for SD43920, far below what a temperature
   step moves); an axis whose data all match is not written.
2. **At most once per** ``min_interval_s`` (100 ms) **per axis**, counted from the end of
   the axis's last write (:meth:`SdWritePlanner.sent`), so the NC sees two writes of one
   axis at least that far apart whatever the network's delay. A change within the
   interval waits; the write then carries the newest value (intermediate ones are
   skipped, never queued: the NC only needs the latest state).
3. **One request per axis holds all its changed data**, so the NC never evaluates a new
   slope about an old reference.
4. **Within limits.** Values beyond :class:`~volumetric.compensate.tempcomp.
   TempCompLimits` are clamped (the computation clamps already; this is the last guard
   before the wire) and non-finite values are refused.
5. **A failed write is written again**: :meth:`SdWritePlanner.failed` forgets what the NC
   was assumed to hold for that axis; the interval still applies, lengthened by a hold
   for a write the NC refused (it will likely refuse it again until someone changes its
   machine data).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Final

from volumetric.compensate.tempcomp import AxisTempComp, TempCompLimits

__all__ = ["MIN_INTERVAL_S", "RESOLUTION", "SD_ABS_VALUE", "SD_REF_POSITION", "SD_SLOPE",
           "SdWrite", "SdWritePlanner"]

SD_ABS_VALUE: Final = 43900
SD_SLOPE: Final = 43910
SD_REF_POSITION: Final = 43920
MIN_INTERVAL_S: Final = 0.1
"""Issue 31: at most one write per axis per 100 ms (the OPC UA server samples no faster
either, and the NC spreads a change over IPO cycles by MD32760 anyway)."""
RESOLUTION: Final = {SD_ABS_VALUE: 1e-5, SD_SLOPE: 1e-9, SD_REF_POSITION: 1e-3}
"""Smallest change worth a write, per datum (mm, mm/mm, mm)."""


@dataclass(frozen=True, slots=True)
class SdWrite:
    """One axis's write: the changed data, sent in one request.

    Attributes
    ----------
    axis : str
        Upper-case axis name.
    values : tuple of (int, float)
        (SD number, value) pairs: mm for 43900 and 43920, mm/mm for 43910.
    """

    axis: str
    values: tuple[tuple[int, float], ...]


def _data(d: AxisTempComp, limits: TempCompLimits) -> dict[int, float]:
    for v in (d.offset_mm, d.slope, d.ref_mm):
        if not math.isfinite(v):
            raise ValueError(f"setting data must be finite, got {d!r}")
    return {SD_ABS_VALUE: max(-limits.max_offset_mm, min(limits.max_offset_mm, d.offset_mm)),
            SD_SLOPE: max(-limits.max_slope, min(limits.max_slope, d.slope)),
            SD_REF_POSITION: d.ref_mm}


class SdWritePlanner:
    """Rate-limited, change-only writes of SD43900/43910/43920 per axis (module docstring).

    Parameters
    ----------
    axes : iterable of str
        The NC's axes this link writes.
    limits : TempCompLimits, optional
    min_interval_s : float
        Least time between the end of one write of an axis and the start of the next, s.
    """

    def __init__(self, axes: Iterable[str], *, limits: TempCompLimits | None = None,
                 min_interval_s: float = MIN_INTERVAL_S) -> None:
        if not min_interval_s >= 0:
            raise ValueError(f"min_interval_s must be >= 0, got {min_interval_s!r}")
        self.axes = [a.upper() for a in axes]
        self.limits = limits or TempCompLimits()
        self.min_interval_s = float(min_interval_s)
        self._want: dict[str, dict[int, float]] = {}
        self._held: dict[str, dict[int, float]] = {a: {} for a in self.axes}
        self._last_s: dict[str, float] = {}
        self._in_flight: set[str] = set()

    def _axis(self, axis: str) -> str:
        a = axis.upper()
        if a not in self._held:
            raise ValueError(f"axis {axis!r} is not written by this link ({self.axes})")
        return a

    def want(self, data: Mapping[str, AxisTempComp]) -> None:
        """The setting data wanted now per axis (axes left out keep their last wish)."""
        for axis, d in data.items():
            self._want[self._axis(axis)] = _data(d, self.limits)

    def held(self, axis: str, values: Mapping[int, float]) -> None:
        """What the NC holds (read back at connect): only differences are written."""
        self._held[self._axis(axis)].update({int(k): float(v) for k, v in values.items()})

    def _changes(self, axis: str) -> tuple[tuple[int, float], ...]:
        want, held = self._want.get(axis, {}), self._held[axis]
        return tuple((n, v) for n, v in want.items()
                     if n not in held or abs(v - held[n]) > RESOLUTION[n])

    def due(self, now_s: float) -> list[SdWrite]:
        """The writes to send now; each is assumed held until :meth:`failed`. Call
        :meth:`sent` when a write's request has been answered."""
        out: list[SdWrite] = []
        for axis in self.axes:
            if axis in self._in_flight:
                continue
            last = self._last_s.get(axis)
            if last is not None and now_s - last < self.min_interval_s:
                continue
            changes = self._changes(axis)
            if not changes:
                continue
            self._held[axis].update(changes)
            self._in_flight.add(axis)
            self._last_s[axis] = now_s
            out.append(SdWrite(axis, changes))
        return out

    def sent(self, write: SdWrite, now_s: float) -> None:
        """The request of ``write`` was answered at ``now_s`` (the interval runs from
        here)."""
        self._in_flight.discard(write.axis)
        self._last_s[write.axis] = now_s

    def failed(self, write: SdWrite, now_s: float, hold_s: float = 0.0) -> None:
        """``write`` did not reach the NC (or was refused): write it again when due, and
        not before ``hold_s`` more (a refusal is not retried ten times a second)."""
        self.sent(write, now_s + max(0.0, hold_s))
        for n, _ in write.values:
            self._held[write.axis].pop(n, None)

    def next_due_s(self) -> float | None:
        """The earliest time a pending change may be written (None: nothing pending or
        only writes in flight)."""
        times = [self._last_s.get(a, float("-inf")) + self.min_interval_s
                 for a in self.axes if a not in self._in_flight and self._changes(a)]
        return min(times) if times else None
