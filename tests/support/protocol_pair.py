"""Two Connections brought to a given stage of the session (``pair``), and ``Raw``, frames
fed to a Connection without its own checks, for the state-machine tests."""

from __future__ import annotations

from protocol import (
    AuthResponse,
    Challenge,
    Connection,
    Message,
    Role,
    Welcome,
)
from protocol.codec import encode_payload
from protocol.messages import TYPE_OF
from tests.support.protocol import HELLO, deliver, frame

CHALLENGE = Challenge(bytes(32))


AUTH = AuthResponse(bytes(32))


WELCOME = Welcome(5000, 1000)


def pair(upto: str = "ready") -> tuple[Connection, Connection]:
    """(center, machine), driven through the handshake as far as ``upto``."""
    center, machine = Connection(Role.CENTER), Connection(Role.MACHINE)
    steps: list[tuple[Connection, Connection, Message, str]] = [
        (machine, center, HELLO, "hello"),
        (center, machine, CHALLENGE, "challenge"),
        (machine, center, AUTH, "auth"),
        (center, machine, WELCOME, "ready"),
    ]
    if upto == "start":
        return center, machine
    for sender, receiver, msg, name in steps:
        deliver(sender, receiver, msg)
        if name == upto:
            break
    return center, machine


class Raw:
    """Writes frames a real peer could not produce, with the right sequence numbers."""

    def __init__(self) -> None:
        self.seq = 0

    def __call__(self, msg: Message) -> bytes:
        wire = frame(TYPE_OF[type(msg)], self.seq, encode_payload(msg))
        self.seq += 1
        return wire
