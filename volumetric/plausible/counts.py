"""Counts: how many points, machines, readings a command makes or takes.

A count is refused outside its range before anything is made, with what the range is for.
"""

from __future__ import annotations

from .limit import Implausible

__all__ = ["MAX_GENERATED_MACHINES", "MAX_TABLE_POINTS", "check_count"]

MAX_TABLE_POINTS = 100_000
"""Positions per axis of an exported table: a 1 µm step over 100 mm; an ISO 230-2 test
has tens, a controller's compensation table at most a few thousand."""
MAX_GENERATED_MACHINES = 64_000
"""Generated simulated machines: each needs its own loopback address (127.x.y.z)."""


def check_count(value: int, name: str, lo: int, hi: int, meaning: str = "") -> int:
    """``value`` within [lo, hi], else :class:`Implausible` naming ``name``."""
    if not lo <= value <= hi:
        raise Implausible(f"{name} {value}: must be within [{lo}, {hi}]{meaning}")
    return value
