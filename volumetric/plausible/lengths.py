"""Lengths and travels, mm: axis travels, positions, tool lengths, pivots.

100 m is beyond the largest gantry; a tool of 10 m is no tool. The slips:

* µm for mm: an 800 mm travel written as 800 000, refused and named;
* metres for mm: an 800 mm travel written as 0.8, inside the range; a machine whose every
  linear axis travels at most :data:`METRES_SPAN_MM` is refused as metres (no machine
  tool is that small, and every map and campaign over it would be meaningless), a single
  axis under :data:`SHORT_SPAN_MM` is warned about;
* inches: 31.5 for 800 mm is a plausible small machine; only a column or option that
  names inches (``x_in``) can tell (:mod:`volumetric.plausible.columns`).
"""

from __future__ import annotations

from collections.abc import Sequence

from .limit import Limit, Slip, likely_unit, looks_like

__all__ = ["LINEAR_POSITION", "METRES_SPAN_MM", "SHORT_SPAN_MM", "TOOL_LENGTH",
           "length_cause", "linear_travels_problem", "short_travel_warning"]

LINEAR_POSITION = Limit(-100_000.0, 100_000.0, "mm", "a linear position")
TOOL_LENGTH = Limit(0.0, 10_000.0, "mm", "a tool length")
METRES_SPAN_MM = 2.0
SHORT_SPAN_MM = 10.0
_TYPICAL_MM = (-20_000.0, 20_000.0)
_TOO_LARGE = (Slip("µm", 1e-3, fix="divide by 1000"),)


def length_cause(values: Sequence[float]) -> str | None:
    """The likely unit of lengths too large for mm, or None."""
    return looks_like(likely_unit(values, _TOO_LARGE, _TYPICAL_MM), "mm", "they look")


def linear_travels_problem(travels: dict[str, tuple[float, float]]) -> str | None:
    """Why these linear travels (key to (low, high), mm) are metres, or None: every one
    spans at most :data:`METRES_SPAN_MM`."""
    if not travels or any(hi - lo > METRES_SPAN_MM for lo, hi in travels.values()):
        return None
    shown = ", ".join(f"{k} [{lo:g}, {hi:g}]" for k, (lo, hi) in travels.items())
    as_mm = ", ".join(f'"{k}": [{lo * 1000:g}, {hi * 1000:g}]'
                      for k, (lo, hi) in travels.items())
    return (f"travel_mm: every linear axis travels at most {METRES_SPAN_MM:g} mm ({shown}): "
            f"they look like metres; travel_mm is mm ({as_mm})")


def short_travel_warning(key: str, lo: float, hi: float) -> str | None:
    """A warning for one linear travel shorter than :data:`SHORT_SPAN_MM`, or None."""
    if hi - lo >= SHORT_SPAN_MM:
        return None
    return (f"travel_mm.{key}: [{lo:g}, {hi:g}] is {hi - lo:g} mm long; if it is metres, "
            f"write [{lo * 1000:g}, {hi * 1000:g}] (travel_mm is mm)")
