"""The two ways a conversation can go wrong: we broke the protocol, or the peer did.

``LocalProtocolError`` means *our* code asked for something the protocol forbids (sending a
map before Welcome, a message our role may not send); nothing was changed and nothing was
sent, so the caller may still send an ``Error`` and close. ``RemoteProtocolError`` means the
bytes the peer sent cannot be a valid conversation (bad frame, bad field, a message out of
turn, a sequence gap); the connection is then broken for receiving and the caller should
send ``Error`` and close that one connection.
"""

from __future__ import annotations


class ProtocolError(Exception):
    """Base class of both protocol errors; ``str(exc)`` says what was wrong and where."""


class LocalProtocolError(ProtocolError):
    """We tried to do something the protocol does not allow in the current state."""


class RemoteProtocolError(ProtocolError):
    """The peer sent bytes that are not a valid frame or not allowed in the current state."""
