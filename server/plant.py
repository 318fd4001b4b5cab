"""The whole plant's live links, whichever node serves each machine.

Each node keeps the links of its own sessions in memory (:class:`server.state.Registry`).
So that the dashboard and the status of *any* node show every machine:

* :class:`LinkPublisher` copies the node's registry into the ``live_links`` table, only
  the links that changed, in one statement every ``period_s`` (1 s): at most one write
  per machine per second however often it sends telemetry;
* :func:`plant_view` reads every stored link and merges it with the local registry into a
  :class:`PlantView`, whose links carry ``owner``, the node serving the machine now.

Merging, per machine: a link this node serves is taken from memory (the freshest); else
a stored link is *live* when its node still holds the machine's lease (a node that died
leaves rows that say connected, and its leases expire); else the machine is offline, and
shows whichever of the local and stored links was seen last.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType, TracebackType
from typing import Any

from sqlalchemy.exc import SQLAlchemyError

from server.background import Background, every
from server.center import Center
from server.db import live_links as live_repo
from server.db.live_links import LiveLink
from server.state import LinkState, Registry

log = logging.getLogger(__name__)

PUBLISH_PERIOD_S = 1.0


def _plain(value: Any) -> Any:
    """Telemetry as plain JSON containers (the registry holds read-only mappings)."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    return value


def link_row(link: LinkState) -> dict[str, Any]:
    """A registry link as a ``live_links`` row (see :func:`server.db.live_links.publish`)."""
    return {"machine": link.name, "connected": link.connected, "address": link.address,
            "connected_since": link.connected_since, "last_seen": link.last_seen,
            "telemetry": _plain(link.telemetry)}


class LinkPublisher:
    """Writes this node's changed links to ``live_links``; an async context manager.

    Leaving it writes once more, so links closed at shutdown are stored as disconnected.
    """

    def __init__(self, center: Center, *, period_s: float = PUBLISH_PERIOD_S) -> None:
        self.center = center
        self.period_s = period_s
        self._written: dict[str, LinkState] = {}
        self._background = Background()

    async def __aenter__(self) -> LinkPublisher:
        self._background.start(every(self.period_s, self.flush), "live-links:publish")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        await self._background.stop()
        await self.flush()

    async def flush(self) -> int:
        """Write the links that changed since the last write; returns how many."""
        changed = [link for link in self.center.registry.all()
                   if self._written.get(link.name) is not link]
        if not changed:
            return 0
        try:
            await self.center.db.run(live_repo.publish, self.center.settings.node_id,
                                     [link_row(link) for link in changed])
        except SQLAlchemyError as exc:  # try again with whatever has changed by then
            log.warning("live links not stored (%d machines): %s", len(changed), exc)
            return 0
        for link in changed:
            self._written[link.name] = link
        return len(changed)


def _stored(link: LiveLink, owner: str | None) -> LinkState:
    return LinkState(name=link.machine, connected=owner is not None, address=link.address,
                     connected_since=link.connected_since if owner else None,
                     last_seen=link.last_seen, telemetry=MappingProxyType(link.telemetry),
                     owner=owner)


class PlantView:
    """Every machine's link, merged from this node's registry and the stored links
    (module docstring); read like a :class:`~server.state.Registry`."""

    def __init__(self, local: Registry, stored: list[LiveLink], node: str) -> None:
        self.local = local
        self.node = node
        self.stored = {link.machine: link for link in stored}

    def get(self, name: str) -> LinkState:
        """The machine's link, with ``owner`` the node serving it (None when offline)."""
        mine = self.local.get(name)
        if mine.connected:
            return replace(mine, owner=self.node)
        other = self.stored.get(name)
        if other is None:
            return mine
        if other.live and other.node != self.node:
            return _stored(other, other.node)
        if mine.link_reason:  # this node is trying and knows why it fails: say so
            return mine
        if mine.last_seen is not None and (other.last_seen is None
                                           or mine.last_seen >= other.last_seen):
            return mine
        return _stored(other, None)

    def names(self) -> list[str]:
        """Every machine with a link here or in the table, by name."""
        return sorted({link.name for link in self.local.all()} | set(self.stored))

    def connected_count(self) -> int:
        """How many machines some node serves now."""
        return sum(1 for name in self.names() if self.get(name).connected)


async def plant_view(center: Center) -> PlantView:
    """The plant now: one read of ``live_links`` (and leases), merged with the registry."""
    stored = await center.db.run(live_repo.plant_links)
    return PlantView(center.registry, stored, center.settings.node_id)


__all__ = ["PUBLISH_PERIOD_S", "LinkPublisher", "PlantView", "link_row", "plant_view"]
