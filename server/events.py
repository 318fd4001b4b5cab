"""The kinds of event the service records (the ``events`` table, ``GET /api/events``)."""

from __future__ import annotations

from enum import StrEnum


class EventKind(StrEnum):
    """What happened on a machine link."""

    REFUSED = "refused"
    """A peer was refused: unknown address, failed challenge, second session, bad frame."""
    CONNECTED = "connected"
    """A known machine opened a session."""
    DISCONNECTED = "disconnected"
    """A machine's session ended."""
    PUSHED = "pushed"
    """An error map was sent to a machine."""
    APPLIED = "applied"
    """A machine acknowledged that it applied a map."""
    REJECTED = "rejected"
    """A machine rejected a map (the detail says why)."""
    LINK = "link"
    """The center's link to a machine's controller is down: the detail gives its state,
    its reason and what was seen (the first of each reason, then one a minute)."""
    ERROR = "error"
    """Something failed on the center's side for this machine."""
    WARNING = "warning"
    """A link works but needs the operator's eye: OPC UA without security (the password
    in clear), a controller certificate trusted on first use."""
