"""MQTT test helpers: ``publisher``, a client of the loopback broker that always lets go
within a deadline, and ``TcpProxy``, a TCP relay on loopback that can cut and restore a
peer's connection, to play a broker or center outage."""

from __future__ import annotations

import asyncio
import uuid
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager, suppress

import aiomqtt


class TcpProxy:
    """A loopback TCP forwarder that can be switched off (the broker 'goes away') and on
    again on the same port."""

    def __init__(self, target: tuple[str, int]) -> None:
        self.target = target
        self.port = 0
        self._server: asyncio.Server | None = None
        self._writers: set[asyncio.StreamWriter] = set()

    async def start(self) -> None:
        self._server = await asyncio.start_server(self._handle, "127.0.0.1", self.port)
        self.port = self._server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        server, self._server = self._server, None
        if server is not None:
            server.close()
        for w in list(self._writers):  # reset, not a polite close: the broker is gone
            w.transport.abort()
        if server is not None:
            with suppress(TimeoutError):  # 3.11 may wait for the connections themselves
                async with asyncio.timeout(2.0):
                    await server.wait_closed()

    async def _pipe(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        with suppress(OSError, ConnectionError):
            while data := await reader.read(65536):
                writer.write(data)
                await writer.drain()
        writer.close()

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self._writers.add(writer)
        try:
            up_reader, up_writer = await asyncio.open_connection(*self.target)
        except OSError:
            self._writers.discard(writer)
            writer.transport.abort()
            return
        self._writers.add(up_writer)
        try:
            await asyncio.gather(self._pipe(reader, up_writer), self._pipe(up_reader, writer))
        finally:
            self._writers -= {writer, up_writer}


@asynccontextmanager
async def publisher(broker: tuple[str, int]) -> AsyncIterator[aiomqtt.Client]:
    client = aiomqtt.Client(broker[0], broker[1], identifier=f"test-{uuid.uuid4().hex[:8]}")
    await client.__aenter__()
    try:
        yield client
    finally:
        # aiomqtt's exit has no deadline of its own (it waits for the broker's answer)
        with suppress(TimeoutError, aiomqtt.MqttError):
            async with asyncio.timeout(5.0):
                await client.__aexit__(None, None, None)
