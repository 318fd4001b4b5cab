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
* the Modbus PDU's own limits (Modbus Application Protocol V1.1b3, 6.3, 6.12, 6.17): at
  most 125 registers per read, 123 per write (121 in a 17h request), a byte count equal
  to twice the register count; a request that breaks them, or whose length does not
  match its function, is answered with exception 03 "illegal data value";
* a request for another unit id is answered with exception 0Bh (gateway target device
  failed to respond).

Requests are answered **in order, each of them**, also when a client sends several in
one TCP segment (pipelined: Modbus/TCP frames carry their own length, and a server reads
them one after the other). A frame of another protocol id than 0 is discarded; one
longer than a PDU may be (253 bytes) is read whole and answered with exception 03; an
MBAP length below 2 or beyond 1024 ends the connection, as there is no telling where
the next frame starts.

A register maps onto two bytes of PMC memory in the configured ``byte_order``
(:data:`protocol.ctrlmem.ByteOrder`). ``delay_s`` adds a simulated network and scan delay
to every request (the benchmark's 2 ms).

**Nonvolatile memory.** A PMC's D area is battery-backed: the window (status, buffers,
the center's switch word and slots) survives a power cycle (§13.1), and the PLC program
finds its last verdict and active buffer there at start-up (§13.3). ``nonvolatile``
names a file that plays that memory for one machine: its contents are put into the
window when the server is built (before the PLC program boots), and the window is
written back to it (atomically) when what a restart needs changed (anything but the
heartbeat, positions and corrections, which change every scan), checked every
``flush_s``, after every write request and when the server stops. Without it the
window starts empty at every start, as the memory of a fresh PMC.

The server is a small asyncio Modbus/TCP server of its own (MBAP framing is a 7-byte
header): the stack it replaced answered only the first of pipelined requests and gave
exception 01 for a read with a bad count.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import struct
import zlib
from collections.abc import Callable
from pathlib import Path
from typing import Final

from protocol.ctrlmem import ByteOrder, from_registers, to_registers

from .windowcnc import WindowCNC

__all__ = ["FUNCTION_CODES", "PmcArea", "PmcModbusServer"]

log = logging.getLogger(__name__)

FUNCTION_CODES = (0x03, 0x10, 0x17)
"""What the Fanuc Modbus/TCP Server function answers (B-64414EN/01 appendix H)."""

ILLEGAL_FUNCTION: Final = 0x01
ILLEGAL_ADDRESS: Final = 0x02
ILLEGAL_VALUE: Final = 0x03
GATEWAY_NO_RESPONSE: Final = 0x0B
MAX_READ: Final = 125
MAX_WRITE: Final = 123
MAX_RW_WRITE: Final = 121
_MBAP: Final = struct.Struct(">HHHB")
MAX_FRAME: Final = 1024
"""An MBAP length beyond this is no Modbus client's: the connection is closed (up to it,
a frame too long for a PDU, 253 bytes, is read whole and answered with exception 03)."""


class _Refused(Exception):
    """A request answered with a Modbus exception (its code)."""

    def __init__(self, code: int) -> None:
        super().__init__(code)
        self.code = code


class PmcArea:
    """The holding-register area over the window bytes, sans I/O: one request PDU in,
    one response PDU out (exceptions included).

    Attributes
    ----------
    requests, refused : int
        Requests answered, and how many of them with an exception.
    """

    def __init__(self, window: bytearray, register: int, order: ByteOrder, unit_id: int
                 ) -> None:
        self.window = window
        self.register = register
        self.order: ByteOrder = order
        self.unit_id = unit_id
        self.requests = 0
        self.refused = 0
        self.writes = 0

    def _span(self, address: int, count: int, most: int) -> tuple[int, int]:
        if not 1 <= count <= most:
            raise _Refused(ILLEGAL_VALUE)
        start = (address - self.register) * 2
        end = start + 2 * count
        if start < 0 or end > len(self.window):
            raise _Refused(ILLEGAL_ADDRESS)
        return start, end

    def _read(self, address: int, count: int) -> bytes:
        a, b = self._span(address, count, MAX_READ)
        regs = to_registers(bytes(self.window[a:b]), self.order)
        return bytes([2 * count]) + struct.pack(f">{count}H", *regs)

    def _write(self, address: int, count: int, data: bytes, most: int) -> None:
        if len(data) != 2 * count:
            raise _Refused(ILLEGAL_VALUE)
        a, b = self._span(address, count, most)
        values = struct.unpack(f">{count}H", data)
        self.window[a:b] = from_registers(list(values), self.order)
        self.writes += 1

    def too_long(self, fc: int) -> bytes:
        """The answer to a frame longer than a PDU may be (253 bytes)."""
        self.requests += 1
        self.refused += 1
        return bytes([(fc | 0x80) & 0xFF, ILLEGAL_VALUE])

    def answer(self, unit: int, pdu: bytes) -> bytes:
        """The response PDU to a request PDU for unit ``unit``."""
        self.requests += 1
        fc = pdu[0] if pdu else 0
        try:
            if unit != self.unit_id:
                raise _Refused(GATEWAY_NO_RESPONSE)
            if fc not in FUNCTION_CODES:
                raise _Refused(ILLEGAL_FUNCTION)
            if fc == 0x03:
                if len(pdu) != 5:
                    raise _Refused(ILLEGAL_VALUE)
                address, count = struct.unpack_from(">HH", pdu, 1)
                return bytes([fc]) + self._read(address, count)
            if fc == 0x10:
                if len(pdu) < 6:
                    raise _Refused(ILLEGAL_VALUE)
                address, count, nbytes = struct.unpack_from(">HHB", pdu, 1)
                if nbytes != len(pdu) - 6:
                    raise _Refused(ILLEGAL_VALUE)
                self._write(address, count, pdu[6:], MAX_WRITE)
                return pdu[:5]
            # 17h: the write is performed before the read (Modbus spec 6.17)
            if len(pdu) < 10:
                raise _Refused(ILLEGAL_VALUE)
            r_addr, r_count, w_addr, w_count, nbytes = struct.unpack_from(">HHHHB", pdu, 1)
            if nbytes != len(pdu) - 10 or not 1 <= r_count <= MAX_READ:
                raise _Refused(ILLEGAL_VALUE)
            self._span(r_addr, r_count, MAX_READ)  # refuse before writing anything
            self._write(w_addr, w_count, pdu[10:], MAX_RW_WRITE)
            return bytes([fc]) + self._read(r_addr, r_count)
        except _Refused as exc:
            self.refused += 1
            return bytes([(fc | 0x80) & 0xFF, exc.code])


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
    nonvolatile : Path, optional
        The file that keeps the window across a power cycle (module docstring).
    flush_s : float
        How often the window is checked for a change worth keeping (anything but the
        heartbeat, positions and corrections) and then written to ``nonvolatile``, s.
    """

    def __init__(self, cnc: WindowCNC, *, host: str = "127.0.0.1", port: int = 502,
                 register: int = 0, unit_id: int = 1, byte_order: ByteOrder = "little",
                 delay_s: float = 0.0, nonvolatile: Path | None = None,
                 flush_s: float = 0.05) -> None:
        if register + len(cnc.window) // 2 > 0x10000:
            raise ValueError(f"a window of {len(cnc.window) // 2} registers from register "
                             f"{register} leaves the 64 K-word Modbus area")
        self.host = host
        self.port = port
        self.delay_s = float(delay_s)
        self.area = PmcArea(cnc.window, register, byte_order, unit_id)
        # the controller behind takes a new switch word early if it can (WindowCNC's
        # switch_scan_s); one running the ST program scans at its own pace
        self._written: Callable[[], None] = getattr(cnc, "window_written", lambda: None)
        self.nonvolatile = nonvolatile
        self.flush_s = float(flush_s)
        self._saved_digest = -1
        if nonvolatile is not None:
            self._load(nonvolatile)
        self._server: asyncio.Server | None = None
        self._tasks: set[asyncio.Task[None]] = set()
        self._writers: set[asyncio.StreamWriter] = set()
        self._flusher: asyncio.Task[None] | None = None

    @property
    def address(self) -> str:
        return f"modbus://{self.host}:{self.port}"

    # -- nonvolatile memory
    def _load(self, path: Path) -> None:
        window = self.area.window
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            return
        if len(data) != len(window):
            log.warning("%s: %d bytes, the window has %d: not taken (a PMC whose memory "
                        "layout changed starts empty)", path, len(data), len(window))
            return
        window[:] = data
        self._saved_digest = self._digest()

    def _digest(self) -> int:
        """CRC-32 of what a restart needs: the window but the heartbeat (bytes 64-67),
        positions and applied corrections (84-147), which change every scan."""
        w = self.area.window
        crc = zlib.crc32(w[:64])
        crc = zlib.crc32(w[68:84], crc)
        return zlib.crc32(w[148:], crc)

    def flush(self) -> None:
        """Write the window to the nonvolatile file if what a restart needs changed
        (atomically: a file is always a whole window)."""
        if self.nonvolatile is None:
            return
        digest = self._digest()
        if digest == self._saved_digest:
            return
        tmp = self.nonvolatile.with_name(self.nonvolatile.name + ".tmp")
        tmp.write_bytes(bytes(self.area.window))
        os.replace(tmp, self.nonvolatile)
        self._saved_digest = digest

    async def _flush_loop(self) -> None:
        while True:
            await asyncio.sleep(self.flush_s)
            self.flush()

    # -- serving
    async def start(self) -> None:
        self._server = await asyncio.start_server(self._serve, self.host, self.port)
        sockets = self._server.sockets
        if sockets:
            self.port = int(sockets[0].getsockname()[1])
        if self.nonvolatile is not None:
            self._flusher = asyncio.create_task(self._flush_loop(),
                                                name=f"modbus:{self.port}:nonvolatile")

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter
                     ) -> None:
        task = asyncio.current_task()
        if task is not None:
            self._tasks.add(task)
        self._writers.add(writer)
        buffer = bytearray()
        try:
            while True:
                chunk = await reader.read(65536)
                if not chunk:
                    return
                buffer += chunk
                # every complete frame in the buffer, in order (pipelined requests); their
                # answers go out in one send (one wake-up of the client, not one per
                # answer) unless each waits for a simulated delay
                out = bytearray()
                while len(buffer) >= _MBAP.size:
                    tid, pid, length, unit = _MBAP.unpack_from(buffer, 0)
                    if not 2 <= length <= MAX_FRAME:
                        log.info("modbus: MBAP length %d: connection closed", length)
                        if out:  # the frames before it are answered
                            writer.write(bytes(out))
                        return
                    end = 6 + length
                    if len(buffer) < end:
                        break
                    pdu = bytes(buffer[_MBAP.size:end])
                    del buffer[:end]
                    if pid != 0:
                        continue  # not a Modbus frame: discarded, as the spec says
                    if self.delay_s:
                        await asyncio.sleep(self.delay_s)
                    fc = pdu[0] if pdu else 0
                    answer = (self.area.answer(unit, pdu) if length <= 254  # PDU <= 253
                              else self.area.too_long(fc))
                    out += _MBAP.pack(tid, 0, len(answer) + 1, unit)
                    out += answer
                    if self.delay_s:
                        writer.write(bytes(out))
                        out.clear()
                    if fc in (0x10, 0x17) and not answer[0] & 0x80:
                        self.flush()  # the center's write is in the D area now
                        self._written()  # a switch word is taken within a ladder scan
                if out:
                    writer.write(bytes(out))
                await writer.drain()
        except (ConnectionError, asyncio.IncompleteReadError):
            return
        finally:
            if task is not None:
                self._tasks.discard(task)
            self._writers.discard(writer)
            writer.close()
            with contextlib.suppress(Exception):
                await writer.wait_closed()

    async def stop(self) -> None:
        server, self._server = self._server, None
        if server is not None:
            server.close()
            for w in list(self._writers):  # each connection's read then sees its end
                w.close()
            await asyncio.gather(*self._tasks, return_exceptions=True)
            with contextlib.suppress(Exception):
                await server.wait_closed()
        if self._flusher is not None:
            self._flusher.cancel()
            await asyncio.gather(self._flusher, return_exceptions=True)
            self._flusher = None
        self.flush()
