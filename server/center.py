"""The :class:`Center`: the long-lived services of one control-center process, in one object.

The lifespan in :mod:`server.app` builds it and stores it as ``app.state.center``; REST
routes reach it through ``server.api.deps``; the machine TCP server, the push scheduler and
the MQTT bridge get it as their constructor argument. Add new long-lived collaborators here
rather than as new globals.
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from server.db import Database
from server.db import events as event_repo
from server.db.tables import EventRow
from server.events import EventKind
from server.metrics import Metrics
from server.settings import Settings
from server.state import Registry

if TYPE_CHECKING:  # the intake imports this module
    from server.intake import TemperatureIntake
    from server.temperatures import TemperatureBoard


def _now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


@dataclass
class Center:
    """Settings, database, live link registry and metrics of the running service."""

    settings: Settings
    db: Database
    registry: Registry = field(default_factory=Registry)
    metrics: Metrics = field(default_factory=Metrics)
    started_at: dt.datetime = field(default_factory=_now)
    intake: TemperatureIntake | None = None
    """The temperature intake while the machine services run (REST posts go to it)."""
    temperatures: TemperatureBoard | None = None
    """The machine services' temperature board while they run (the dashboard shows its
    readings: MQTT, REST, the center's lag states, and their staleness)."""

    def __post_init__(self) -> None:
        self.metrics.track_connected(self.registry.connected_count)

    async def record_event(
        self, kind: EventKind, machine: str, detail: str = "", *, reason: str | None = None
    ) -> EventRow:
        """Store an event and count it; a refusal also counts under ``reason``.

        Parameters
        ----------
        kind
            What happened.
        machine
            The machine's name, or the peer address when the peer is not a known machine.
        detail
            Free text for the dashboard (why it was refused, which version was pushed...).
        reason
            For refusals: a short fixed label for the metrics (``unknown``, ``auth``...).
        """
        row = await self.db.run(
            event_repo.add_event, kind=kind.value, machine=machine, detail=detail
        )
        self.metrics.events.labels(kind=kind.value).inc()
        if kind is EventKind.REFUSED:
            self.metrics.refusals.labels(reason=reason or "other").inc()
        return row
