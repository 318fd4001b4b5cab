"""A minimal center for the simulated machine's link tests: ``MiniCenter`` serves the wire
protocol on a loopback port and hands each connection over as a ``Session``."""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field

from protocol import (
    NEED_DATA,
    AuthResponse,
    Challenge,
    Connection,
    ErrorCode,
    Hello,
    Message,
    Reject,
    Role,
    Telemetry,
    Welcome,
    new_nonce,
    verify_mac,
)

SECRET = b"0123456789abcdef-secret"


@dataclass
class Session:
    """The center's end of one connection."""

    conn: Connection
    reader: asyncio.StreamReader
    writer: asyncio.StreamWriter
    hello: Hello | None = None

    async def send(self, msg: Message) -> None:
        self.writer.write(self.conn.send(msg))
        await self.writer.drain()

    async def next(self) -> Message:
        while True:
            event = self.conn.next_event()
            if event is not NEED_DATA:
                assert isinstance(event, Message), event
                return event
            self.conn.receive_data(await self.reader.read(65536))

    async def expect(self, kind: type, skip: tuple[type, ...] = (Telemetry,)) -> Message:
        while True:
            msg = await self.next()
            if isinstance(msg, kind):
                return msg
            assert isinstance(msg, skip), f"expected {kind.__name__}, got {msg!r}"


@dataclass
class MiniCenter:
    secret: bytes
    sessions: asyncio.Queue[Session] = field(default_factory=asyncio.Queue)
    port: int = 0

    async def handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        s = Session(Connection(Role.CENTER), reader, writer)
        hello = await s.expect(Hello, ())
        assert isinstance(hello, Hello)
        s.hello = hello
        nonce = new_nonce()
        await s.send(Challenge(nonce))
        auth = await s.expect(AuthResponse, ())
        assert isinstance(auth, AuthResponse)
        if not verify_mac(self.secret, nonce, hello.name, auth.mac):
            await s.send(Reject(ErrorCode.AUTH_FAILED, "bad secret"))
            writer.close()
            return
        await s.send(Welcome(heartbeat_period_ms=500, telemetry_period_ms=20))
        await self.sessions.put(s)
