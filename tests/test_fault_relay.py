"""The Modbus/TCP fault relay (machine_sim/faultrelay.py) over real loopback sockets.

Upstream is a raw Modbus/TCP server written here that records every byte it receives and
answers each request with a frame of its own (the request's transaction id, a body that
differs per request), so "byte for byte" can be checked in both directions."""

from __future__ import annotations

import asyncio
import random
import struct
import time
from collections.abc import AsyncIterator

import pytest

from machine_sim.faultrelay import FaultRelay, Faults
from protocol.mbap import HEADER, frame_size

pytestmark = pytest.mark.timeout(60)


class Upstream:
    """A Modbus/TCP server that answers every request with a 03h-style answer whose
    registers count the requests it has answered."""

    def __init__(self) -> None:
        self.received = bytearray()
        self.sent = bytearray()
        self.port = 0
        self._server: asyncio.Server | None = None

    async def __aenter__(self) -> Upstream:
        self._server = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = int(self._server.sockets[0].getsockname()[1])
        return self

    async def __aexit__(self, *exc: object) -> None:
        assert self._server is not None
        self._server.close()

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while True:
                head = await reader.readexactly(HEADER.size)
                frame = head + await reader.readexactly(frame_size(head) - HEADER.size)
                self.received += frame
                tid, _, _, unit = HEADER.unpack_from(frame)
                n = len(self.sent) % 65536
                answer = HEADER.pack(tid, 0, 7, unit) + struct.pack(">BBHH", 3, 4, n, tid)
                self.sent += answer
                writer.write(answer)
                await writer.drain()
        except (asyncio.IncompleteReadError, ConnectionError):
            writer.close()


def read_request(tid: int, first: int, count: int, unit: int = 1) -> bytes:
    return HEADER.pack(tid, 0, 6, unit) + struct.pack(">BHH", 3, first, count)


def write_request(tid: int, first: int, values: list[int], unit: int = 1) -> bytes:
    body = struct.pack(f">BHHB{len(values)}H", 0x10, first, len(values), 2 * len(values),
                       *values)
    return HEADER.pack(tid, 0, 1 + len(body), unit) + body


async def answer(reader: asyncio.StreamReader) -> bytes:
    head = await reader.readexactly(HEADER.size)
    return head + await reader.readexactly(frame_size(head) - HEADER.size)


@pytest.fixture
async def upstream() -> AsyncIterator[Upstream]:
    async with Upstream() as up:
        yield up


async def test_frames_pass_byte_for_byte_and_connects_are_counted(upstream: Upstream) -> None:
    rng = random.Random(7)
    requests = [read_request(t, rng.randrange(0, 60000), rng.randrange(1, 126))
                if t % 3 else
                write_request(t, rng.randrange(0, 60000),
                              [rng.randrange(0, 65536) for _ in range(rng.randrange(1, 124))])
                for t in range(60)]
    async with FaultRelay(("127.0.0.1", upstream.port)) as relay:
        reader, writer = await asyncio.open_connection("127.0.0.1", relay.port)
        got = bytearray()
        for r in requests[:30]:  # one at a time
            writer.write(r)
            got += await answer(reader)
        writer.write(b"".join(requests[30:]))  # thirty in one segment: answered in turn
        for _ in requests[30:]:
            got += await answer(reader)
        writer.close()
        assert relay.connects == 1
        for _ in range(2):
            _, w = await asyncio.open_connection("127.0.0.1", relay.port)
            w.close()
        for _ in range(100):
            if relay.connects == 3:
                break
            await asyncio.sleep(0.01)
        assert relay.connects == 3
    assert bytes(upstream.received) == b"".join(requests)
    assert bytes(got) == bytes(upstream.sent)
    assert [s.request.write for s in relay.seen] == [t % 3 == 0 for t in range(60)]
    assert relay.forwarded == 60 and relay.exceptions == 0


async def test_busy_answers_at_the_asked_fraction(upstream: Upstream) -> None:
    n, share = 400, 0.3
    faults = Faults(exception_fraction=share, exception_code=6)
    async with FaultRelay(("127.0.0.1", upstream.port), faults=faults, seed=3) as relay:
        reader, writer = await asyncio.open_connection("127.0.0.1", relay.port)
        busy = 0
        for t in range(n):
            writer.write(read_request(t, 10, 2))
            a = await answer(reader)
            tid, _, _, unit = HEADER.unpack_from(a)
            assert (tid, unit) == (t, 1)
            if a[HEADER.size:] == bytes((0x83, 6)):
                busy += 1
            else:
                assert a[HEADER.size] == 3
        writer.close()
    sigma = (n * share * (1 - share)) ** 0.5
    assert abs(busy - n * share) < 4 * sigma, busy  # 120 +- 37
    assert len(upstream.received) == (n - busy) * 12  # only the others went on


async def test_refused_writes_drop_delay_and_swallow(upstream: Upstream) -> None:
    faults = Faults(refuse_writes=((256, 300),), drop_after=3)
    async with FaultRelay(("127.0.0.1", upstream.port), faults=faults) as relay:
        reader, writer = await asyncio.open_connection("127.0.0.1", relay.port)
        writer.write(write_request(1, 250, [0] * 10))  # 250..259 touches 256
        assert (await answer(reader))[HEADER.size:] == bytes((0x90, 2))
        writer.write(write_request(2, 240, [0] * 16))  # 240..255 does not
        assert (await answer(reader))[HEADER.size] == 3
        writer.write(read_request(3, 256, 10))  # a read of them is no write
        assert (await answer(reader))[HEADER.size] == 3
        assert await reader.read(1) == b""  # three answered: closed
        assert relay.dropped == 1

        relay.faults = Faults(delay_s=0.3)
        reader, writer = await asyncio.open_connection("127.0.0.1", relay.port)
        t0 = time.monotonic()
        writer.write(read_request(4, 0, 1))
        await answer(reader)
        assert time.monotonic() - t0 >= 0.3

        relay.faults = Faults(swallow=True)
        writer.write(read_request(5, 0, 1))
        with pytest.raises(TimeoutError):
            async with asyncio.timeout(0.5):
                await answer(reader)
        relay.faults = Faults()  # cleared: the next request is answered
        writer.write(read_request(6, 0, 1))
        assert HEADER.unpack_from(await answer(reader))[0] == 6
        writer.close()
        assert relay.connects == 2 and relay.swallowed == 1
