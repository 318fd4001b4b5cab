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
an IndexRange. Writes are at most :attr:`OpcuaMemory.block` bytes (default 960: an
S7-1500's largest PDU; a bigger write is split into PDUs by the controller anyway, so it
would not be more atomic, and the header-last layout needs no atomicity beyond the
two-byte switch word).

Every failure raises :class:`~server.links.window.memory.LinkError` with a text that says
what to fix (a missing password, a refused login, a user without ``PlcWrite``, no free
session, bytes outside the data block). Reconnecting is the session's: :meth:`close`,
then :meth:`connect` again.

:meth:`OpcuaMemory.read_axes` reads, per axis, the machine position and the NC's
temperature compensation setting data SD43900/43910/43920 in one request, for telemetry.
"""

from __future__ import annotations

import asyncio
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import security_policies
from asyncua.ua.attribute_ids import AttributeIds

from server.links.window.memory import LinkError
from server.schemas.link import OpcuaLink

__all__ = ["SD_NUMBERS", "AxisReading", "OpcuaMemory", "read_password"]

SD_NUMBERS: Final = (43900, 43910, 43920)
_SD_NAMES: Final = {43900: "TEMP_COMP_ABS_VALUE", 43910: "TEMP_COMP_SLOPE",
                    43920: "TEMP_COMP_REF_POSITION"}
_DB_NODE = re.compile(r"^ns=(\d+);s=(/Plc/DB\d+)$")
_READ_CHUNK: Final = 16_384
"""Bytes of the window per Read request (responses stay well inside one 64 kB chunk)."""
_HINTS: Final = {
    "BadTooManySessions": "the controller has no free OPC UA session (a SINUMERIK allows "
                          "10; close other clients)",
    "BadIdentityTokenRejected": "the server does not accept user-and-password logins",
    "BadNodeIdUnknown": "no such node on the controller (check window_node / sd_nodes)",
    "BadOutOfRange": "outside the controller's data block (window larger than the DB?)",
    "BadTypeMismatch": "the node holds another type than UInt32 words",
    "BadSecurityPolicyRejected": "the server does not offer this security policy",
    "BadCertificateUntrusted": "the controller does not trust the center's certificate "
                               "(add client_certificate to its trusted clients)",
}


def read_password(ref: str, user: str) -> str:
    """The password ``ref`` points at (``env:NAME`` or ``file:/path``; a file's trailing
    newline dropped); raises :class:`LinkError` naming what is missing."""
    kind, _, where = ref.partition(":")
    if kind == "env":
        value = os.environ.get(where)
        if value is None:
            raise LinkError(f"password of OPC UA user {user!r}: environment variable "
                            f"{where} is not set")
        return value
    if kind == "file":
        try:
            return Path(where).read_text(encoding="utf-8").rstrip("\r\n")
        except (OSError, UnicodeDecodeError) as e:
            raise LinkError(f"password of OPC UA user {user!r}: cannot read {where} "
                            f"({e.__class__.__name__})") from None
    raise LinkError(f"password of OPC UA user {user!r}: reference {ref!r} is neither "
                    "env:NAME nor file:/path")


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


def _status_name(e: BaseException) -> str | None:
    code = getattr(e, "code", None)
    if isinstance(code, int):
        return ua.StatusCode(ua.UInt32(code)).name
    return None


class OpcuaMemory:
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
        ``None``/``None``, or ``Basic256Sha256`` with ``Sign`` or ``SignAndEncrypt`` (then
        ``client_certificate`` and ``client_private_key`` are needed; the server's
        certificate is taken from its endpoint list).
    sd_nodes : mapping of str to str
        Node ids of setting data, keyed ``"<AXIS>.<number>"`` (``"X.43900"``); the rest
        default to the SINUMERIK paths of machine axis k (1-based, the order of
        ``read_axes``'s axes).
    timeout_s : float
        Per request and for the whole login.
    block : int
        Largest write, bytes (a multiple of 4).
    """

    def __init__(self, endpoint: str, user: str, password_ref: str, *,
                 window_node: str = "ns=2;s=/Plc/DB900", security_policy: str = "None",
                 security_mode: str = "None", client_certificate: str | None = None,
                 client_private_key: str | None = None,
                 sd_nodes: Mapping[str, str] | None = None, timeout_s: float = 5.0,
                 block: int = 960, password: str | None = None) -> None:
        m = _DB_NODE.match(window_node)
        if m is None:
            raise LinkError(f"window_node {window_node!r}: expected ns=<i>;s=/Plc/DB<n>, "
                            "the PLC data block holding the window")
        if block < 4 or block % 4:
            raise LinkError(f"block {block}: a multiple of 4 bytes")
        if (security_policy == "None") != (security_mode == "None"):
            raise LinkError(f"security policy {security_policy} with mode {security_mode}: "
                            "None goes with None, Basic256Sha256 with Sign or SignAndEncrypt")
        self.endpoint = endpoint
        self.user = user
        self.password_ref = password_ref
        self._password = password
        self.window_node = window_node
        self._ns = int(m.group(1))
        self._db = m.group(2)
        self.security_policy = security_policy
        self.security_mode = security_mode
        self.client_certificate = client_certificate
        self.client_private_key = client_private_key
        self.sd_nodes = dict(sd_nodes or {})
        self.timeout_s = float(timeout_s)
        self.block = block
        self._client: Client | None = None

    @classmethod
    def from_link(cls, link: OpcuaLink, *, password: str | None = None,
                  timeout_s: float = 5.0) -> OpcuaMemory:
        """The memory of a machine registered with ``link`` (``password``: the resolved
        ``password_ref``, else it is read at each connect)."""
        return cls(link.endpoint, link.user, link.password_ref, window_node=link.window_node,
                   security_policy=link.security_policy, security_mode=link.security_mode,
                   client_certificate=link.client_certificate,
                   client_private_key=link.client_private_key, sd_nodes=link.sd_nodes,
                   timeout_s=timeout_s, block=link.block_bytes, password=password)

    from_spec = from_link

    @property
    def address(self) -> str:
        return self.endpoint.removeprefix("opc.tcp://").split("/", 1)[0]

    # -- connection

    async def connect(self) -> None:
        """Open a session as :attr:`user`; raises :class:`LinkError`."""
        await self.close()
        password = (self._password if self._password is not None
                    else read_password(self.password_ref, self.user))
        client = Client(self.endpoint, timeout=self.timeout_s, watchdog_intervall=5.0)
        client.session_timeout = 60_000  # the SINUMERIK's; it revises longer ones to this
        client.set_user(self.user)
        client.set_password(password)
        try:
            async with asyncio.timeout(self.timeout_s * 2):
                if self.security_policy != "None":
                    await self._secure(client)
                await client.connect()
        except LinkError:
            raise
        except Exception as e:  # asyncua raises many kinds; each becomes one clear line
            client.disconnect_socket()
            raise LinkError(self._login_error(e)) from None
        self._client = client

    async def _secure(self, client: Client) -> None:
        if self.security_policy != "Basic256Sha256":
            raise LinkError(f"security policy {self.security_policy}: None or "
                            "Basic256Sha256")
        if not (self.client_certificate and self.client_private_key):
            raise LinkError(f"{self.endpoint}: Basic256Sha256 needs client_certificate and "
                            "client_private_key (the center's application instance "
                            "certificate, trusted by the controller)")
        mode = (ua.MessageSecurityMode.Sign if self.security_mode == "Sign"
                else ua.MessageSecurityMode.SignAndEncrypt)
        await client.set_security(security_policies.SecurityPolicyBasic256Sha256,
                                  self.client_certificate, self.client_private_key, mode=mode)

    def _login_error(self, e: BaseException) -> str:
        name = _status_name(e)
        where = self.endpoint
        if name == "BadUserAccessDenied":
            return (f"{where}: login as {self.user!r} refused (BadUserAccessDenied): wrong "
                    "user or password")
        if name is not None:
            return f"{where}: {_HINTS.get(name, 'refused')} ({name})"
        if isinstance(e, TimeoutError):
            return f"{where}: no answer within {self.timeout_s * 2:g} s"
        if isinstance(e, OSError):
            return f"{where}: cannot connect ({e.strerror or e.__class__.__name__})"
        return f"{where}: {e.__class__.__name__}: {e}"

    async def close(self) -> None:
        """End the session (never raises)."""
        client, self._client = self._client, None
        if client is None:
            return
        try:
            async with asyncio.timeout(self.timeout_s):
                await client.disconnect()
        except Exception:  # a dead connection has nothing to close politely
            pass
        finally:
            client.disconnect_socket()

    def _session(self) -> Client:
        if self._client is None:
            raise LinkError(f"{self.endpoint}: not connected")
        return self._client

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
        values = await self._call(self._session().uaclient.read(params), "read", offset, size)
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
        codes = await self._call(self._session().uaclient.write(params), "write", offset,
                                 len(data))
        for (at, width, count), code in zip(pieces, codes, strict=True):
            self._good(code, "write", at, width * count)

    async def _call(self, request: Any, what: str, offset: int, size: int) -> Any:
        try:
            async with asyncio.timeout(self.timeout_s):
                return await request
        except Exception as e:
            name = _status_name(e)
            if name is not None:
                raise LinkError(self._refused(name, what, offset, size)) from None
            if isinstance(e, TimeoutError):
                raise LinkError(f"{self.endpoint}: {what} of {self._db} byte {offset}: no "
                                f"answer within {self.timeout_s:g} s") from None
            raise LinkError(f"{self.endpoint}: {what} of {self._db} byte {offset}: "
                            f"connection lost ({e.__class__.__name__})") from None

    def _good(self, code: ua.StatusCode | None, what: str, offset: int, size: int) -> None:
        if code is not None and not code.is_good():
            raise LinkError(self._refused(code.name, what, offset, size))

    def _refused(self, name: str, what: str, offset: int, size: int) -> str:
        where = f"{self.endpoint}: {what} of {self._db} bytes {offset}..{offset + size - 1}"
        if name == "BadUserAccessDenied":
            right = "PlcWrite" if what == "write" else "SinuReadAll"
            return f"{where}: user {self.user!r} lacks {right} (BadUserAccessDenied)"
        return f"{where}: {_HINTS.get(name, 'refused')} ({name})"

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
        values = await self._call(self._session().uaclient.read(params), "read", 0, 0)
        out: dict[str, AxisReading] = {}
        for j, axis in enumerate(axes):
            got: list[float] = []
            for i, dv in enumerate(values[4 * j:4 * j + 4]):
                node = params.NodesToRead[4 * j + i].NodeId.to_string()
                if dv.StatusCode is not None and not dv.StatusCode.is_good():
                    name = dv.StatusCode.name
                    hint = (f"user {self.user!r} lacks SinuReadAll"
                            if name == "BadUserAccessDenied" else _HINTS.get(name, "refused"))
                    raise LinkError(f"{self.endpoint}: read of {node}: {hint} ({name})")
                v = dv.Value.Value if dv.Value is not None else None
                if not isinstance(v, (int, float)) or isinstance(v, bool):
                    raise LinkError(f"{self.endpoint}: {node} holds {type(v).__name__}, "
                                    "not a number")
                got.append(float(v))
            out[axis] = AxisReading(*got)
        return out
