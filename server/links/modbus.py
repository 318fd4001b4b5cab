"""The Modbus/TCP link: the center as client of a Fanuc PMC's Modbus/TCP Server function.

Only what that server answers is used: 03h Read Holding Registers (at most 125 per
request) and 10h Write Multiple Registers (at most 123). A window byte offset is a
register offset (two bytes a register), placed in PMC memory in the link's byte order.
Requests go one at a time on the connection (a PMC answers them in turn anyway); any
exception response, time-out or lost connection is a :class:`LinkError` naming it.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable
from typing import Any

from pymodbus.client import AsyncModbusTcpClient
from pymodbus.exceptions import ModbusException

from protocol.ctrlmem import ByteOrder, from_registers, to_registers
from server.links.window.memory import LinkError

__all__ = ["MAX_READ_REGISTERS", "MAX_WRITE_REGISTERS", "ModbusMemory"]

# pymodbus logs every time-out with a hex dump of the frames; the LinkError raised here
# names the request and the session logs it once, so only its errors' own failures remain
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

MAX_READ_REGISTERS = 125
MAX_WRITE_REGISTERS = 123

_EXCEPTIONS = {1: "illegal function", 2: "illegal data address", 3: "illegal data value",
               4: "server device failure", 6: "server device busy",
               11: "gateway target failed to respond"}


class ModbusMemory:
    """A controller window behind a Modbus/TCP server (a ``MemoryClient``).

    Parameters
    ----------
    host, port : str, int
    unit_id : int
    register : int
        First holding register of the window.
    byte_order : {"little", "big"}
    timeout_s : float
        Per request.
    """

    block = 2 * MAX_WRITE_REGISTERS

    def __init__(self, host: str, port: int = 502, *, unit_id: int = 1, register: int = 0,
                 byte_order: ByteOrder = "little", timeout_s: float = 2.0) -> None:
        self.host = host
        self.port = port
        self.unit_id = unit_id
        self.register = register
        self.byte_order: ByteOrder = byte_order
        self.timeout_s = timeout_s
        self._client: AsyncModbusTcpClient | None = None
        self._lock = asyncio.Lock()
        self.requests = 0

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    async def connect(self) -> None:
        await self.close()
        # pymodbus' own reconnects and retries are off: the session reconnects with its
        # backoff and must see every failure
        client = AsyncModbusTcpClient(self.host, port=self.port, timeout=self.timeout_s,
                                      retries=0, reconnect_delay=0)
        try:
            ok = await client.connect()
        except (OSError, ModbusException) as exc:
            client.close()
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect: {exc}") from None
        if not ok:
            client.close()
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect")
        self._client = client

    def _live(self) -> AsyncModbusTcpClient:
        client = self._client
        if client is None or not client.connected:
            raise LinkError(f"Modbus/TCP {self.address}: not connected")
        return client

    def _register(self, offset: int, size: int) -> int:
        if offset % 2 or size % 2 or size <= 0:
            raise LinkError(f"window offset {offset} and size {size} must be even and > 0")
        return self.register + offset // 2

    async def _request(self, what: str, first: int, count: int,
                       call: Awaitable[Any]) -> Any:
        """Await one request's answer; a failure or an exception answer is a LinkError
        naming ``what`` (read or write) and the registers."""
        span = f"{what} of registers {first}..{first + count - 1}"
        try:
            rr = await call
        except (TimeoutError, ModbusException, OSError) as exc:
            raise LinkError(f"Modbus/TCP {self.address}: {span} failed: {exc}") from None
        self.requests += 1
        if rr.isError():
            code = getattr(rr, "exception_code", 0)
            raise LinkError(f"Modbus/TCP {self.address}: {span}: exception {code} "
                            f"({_EXCEPTIONS.get(code, '?')})")
        return rr

    async def read(self, offset: int, size: int) -> bytes:
        first = self._register(offset, size)
        count = size // 2
        out: list[int] = []
        async with self._lock:
            client = self._live()
            for k in range(0, count, MAX_READ_REGISTERS):
                n = min(MAX_READ_REGISTERS, count - k)
                rr = await self._request("read", first + k, n, client.read_holding_registers(
                    first + k, count=n, device_id=self.unit_id))
                out.extend(rr.registers)
        return from_registers(out, self.byte_order)

    async def write(self, offset: int, data: bytes) -> None:
        first = self._register(offset, len(data))
        if len(data) > self.block:
            raise LinkError(f"a write of {len(data)} bytes exceeds {self.block} (123 "
                            "registers, the Modbus limit)")
        values = to_registers(data, self.byte_order)
        async with self._lock:
            client = self._live()
            await self._request("write", first, len(values), client.write_registers(
                first, values, device_id=self.unit_id))

    async def close(self) -> None:
        client, self._client = self._client, None
        if client is not None:
            client.close()
