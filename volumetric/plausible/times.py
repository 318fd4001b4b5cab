"""Times: a campaign's ``time_s`` (seconds since it started), the time stamp of a
temperature reading (seconds since the Unix epoch) and durations of options (s).

The slips are factors of 1000: milliseconds in a seconds field (a stamp far in the
future, a campaign that seems to last a year) and seconds in a milliseconds field (a stamp
in January 1970).
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike

from .limit import Limit, Slip, likely_unit

__all__ = ["CAMPAIGN_TIME", "EARLIEST_STAMP_S", "FUTURE_S", "LONG_CAMPAIGN_S",
           "campaign_time_warning", "duration_warning", "stamp_problem"]

CAMPAIGN_TIME = Limit(-3.2e9, 3.2e9, "s", "a campaign time")
"""A century either way."""
LONG_CAMPAIGN_S = 60 * 86400.0
"""A campaign that seems longer than 60 days is warned about as milliseconds."""
EARLIEST_STAMP_S = 946_684_800.0
"""2000-01-01T00:00Z: no reading the center gets is older."""
FUTURE_S = 86400.0
"""A stamp this far ahead of the center's clock is not a clock's drift."""
_STAMP_SLIPS = (
    Slip("milliseconds", 1e-3, fix="seconds since the epoch; or send timestamp_ms"),
    Slip("microseconds", 1e-6, fix="seconds since the epoch"),
    Slip("nanoseconds", 1e-9, fix="seconds since the epoch"),
    Slip("seconds", 1e3, fix="give milliseconds, or send time in seconds"),
)


def stamp_problem(seconds: float, field: str = "time", now: float | None = None
                  ) -> str | None:
    """Why ``seconds`` (since the epoch) cannot be when a reading was taken, or None.

    Parameters
    ----------
    seconds : float
        The stamp as read, converted to seconds by the field's own unit.
    field : str
        The field's name for the message (``time``, ``timestamp_ms``).
    now : float, optional
        The clock (``time.time()`` by default).
    """
    now = time.time() if now is None else now
    if not np.isfinite(seconds):
        return f"{field}: not a finite time"
    if EARLIEST_STAMP_S <= seconds <= now + FUTURE_S:
        return None
    when = "in the future" if seconds > now else "before 2000"
    slip = likely_unit([seconds], _STAMP_SLIPS, (EARLIEST_STAMP_S, now + FUTURE_S))
    cause = f"; it looks like {slip.say} ({slip.fix})" if slip is not None else ""
    return f"{field}: {seconds:.6g} s since the epoch is {when}{cause}"


def campaign_time_warning(values: ArrayLike, where: str) -> str | None:
    """A warning when ``time_s`` spans more than :data:`LONG_CAMPAIGN_S` (ms for s)."""
    t = np.asarray(values, dtype=np.float64).ravel()
    if t.size < 2:
        return None
    span = float(np.max(t) - np.min(t))
    if span <= LONG_CAMPAIGN_S:
        return None
    return (f"{where}: the readings span {span / 86400:.0f} days; if time_s is "
            f"milliseconds, they span {span / 3.6e6:.3g} h (time_s is seconds)")


def duration_warning(seconds: float, option: str, usual_s: float) -> str | None:
    """A warning when a duration option is over 1000 times its usual size (ms for s)."""
    if seconds <= 1000.0 * usual_s:
        return None
    return (f"{option} {seconds:g} s is {seconds / 3600:.3g} h; if you meant "
            f"milliseconds, give {seconds / 1000:g} ({option} is seconds)")
