"""A simulated Fanuc PMC behind its Modbus/TCP server, with the faults a plant meets.

Faults are injected at the server's register area (what pymodbus asks of the PMC memory),
so the center sees real exception answers on a real socket: busy answers (06) at a given
rate, a write refused (02) on part of the window, the PLC program stopped. A silent
server accepts connections and never answers.
"""

from __future__ import annotations

import asyncio
import functools
import random
import struct
from collections.abc import AsyncIterator
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass, field
from typing import Any

from machine_sim.fanuc import FanucConfig
from machine_sim.modbus_server import PmcModbusServer
from machine_sim.runtime import MachineRuntime
from machine_sim.windowcnc import WindowCNC
from protocol.ctrlmem import BUFFERS_AT, SWITCH_AT
from tests.support.integration import Spec

REGISTER = 2000
"""First holding register of the simulated windows."""


@dataclass
class Faults:
    """What the PMC's server does wrong, changeable while it runs.

    Attributes
    ----------
    busy : float
        Fraction of requests answered with exception 06 (server device busy).
    refuse_buffer_writes : bool
        Writes into the map buffers answered with exception 02 (illegal data address):
        a push fails after the session opened.
    """

    busy: float = 0.0
    refuse_buffer_writes: bool = False
    rng: random.Random = field(default_factory=lambda: random.Random(7))
    busy_answers: int = 0
    buffer_writes: int = 0
    """Writes into the buffers asked for (refused or not): one push writes several."""
    switch_writes: int = 0
    """Writes of the switch word (one per push that got that far)."""
    identity_reads: int = 0
    """Reads of the identity block: one per session the center opens."""
    tear_headers: int = 0
    """Buffer headers still to tear: the next this many written get one byte flipped (the
    PLC answers code 100)."""
    headers_at: tuple[int, ...] = ()
    """Window offsets of the buffer headers (set by :func:`pmc`)."""


def inject(srv: PmcModbusServer, faults: Faults) -> None:
    """Put ``faults`` between the server and the PMC memory of ``srv`` (its area answers
    one request PDU at a time: :meth:`machine_sim.modbus_server.PmcArea.answer`)."""
    area: Any = srv.area
    plain = area.answer
    first = area.register

    def answer(unit: int, pdu: bytes) -> bytes:
        fc = pdu[0] if pdu else 0
        if unit != area.unit_id or fc not in (0x03, 0x10) or len(pdu) < 5:
            return bytes(plain(unit, pdu))
        if faults.busy and faults.rng.random() < faults.busy:
            faults.busy_answers += 1
            return bytes([fc | 0x80, 6])
        address, count = struct.unpack_from(">HH", pdu, 1)
        offset = (address - first) * 2
        if fc == 0x03:
            if offset == 0:
                faults.identity_reads += 1
            return bytes(plain(unit, pdu))
        if offset >= BUFFERS_AT:
            faults.buffer_writes += 1
            if faults.refuse_buffer_writes:
                return bytes([fc | 0x80, 2])
            data = pdu[6:]
            # a header written, not one cleared (32 zero bytes, alone or at the start of
            # the first payload block's request)
            if faults.tear_headers and offset in faults.headers_at and any(data[:32]):
                faults.tear_headers -= 1
                pdu = pdu[:6] + bytes([data[0] ^ 1, data[1] ^ 1]) + data[2:]
        elif offset <= SWITCH_AT < offset + 2 * count:
            faults.switch_writes += 1
        return bytes(plain(unit, pdu))

    area.answer = answer


@asynccontextmanager
async def pmc(s: Spec, *, faults: Faults | None = None, byte_order: str = "little",
              unit_id: int = 1, cycle_s: float = 0.02, **runtime: Any
              ) -> AsyncIterator[WindowCNC]:
    """The machine of ``s`` with its PMC window served at :data:`REGISTER` on loopback."""
    def factory(cnc: WindowCNC) -> PmcModbusServer:
        srv = PmcModbusServer(cnc, port=0, register=REGISTER, unit_id=unit_id,
                              byte_order=byte_order)  # type: ignore[arg-type]
        if faults is not None:
            inject(srv, faults)
        return srv

    rt = MachineRuntime(s.machine, seed=s.seed, fanuc=FanucConfig(max_step_counts=1000),
                        **runtime)
    async with WindowCNC(s.machine, factory, runtime=rt, cycle_s=cycle_s) as cnc:
        if faults is not None:
            faults.headers_at = (cnc.layout.buffer_at(1), cnc.layout.buffer_at(2))
        yield cnc


def modbus_link(port: int, **more: Any) -> dict[str, Any]:
    """A registration's ``link`` to a PMC of :func:`pmc` on loopback ``port``."""
    return {"kind": "modbus", "host": "127.0.0.1", "port": port,
            "start_register": REGISTER, "poll_ms": 20, **more}


def linked(s: Spec, port: int, **more: Any) -> Spec:
    """``s`` registered with a modbus link (:func:`modbus_link`)."""
    return Spec({**s.description, "link": modbus_link(port, **more)}, s.secret, s.seed,
                s.effects)


@asynccontextmanager
async def silent_server() -> AsyncIterator[int]:
    """A TCP server on loopback that accepts and never answers; yields its port."""
    held: list[asyncio.StreamWriter] = []

    async def hold(_r: asyncio.StreamReader, w: asyncio.StreamWriter) -> None:
        held.append(w)

    server = await asyncio.start_server(hold, "127.0.0.1", 0)
    try:
        yield int(server.sockets[0].getsockname()[1])
    finally:
        for w in held:
            w.close()
        server.close()
        await server.wait_closed()


@functools.cache
def built_map(name: str = "gantry-02") -> Any:
    """The map the center builds for a Fanuc machine of the test fleet from its fitted
    model, for a factored-map ladder (a ``MapContent``: ``encode(with_version(m, v))``)."""
    from protocol import MapEncoding
    from server.push.adapter import build_for
    from tests.support.integration import campaign, spec
    from volumetric.identify.fit import fit

    sim, readings, _ = campaign(name)
    body = fit(sim.machine, readings).model.to_json()
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    return build_for(spec(name).description, "fanuc", body, {}, 1.0, formats)


def payload(version: int, name: str = "gantry-02") -> bytes:
    """:func:`built_map` as map ``version``, encoded."""
    from server.mapcodec import encode, with_version

    return encode(with_version(built_map(name), version))


class _Gateway:
    """A Modbus/TCP gateway's register space: each unit id another controller's window
    (their :class:`~machine_sim.modbus_server.PmcArea` objects, answering in turn)."""

    def __init__(self, areas: dict[int, Any]) -> None:
        self.areas = areas

    def answer(self, unit: int, pdu: bytes) -> bytes:
        area = self.areas.get(unit)
        if area is None:
            return bytes([(pdu[0] if pdu else 0) | 0x80, 0x0B])  # no target there
        return bytes(area.answer(unit, pdu))

    def too_long(self, fc: int) -> bytes:
        return bytes(next(iter(self.areas.values())).too_long(fc))


@asynccontextmanager
async def gateway(specs: dict[int, Spec]) -> AsyncIterator[tuple[int, dict[int, WindowCNC]]]:
    """Several PMCs behind one Modbus/TCP address, one unit id each; yields the port and
    the machines by unit id. The first PMC's server is the gateway: it answers for all."""
    async with AsyncExitStack() as stack:
        cncs: dict[int, WindowCNC] = {}
        for unit, s in specs.items():
            def make(cnc: WindowCNC, unit: int = unit) -> PmcModbusServer:
                return PmcModbusServer(cnc, port=0, register=REGISTER, unit_id=unit)
            rt = MachineRuntime(s.machine, seed=s.seed, fanuc=FanucConfig(max_step_counts=1000))
            cncs[unit] = await stack.enter_async_context(
                WindowCNC(s.machine, make, runtime=rt, cycle_s=0.02))
        servers: dict[int, Any] = {unit: cnc.server for unit, cnc in cncs.items()}
        front = next(iter(servers.values()))
        front.area = _Gateway({unit: srv.area for unit, srv in servers.items()})
        yield int(front.port), cncs
