"""The applied-correction history: :class:`CorrectionSampler`, one of the lifespan's
services.

The compensation a machine applies arrives in its telemetry (about once a second) and is
kept only as the latest value. The sampler reads the links this node serves every
``poll_s``, skips telemetry it already counted (same timestamp), and keeps per machine and
axis the mean, smallest and largest value; every ``period_s`` it writes one row per
machine and axis (:class:`~server.db.tables.CorrectionSampleRow`), so a month of an axis
is 43,200 rows at the default minute. Rows older than ``retention_days`` are deleted
every hour. Costs nothing while no machine is connected.
"""

from __future__ import annotations

import datetime as dt
import logging
from dataclasses import dataclass
from types import TracebackType
from typing import Final

from sqlalchemy import select
from sqlalchemy.exc import SQLAlchemyError
from sqlalchemy.orm import Session

from server.background import Background, every
from server.center import Center
from server.dashboard.telemetry import live_values
from server.db import corrections as correction_repo
from server.db.corrections import NewSample
from server.db.tables import MachineRow

log = logging.getLogger(__name__)

POLL_S: Final = 1.0
PERIOD_S: Final = 60.0
RETENTION_DAYS: Final = 30.0
PRUNE_EVERY_S: Final = 3600.0


@dataclass(slots=True)
class _Running:
    """One axis's values in the current period."""

    total: float = 0.0
    low: float = float("inf")
    high: float = float("-inf")
    count: int = 0

    def add(self, value: float) -> None:
        self.total += value
        self.low = min(self.low, value)
        self.high = max(self.high, value)
        self.count += 1


class CorrectionSampler:
    """Samples the applied corrections of connected machines (module docstring).

    Parameters
    ----------
    center
        The running Center (its registry: the links this node serves).
    poll_s, period_s
        How often telemetry is read, and how long one stored row summarises, s.
    retention_days
        Rows older than this are deleted, days.
    """

    def __init__(self, center: Center, *, poll_s: float = POLL_S, period_s: float = PERIOD_S,
                 retention_days: float = RETENTION_DAYS) -> None:
        self.center = center
        self.poll_s = poll_s
        self.period_s = period_s
        self.retention_days = retention_days
        self._seen: dict[str, object] = {}
        self._running: dict[tuple[str, str], _Running] = {}
        self._background = Background()

    def poll(self) -> int:
        """Count the new telemetry of every connected link; returns how many links had any."""
        fresh = 0
        for link in self.center.registry.all():
            if not link.connected or not link.telemetry:
                continue
            stamp = link.telemetry.get("timestamp_ms", link.last_seen)
            if self._seen.get(link.name) == stamp:
                continue  # the same message as last poll: the machine sent nothing new
            self._seen[link.name] = stamp
            fresh += 1
            for axis in live_values(link.telemetry).axes:
                self._running.setdefault((link.name, axis.name), _Running()).add(
                    axis.compensation)
        return fresh

    async def flush(self, now: dt.datetime | None = None) -> int:
        """Store the period's rows and start a new period; returns how many rows."""
        running, self._running = self._running, {}
        if not running:
            return 0
        now = now or dt.datetime.now(dt.UTC)
        names = sorted({name for name, _ in running})

        def store(session: Session) -> int:
            ids = dict(session.execute(select(MachineRow.name, MachineRow.id).where(
                MachineRow.name.in_(names))).all())
            rows = [NewSample(machine_id=ids[name], axis=axis, time=now,
                              mean=r.total / r.count, low=r.low, high=r.high, samples=r.count)
                    for (name, axis), r in sorted(running.items()) if name in ids]
            return correction_repo.add_samples(session, rows)

        return await self.center.db.run(store)

    async def prune_once(self) -> int:
        """Delete the rows older than the retention period; returns how many."""
        cutoff = dt.datetime.now(dt.UTC) - dt.timedelta(days=self.retention_days)
        return await self.center.db.run(correction_repo.delete_samples_before, cutoff)

    async def _poll(self) -> None:
        self.poll()

    async def __aenter__(self) -> CorrectionSampler:
        errors = (SQLAlchemyError,)
        self._background.start(every(self.poll_s, self._poll, what="correction poll"),
                               "correction-poll")
        self._background.start(every(self.period_s, self.flush, errors=errors,
                                     what="correction history"), "correction-flush")
        self._background.start(every(PRUNE_EVERY_S, self.prune_once, errors=errors,
                                     what="correction retention"), "correction-retention")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        await self._background.stop()
        try:
            await self.flush()  # the last partial period is history too
        except SQLAlchemyError as error:
            log.warning("last correction samples not stored: %s", str(error).splitlines()[0])
