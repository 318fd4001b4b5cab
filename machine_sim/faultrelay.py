"""A Modbus/TCP relay that injects the faults a plant network and a busy PMC produce.

It stands between the center (the Modbus client) and a controller's Modbus/TCP server,
reads whole request frames (:mod:`protocol.mbap`), and for each one either forwards
it and passes the server's answer back byte for byte, or does what :class:`Faults` asks:
answer it itself with an exception (a fraction of all requests, e.g. 06 "server device
busy"; every write that touches given registers, e.g. 02), delay the answer, swallow it
(never answer), or close the connection after a number of requests. The faults can be
changed while it runs (:attr:`FaultRelay.faults`), so a benchmark can clear a fault and
time the recovery. What the center did is counted from outside: TCP connects and every
request with its time (:attr:`FaultRelay.seen`).

Requests are answered in turn, one at a time per connection, as a PMC does: a request
whose answer is delayed or never comes holds back the ones behind it.
"""

from __future__ import annotations

import asyncio
import contextlib
import random
from collections import deque
from dataclasses import dataclass
from types import TracebackType

from protocol.mbap import HEADER, MbapError, Request, exception_answer, frame_size, parse_request

__all__ = ["FaultRelay", "Faults", "Seen"]


@dataclass(frozen=True, slots=True)
class Faults:
    """What the relay does to the requests (the default: nothing, a plain relay).

    Attributes
    ----------
    exception_fraction : float
        Share of requests (0..1, drawn at random) answered with ``exception_code``
        instead of being forwarded.
    exception_code : int
        06 server device busy, 05 acknowledge (both: "try again later"), ...
    refuse_writes : tuple of (first, end) register ranges
        A write touching any register of ``[first, end)`` is answered with
        ``refuse_code`` and not forwarded.
    refuse_code : int
        02 illegal data address by default.
    drop_after : int or None
        Close the connection once this many of its requests are answered.
    delay_s : float
        Wait this long before passing each answer back, s.
    swallow : bool
        Never answer (the requests are not forwarded either): a controller that
        accepts the connection and stays silent.
    """

    exception_fraction: float = 0.0
    exception_code: int = 6
    refuse_writes: tuple[tuple[int, int], ...] = ()
    refuse_code: int = 2
    drop_after: int | None = None
    delay_s: float = 0.0
    swallow: bool = False


@dataclass(frozen=True, slots=True)
class Seen:
    """One request as it reached the relay.

    Attributes
    ----------
    t : float
        Event-loop time it arrived, s.
    connection : int
        Which connection (1 for the first accepted).
    request : Request
    """

    t: float
    connection: int
    request: Request


async def _read_frame(reader: asyncio.StreamReader) -> bytes:
    head = await reader.readexactly(HEADER.size)
    return head + await reader.readexactly(frame_size(head) - HEADER.size)


class FaultRelay:
    """Listen on ``host:port`` and relay each connection to ``upstream``.

    Parameters
    ----------
    upstream : (host, port)
        The controller's Modbus/TCP server; may be changed later (new connections only).
    host, port : str, int
        Where to listen (port 0: any free one; :attr:`port` is the bound one).
    faults : Faults
    seed : int
        For the draws of ``exception_fraction``.
    keep : int
        Most requests kept in :attr:`seen` (the oldest go first).
    """

    def __init__(self, upstream: tuple[str, int], *, host: str = "127.0.0.1", port: int = 0,
                 faults: Faults | None = None, seed: int = 0, keep: int = 100_000) -> None:
        self.upstream = upstream
        self.host = host
        self.port = port
        self.faults = faults or Faults()
        self.connects = 0
        self.connect_times: deque[float] = deque(maxlen=keep)
        self.seen: deque[Seen] = deque(maxlen=keep)
        self.forwarded = 0
        self.exceptions = 0
        self.swallowed = 0
        self.dropped = 0
        self._rng = random.Random(seed)
        self._server: asyncio.Server | None = None
        self._tasks: set[asyncio.Task[None]] = set()
        self._writers: set[asyncio.StreamWriter] = set()

    async def __aenter__(self) -> FaultRelay:
        self._server = await asyncio.start_server(self._accept, self.host, self.port)
        self.port = int(self._server.sockets[0].getsockname()[1])
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        if self._server is not None:
            self._server.close()
            self._server = None
        self.cut()  # each connection's reader sees the end and cleans up
        tasks = list(self._tasks)
        if tasks:
            _, late = await asyncio.wait(tasks, timeout=1.0)
            for t in late:  # e.g. still connecting upstream
                t.cancel()
            await asyncio.gather(*late, return_exceptions=True)

    def cut(self) -> None:
        """Close every connection relayed now (the listener stays)."""
        for w in list(self._writers):
            w.close()

    def writes(self, since: float = 0.0) -> list[Request]:
        """Write requests that arrived at or after loop time ``since``."""
        return [s.request for s in self.seen if s.t >= since and s.request.write]

    def connects_since(self, since: float) -> int:
        return sum(1 for t in self.connect_times if t >= since)

    async def _accept(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        assert task is not None
        self._tasks.add(task)
        self._writers.add(writer)
        self.connects += 1
        cid = self.connects
        loop = asyncio.get_running_loop()
        self.connect_times.append(loop.time())
        up: asyncio.StreamWriter | None = None
        answering: asyncio.Task[None] | None = None
        try:
            up_reader, up = await asyncio.open_connection(*self.upstream)
            self._writers.add(up)
            queue: asyncio.Queue[bytes] = asyncio.Queue()
            answering = asyncio.create_task(self._answer(queue, writer, up_reader, up))
            # frames are read here as they come, so the client's closing is noticed even
            # while an answer is held back (a delay, a swallowed request, a silent server)
            while not answering.done():
                frame = await _read_frame(reader)
                self.seen.append(Seen(loop.time(), cid, parse_request(frame)))
                queue.put_nowait(frame)
        except (asyncio.IncompleteReadError, ConnectionError, OSError, MbapError):
            pass
        finally:
            if answering is not None:
                answering.cancel()
                await asyncio.gather(answering, return_exceptions=True)
            for w in (writer, up):
                if w is not None:
                    self._writers.discard(w)
                    w.close()
            self._tasks.discard(task)

    async def _answer(self, queue: asyncio.Queue[bytes], writer: asyncio.StreamWriter,
                      up_reader: asyncio.StreamReader, up: asyncio.StreamWriter) -> None:
        answered = 0
        try:
            while True:
                frame = await queue.get()
                f = self.faults
                if f.swallow:
                    self.swallowed += 1
                    continue
                request = parse_request(frame)
                if any(request.touches(a, b) for a, b in f.refuse_writes):
                    answer = exception_answer(frame, f.refuse_code)
                    self.exceptions += 1
                elif f.exception_fraction and self._rng.random() < f.exception_fraction:
                    answer = exception_answer(frame, f.exception_code)
                    self.exceptions += 1
                else:
                    up.write(frame)
                    await up.drain()
                    answer = await _read_frame(up_reader)
                    self.forwarded += 1
                if f.delay_s:
                    await asyncio.sleep(f.delay_s)
                writer.write(answer)
                await writer.drain()
                answered += 1
                if f.drop_after is not None and answered >= f.drop_after:
                    self.dropped += 1
                    return
        except (asyncio.IncompleteReadError, ConnectionError, OSError, MbapError):
            return
        finally:
            with contextlib.suppress(Exception):
                writer.close()  # the reading side sees the end and cleans up
