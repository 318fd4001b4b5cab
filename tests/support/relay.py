"""A TCP relay that keeps every byte passing each way: what a capture on the plant's
network would see (the OPC UA links' tests look for a password in it)."""

from __future__ import annotations

import asyncio
import contextlib


class Relay:
    """A TCP relay to ``upstream`` keeping what passes each way (``to_server``,
    ``to_client``); ``upstream`` may be changed between connections."""

    def __init__(self, upstream: int) -> None:
        self.upstream = upstream
        self.to_server = bytearray()
        self.to_client = bytearray()
        self.port = 0
        self._server: asyncio.Server | None = None
        self._tasks: set[asyncio.Task[None]] = set()

    async def __aenter__(self) -> Relay:
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = self._server.sockets[0].getsockname()[1]
        return self

    async def __aexit__(self, *exc: object) -> None:
        assert self._server is not None
        self._server.close()
        for t in list(self._tasks):
            t.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)

    @property
    def endpoint(self) -> str:
        return f"opc.tcp://127.0.0.1:{self.port}"

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
                     ) -> None:
        up_r, up_w = await asyncio.open_connection("127.0.0.1", self.upstream)

        async def pipe(r: asyncio.StreamReader, w: asyncio.StreamWriter,
                       keep: bytearray) -> None:
            with contextlib.suppress(ConnectionError):
                while data := await r.read(65536):
                    keep += data
                    w.write(data)
                    await w.drain()
            w.close()

        for t in (asyncio.create_task(pipe(reader, up_w, self.to_server)),
                  asyncio.create_task(pipe(up_r, writer, self.to_client))):
            self._tasks.add(t)
            t.add_done_callback(self._tasks.discard)


def appears(secret: str, data: bytes) -> bool:
    """``secret`` in ``data`` in any encoding OPC UA may carry it (UTF-8, UTF-16)."""
    return any(secret.encode(enc) in data for enc in ("utf-8", "utf-16-le", "utf-16-be"))
