"""The connection state machine: one table, shared by both roles.

A connection has three small state machines ("channels") that move independently once the
session is up: SESSION (handshake and close), MAP (one error-map push at a time) and RELEASE
(one release command at a time). ``TRANSITIONS`` maps (sender role, message class) to the
moves that message may make: {state it may be sent in: state it leads to}; all states in
one entry belong to the same channel. The same table checks what we send (violations raise
LocalProtocolError) and what we receive (RemoteProtocolError), so both ends apply
identical rules.

Rules (each is enforced by the table or by ``ConnectionState.check``; tests cover each):

1. Every message class has exactly one sender role, except Error, which either role may
   send. A message from the wrong role is a violation.
2. The machine speaks first, and only with Hello (SESSION starts in AWAIT_HELLO).
3. The handshake is lock-step: Hello (machine) → Challenge or Reject (center) →
   AuthResponse (machine) → Welcome or Reject (center). In each handshake state exactly
   one role may speak, so both ends always agree on the state.
4. Nothing but the handshake messages and Error is allowed before Welcome: in particular
   no map, telemetry or heartbeat reaches an unauthenticated peer.
5. MAP and RELEASE messages, Telemetry, Temperatures and heartbeats need SESSION == READY.
   Temperatures (center → machine) moves no channel: any number may follow one another,
   crossing map pushes and releases; the machine only stores the values (rule 10).
6. The MAP channel is lock-step too: the center sends MapBegin, any number of MapChunk,
   then MapEnd; then only the machine moves it, with exactly one MapAck or MapReject.
   Only then may the next MapBegin follow. (Chunk indices, sizes and checksums are the
   map's business, checked by MapAssembler and answered with MapReject, not here.)
7. The RELEASE channel: one ReleaseCompensation outstanding at a time, answered by exactly
   one Released; Released is never sent unasked.
8. Reject and Error close the session (SESSION → CLOSED); after them no message is
   allowed in either direction, and the sender closes the TCP connection.
9. Because every lock-step state lets one role move its channel, frames crossing in
   flight (Telemetry against MapChunk, Heartbeat against MapAck) never make the two ends
   disagree about a channel.
10. Temperatures is never answered: a machine that cannot use a reading (an unknown sensor)
    ignores that reading, not the message, and never closes the session for it, so the
    center may forward readings without waiting for anything.
"""

from __future__ import annotations

from enum import Enum
from typing import Final

from .errors import LocalProtocolError, RemoteProtocolError
from .messages import (
    AuthResponse,
    Challenge,
    Error,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAck,
    MapBegin,
    MapChunk,
    MapEnd,
    MapReject,
    Message,
    Reject,
    ReleaseCompensation,
    Released,
    Telemetry,
    Temperatures,
    Welcome,
)


class Role(Enum):
    """Which end of the connection."""

    CENTER = "center"
    MACHINE = "machine"

    @property
    def peer(self) -> Role:
        """The other end."""
        return Role.MACHINE if self is Role.CENTER else Role.CENTER


class Channel(Enum):
    """The three independent sub-machines of a connection."""

    SESSION = "session"
    MAP = "map"
    RELEASE = "release"


class State(Enum):
    """States of all channels; ``CHANNEL_OF`` says which channel each belongs to."""

    AWAIT_HELLO = "await hello"
    AWAIT_CHALLENGE = "await challenge"
    AWAIT_AUTH = "await auth response"
    AWAIT_VERDICT = "await welcome"
    READY = "ready"
    CLOSED = "closed"
    MAP_IDLE = "no map transfer"
    MAP_SENDING = "map transfer in progress"
    MAP_VERIFYING = "map awaiting ack"
    RELEASE_IDLE = "no release pending"
    RELEASE_PENDING = "release pending"


CENTER: Final = Role.CENTER
MACHINE: Final = Role.MACHINE
S: Final = State

CHANNEL_OF: Final[dict[State, Channel]] = {
    **{s: Channel.SESSION for s in (S.AWAIT_HELLO, S.AWAIT_CHALLENGE, S.AWAIT_AUTH,
                                    S.AWAIT_VERDICT, S.READY, S.CLOSED)},
    **{s: Channel.MAP for s in (S.MAP_IDLE, S.MAP_SENDING, S.MAP_VERIFYING)},
    **{s: Channel.RELEASE for s in (S.RELEASE_IDLE, S.RELEASE_PENDING)},
}

INITIAL: Final[dict[Channel, State]] = {
    Channel.SESSION: S.AWAIT_HELLO,
    Channel.MAP: S.MAP_IDLE,
    Channel.RELEASE: S.RELEASE_IDLE,
}

_OPEN: Final = {S.AWAIT_HELLO: S.CLOSED, S.AWAIT_CHALLENGE: S.CLOSED, S.AWAIT_AUTH: S.CLOSED,
                S.AWAIT_VERDICT: S.CLOSED, S.READY: S.CLOSED}

TRANSITIONS: Final[dict[tuple[Role, type[Message]], dict[State, State]]] = {
    # SESSION: handshake (rules 2-4) and close (rule 8)
    (MACHINE, Hello): {S.AWAIT_HELLO: S.AWAIT_CHALLENGE},
    (CENTER, Challenge): {S.AWAIT_CHALLENGE: S.AWAIT_AUTH},
    (MACHINE, AuthResponse): {S.AWAIT_AUTH: S.AWAIT_VERDICT},
    (CENTER, Welcome): {S.AWAIT_VERDICT: S.READY},
    (CENTER, Reject): {S.AWAIT_CHALLENGE: S.CLOSED, S.AWAIT_VERDICT: S.CLOSED},
    (CENTER, Error): _OPEN,
    (MACHINE, Error): _OPEN,
    # SESSION while READY, no state change (rule 5)
    (MACHINE, Telemetry): {S.READY: S.READY},
    (CENTER, Heartbeat): {S.READY: S.READY},
    (MACHINE, HeartbeatReply): {S.READY: S.READY},
    (CENTER, Temperatures): {S.READY: S.READY},  # rules 5 and 10
    # MAP (rule 6)
    (CENTER, MapBegin): {S.MAP_IDLE: S.MAP_SENDING},
    (CENTER, MapChunk): {S.MAP_SENDING: S.MAP_SENDING},
    (CENTER, MapEnd): {S.MAP_SENDING: S.MAP_VERIFYING},
    (MACHINE, MapAck): {S.MAP_VERIFYING: S.MAP_IDLE},
    (MACHINE, MapReject): {S.MAP_VERIFYING: S.MAP_IDLE},
    # RELEASE (rule 7)
    (CENTER, ReleaseCompensation): {S.RELEASE_IDLE: S.RELEASE_PENDING},
    (MACHINE, Released): {S.RELEASE_PENDING: S.RELEASE_IDLE},
}


def _channel_of(moves: dict[State, State]) -> Channel:
    channels = {CHANNEL_OF[s] for s in (*moves, *moves.values())}
    assert len(channels) == 1, f"a table entry spans channels {channels}"
    return channels.pop()


class ConnectionState:
    """The current state of each channel, moved by ``process`` after ``check`` allows it."""

    __slots__ = ("states",)

    def __init__(self) -> None:
        self.states: dict[Channel, State] = dict(INITIAL)

    def check(self, sender: Role, msg: Message, *, local: bool) -> tuple[Channel, State]:
        """The (channel, new state) that ``msg`` from ``sender`` leads to.

        Raises
        ------
        LocalProtocolError
            ``local`` is True (we are sending) and the rules forbid the message now.
        RemoteProtocolError
            ``local`` is False (the peer sent it) and the rules forbid it now.
        """
        error = LocalProtocolError if local else RemoteProtocolError
        name = type(msg).__name__
        who = f"{sender.value} may not send {name}"
        moves = TRANSITIONS.get((sender, type(msg)))
        if moves is None:
            raise error(f"{who}: only the {sender.peer.value} sends it (rule 1)")
        session = self.states[Channel.SESSION]
        if session is S.CLOSED:
            raise error(f"{who}: the session is closed (rule 8)")
        channel = _channel_of(moves)
        if channel is not Channel.SESSION and session is not S.READY:
            raise error(f"{who} before Welcome: session is '{session.value}' (rule 5)")
        current = self.states[channel]
        if current not in moves:
            allowed = ", ".join(sorted(f"'{s.value}'" for s in moves))
            raise error(f"{who} in state '{current.value}'; allowed in {allowed}")
        return channel, moves[current]

    def process(self, sender: Role, msg: Message, *, local: bool) -> None:
        """Check ``msg`` and move its channel."""
        channel, new = self.check(sender, msg, local=local)
        self.states[channel] = new
