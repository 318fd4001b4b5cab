"""The Modbus link's own client: several requests in flight, and the servers that do not
take that.

:class:`~server.links.modbus.ModbusMemory` sends a push's payload blocks together (Modbus/TCP
transaction ids match the answers) and the header and switch word each alone after them.
Against a server that answers only the first of several requests it goes on one at a
time; against pymodbus' own server (a maintained stack, which behaves so) a whole map is
written and read back. Busy answers within a batch, an answer from another unit and a
garbled frame are told apart.
"""

from __future__ import annotations

import asyncio
import contextlib
import socket
import struct
from collections.abc import AsyncIterator, Callable, Sequence

import pytest
from pymodbus.datastore import ModbusDeviceContext, ModbusSequentialDataBlock, ModbusServerContext
from pymodbus.server import ModbusTcpServer

from protocol.ctrlmem import STATUS_AT, STATUS_SIZE, SWITCH_AT, Layout
from protocol.mbap import HEADER, frame, take_frame
from server.links.modbus import ModbusMemory
from server.links.window.memory import LinkError
from server.links.window.session import map_writes
from tests.support.gantry import machine, payloads, session

pytestmark = pytest.mark.timeout(120)

Answer = Callable[[int, int, bytes], bytes | None]
"""What a test server answers to one request (tid, unit, PDU): a PDU, or None for none."""


class RawServer:
    """A Modbus/TCP server of a few lines: each request's answer comes from ``answer``
    after ``delay_s``; it notes how many requests were waiting for their answer at once.
    ``first_only``: of the requests in one TCP segment only the first is read (the rest
    are dropped), as a server that reads one frame per segment does."""

    def __init__(self, answer: Answer, *, delay_s: float = 0.0,
                 first_only: bool = False) -> None:
        self.answer = answer
        self.delay_s = delay_s
        self.first_only = first_only
        self.most_waiting = 0
        self.requests: list[bytes] = []
        self.port = 0

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
                     ) -> None:
        buffer = bytearray()
        with contextlib.suppress(ConnectionError):
            while chunk := await reader.read(65536):
                buffer += chunk
                frames = []
                while (got := take_frame(buffer)) is not None:
                    frames.append(got)
                if self.first_only:
                    frames, buffer = frames[:1], bytearray()
                self.most_waiting = max(self.most_waiting, len(frames))
                for tid, unit, pdu in frames:
                    self.requests.append(pdu)
                    await asyncio.sleep(self.delay_s)
                    out = self.answer(tid, unit, pdu)
                    if out is not None:
                        writer.write(frame(tid, unit, out))
        writer.close()

    @contextlib.asynccontextmanager
    async def running(self) -> AsyncIterator[RawServer]:
        server = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = server.sockets[0].getsockname()[1]
        async with server:
            yield self


def registers(memory: dict[int, bytes]) -> Answer:
    """Answers as a holding-register area kept in ``memory`` (register -> two bytes)."""
    def answer(_tid: int, _unit: int, pdu: bytes) -> bytes:
        fc, first, count = struct.unpack_from(">BHH", pdu)
        if fc == 0x10:
            for k in range(count):
                memory[first + k] = pdu[6 + 2 * k:8 + 2 * k]
            return pdu[:5]
        data = b"".join(memory.get(first + k, b"\0\0") for k in range(count))
        return bytes((0x03, 2 * count)) + data
    return answer


BLOCKS = [(200 + 246 * k, bytes(range(k, k + 246))) for k in range(5)]
"""Five full write blocks (123 registers each), as a push's payload goes."""


async def test_a_pushs_blocks_are_in_flight_together_and_land_in_order_of_registers() -> None:
    memory: dict[int, bytes] = {}
    async with RawServer(registers(memory), delay_s=0.02).running() as srv:
        client = ModbusMemory("127.0.0.1", srv.port, byte_order="big")
        await client.connect()
        try:
            await client.write_many(BLOCKS)
            assert srv.most_waiting == 5  # all five sent before the first answer
            for offset, data in BLOCKS:
                assert await client.read(offset, len(data)) == data
            one_by_one = ModbusMemory("127.0.0.1", srv.port, pipeline=False)
            await one_by_one.connect()
            srv.most_waiting = 0
            await one_by_one.write_many(BLOCKS)
            assert srv.most_waiting == 1
            await one_by_one.close()
        finally:
            await client.close()


async def test_answers_coming_one_by_one_are_waited_for_from_the_last_one() -> None:
    """The time-out runs from the last answer, not from the send: five answers 0.15 s
    apart (0.75 s in all) with a time-out of 0.3 s are all taken, none asked again."""
    memory: dict[int, bytes] = {}
    async with RawServer(registers(memory), delay_s=0.15).running() as srv:
        client = ModbusMemory("127.0.0.1", srv.port, byte_order="big", timeout_s=0.3)
        await client.connect()
        try:
            await client.write_many(BLOCKS)
            assert srv.most_waiting == 5
            assert client.no_answer_retries == 0 and client.pipeline
            assert len(srv.requests) == 5
            for offset, data in BLOCKS:
                assert await client.read(offset, len(data)) == data
        finally:
            await client.close()


async def test_a_connection_lost_mid_round_ends_the_exchange_when_it_goes() -> None:
    """Three of five answers, then the server closes the connection: the exchange ends
    then, with the lost connection as its reason, not after the 10 s time-out."""
    answer = registers({})

    async def three_then_close(r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
        buffer = bytearray()
        frames: list[tuple[int, int, bytes]] = []
        while len(frames) < 5:
            buffer += await r.read(65536)
            while (got := take_frame(buffer)) is not None:
                frames.append(got)
        for tid, unit, pdu in frames[:3]:
            out = answer(tid, unit, pdu)
            assert out is not None
            w.write(frame(tid, unit, out))
        await w.drain()
        await asyncio.sleep(0.2)  # the three answers are in before the close
        w.close()

    server = await asyncio.start_server(three_then_close, "127.0.0.1", 0)
    async with server:
        client = ModbusMemory("127.0.0.1", server.sockets[0].getsockname()[1],
                              byte_order="big", timeout_s=10.0)
        await client.connect()
        loop = asyncio.get_running_loop()
        t0 = loop.time()
        try:
            with pytest.raises(LinkError) as lost:
                await client.write_many(BLOCKS)
            assert loop.time() - t0 < 5.0
            assert lost.value.reason == "connection_lost", lost.value
            assert "write of registers 469..591 failed" in str(lost.value), lost.value
        finally:
            await client.close()


async def test_a_server_answering_only_the_first_request_is_asked_one_at_a_time() -> None:
    memory: dict[int, bytes] = {}
    async with RawServer(registers(memory), first_only=True).running() as srv:
        client = ModbusMemory("127.0.0.1", srv.port, byte_order="big", timeout_s=0.3)
        await client.connect()
        try:
            await client.read(0, 2)  # the connection has answered once
            await client.write_many(BLOCKS[:3])
            assert not client.pipeline
            assert client.no_answer_retries == 2  # the two dropped, asked again
            for offset, data in BLOCKS[:3]:
                assert await client.read(offset, len(data)) == data
            srv.most_waiting = 0
            await client.write_many(BLOCKS)
            assert srv.most_waiting == 1
        finally:
            await client.close()


async def test_busy_answers_within_a_batch_are_asked_again_alone() -> None:
    memory: dict[int, bytes] = {}
    plain = registers(memory)
    seen: set[bytes] = set()

    def busy_once(tid: int, unit: int, pdu: bytes) -> bytes | None:
        if pdu not in seen:  # each request's first try: 06 server device busy
            seen.add(pdu)
            return bytes((pdu[0] | 0x80, 6))
        return plain(tid, unit, pdu)

    async with RawServer(busy_once).running() as srv:
        client = ModbusMemory("127.0.0.1", srv.port, byte_order="big")
        await client.connect()
        try:
            await client.write_many(BLOCKS)
            assert client.busy_retries == 5 and "exception 06" in client.busy_note
            assert all(memory[100 + 123 * k] == bytes((k, k + 1)) for k in range(5))
        finally:
            await client.close()


@pytest.mark.parametrize(("answer", "reason"), [
    (lambda tid, unit, pdu: pdu[:1] + b"\x00\x00", "answer"),  # not a write's echo
    (lambda tid, unit, pdu: bytes((pdu[0] | 0x80, 2)), "exception_02"),
    (lambda tid, unit, pdu: bytes((pdu[0] | 0x80, 6)), "exception_06"),  # busy for good
])
async def test_a_wrong_answer_ends_the_exchange_with_its_reason(answer: Answer,
                                                                reason: str) -> None:
    async with RawServer(answer).running() as srv:
        client = ModbusMemory("127.0.0.1", srv.port)
        await client.connect()
        try:
            with pytest.raises(LinkError) as caught:
                await client.write_many(BLOCKS[:2])
            assert caught.value.reason == reason, caught.value
        finally:
            await client.close()


async def test_an_answer_from_another_unit_or_garbled_bytes_is_no_answer_to_the_request(
        ) -> None:
    async def reply(r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
        head = await r.readexactly(HEADER.size)
        tid, _protocol, length, unit = HEADER.unpack(head)
        await r.readexactly(length - 1)
        w.write(frame(tid, unit + 1, bytes((0x03, 2)) + b"\0\0"))  # another unit's
        w.write(b"\x00\x01\x00\x07\x00\x03garbage")  # protocol id 7: no frame
        await w.drain()
        await asyncio.sleep(1)

    server = await asyncio.start_server(reply, "127.0.0.1", 0)
    async with server:
        port = server.sockets[0].getsockname()[1]
        client = ModbusMemory("127.0.0.1", port, unit_id=3)
        await client.connect()
        try:
            with pytest.raises(LinkError) as caught:
                await client.read(0, 2)
            assert caught.value.reason == "answer" and "unit id 4" in str(caught.value)
            with pytest.raises(LinkError) as lost:
                await client.read(0, 2)  # the garbled bytes ended the connection
            assert lost.value.reason == "connection_lost", lost.value
        finally:
            await client.close()


async def test_pymodbus_own_server_takes_a_whole_map() -> None:
    """A maintained stack's server: it answers one request of a segment, so the link
    falls back to one at a time within the first push and writes the map whole."""
    block = ModbusSequentialDataBlock(1, [0] * 20_000)  # type: ignore[no-untyped-call]
    context = ModbusServerContext(devices=ModbusDeviceContext(hr=block), single=True)
    with socket.socket() as probe:  # a free port for it
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = ModbusTcpServer(context, address=("127.0.0.1", port))
    task = asyncio.create_task(server.serve_forever())
    try:
        async with asyncio.timeout(5):
            while True:
                with contextlib.suppress(OSError):
                    _r, w = await asyncio.open_connection("127.0.0.1", port)
                    w.close()
                    break
                await asyncio.sleep(0.02)
        client = ModbusMemory("127.0.0.1", port, timeout_s=0.5)
        await client.connect()
        try:
            payload = payloads()[0]
            layout = Layout(4096)
            writes = map_writes(layout, 1, payload, 1, 1, block=client.block)
            *blocks, header, switch = writes
            await client.read(0, 2)
            await client.write_many([(w.offset, w.data) for w in blocks])
            for alone in (header, switch):
                await client.write(alone.offset, alone.data)
            window = bytearray(layout.size)  # what the writes leave, in their order
            for each in writes:
                window[each.offset:each.offset + len(each.data)] = each.data
            for each in writes:
                end = each.offset + len(each.data)
                assert await client.read(each.offset, len(each.data)) == window[each.offset:end]
            assert not client.pipeline  # it fell back within the first push
        finally:
            await client.close()
    finally:
        await server.shutdown()  # type: ignore[no-untyped-call]
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task


async def test_a_push_reads_the_status_with_its_buffer_writes_and_switches_after_them(
        ) -> None:
    calls: list[tuple[list[int], tuple[int, int] | None]] = []

    class Recording(ModbusMemory):
        async def write_many(self, writes: Sequence[tuple[int, bytes]], *,
                             read: tuple[int, int] | None = None) -> bytes:
            calls.append(([offset for offset, _ in writes], read))
            return await super().write_many(writes, read=read)

    p1, p2 = payloads()
    async with machine() as (_cnc, srv):
        s = session(srv, client=Recording("127.0.0.1", srv.port, register=1000))
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            assert s.layout is not None
            for version, payload, target in ((1, p1, 1), (2, p2, 2)):
                calls.clear()
                assert (await s.push_map(version, payload, 20.0)).applied
                at = s.layout.buffer_at(target)
                (offsets, read), (switch, none) = calls[:2]  # then the slots, maybe
                # status, cleared header with the first block, the other four, the header
                assert read == (STATUS_AT, STATUS_SIZE)
                assert len(offsets) == 6 and offsets[0] == offsets[-1] == at, offsets
                assert switch == [SWITCH_AT] and none is None
        finally:
            s.abort(None, "test over")
            await runner


async def test_a_buffer_switched_by_someone_else_is_not_written_over() -> None:
    """Another writer switched the PLC to the buffer this session would write: the fresh
    status read with the writes says so, and the map goes into the other buffer."""
    p1, p2 = payloads()
    async with machine() as (cnc, srv):
        s = session(srv, idle_poll_s=60.0)  # no look at the status between pushes
        await s.open()
        runner = asyncio.create_task(s.run())
        other = session(srv)
        await other.open()
        other_runner = asyncio.create_task(other.run())
        try:
            assert (await s.push_map(1, p1, 20.0)).applied  # into buffer 1
            assert (await other.push_map(2, p2, 20.0)).applied  # buffer 2, unseen by s
            assert s.status is not None and s.status.active == 1  # s's last look
            assert (await s.push_map(2, p2, 20.0)).applied
            assert s.status is not None and s.status.active == 1  # not buffer 2 again
            assert cnc.runtime.controller.store.version == 2
        finally:
            for one, task in ((s, runner), (other, other_runner)):
                one.abort(None, "test over")
                await task
