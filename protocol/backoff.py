"""Reconnect delays, one rule for both ends of the protocol (pure, no I/O).

After a lost connection a peer waits ``min(cap, initial · factor^n)`` seconds before its
n-th retry, shortened by a random part of up to ``jitter`` of itself, so that a fleet that
lost its center (or a center that lost its broker) does not come back in step.
"""

from __future__ import annotations

import random
from dataclasses import dataclass


@dataclass(frozen=True, kw_only=True)
class Backoff:
    """Reconnect delays: ``min(cap_s, initial_s · factor^n) · (1 - jitter · u)``, u uniform
    in [0, 1).

    Attributes
    ----------
    initial_s : float
        Delay before the first retry, s (before jitter).
    factor : float
        Growth per failed attempt.
    cap_s : float
        Longest delay, s.
    jitter : float
        Largest fraction by which a delay is shortened at random, in [0, 1].
    """

    initial_s: float = 1.0
    factor: float = 2.0
    cap_s: float = 60.0
    jitter: float = 0.5

    def __post_init__(self) -> None:
        if not (self.initial_s > 0 and self.factor >= 1 and self.cap_s >= self.initial_s
                and 0 <= self.jitter <= 1):
            raise ValueError(f"backoff needs initial_s > 0, factor >= 1, cap_s >= initial_s "
                             f"and jitter in [0, 1]; got {self}")

    def delay(self, attempt: int, rng: random.Random) -> float:
        """Delay before retry ``attempt`` (0 for the first), s."""
        base = min(self.cap_s, self.initial_s * self.factor ** min(attempt, 64))
        return base * (1.0 - self.jitter * rng.random())


__all__ = ["Backoff"]
