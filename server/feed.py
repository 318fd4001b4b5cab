"""The in-process feed of link events: who connected, was refused, got which map.

The machine server and the push scheduler :meth:`Feed.record` what happens (stored in the
``events`` table through :meth:`Center.record_event`, counted in the metrics) and every
subscriber hears it at once, in the event loop: the MQTT bridge republishes it on
``<prefix>/events`` and updates the machine's retained status.
"""

from __future__ import annotations

import datetime as dt
import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

from sqlalchemy.exc import SQLAlchemyError

from server.events import EventKind

log = logging.getLogger(__name__)


class EventRecorder(Protocol):
    """What the feed needs of the :class:`~server.center.Center`: its ``record_event``.
    (Importing the center here would close a circle: center -> intake -> feed -> center.)
    """

    async def record_event(self, kind: EventKind, machine: str, detail: str = "", *,
                           reason: str | None = None) -> object: ...


def _now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


@dataclass(frozen=True, slots=True)
class Notice:
    """One thing that happened on a machine link.

    ``machine`` is the machine's name, or the peer address for a peer that is not a known
    machine (as in the events table); ``version`` the map version of a push, if any.
    """

    kind: EventKind
    machine: str
    detail: str = ""
    version: int | None = None
    at: dt.datetime = field(default_factory=_now)


Listener = Callable[[Notice], None]


class Feed:
    """Records link events and tells every subscriber (synchronously, in the loop)."""

    def __init__(self, center: EventRecorder) -> None:
        self.center = center
        self._listeners: list[Listener] = []

    def subscribe(self, listener: Listener) -> Callable[[], None]:
        """Call ``listener`` with every notice from now on; returns the unsubscribe."""
        self._listeners.append(listener)
        return lambda: self._listeners.remove(listener)

    def publish(self, notice: Notice) -> None:
        """Tell the subscribers only (the caller stored the event itself)."""
        for listener in list(self._listeners):
            try:
                listener(notice)
            except Exception:  # a listener's bug must not break the link that reported
                log.exception("feed listener %r failed on %s", listener, notice)

    async def record(
        self, kind: EventKind, machine: str, detail: str = "", *,
        reason: str | None = None, version: int | None = None,
    ) -> None:
        """Store the event (events table, metrics) and publish it.

        A database failure is logged, not raised: losing one event row must not drop a
        machine's session.
        """
        try:
            await self.center.record_event(kind, machine, detail, reason=reason)
        except SQLAlchemyError:
            log.exception("could not store %s event of %s", kind.value, machine)
        self.publish(Notice(kind, machine, detail, version))
