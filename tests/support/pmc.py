"""A simulated Fanuc PMC behind its Modbus/TCP server, with the faults a plant meets.

Faults are injected at the server's register area (what pymodbus asks of the PMC memory),
so the center sees real exception answers on a real socket: busy answers (06) at a given
rate, a write refused (02) on part of the window, the PLC program stopped. A silent
server accepts connections and never answers.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import random
from collections.abc import AsyncIterator, Sequence
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass, field
from typing import Any

from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.exceptions import NoSuchIdException
from pymodbus.server import ModbusTcpServer

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
    """Put ``faults`` between the server and the PMC memory of ``srv``."""
    area: Any = srv.area
    get, put = area.async_getValues, area.async_setValues
    first = area.register

    def busy() -> bool:
        if faults.busy and faults.rng.random() < faults.busy:
            faults.busy_answers += 1
            return True
        return False

    async def get_values(device_id: int, func_code: int, address: int,
                         count: int = 1) -> Any:
        area._device(device_id)
        if address == first:
            faults.identity_reads += 1
        if busy():
            return ExcCodes.DEVICE_BUSY
        return await get(device_id, func_code, address, count)

    async def set_values(device_id: int, func_code: int, address: int,
                         values: Sequence[int]) -> Any:
        area._device(device_id)
        if busy():
            return ExcCodes.DEVICE_BUSY
        offset = (address - first) * 2
        if offset >= BUFFERS_AT:
            faults.buffer_writes += 1
            if faults.refuse_buffer_writes:
                return ExcCodes.ILLEGAL_ADDRESS
            if faults.tear_headers and offset in faults.headers_at and any(values):
                faults.tear_headers -= 1
                values = [values[0] ^ 0x0101, *values[1:]]
        elif offset <= SWITCH_AT < offset + 2 * len(values):
            faults.switch_writes += 1
        return await put(device_id, func_code, address, values)

    area.async_getValues = get_values
    area.async_setValues = set_values


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


class _Gateway(ModbusServerContext):
    """A Modbus/TCP gateway's register space: each unit id is another controller's
    window (the areas of unstarted :class:`PmcModbusServer` objects)."""

    def __init__(self, areas: dict[int, Any]) -> None:  # no super(): no pymodbus store
        self.areas = areas
        self.old_simulator = True
        self.simdevices: list[Any] = []

    def _area(self, device_id: int) -> Any:
        area = self.areas.get(device_id)
        if area is None:
            raise NoSuchIdException(f"unit id {device_id}")
        return area

    async def async_getValues(self, device_id: int, func_code: int, address: int,
                              count: int = 1) -> Any:
        return await self._area(device_id).async_getValues(device_id, func_code, address,
                                                            count)

    async def async_setValues(self, device_id: int, func_code: int, address: int,
                              values: Any) -> Any:
        return await self._area(device_id).async_setValues(device_id, func_code, address,
                                                            values)

    def device_ids(self) -> list[int]:
        return sorted(self.areas)


@asynccontextmanager
async def gateway(specs: dict[int, Spec]) -> AsyncIterator[tuple[int, dict[int, WindowCNC]]]:
    """Several PMCs behind one Modbus/TCP address, one unit id each; yields the port and
    the machines by unit id."""
    async def idle() -> None:
        return None

    def factory(unit: int) -> Any:
        def make(cnc: WindowCNC) -> PmcModbusServer:
            srv = PmcModbusServer(cnc, port=0, register=REGISTER, unit_id=unit)
            srv.start = idle  # type: ignore[method-assign]  # the gateway serves it
            srv.stop = idle  # type: ignore[method-assign]
            return srv
        return make

    async with AsyncExitStack() as stack:
        cncs: dict[int, WindowCNC] = {}
        for unit, s in specs.items():
            rt = MachineRuntime(s.machine, seed=s.seed, fanuc=FanucConfig(max_step_counts=1000))
            cncs[unit] = await stack.enter_async_context(
                WindowCNC(s.machine, factory(unit), runtime=rt, cycle_s=0.02))
        areas = {unit: cnc.server.area for unit, cnc in cncs.items()}  # type: ignore[attr-defined]
        server = ModbusTcpServer(_Gateway(areas), address=("127.0.0.1", 0))
        await server.serve_forever(background=True)
        try:
            transport: Any = server.transport
            yield int(transport.sockets[0].getsockname()[1]), cncs
        finally:
            with contextlib.suppress(Exception):
                await server.shutdown()  # type: ignore[no-untyped-call]
