"""``/api/live``: the dashboard snapshot as server-sent events, built once for all viewers.

One :class:`LiveFeed` per running Center builds a snapshot every ``period_s`` while at least
one viewer is connected, and only then: a dashboard nobody watches costs nothing. Each
viewer gets the current snapshot at once, then every snapshot that differs from the one
before (ignoring its timestamp), and a comment line when nothing changed for a while so
that proxies keep the connection open.

A stream ends by itself after ``max_stream_s`` (the browser's EventSource reconnects
within the ``retry`` delay and gets a fresh snapshot). Why: uvicorn's graceful shutdown
waits for open responses to finish and does not tell the app it is stopping, so an endless
stream would hold a shutdown forever. A viewer that goes away is noticed by Starlette,
which cancels the stream; :meth:`LiveFeed.subscribe` unsubscribes in ``finally``, and the
producer stops when the last viewer has left.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import AsyncGenerator, AsyncIterator, Awaitable, Callable

from server.dashboard.schemas import DashboardSnapshot

log = logging.getLogger(__name__)

PERIOD_S = 1.0
KEEPALIVE_S = 5.0
MAX_STREAM_S = 10.0
"""Longest life of one stream, s: the most an open dashboard can delay a shutdown. A
reconnect costs one request and one snapshot, which a viewer gets every second anyway."""
RETRY_MS = 1000

SnapshotSource = Callable[[], Awaitable[DashboardSnapshot]]


def _content(snapshot: DashboardSnapshot) -> str:
    """The snapshot without its timestamp, to tell a change from a tick."""
    return snapshot.model_copy(update={"generated_at": None}).model_dump_json()


class LiveFeed:
    """The shared snapshot producer; see the module docstring.

    Parameters
    ----------
    source
        Builds one snapshot (reads the database and the registry).
    period_s
        How often the producer builds a snapshot while viewers are connected, s.
    owner
        What the feed belongs to (the running Center), so that a restarted app makes anew.
    """

    def __init__(self, source: SnapshotSource, period_s: float | None = None,
                 owner: object = None) -> None:
        self.owner = owner
        self._source = source
        self._period_s = PERIOD_S if period_s is None else period_s
        self._latest: DashboardSnapshot | None = None
        self._changed = asyncio.Condition()
        self._serial = 0
        self._viewers = 0
        self._producer: asyncio.Task[None] | None = None
        self._closed = False

    @property
    def viewers(self) -> int:
        """How many streams are open."""
        return self._viewers

    async def _produce(self) -> None:
        last = None if self._latest is None else _content(self._latest)
        while True:
            await asyncio.sleep(self._period_s)
            try:
                snapshot = await self._source()
            except Exception:  # a database hiccup must not end every viewer's stream
                log.exception("dashboard snapshot failed; retrying in %.1f s", self._period_s)
                continue
            content = _content(snapshot)
            if content != last:
                last = content
                async with self._changed:
                    self._latest = snapshot
                    self._serial += 1
                    self._changed.notify_all()

    def closed(self) -> bool:
        """Whether :meth:`close` was called."""
        return self._closed

    def _news_since(self, serial: int) -> Callable[[], bool]:
        return lambda: self._serial != serial or self._closed

    async def subscribe(self) -> AsyncGenerator[DashboardSnapshot | None, None]:
        """The current snapshot, then each changed one; None when nothing changed for
        :data:`KEEPALIVE_S` (the caller sends a keep-alive). Ends when the feed closes."""
        if self.closed():
            return
        self._viewers += 1
        try:
            if self._latest is None or self._producer is None:
                # Nobody was watching: the last snapshot may be old.
                self._latest = await self._source()
            if self._producer is None or self._producer.done():
                self._producer = asyncio.create_task(self._produce(), name="dashboard-live")
            serial = self._serial
            yield self._latest
            while True:
                async with self._changed:
                    try:
                        async with asyncio.timeout(KEEPALIVE_S):
                            await self._changed.wait_for(self._news_since(serial))
                    except TimeoutError:
                        pass
                if self.closed():
                    return
                if self._serial == serial:
                    yield None
                    continue
                serial = self._serial
                assert self._latest is not None
                yield self._latest
        finally:
            self._viewers -= 1
            if self._viewers == 0:
                await self._stop_producer()

    async def _stop_producer(self) -> None:
        task, self._producer = self._producer, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task

    async def close(self) -> None:
        """End every stream and the producer (the app is stopping)."""
        self._closed = True
        async with self._changed:
            self._changed.notify_all()
        await self._stop_producer()


def sse_event(event: str, data: str) -> str:
    """One server-sent event (``data`` must be one line, as JSON from pydantic is)."""
    return f"event: {event}\ndata: {data}\n\n"


async def sse_stream(feed: LiveFeed, *, max_stream_s: float | None = None
                     ) -> AsyncIterator[str]:
    """The text of ``/api/live``: ``snapshot`` events, keep-alive comments, and the end
    after ``max_stream_s`` (default :data:`MAX_STREAM_S`; see the module docstring)."""
    yield f"retry: {RETRY_MS}\n\n"
    deadline = time.monotonic() + (MAX_STREAM_S if max_stream_s is None else max_stream_s)
    updates = feed.subscribe()
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                break
            try:
                async with asyncio.timeout(left):
                    snapshot = await anext(updates)
            except (TimeoutError, StopAsyncIteration):
                break
            if snapshot is None:
                yield ": keep-alive\n\n"
            else:
                yield sse_event("snapshot", snapshot.model_dump_json())
    finally:
        await updates.aclose()
