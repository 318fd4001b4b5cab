"""A closed range of plausible values, and the other units a number is often written in.

Every quantity module of :mod:`volumetric.plausible` builds on these two: a
:class:`Limit` refuses what cannot be, and :func:`likely_unit` names the unit slip that
would explain a refused (or suspicious) number, so that the message says the cause
("looks like kelvin") and not only the range.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

__all__ = ["Implausible", "Limit", "Slip", "likely_unit", "looks_like"]


class Implausible(ValueError):
    """A number of an impossible size for its quantity; the text says which, the range
    and, where one explains it, the likely wrong unit."""


@dataclass(frozen=True, slots=True)
class Limit:
    """The accepted closed range of one quantity, and its unit and name for messages."""

    lo: float
    hi: float
    unit: str
    what: str

    def holds(self, value: float) -> bool:
        """True for a finite value within [lo, hi]."""
        return math.isfinite(value) and self.lo <= value <= self.hi

    def text(self) -> str:
        gap = "" if self.unit in ("°", "°C") else " "
        return f"{self.what} must lie within [{self.lo:g}, {self.hi:g}]{gap}{self.unit}"

    def refusal(self, value: float, cause: str | None = None) -> str:
        """Why ``value`` is refused, with its likely cause when one is known."""
        return f"{self.text()} (got {value:g})" + (f"; {cause}" if cause else "")


@dataclass(frozen=True, slots=True)
class Slip:
    """A unit a number of this quantity is often written in by mistake.

    ``value_in_ours = value * factor + offset``; ``say`` names it in a message
    ("kelvin"), ``fix`` tells the conversion ("subtract 273.15").
    """

    say: str
    factor: float
    offset: float = 0.0
    fix: str = ""
    at_least: float = 0.0
    """Only for numbers at least this large in magnitude (m°C are thousands, not 150)."""

    def convert(self, value: float) -> float:
        return value * self.factor + self.offset


def likely_unit(values: Iterable[float], slips: Sequence[Slip], typical: tuple[float, float]
                ) -> Slip | None:
    """The first slip under which every value falls within ``typical``, or None.

    Parameters
    ----------
    values : iterable of float
        The suspicious numbers (finite).
    slips : sequence of Slip
        Candidate wrong units, most likely first.
    typical : (float, float)
        Where this quantity's values usually lie, in our unit.
    """
    vs = [float(v) for v in values]
    if not vs:
        return None
    lo, hi = typical
    for slip in slips:
        if all(lo <= slip.convert(v) <= hi and abs(v) >= slip.at_least for v in vs):
            return slip
    return None


def looks_like(slip: Slip | None, ours: str, what: str = "it looks") -> str | None:
    """The cause text for a slip: "it looks like kelvin; this is °C (subtract 273.15)",
    or None. ``what`` is the subject and verb ("the values look")."""
    if slip is None:
        return None
    fix = f" ({slip.fix})" if slip.fix else ""
    return f"{what} like {slip.say}; this is {ours}{fix}"
