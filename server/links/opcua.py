"""The OPC UA link: a SINUMERIK's PLC data block as the center's memory window.

:class:`OpcuaMemory` is the :class:`~server.links.window.memory.MemoryClient` of a machine
registered with an ``opcua`` link (:class:`~server.schemas.link.OpcuaLink`): the center
logs in to the controller's OPC UA server (asyncua's client) as a user with ``PlcWrite``
and reads and writes bytes of the window the PLC program reads (protocol/README.md §13).

The window is addressed as the SINUMERIK addresses PLC data, by BTSS path (SINUMERIK
Access MyMachine / OPC UA configuration manual, "PLC syntax"): the link's ``window_node``
names the data block (``ns=2;s=/Plc/DB900``), and a write of ``data`` at byte ``offset``
goes as ``ns=2;s=/Plc/DB900.DBD<offset>:[<n>]`` (UInt32 array, four window bytes per
value, big-endian as in every S7 data block), with a ``.DBW<x>:[1]`` word for a two-byte
edge, all in one Write request. See :mod:`machine_sim.opcua_server` for why paths and not
an IndexRange. Writes are at most :attr:`OpcuaMemory.block` bytes, by the PLC's class
(:data:`PLC_BLOCK`): 240 for an S7-300-class PLC (the 840D sl's, the safe default), 960
for an S7-1500 (SINUMERIK ONE); a bigger write is split into PDUs by the controller
anyway, so it would not be more atomic, and the header-last layout needs no atomicity
beyond the two-byte switch word.

**Secure by default.** The channel is Basic256Sha256 SignAndEncrypt (or Sign) with the
center's own certificate (:mod:`server.links.opcuapki`: made on first use, one per
process, its thumbprint for the controller's trust list) and the controller's
certificate trusted on first use or from the trust list. The password then never crosses
the wire in clear (SignAndEncrypt encrypts the channel; with Sign the user token is
encrypted with the controller's key). Security policy ``None`` must be asked for in the
link, and the memory then carries a warning (:meth:`OpcuaMemory.take_notices`) and logs
it: the password travels as plain text.

Transient answers (``BadTooManySessions``, ``BadResourceUnavailable``, ``BadTimeout``:
the controller is busy) are retried per request within the session, a bounded number of
times over a few seconds (:data:`RETRY_DELAYS_S`); only a failure that persists ends
it.

Every failure raises :class:`~server.links.window.memory.LinkError` with a text that says
what to fix (a missing password, a refused login, a user without ``PlcWrite``, no free
session, bytes outside the data block, an untrusted certificate), classified as every
OPC UA link of the center classifies it (:mod:`server.links.opcualogin`, where the login
and the security are too). Reconnecting is the session's: :meth:`close`, then
:meth:`connect` again.

:meth:`OpcuaMemory.read_axes` reads, per axis, the machine position and the NC's
temperature compensation setting data SD43900/43910/43920 in one request, for telemetry.
"""

from __future__ import annotations

import asyncio
import logging
import re
from collections.abc import Awaitable, Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Final

from asyncua import ua
from asyncua.ua.attribute_ids import AttributeIds

from server.links.opcualogin import (
    RETRY_DELAYS_S,
    TRANSIENT,
    OpcuaClient,
    OpcuaSecurity,
    jittered,
    status_error,
)
from server.links.opcuapki import Pki, TrustMode
from server.links.secret import read_secret
from server.links.window.memory import LinkError
from server.schemas.link import OpcuaLink

__all__ = ["PLC_BLOCK", "RETRY_DELAYS_S", "SD_NUMBERS", "TRANSIENT", "AxisReading",
           "OpcuaMemory", "memory_for_link"]

log = logging.getLogger(__name__)

PLC_BLOCK: Final = {"s7-300": 240, "s7-1500": 960}
"""Bytes per write by PLC class: the payload an S7-300-class PLC (840D sl) takes in one
PDU (240-byte PDU) and an S7-1500's (960). The OPC UA server forwards a write to the PLC
in PDUs of its size; a block of one PDU is written in one PLC access."""
SD_NUMBERS: Final = (43900, 43910, 43920)
_SD_NAMES: Final = {43900: "TEMP_COMP_ABS_VALUE", 43910: "TEMP_COMP_SLOPE",
                    43920: "TEMP_COMP_REF_POSITION"}
_DB_NODE = re.compile(r"^ns=(\d+);s=(/Plc/DB\d+)$")
_READ_CHUNK: Final = 16_384
"""Bytes of the window per Read request (responses stay well inside one 64 kB chunk)."""
@dataclass(frozen=True, slots=True)
class AxisReading:
    """One axis as the NC reports it.

    Attributes
    ----------
    position_mm : float
        Machine axis position (MCS), mm (degrees for a rotary axis).
    sd43900_mm : float
        TEMP_COMP_ABS_VALUE, mm.
    sd43910 : float
        TEMP_COMP_SLOPE, mm/mm.
    sd43920_mm : float
        TEMP_COMP_REF_POSITION, mm.
    """

    position_mm: float
    sd43900_mm: float
    sd43910: float
    sd43920_mm: float


class OpcuaMemory(OpcuaClient):
    """A SINUMERIK's window over OPC UA (a ``MemoryClient``).

    Parameters
    ----------
    endpoint : str
        ``opc.tcp://host:port``.
    user : str
    password_ref : str
        ``env:NAME`` or ``file:/path``; read at each :meth:`connect` unless ``password``
        is given.
    password : str, optional
        The password itself, when the caller resolved the reference already.
    window_node : str
        The data block holding the window, ``ns=<i>;s=/Plc/DB<n>``.
    security_policy, security_mode : str
        ``Basic256Sha256`` with ``SignAndEncrypt`` (the default) or ``Sign``; ``None`` in
        either (and nothing else in the other) is no security at all: the password in
        clear, a warning in :meth:`take_notices`.
    trust : {"first_use", "list"}
        How the controller's certificate is trusted (:mod:`server.links.opcuapki`).
    pki : Pki, optional
        The center's certificates (default: :func:`~server.links.opcuapki.pki_at`).
    client_certificate, client_private_key : str, optional
        Another certificate and key (files) than the PKI's own, both or neither.
    sd_nodes : mapping of str to str
        Node ids of setting data, keyed ``"<AXIS>.<number>"`` (``"X.43900"``); the rest
        default to the SINUMERIK paths of machine axis k (1-based, the order of
        ``read_axes``'s axes).
    timeout_s : float
        Per request and for the whole login.
    block : int
        Largest write, bytes (a multiple of 4; :data:`PLC_BLOCK`).
    retry_delays_s : sequence of float
        Waits before each retry of a request answered with a :data:`TRANSIENT` code.
    """

    def __init__(self, endpoint: str, user: str, password_ref: str, *,
                 window_node: str = "ns=2;s=/Plc/DB900",
                 security_policy: str = "Basic256Sha256",
                 security_mode: str = "SignAndEncrypt", trust: TrustMode = "first_use",
                 pki: Pki | None = None, client_certificate: str | None = None,
                 client_private_key: str | None = None,
                 sd_nodes: Mapping[str, str] | None = None, timeout_s: float = 5.0,
                 block: int = PLC_BLOCK["s7-300"], password: str | None = None,
                 retry_delays_s: Sequence[float] = RETRY_DELAYS_S) -> None:
        m = _DB_NODE.match(window_node)
        if m is None:
            raise LinkError(f"window_node {window_node!r}: expected ns=<i>;s=/Plc/DB<n>, "
                            "the PLC data block holding the window")
        if block < 4 or block % 4:
            raise LinkError(f"block {block}: a multiple of 4 bytes")
        super().__init__(endpoint, user, security=OpcuaSecurity(
            security_policy, security_mode, trust, client_certificate, client_private_key),
            pki=pki, timeout_s=timeout_s, retry_delays_s=retry_delays_s)
        self.password_ref = password_ref
        self._password = password
        self.window_node = window_node
        self._ns = int(m.group(1))
        self._db = m.group(2)
        self.security_policy = self.security.policy
        self.security_mode = self.security.mode
        self.trust: TrustMode = trust
        self.client_certificate = client_certificate
        self.client_private_key = client_private_key
        self.sd_nodes = dict(sd_nodes or {})
        self.block = block
        self.busy_retries = 0
        """Requests asked again after a transient answer (the window session shows the
        link busy while this grows)."""
        self.busy_note = ""
        """The last transient answer, for the operator."""

    @classmethod
    def from_link(cls, link: OpcuaLink, *, password: str | None = None,
                  timeout_s: float = 5.0, pki: Pki | None = None) -> OpcuaMemory:
        """The memory of a machine registered with ``link`` (``password``: the resolved
        ``password_ref``, else it is read at each connect)."""
        block = link.block_bytes if link.block_bytes is not None else \
            PLC_BLOCK[link.plc_class]
        return cls(link.endpoint, link.user, link.password_ref, window_node=link.window_node,
                   security_policy=link.security_policy, security_mode=link.security_mode,
                   trust=link.trust, pki=pki, client_certificate=link.client_certificate,
                   client_private_key=link.client_private_key, sd_nodes=link.sd_nodes,
                   timeout_s=timeout_s, block=block, password=password)

    from_spec = from_link

    @property
    def address(self) -> str:
        return self.endpoint.removeprefix("opc.tcp://").split("/", 1)[0]

    # -- connection

    async def connect(self) -> None:
        """Open a session as :attr:`user`; raises :class:`LinkError`.

        A controller answering ``BadTooManySessions`` (or busy) is asked again, within
        the retry budget: a SINUMERIK frees a session that was never activated."""
        await self.close()
        password = (self._password if self._password is not None
                    else read_secret(self.password_ref, f"OPC UA user {self.user!r}"))
        await self._open(password, on_busy=self._busy)

    def _busy(self, answer: LinkError) -> None:
        self.busy_retries += 1
        self.busy_note = str(answer)

    # -- the window

    def _nid(self, path: str) -> ua.NodeId:
        return ua.NodeId(ua.String(path), ua.Int16(self._ns))

    def _node(self, offset: int, width: int, count: int) -> ua.NodeId:
        letter = "D" if width == 4 else "W"
        return self._nid(f"{self._db}.DB{letter}{offset}:[{count}]")

    @staticmethod
    def _pieces(offset: int, size: int) -> list[tuple[int, int, int]]:
        """(offset, width, count) of the arrays covering ``size`` bytes from ``offset``
        (both even): a word up to a 4-byte boundary, double words, a word left over."""
        out: list[tuple[int, int, int]] = []
        end = offset + size
        if offset % 4 and offset < end:
            out.append((offset, 2, 1))
            offset += 2
        n = (end - offset) // 4
        if n:
            out.append((offset, 4, n))
            offset += 4 * n
        if offset < end:
            out.append((offset, 2, 1))
        return out

    @staticmethod
    def _check(offset: int, size: int) -> None:
        if offset < 0 or offset % 2 or size % 2 or size < 0:
            raise LinkError(f"window access at byte {offset}, {size} bytes: offsets and "
                            "sizes are even")

    async def read(self, offset: int, size: int) -> bytes:
        """``size`` bytes of the window from ``offset``; raises :class:`LinkError`."""
        self._check(offset, size)
        out = bytearray()
        for at in range(offset, offset + size, _READ_CHUNK):
            out += await self._read(at, min(_READ_CHUNK, offset + size - at))
        return bytes(out)

    async def _read(self, offset: int, size: int) -> bytes:
        pieces = self._pieces(offset, size)
        params = ua.ReadParameters()
        for at, width, count in pieces:
            rv = ua.ReadValueId()
            rv.NodeId = self._node(at, width, count)
            rv.AttributeId = AttributeIds.Value
            params.NodesToRead.append(rv)
        values = await self._call(lambda: self._session().uaclient.read(params), "read",
                                  offset, size, lambda vs: [dv.StatusCode for dv in vs])
        out = bytearray()
        for (at, width, count), dv in zip(pieces, values, strict=True):
            self._good(dv.StatusCode, "read", at, width * count)
            v = dv.Value.Value if dv.Value is not None else None
            if not isinstance(v, list) or len(v) != count:
                raise LinkError(f"{self.endpoint}: {self._db} byte {at}: expected {count} "
                                f"UInt32 values, got {type(v).__name__}")
            try:
                out += b"".join(int(x).to_bytes(width, "big") for x in v)
            except (OverflowError, TypeError, ValueError):
                raise LinkError(f"{self.endpoint}: {self._db} byte {at}: a value does not "
                                f"fit {width} bytes") from None
        return bytes(out)

    async def write(self, offset: int, data: bytes) -> None:
        """Write ``data`` (at most :attr:`block` bytes) at ``offset`` in one request;
        raises :class:`LinkError`."""
        self._check(offset, len(data))
        if len(data) > self.block:
            raise LinkError(f"a {len(data)}-byte write: at most {self.block} per request")
        params = ua.WriteParameters()
        pieces = self._pieces(offset, len(data))
        for at, width, count in pieces:
            chunk = data[at - offset:at - offset + width * count]
            values = [int.from_bytes(chunk[i:i + width], "big")
                      for i in range(0, len(chunk), width)]
            wv = ua.WriteValue()
            wv.NodeId = self._node(at, width, count)
            wv.AttributeId = AttributeIds.Value
            wv.Value = ua.DataValue(ua.Variant(values, ua.VariantType.UInt32, is_array=True))
            params.NodesToWrite.append(wv)
        codes = await self._call(lambda: self._session().uaclient.write(params), "write",
                                 offset, len(data), list)
        for (at, width, count), code in zip(pieces, codes, strict=True):
            self._good(code, "write", at, width * count)

    async def write_many(self, writes: Sequence[tuple[int, bytes]], *,
                         read: tuple[int, int] | None = None) -> bytes:
        """The read, then each write in turn (one Write service call each: the PLC's
        class limits what one call carries)."""
        got = await self.read(*read) if read is not None else b""
        for offset, data in writes:
            await self.write(offset, data)
        return got

    async def _call(self, request: Callable[[], Awaitable[Any]], what: str, offset: int,
                    size: int, codes: Callable[[Any], list[ua.StatusCode | None]]) -> Any:
        """``request()``'s answer, asked again while the controller answers busy (the
        whole service, or any node of it, with a :data:`TRANSIENT` code: a read or a
        write of the same bytes is safe to repeat), at most ``len(retry_delays_s)``
        times."""
        for attempt in range(len(self.retry_delays_s) + 1):
            last = attempt == len(self.retry_delays_s)
            try:
                answer = await self._ask(request, self._where(what, offset, size),
                                         self._right(what))
            except LinkError as e:
                if last or not e.transient:
                    raise
                self.busy_note = str(e)
            else:
                busy = [c.name for c in codes(answer) if c is not None and c.name in TRANSIENT]
                if not busy or last:
                    return answer
                self.busy_note = str(self._refused(busy[0], what, offset, size))
            self.busy_retries += 1
            await asyncio.sleep(jittered(self.retry_delays_s[attempt]))
        raise AssertionError("unreachable")  # the last attempt returned or raised

    def _good(self, code: ua.StatusCode | None, what: str, offset: int, size: int) -> None:
        if code is not None and not code.is_good():
            raise self._refused(code.name, what, offset, size)

    def _where(self, what: str, offset: int, size: int) -> str:
        return f"{self.endpoint}: {what} of {self._db} bytes {offset}..{offset + size - 1}"

    @staticmethod
    def _right(what: str) -> str:
        """The SINUMERIK right a request needs (what a user answered
        ``BadUserAccessDenied`` lacks)."""
        return "PlcWrite" if what == "write" else "SinuReadAll"

    def _refused(self, name: str, what: str, offset: int, size: int) -> LinkError:
        """A request answered with status ``name``, classified (:func:`status_error`)."""
        return status_error(name, self._where(what, offset, size), user=self.user,
                            right=self._right(what))

    # -- telemetry

    def sd_node(self, axis: str, k: int, number: int) -> ua.NodeId:
        """Node of SD``number`` of ``axis``, machine axis ``k`` (1-based)."""
        given = self.sd_nodes.get(f"{axis}.{number}")
        if given is not None:
            return ua.NodeId.from_string(given)
        return self._nid(f"/NC/_N_AX_SEA_ACX/$SA_{_SD_NAMES[number]}[u{k}]")

    async def read_axes(self, axes: Sequence[str]) -> dict[str, AxisReading]:
        """Per axis (``axes`` in the machine's order: machine axis 1, 2, ...) its position
        and SD43900/43910/43920, in one Read request; needs ``SinuReadAll``. Raises
        :class:`LinkError`."""
        params = ua.ReadParameters()
        for k, axis in enumerate(axes, start=1):
            nodes = [self._nid(f"/Channel/MachineAxis/actToolBasePos[u1,{k}]")]
            nodes += [self.sd_node(axis, k, n) for n in SD_NUMBERS]
            for node in nodes:
                rv = ua.ReadValueId()
                rv.NodeId = node
                rv.AttributeId = AttributeIds.Value
                params.NodesToRead.append(rv)
        values = await self._call(lambda: self._session().uaclient.read(params), "read", 0, 0,
                                  lambda vs: [dv.StatusCode for dv in vs])
        out: dict[str, AxisReading] = {}
        for j, axis in enumerate(axes):
            got: list[float] = []
            for i, dv in enumerate(values[4 * j:4 * j + 4]):
                node = params.NodesToRead[4 * j + i].NodeId.to_string()
                if dv.StatusCode is not None and not dv.StatusCode.is_good():
                    raise status_error(dv.StatusCode.name, f"{self.endpoint}: read of {node}",
                                       user=self.user, right="SinuReadAll")
                v = dv.Value.Value if dv.Value is not None else None
                if not isinstance(v, (int, float)) or isinstance(v, bool):
                    raise LinkError(f"{self.endpoint}: {node} holds {type(v).__name__}, "
                                    "not a number")
                got.append(float(v))
            out[axis] = AxisReading(*got)
        return out


def memory_for_link(spec: OpcuaLink, ip: str) -> OpcuaMemory:
    """The memory client of a registration's ``opcua`` link (the registry's entry,
    :data:`server.links.BACKENDS`); its password is read now, so that a reference not set
    is a refusal at registration, not at each connect."""
    return OpcuaMemory.from_spec(spec, password=read_secret(
        spec.password_ref, f"OPC UA user {spec.user!r}"))
