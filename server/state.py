"""The live state of the machine links, in memory: who is connected and what they last said.

The machine TCP server fills it (``connected`` / ``seen`` / ``disconnected``); the REST
status endpoints, the dashboard and the metrics read it. Persistent facts (which map
version was sent, acknowledged or rejected) live in the database instead, so that a
restart loses nothing; this registry holds only what is meaningless after a restart.

It is used from the event loop only (no locking): every writer and reader is a coroutine
of the same loop.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any


def _now() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


@dataclass(frozen=True, slots=True)
class LinkState:
    """A snapshot of one machine's link.

    Attributes
    ----------
    name : str
        The machine's name.
    connected : bool
        Whether a session is open now.
    address : str or None
        The peer address of the current (or last) session, ``host:port``.
    connected_since, last_seen : datetime or None
        When the current session opened; when the machine last sent anything (UTC).
    telemetry : mapping
        The machine's last telemetry fields (positions, temperatures, ...), as received.
    owner : str or None
        The node (``EDNC_NODE_ID``) serving the machine now, in the plant-wide view
        (:mod:`server.plant`); None in a node's own registry and when nobody serves it.
    link_state, link_reason, link_text : str
        What the link is doing and why (:mod:`server.links.state`): ``connected``,
        ``connecting``, ``plc_stopped``, ``refused``, ``unreachable``, ``failed`` or
        ``offline``; a stable reason label; the text for the operator.
    """

    name: str
    connected: bool = False
    address: str | None = None
    connected_since: dt.datetime | None = None
    last_seen: dt.datetime | None = None
    telemetry: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))
    owner: str | None = None
    link_state: str = "offline"
    link_reason: str = ""
    link_text: str = ""


def shown_state(link: LinkState) -> str:
    """The link state to show: what the registry holds, but ``connected`` for a session
    open and well (a link served by another node carries no state of its own)."""
    if link.connected:
        return "plc_stopped" if link.link_state == "plc_stopped" else "connected"
    return link.link_state


class Registry:
    """The links of all machines, keyed by machine name."""

    def __init__(self) -> None:
        self._links: dict[str, LinkState] = {}

    def connected(self, name: str, address: str, at: dt.datetime | None = None) -> LinkState:
        """A machine opened a session (replacing any previous one)."""
        at = at or _now()
        link = replace(self.get(name), connected=True, address=address,
                       connected_since=at, last_seen=at, link_state="connected",
                       link_reason="", link_text="")
        self._links[name] = link
        return link

    def seen(
        self, name: str, telemetry: Mapping[str, Any] | None = None,
        at: dt.datetime | None = None,
    ) -> LinkState:
        """The machine sent something; ``telemetry`` replaces the last telemetry if given."""
        link = replace(self.get(name), last_seen=at or _now())
        if telemetry is not None:
            link = replace(link, telemetry=MappingProxyType(dict(telemetry)))
        self._links[name] = link
        return link

    def disconnected(self, name: str) -> LinkState:
        """The machine's session ended; its last address and telemetry are kept."""
        link = replace(self.get(name), connected=False, connected_since=None,
                       link_state="offline", link_reason="", link_text="")
        self._links[name] = link
        return link

    def condition(self, name: str, state: str, reason: str = "", text: str = ""
                  ) -> LinkState:
        """What a machine's link is doing while it has no session (the center trying to
        reach its controller, and why that failed); a session's state is set by
        :meth:`connected` and :meth:`disconnected`."""
        link = replace(self.get(name), link_state=state, link_reason=reason, link_text=text)
        self._links[name] = link
        return link

    def forget(self, name: str) -> None:
        """Drop a machine (deleted or renamed)."""
        self._links.pop(name, None)

    def get(self, name: str) -> LinkState:
        """The machine's link; a never-seen machine is simply not connected."""
        return self._links.get(name) or LinkState(name=name)

    def all(self) -> list[LinkState]:
        """Every machine that has ever connected since start-up, by name."""
        return [self._links[n] for n in sorted(self._links)]

    def connected_count(self) -> int:
        """How many machines have a session open now."""
        return sum(1 for link in self._links.values() if link.connected)
