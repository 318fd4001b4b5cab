"""How often the center tries a controller again: per machine, after every failure.

A link that fails after its session opened (a push refused with exception 02, a login
without write rights) must not be retried at once: a reset of the backoff whenever a
session opens turned such a fault into 21 connects and 22 pushes in 12 s, forever. Here
the backoff grows with every failure, opened session or not, and only proof that the
link works resets it: a map the controller applied, or a healthy poll cycle (the session
up for :data:`HEALTHY_AFTER_S` with the PLC's heartbeat moving and no push in flight).

On top of the backoff, a budget as a safety net: at most :data:`ATTEMPTS_PER_MINUTE`
connects and as many pushes per machine in any 60 s, also for a link that keeps proving
itself and failing again (each proof resets the backoff).
"""

from __future__ import annotations

import random
from collections import deque
from dataclasses import dataclass, field
from typing import Final

from protocol.backoff import Backoff

__all__ = ["ATTEMPTS_PER_MINUTE", "BACKOFF", "HEALTHY_AFTER_S", "Pacer"]

ATTEMPTS_PER_MINUTE: Final = 4
"""Connects per machine in any 60 s while its link keeps failing (issue 30's target)."""

HEALTHY_AFTER_S: Final = 5.0
"""A session that has run this long with the PLC's heartbeat moving and no push in flight
has proved the link; its next failure starts the backoff from the beginning, s."""

BACKOFF: Final = Backoff(initial_s=4.0, factor=3.0, cap_s=60.0, jitter=0.25)
"""Delays after the n-th failure in a row: 4, 12, 36, 60 s, shortened by up to a quarter
at random so that controllers behind one failed switch are not retried in step. Chosen so
that a fault that persists costs at most 4 connects in its first minute (0, 3-4, 12-16,
39-52 s) without the per-minute budget having to hold a retry back: a retry held back by
the budget would delay the recovery beyond the backoff step the operator sees."""


@dataclass
class Pacer:
    """One machine's retry schedule (used from the event loop only).

    Attributes
    ----------
    backoff : Backoff
    per_minute : int
        Largest number of attempts in any 60 s.
    failures : int
        Failures in a row since the link last proved itself.
    """

    backoff: Backoff = BACKOFF
    per_minute: int = ATTEMPTS_PER_MINUTE
    rng: random.Random = field(default_factory=random.Random)
    failures: int = 0
    _attempts: deque[float] = field(default_factory=deque)
    _pushes: deque[float] = field(default_factory=deque)

    def attempt(self, now: float) -> None:
        """An attempt (a connect) starts at ``now`` (monotonic, s)."""
        self._keep(self._attempts, now)

    def pushed(self, at: float) -> None:
        """A session pushed a map at ``at``: a session that opens next pushes again, so
        the next attempt also waits for the push budget."""
        self._keep(self._pushes, at)

    def _keep(self, times: deque[float], t: float) -> None:
        times.append(t)
        while len(times) > self.per_minute:
            times.popleft()

    def failed(self) -> None:
        """The attempt, or the session it opened, failed."""
        self.failures += 1

    def healthy(self) -> None:
        """The link proved itself (a map applied, a healthy poll cycle)."""
        self.failures = 0

    def delay(self, now: float) -> float:
        """Seconds to wait from ``now`` before the next attempt: the backoff step of the
        failures so far (none after a healthy session), and no sooner than 60 s after the
        attempt, or the push, :attr:`per_minute` back."""
        wait = 0.0 if self.failures == 0 else self.backoff.delay(self.failures - 1, self.rng)
        for times in (self._attempts, self._pushes):
            if len(times) >= self.per_minute:
                wait = max(wait, times[0] + 60.0 - now)
        return max(0.0, wait)
