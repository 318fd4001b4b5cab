"""Finding controllers on a network: which hosts serve Modbus/TCP, OPC UA or EDNC.

The first seed's center "connects all machine tools after searching the local network";
here a search is a bounded set of TCP probes, each with a deadline:

* **Modbus/TCP** (port 502 by default): a 03h read of the window's identity block
  through pymodbus, at each unit id asked (1 by default; a gateway's controllers each
  have their own). An answer is a Modbus server; ``EDCM`` there is an EDNC PLC program's
  window, whose identity block then names the machine, the map formats and the capacity.
  An exception answer (01, 02) is still a Modbus server (another window start, or none);
* **OPC UA** (4840): the binary protocol's Hello (``HEL``); an ``ACK`` is an OPC UA
  server, whose endpoints (security policies and modes) asyncua then lists;
* **EDNC** (7878): a center's machine port (open; a center closes connections from
  unregistered addresses at once, so nothing more is learnt).

Nothing is written anywhere. :func:`discover` returns one :class:`Found` per answering
endpoint, with the ``link`` a registration would take.
"""

from __future__ import annotations

import asyncio
import contextlib
import ipaddress
import struct
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Final

from pymodbus.client import AsyncModbusTcpClient
from pymodbus.exceptions import ModbusException

from protocol.ctrlmem import IDENTITY_SIZE, ControllerMemoryError, decode_identity

__all__ = ["DEFAULT_PORTS", "MAX_HOSTS", "Found", "discover", "hosts_of"]

DEFAULT_PORTS: Final = {"modbus": 502, "opcua": 4840, "ednc": 7878}
MAX_HOSTS: Final = 4096
"""Largest search: a /20. Bigger networks are searched a part at a time."""


@dataclass(frozen=True)
class Found:
    """One endpoint that answered.

    Attributes
    ----------
    host : str
    port : int
    kind : {"modbus", "opcua", "ednc"}
    detail : str
        What it is, for people.
    link : dict
        The registration's ``link`` for it (empty for an EDNC center port).
    machine : str or None
        The machine an EDNC window declares.
    """

    host: str
    port: int
    kind: str
    detail: str
    link: dict[str, Any] = field(default_factory=dict)
    machine: str | None = None


def hosts_of(subnet: str) -> list[str]:
    """The host addresses of a CIDR network (a single address for /32).

    Raises
    ------
    ValueError
        Not a network, or more than :data:`MAX_HOSTS` hosts.
    """
    net = ipaddress.ip_network(subnet, strict=False)
    if net.num_addresses > MAX_HOSTS + 2:
        raise ValueError(f"{subnet} has {net.num_addresses} addresses; search at most "
                         f"{MAX_HOSTS} at a time (a /20)")
    hosts = [str(h) for h in net.hosts()] or [str(net.network_address)]
    return hosts


async def _modbus(host: str, port: int, register: int, timeout_s: float,
                  unit_ids: Sequence[int] = (1,)) -> list[Found]:
    """The Modbus/TCP server at ``host:port`` and, per unit id asked, what it serves
    (a gateway answers for several controllers, one unit id each)."""
    client = AsyncModbusTcpClient(host, port=port, timeout=timeout_s, retries=0,
                                  reconnect_delay=0)
    try:
        try:
            async with asyncio.timeout(timeout_s):
                if not await client.connect():
                    return []
        except (TimeoutError, OSError, ModbusException):
            return []
        return [await _modbus_unit(client, host, port, register, unit) for unit in unit_ids]
    finally:
        client.close()


async def _modbus_unit(client: AsyncModbusTcpClient, host: str, port: int, register: int,
                       unit: int) -> Found:
    link: dict[str, Any] = {"kind": "modbus", "host": host, "port": port,
                            "start_register": register}
    if unit != 1:
        link["unit_id"] = unit
    which = "" if unit == 1 else f" unit id {unit}"
    try:
        rr = await client.read_holding_registers(register, count=IDENTITY_SIZE // 2,
                                                 device_id=unit)
    except (TimeoutError, OSError, ModbusException) as exc:
        return Found(host, port, "modbus", f"TCP port open, no Modbus answer{which} ({exc})")
    if rr.isError():
        code = getattr(rr, "exception_code", 0)
        return Found(host, port, "modbus",
                     f"Modbus/TCP server{which} (exception {code} at register {register}: "
                     "no EDNC window there)", link)
    for order in ("little", "big"):
        fmt = f"{'<' if order == 'little' else '>'}{len(rr.registers)}H"
        raw = struct.pack(fmt, *rr.registers)
        try:
            ident = decode_identity(raw)
        except ControllerMemoryError:
            continue
        return Found(host, port, "modbus",
                     f"Modbus/TCP server{which} with the EDNC window of {ident.name!r} at "
                     f"register {register} ({order}-endian words; formats "
                     f"{int(ident.formats)}, {ident.capacity} B buffers)",
                     {**link, "byte_order": order}, ident.name)
    return Found(host, port, "modbus", f"Modbus/TCP server{which} (no EDNC window at "
                                       f"register {register})", link)


def _opcua_hello(url: str) -> bytes:
    body = struct.pack("<IIIII", 0, 65536, 65536, 0, 0)
    encoded = url.encode()
    body += struct.pack("<i", len(encoded)) + encoded
    return b"HELF" + struct.pack("<I", 8 + len(body)) + body


async def _opcua(host: str, port: int, timeout_s: float) -> Found | None:
    url = f"opc.tcp://{host}:{port}"
    try:
        async with asyncio.timeout(timeout_s):
            reader, writer = await asyncio.open_connection(host, port)
    except (TimeoutError, OSError):
        return None
    try:
        writer.write(_opcua_hello(url))
        async with asyncio.timeout(timeout_s):
            await writer.drain()
            head = await reader.readexactly(8)
    except (TimeoutError, OSError, asyncio.IncompleteReadError):
        return Found(host, port, "opcua", "TCP port open, no OPC UA answer")
    finally:
        writer.close()
        with contextlib.suppress(OSError):
            await writer.wait_closed()
    if head[:3] != b"ACK":
        return Found(host, port, "opcua", f"TCP port open, answered {head[:3]!r} to an "
                                          "OPC UA Hello")
    detail = "OPC UA server"
    with contextlib.suppress(Exception):  # the endpoint list is a courtesy
        from asyncua.client.client import Client

        async with asyncio.timeout(timeout_s * 4):
            client = Client(url, timeout=timeout_s * 4)
            endpoints = await client.connect_and_get_server_endpoints()
        modes = sorted({f"{e.SecurityPolicyUri.rsplit('#', 1)[-1]}/"
                        f"{e.SecurityMode.name.rstrip('_')}" for e in endpoints})
        detail += f" (endpoints {', '.join(modes)})"
    return Found(host, port, "opcua", detail + "; login needed to see its data",
                 {"kind": "opcua", "endpoint": url, "user": "USER",
                  "password_ref": "env:OPCUA_PASSWORD"})


async def _ednc(host: str, port: int, timeout_s: float) -> Found | None:
    try:
        async with asyncio.timeout(timeout_s):
            _reader, writer = await asyncio.open_connection(host, port)
    except (TimeoutError, OSError):
        return None
    writer.close()
    with contextlib.suppress(OSError):
        await writer.wait_closed()
    return Found(host, port, "ednc", "TCP port open (an EDNC center's machine port)")


async def discover(hosts: Iterable[str], *, modbus_port: int | None = 502,
                   opcua_port: int | None = 4840, ednc_port: int | None = 7878,
                   register: int = 0, timeout_s: float = 0.5, concurrency: int = 128,
                   unit_ids: Sequence[int] = (1,)) -> list[Found]:
    """Probe every host on the given ports (None: skip that kind); sorted answers.
    ``unit_ids``: the Modbus unit ids asked at each Modbus server (a gateway serves
    several controllers, one unit id each)."""
    gate = asyncio.Semaphore(concurrency)

    async def probe(host: str) -> list[Found]:
        async with gate:
            found: list[Found | None] = []
            if modbus_port is not None:
                found.extend(await _modbus(host, modbus_port, register, timeout_s,
                                           unit_ids))
            if opcua_port is not None:
                found.append(await _opcua(host, opcua_port, timeout_s))
            if ednc_port is not None:
                found.append(await _ednc(host, ednc_port, timeout_s))
            return [f for f in found if f is not None]

    results = await asyncio.gather(*(probe(h) for h in hosts))
    out = [f for group in results for f in group]
    out.sort(key=lambda f: (ipaddress.ip_address(f.host), f.port))
    return out
