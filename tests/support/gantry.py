"""Gantry-02 (a Fanuc-style 3-axis machine of the test fleet) behind the simulated PMC's
Modbus/TCP server on loopback, and two map versions for it: what the Modbus link's tests
share."""

from __future__ import annotations

import contextlib
import functools
from collections.abc import AsyncIterator

from machine_sim.fanuc import FanucConfig
from machine_sim.modbus_server import PmcModbusServer
from machine_sim.runtime import MachineRuntime
from machine_sim.windowcnc import WindowCNC
from protocol import Controller, MapEncoding
from server.links.modbus import ModbusMemory
from server.links.window.memory import MemoryClient
from server.links.window.session import IDLE_POLL_S, ControllerSession
from server.mapcodec import encode, with_version
from server.push.adapter import build_for
from tests.support.integration import campaign, spec
from volumetric.identify.fit import fit

__all__ = ["GANTRY", "machine", "memory", "payloads", "runtime", "session"]

GANTRY = "gantry-02"  # Fanuc-style 3-axis machine of the test fleet


@functools.cache
def payloads(name: str = GANTRY) -> tuple[bytes, bytes]:
    """Two map versions of the machine (v1 of its fitted model, v2 of that model with a
    constant 5 µm added to x), as the center builds them for a factored-map ladder."""
    sim, readings, _ = campaign(name)
    model = fit(sim.machine, readings).model
    body = model.to_json()
    s = spec(name)
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    one = build_for(s.description, "fanuc", body, {}, 1.0, formats)
    return encode(with_version(one, 1)), encode(with_version(one, 2))


def runtime(name: str = GANTRY) -> MachineRuntime:
    return MachineRuntime(spec(name).machine, seed=1,
                          fanuc=FanucConfig(max_step_counts=100_000))


@contextlib.asynccontextmanager
async def machine(delay_s: float = 0.0, order: str = "little"
                  ) -> AsyncIterator[tuple[WindowCNC, PmcModbusServer]]:
    servers: list[PmcModbusServer] = []

    def factory(cnc: WindowCNC) -> PmcModbusServer:
        srv = PmcModbusServer(cnc, port=0, register=1000, byte_order=order,  # type: ignore[arg-type]
                              delay_s=delay_s)
        servers.append(srv)
        return srv

    async with WindowCNC(spec(GANTRY).machine, factory, runtime=runtime(),
                         cycle_s=0.005) as cnc:
        yield cnc, servers[0]


def memory(srv: PmcModbusServer, order: str = "little") -> ModbusMemory:
    """The center's client of a :func:`machine`'s window (register 1000)."""
    return ModbusMemory("127.0.0.1", srv.port, register=1000, byte_order=order)  # type: ignore[arg-type]


def session(srv: PmcModbusServer, order: str = "little", *,
            client: MemoryClient | None = None, idle_poll_s: float = IDLE_POLL_S
            ) -> ControllerSession:
    """The center's session with gantry-02 behind ``srv`` (the verdict polled every
    10 ms); ``client`` instead of :func:`memory`'s."""
    m = spec(GANTRY).machine
    return ControllerSession(m.name, "127.0.0.1", Controller.FANUC, m.axis_names,
                             client or memory(srv, order), link="modbus", chain=m.chain,
                             poll_s=0.01, idle_poll_s=idle_poll_s)
