"""Per-minute summaries of the temperature readings: :class:`TemperatureRollup`, one of
the lifespan's services.

A trend over a day reads one row per sensor and minute (1,440) instead of every reading
(86,400 per sensor at 1 Hz; the benchmark ``benchmarks/history_query.py`` gives the
difference). Every ``period_s`` the service summarises the complete minutes not
summarised yet (:func:`server.db.history.roll_up`, at most a day per call, a few calls per
period while it catches up), and every hour deletes the summaries older than the
readings' retention. Several nodes on one database may run it: a node that loses the race
for a minute adds nothing (the primary key refuses the second copy).
"""

from __future__ import annotations

import datetime as dt
import logging
from types import TracebackType
from typing import Final

from sqlalchemy.exc import IntegrityError, SQLAlchemyError

from server.background import Background, every
from server.center import Center
from server.db import history as history_repo
from server.intake import RETENTION_DAYS

log = logging.getLogger(__name__)

PERIOD_S: Final = 60.0
CALLS_PER_PERIOD: Final = 8
PRUNE_EVERY_S: Final = 3600.0


class TemperatureRollup:
    """Keeps ``temperature_minutes`` up to date (module docstring)."""

    def __init__(self, center: Center, *, period_s: float = PERIOD_S,
                 retention_days: float = RETENTION_DAYS) -> None:
        self.center = center
        self.period_s = period_s
        self.retention_days = retention_days
        self._background = Background()

    async def roll_once(self, now: dt.datetime | None = None) -> int:
        """Summarise what is complete (a day per call, a few calls); returns rows added."""
        total = 0
        for _ in range(CALLS_PER_PERIOD):
            try:
                added = await self.center.db.run(history_repo.roll_up,
                                                 now or dt.datetime.now(dt.UTC))
            except IntegrityError:  # another node summarised the same minutes first
                log.debug("temperature minutes taken by another node")
                return total
            total += added
            if added == 0:
                break
        return total

    async def prune_once(self) -> int:
        """Delete the summaries older than the retention; returns how many."""
        cutoff = dt.datetime.now(dt.UTC) - dt.timedelta(days=self.retention_days)
        return await self.center.db.run(history_repo.delete_minutes_before, cutoff)

    async def __aenter__(self) -> TemperatureRollup:
        errors = (SQLAlchemyError,)
        self._background.start(every(self.period_s, self.roll_once, errors=errors,
                                     what="temperature minutes"), "temperature-rollup")
        self._background.start(every(PRUNE_EVERY_S, self.prune_once, errors=errors,
                                     what="temperature minutes retention"),
                               "temperature-rollup-retention")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        await self._background.stop()
