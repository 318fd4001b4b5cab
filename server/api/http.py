"""uvicorn as the control center runs it: HTTP/1.1 (h11) with a header deadline.

uvicorn reads request headers without a deadline: its keep-alive timer starts only after a
first response and restarts on every byte, so a client that sends one header byte every
few seconds holds a connection (and its buffers) forever. :class:`GuardedH11Protocol`
gives every request ``HEADER_TIMEOUT_S`` from the connection's start (or the end of the
previous response) to complete its request line and headers, else answers 408 and
closes. Body deadlines are the ASGI guard's (:mod:`server.api.guard`), which knows the
route.

:func:`uvicorn_options` is what ``ednc serve`` passes to uvicorn.
"""

from __future__ import annotations

import asyncio
from typing import Any, Final

import h11
from uvicorn.protocols.http.h11_impl import H11Protocol

HEADER_TIMEOUT_S: Final = 10.0
"""Request line and headers, s: a client on a LAN sends them in one packet."""

MAX_HEADER_BYTES: Final = 32 * 1024
"""Request line plus headers (h11's incomplete-event limit; its default is 16 KiB)."""

_408: Final = (b"HTTP/1.1 408 Request Timeout\r\ncontent-type: text/plain\r\n"
               b"content-length: 29\r\nconnection: close\r\n\r\nrequest headers came too slowly")


class GuardedH11Protocol(H11Protocol):
    """uvicorn's h11 protocol with a deadline on each request's headers."""

    header_timeout_s: float = HEADER_TIMEOUT_S

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._header_timer: asyncio.TimerHandle | None = None

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._arm()

    def connection_lost(self, exc: Exception | None) -> None:
        self._disarm()
        super().connection_lost(exc)

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if not self.transport.is_closing():
            self._arm()  # the next request on this connection has its own deadline

    def handle_events(self) -> None:
        super().handle_events()
        if self.conn.their_state is not h11.IDLE:
            self._disarm()  # headers complete: the request is the app's (and guard's) now

    def _arm(self) -> None:
        self._disarm()
        self._header_timer = self.loop.call_later(self.header_timeout_s, self._expired)

    def _disarm(self) -> None:
        if self._header_timer is not None:
            self._header_timer.cancel()
            self._header_timer = None

    def _expired(self) -> None:
        self._header_timer = None
        if self.transport.is_closing() or self.conn.their_state is not h11.IDLE:
            return
        if self.cycle is not None and not self.cycle.response_complete:
            return  # a response is still being written (pipelining): not idle
        self.transport.write(_408)
        self.transport.close()


def uvicorn_options(header_timeout_s: float = HEADER_TIMEOUT_S) -> dict[str, Any]:
    """Keyword arguments for ``uvicorn.run`` / ``uvicorn.Config``."""
    protocol = type("GuardedH11", (GuardedH11Protocol,), {"header_timeout_s": header_timeout_s})
    return {"http": protocol, "h11_max_incomplete_event_size": MAX_HEADER_BYTES,
            "timeout_keep_alive": 5}
