"""The Fanuc-style machine's Modbus/TCP Server function over its PMC memory.

What the real one offers (FANUC FAST Ethernet / FAST Data Server operator's manual,
B-64414EN/01, appendix H "Modbus/TCP Server function", option R968 with S707), and so
all this one offers:

* server only; **holding registers only** (coils, discrete inputs and input registers
  cannot be used): function codes **03h** Read Holding Registers, **10h** Write Multiple
  Registers and **17h** Read/Write Multiple Registers; any other code is answered with
  exception 01 "illegal function";
* a Modbus area of holding registers mapped onto PMC memory; here the area the operator
  configured is the EDNC window (protocol/README.md §13): ``window_register`` and on, one
  register per two bytes of the window. A request that reaches outside it is answered with
  exception 02 "illegal data address";
* the Modbus PDU's own limits: at most 125 registers per read, 123 per write (121 in a
  17h request) - pymodbus' request classes refuse more with exception 03.

A register maps onto two bytes of PMC memory in the configured ``byte_order``
(:data:`protocol.ctrlmem.ByteOrder`). ``delay_s`` adds a simulated network and scan delay
to every request (the benchmark's 2 ms).

The server runs pymodbus (the maintained stack) in the machine's own event loop.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Sequence
from typing import Any

from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.pdu import DecodePDU, ExceptionResponse, ModbusPDU
from pymodbus.server import ModbusTcpServer

from protocol.ctrlmem import ByteOrder, from_registers, to_registers

from .windowcnc import WindowCNC

__all__ = ["FUNCTION_CODES", "PmcModbusServer"]

log = logging.getLogger(__name__)

FUNCTION_CODES = (0x03, 0x10, 0x17)
"""What the Fanuc Modbus/TCP Server function answers (B-64414EN/01 appendix H)."""


class _PmcArea(ModbusServerContext):
    """The holding-register area over the window bytes; every other table refused.

    Subclasses pymodbus' context to answer from our own memory: pymodbus calls
    ``async_getValues`` / ``async_setValues`` with the function code, the start register
    and the count, and turns a returned :class:`ExcCodes` into an exception response.
    """

    def __init__(self, window: bytearray, register: int, order: ByteOrder, unit_id: int,
                 delay_s: float) -> None:  # no super().__init__: it builds pymodbus' store
        self.window = window
        self.register = register
        self.order: ByteOrder = order
        self.unit_id = unit_id
        self.delay_s = delay_s
        self.old_simulator = True  # pymodbus: use this object's get/set as they are
        self.simdevices = []
        self.requests = 0
        self.refused = 0

    def _span(self, func_code: int, address: int, count: int) -> tuple[int, int] | ExcCodes:
        if func_code not in FUNCTION_CODES:
            self.refused += 1
            return ExcCodes.ILLEGAL_FUNCTION
        start = (address - self.register) * 2
        end = start + 2 * count
        if count < 1 or start < 0 or end > len(self.window):
            self.refused += 1
            return ExcCodes.ILLEGAL_ADDRESS
        return start, end

    def _device(self, device_id: int) -> None:
        if device_id != self.unit_id:
            from pymodbus.exceptions import NoSuchIdException
            raise NoSuchIdException(f"unit id {device_id}")

    async def async_getValues(self, device_id: int, func_code: int, address: int,
                              count: int = 1) -> list[int] | list[bool] | ExcCodes:
        self._device(device_id)
        self.requests += 1
        if self.delay_s and func_code != 0x17:  # 17h waited once, in its write
            await asyncio.sleep(self.delay_s)
        span = self._span(func_code, address, count)
        if isinstance(span, ExcCodes):
            return span
        return to_registers(bytes(self.window[span[0]:span[1]]), self.order)

    async def async_setValues(self, device_id: int, func_code: int, address: int,
                              values: Sequence[int] | Sequence[bool]) -> ExcCodes | None:
        self._device(device_id)
        self.requests += 1
        if self.delay_s:
            await asyncio.sleep(self.delay_s)
        span = self._span(func_code, address, len(values))
        if isinstance(span, ExcCodes):
            return span
        self.window[span[0]:span[1]] = from_registers([int(v) for v in values], self.order)
        return None

    def device_ids(self) -> list[int]:
        return [self.unit_id]


class _IllegalFunction(ModbusPDU):
    """Any request whose function code the PMC does not serve: whatever its body, the
    answer is exception 01 with that function code (pymodbus' own path for an undecodable
    request would answer with function code 0x80, which a client cannot match)."""

    def decode(self, data: bytes) -> None:
        self.body = data

    def encode(self) -> bytes:
        return b""

    async def datastore_update(self, context: Any, device_id: int) -> ModbusPDU:
        return ExceptionResponse(self.function_code, ExcCodes.ILLEGAL_FUNCTION)


def _refusing(fc: int) -> type[ModbusPDU]:
    return type(f"IllegalFunction{fc:02X}", (_IllegalFunction,), {"function_code": fc})


def _pmc_decoder() -> DecodePDU:
    """A server decoder that knows 03h, 10h and 17h, and refuses every other code."""
    decoder = DecodePDU(True)
    table: dict[int, tuple[type[ModbusPDU], type[ModbusPDU]]] = {}
    for fc in range(1, 0x80):
        if fc in FUNCTION_CODES:
            table[fc] = DecodePDU.pdu_table[fc]
        else:
            cls = _refusing(fc)
            table[fc] = (cls, cls)
    decoder.pdu_table = table
    decoder.pdu_sub_table = {}
    return decoder


class PmcModbusServer:
    """Modbus/TCP server of one simulated Fanuc PMC (a ``ControllerServer``).

    Parameters
    ----------
    cnc : WindowCNC
        The machine whose window the registers map onto.
    host, port : str, int
        Where to listen (port 0: any free port; :attr:`port` is the bound one).
    register : int
        First holding register of the window.
    unit_id : int
    byte_order : {"little", "big"}
    delay_s : float
        Simulated delay per request, s.
    """

    def __init__(self, cnc: WindowCNC, *, host: str = "127.0.0.1", port: int = 502,
                 register: int = 0, unit_id: int = 1, byte_order: ByteOrder = "little",
                 delay_s: float = 0.0) -> None:
        if register + len(cnc.window) // 2 > 0x10000:
            raise ValueError(f"a window of {len(cnc.window) // 2} registers from register "
                             f"{register} leaves the 64 K-word Modbus area")
        self.host = host
        self.port = port
        self.area = _PmcArea(cnc.window, register, byte_order, unit_id, delay_s)
        self._server: ModbusTcpServer | None = None

    @property
    def address(self) -> str:
        return f"modbus://{self.host}:{self.port}"

    async def start(self) -> None:
        server = ModbusTcpServer(self.area, address=(self.host, self.port))
        server.decoder = _pmc_decoder()
        await server.serve_forever(background=True)
        self._server = server
        transport: Any = server.transport
        sockets = getattr(transport, "sockets", None)
        if sockets:
            self.port = int(sockets[0].getsockname()[1])

    async def stop(self) -> None:
        server, self._server = self._server, None
        if server is not None:
            with contextlib.suppress(Exception):
                await server.shutdown()  # type: ignore[no-untyped-call]
