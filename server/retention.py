"""Event retention: the events table would otherwise grow with every refused connection.

:class:`EventRetention` is one of the lifespan's services: it deletes events older than
``EDNC_EVENT_RETENTION_DAYS`` when the service starts, then once per ``period_s``.
"""

from __future__ import annotations

import datetime as dt
import logging
from types import TracebackType

from sqlalchemy.exc import SQLAlchemyError

from server.background import Background, every
from server.center import Center
from server.db import events as event_repo

log = logging.getLogger(__name__)


class EventRetention:
    """Prunes old events now and periodically, as an async context manager."""

    def __init__(self, center: Center, *, period_s: float = 3600.0) -> None:
        self.center = center
        self.period_s = period_s
        self._background = Background()

    async def prune_once(self) -> int:
        """Delete the events older than the retention period; return how many."""
        days = self.center.settings.event_retention_days
        cutoff = dt.datetime.now(dt.UTC) - dt.timedelta(days=days)
        deleted = await self.center.db.run(event_repo.delete_events_before, cutoff)
        if deleted:
            log.info("deleted %d events older than %s", deleted, cutoff.isoformat())
        return deleted

    async def __aenter__(self) -> EventRetention:
        await self.prune_once()
        # a database error is logged and tried again next period (it may be back by then)
        self._background.start(every(self.period_s, self.prune_once, errors=(SQLAlchemyError,),
                                     what="event retention"), "event-retention")
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self._background.stop()
