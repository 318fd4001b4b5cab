"""The Modbus/TCP link: the center as client of a Fanuc PMC's Modbus/TCP Server function.

Only what that server answers is used: 03h Read Holding Registers (at most 125 per
request) and 10h Write Multiple Registers (at most 123). A window byte offset is a
register offset (two bytes a register), placed in PMC memory in the link's byte order.
Requests go one at a time on the connection (a PMC answers them in turn anyway). A busy
answer (exception 05 or 06) is asked again a few times within the session, and a request
not answered on a connection that answered before is asked once more; any other exception
response, a second time-out or a lost connection is a :class:`LinkError` naming it, with
its state and reason (:mod:`server.links.state`).
"""

from __future__ import annotations

import asyncio
import functools
import logging
from collections.abc import Awaitable, Callable
from typing import Any

from pymodbus.client import AsyncModbusTcpClient
from pymodbus.exceptions import ModbusException, ModbusIOException

from protocol.ctrlmem import ByteOrder, from_registers, to_registers
from server.links.window.memory import LinkError
from server.schemas.link import ModbusLink

__all__ = ["BUSY_CODES", "BUSY_RETRIES", "MAX_READ_REGISTERS", "MAX_WRITE_REGISTERS",
           "ModbusMemory", "memory_for_link"]

# pymodbus logs every time-out with a hex dump of the frames; the LinkError raised here
# names the request and the session logs it once, so only its errors' own failures remain
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

MAX_READ_REGISTERS = 125
MAX_WRITE_REGISTERS = 123

_EXCEPTIONS = {1: "illegal function", 2: "illegal data address", 3: "illegal data value",
               4: "server device failure", 5: "acknowledge (busy with a long request)",
               6: "server device busy", 10: "gateway path unavailable",
               11: "gateway target failed to respond"}

BUSY_RETRIES = 10
"""Busy answers to one request before the session ends (0.3^11: a controller answering
busy to 30 % of requests ends a session once in half a million requests)."""
BUSY_PAUSE_S = 0.02
BUSY_PAUSE_CAP_S = 0.25
"""Pause before asking again: 20 ms growing by half each time, at most 250 ms (1.4 s
over all the retries of one request)."""

BUSY_CODES = frozenset({5, 6})
"""Exception answers that mean "ask again later" (Modbus application protocol v1.1b3
§7): 05 acknowledge, 06 server device busy."""


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
    block : int
        Largest write, bytes (even, at most 246).
    """

    block: int
    """Largest write, bytes: 246 (123 registers, the Modbus limit) unless the link's
    ``block_registers`` says the controller or its gateway takes fewer."""

    def __init__(self, host: str, port: int = 502, *, unit_id: int = 1, register: int = 0,
                 byte_order: ByteOrder = "little", timeout_s: float = 2.0,
                 block: int = 2 * MAX_WRITE_REGISTERS) -> None:
        if not 2 <= block <= 2 * MAX_WRITE_REGISTERS or block % 2:
            raise LinkError(f"block {block}: 2..{2 * MAX_WRITE_REGISTERS} bytes, even (a "
                            f"write takes at most {MAX_WRITE_REGISTERS} registers)",
                            state="refused", reason="settings")
        self.block = block
        self.host = host
        self.port = port
        self.unit_id = unit_id
        self.register = register
        self.byte_order: ByteOrder = byte_order
        self.timeout_s = timeout_s
        self._client: AsyncModbusTcpClient | None = None
        self._lock = asyncio.Lock()
        self.requests = 0
        self.busy_retries = 0
        """Requests asked again after a busy answer (05, 06)."""
        self.busy_note = ""
        """The last busy answer, for the operator."""
        self.no_answer_retries = 0
        """Requests asked again after a time-out on a connection that answered before."""
        self._answered = False
        """This connection answered a request (a time-out then is asked once more)."""

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    async def connect(self) -> None:
        await self.close()
        # pymodbus' own reconnects and retries are off: the session reconnects with its
        # backoff and must see every failure
        client = AsyncModbusTcpClient(self.host, port=self.port, timeout=self.timeout_s,
                                      retries=0, reconnect_delay=0)
        self._answered = False
        try:
            ok = await client.connect()
        except (OSError, ModbusException) as exc:
            client.close()
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect: {exc}",
                            state="unreachable", reason="connect") from None
        if not ok:
            client.close()
            raise LinkError(f"Modbus/TCP {self.address}: cannot connect (refused or no "
                            "answer)", state="unreachable", reason="connect")
        self._client = client

    def _live(self) -> AsyncModbusTcpClient:
        client = self._client
        if client is None or not client.connected:
            raise LinkError(f"Modbus/TCP {self.address}: not connected",
                            state="unreachable", reason="connection_lost")
        return client

    def _register(self, offset: int, size: int) -> int:
        if offset % 2 or size % 2 or size <= 0:
            raise LinkError(f"window offset {offset} and size {size} must be even and > 0")
        return self.register + offset // 2

    async def _request(self, what: str, first: int, count: int,
                       call: Callable[[], Awaitable[Any]]) -> Any:
        """One request's answer; a failure or an exception answer is a LinkError naming
        ``what`` (read or write) and the registers. A busy answer (05, 06: "ask again
        later") is asked again, at most :data:`BUSY_RETRIES` times with a growing pause:
        a controller busy for a moment does not end the session, one busy for seconds
        does. A request not answered within the time-out on a connection that answered
        before is asked once more (a controller late for a moment, as on a loaded network,
        does not end the session; a second time-out does): asking again is harmless, a
        read reads again and a write writes the same registers again (§13.2: nothing
        before the switch word changes what the PLC uses, and a switch word it handled
        already is no new one); pymodbus skips the late answer to the first by its
        transaction id."""
        timed_out = False
        busy = 0
        while True:
            try:
                rr = await self._once(what, first, count, call)
                self._answered = True
                return rr
            except LinkError as exc:
                if exc.reason == "no_answer" and self._answered and not timed_out:
                    timed_out = True
                    self.no_answer_retries += 1
                    continue
                if not exc.transient or busy == BUSY_RETRIES:
                    raise
                self.busy_retries += 1
                self.busy_note = str(exc)
                await asyncio.sleep(min(BUSY_PAUSE_CAP_S, BUSY_PAUSE_S * 1.5 ** busy))
                busy += 1

    async def _once(self, what: str, first: int, count: int,
                    call: Callable[[], Awaitable[Any]]) -> Any:
        span = f"{what} of registers {first}..{first + count - 1}"
        try:
            rr = await call()
        except (TimeoutError, ModbusIOException) as exc:  # pymodbus: "no response received"
            raise LinkError(f"Modbus/TCP {self.address}: {span}: no answer within "
                            f"{self.timeout_s:g} s ({exc})", state="unreachable",
                            reason="no_answer") from None
        except (ModbusException, OSError) as exc:
            raise LinkError(f"Modbus/TCP {self.address}: {span} failed: {exc}",
                            state="unreachable", reason="connection_lost") from None
        self.requests += 1
        if rr.isError():
            code = int(getattr(rr, "exception_code", 0))
            busy = code in BUSY_CODES
            raise LinkError(f"Modbus/TCP {self.address}: {span}: exception {code:02d} "
                            f"({_EXCEPTIONS.get(code, '?')}, unit id {self.unit_id})",
                            state="failed" if busy or code == 4 else "refused",
                            reason=f"exception_{code:02d}", transient=busy)
        return rr

    async def read(self, offset: int, size: int) -> bytes:
        first = self._register(offset, size)
        count = size // 2
        out: list[int] = []
        async with self._lock:
            client = self._live()
            for k in range(0, count, MAX_READ_REGISTERS):
                n = min(MAX_READ_REGISTERS, count - k)
                rr = await self._request("read", first + k, n, functools.partial(
                    client.read_holding_registers, first + k, count=n,
                    device_id=self.unit_id))
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
            await self._request("write", first, len(values), functools.partial(
                client.write_registers, first, values, device_id=self.unit_id))

    async def close(self) -> None:
        client, self._client = self._client, None
        if client is not None:
            client.close()


def memory_for_link(spec: ModbusLink, ip: str) -> ModbusMemory:
    """The memory client of a registration's ``modbus`` link (the registry's entry,
    :data:`server.links.BACKENDS`): its host, or the machine's ``ip`` when it names none;
    several controllers behind one gateway differ by ``unit_id``."""
    return ModbusMemory(spec.host or ip, spec.port, unit_id=spec.unit_id,
                        register=spec.start_register, byte_order=spec.byte_order,
                        block=2 * spec.block_registers)
