"""Event retention: the events table would otherwise grow with every refused connection.

:class:`EventRetention` is one of the lifespan's services: it deletes events older than
``EDNC_EVENT_RETENTION_DAYS`` when the service starts, then once per ``period_s``.
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import logging
from types import TracebackType

from sqlalchemy.exc import SQLAlchemyError

from server.center import Center
from server.db import events as event_repo

log = logging.getLogger(__name__)


class EventRetention:
    """Prunes old events now and periodically, as an async context manager."""

    def __init__(self, center: Center, *, period_s: float = 3600.0) -> None:
        self.center = center
        self.period_s = period_s
        self._task: asyncio.Task[None] | None = None

    async def prune_once(self) -> int:
        """Delete the events older than the retention period; return how many."""
        days = self.center.settings.event_retention_days
        cutoff = dt.datetime.now(dt.UTC) - dt.timedelta(days=days)
        deleted = await self.center.db.run(event_repo.delete_events_before, cutoff)
        if deleted:
            log.info("deleted %d events older than %s", deleted, cutoff.isoformat())
        return deleted

    async def _loop(self) -> None:
        while True:
            await asyncio.sleep(self.period_s)
            try:
                await self.prune_once()
            except SQLAlchemyError as exc:  # the database may be back next period
                log.warning("event retention failed: %s", exc)

    async def __aenter__(self) -> EventRetention:
        await self.prune_once()
        self._task = asyncio.create_task(self._loop(), name="event-retention")
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
