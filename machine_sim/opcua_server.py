"""A SINUMERIK-style OPC UA server over a simulated machine's PLC window and NC data.

The Siemens-style machine (:class:`~machine_sim.windowcnc.WindowCNC` over a
:class:`~machine_sim.siemens.SiemensNC`) serves what a SINUMERIK 840D sl / ONE offers
through its OPC UA server option (SINUMERIK Access MyMachine / OPC UA configuration
manual, 6FC5397-1DP41; /work/shared/spec/controllers.md), with its limits:

* **login**: user and password; an anonymous session may browse and read the server's
  own nodes but gets ``BadUserAccessDenied`` for every NC or PLC value; a wrong password
  is refused at ActivateSession (``BadUserAccessDenied``);
* **rights per user** (the manual's ``GiveUserAccess`` realms): ``SinuReadAll`` reads
  everything, ``PlcRead``/``SeaRead`` one area; ``PlcWrite`` writes PLC data,
  ``SeaWrite`` setting data, ``SinuWriteAll`` both. A write without the right answers
  ``BadUserAccessDenied``;
* **at most 10 sessions** (840D sl; 5 on an 828D): the 11th CreateSession answers
  ``BadTooManySessions``; at most 10 subscriptions (``BadTooManySubscriptions``);
* **sampling and publishing no faster than 100 ms**: a subscription asking for less gets
  100 ms as its revised publishing interval, and its items 100 ms as their sampling
  interval;
* **session timeout** 60 s (server V2.0 SP1);
* **node ids** ``ns=2;s=<BTSS path>``.

The address space
-----------------
PLC data (the manual's table "PLC syntax", §5.3): ``/Plc/DB<n>.DBB<x>``,
``.DBW<x>``, ``.DBD<x>`` a byte, word or double word at byte ``x`` of data block ``n``,
and with ``:[k]`` an array of ``k`` of them ("/Plc/DB8.DBW2:[10]: Array of 10 words
beginning at byte offset 2"). Their OPC UA type is UInt32 (BYTE, WORD and DWORD all map
to UInt32 there). The data block is big-endian as every S7 data block: DBD\\ *x* is the
bytes x..x+3 with the most significant first.

**The window is data block 900 (configurable), addressed by path, not by IndexRange.**
The center writes a block of the window as one ``/Plc/DB900.DBD<x>:[k]`` array (four
window bytes per UInt32: as many payload bytes on the wire as values, the densest a
SINUMERIK offers) and a two-byte edge as ``.DBW<x>:[1]``, several of them in one Write
request. Why this and not one big array node written with an IndexRange: the SINUMERIK
manual documents addressed arrays (offset and length in the path), not IndexRange on PLC
data, and asyncua's server ignores a WriteValue's IndexRange (it would replace the whole
node with the block; FreeOpcUa/opcua-asyncio#1338 and PR #172 are about the client
side). So a client that works against this server uses only what the real one offers.
An IndexRange on these nodes is refused (``BadIndexRangeInvalid``). The nodes exist for
every offset and length inside the block, as on the real server, which resolves any
valid path; browsing shows ``/Plc/DB900`` only. Bytes outside the block answer
``BadOutOfRange``, another data block ``BadNodeIdUnknown``, a value of another type or
length ``BadTypeMismatch``. All nodes of one Write request are written in one event-loop
step, so no PLC scan sees half of a request. On a real controller the data block must be
at least the window's size (``Layout.size``: 33,344 bytes at the default 16 kB capacity)
and allow byte-offset addressing (on an S7-1500 / SINUMERIK ONE PLC: a DB without
"optimized block access").

NC data, per machine axis ``k`` (1-based, the machine's axis order):

* ``/NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_ABS_VALUE[u<k>]`` SD43900, ``..._SLOPE[u<k>]`` SD43910,
  ``..._REF_POSITION[u<k>]`` SD43920 (Double, mm, mm/mm): read from the NC's setting data
  (:meth:`SiemensNC.read_sd`), written through :meth:`SiemensNC.write_sd` (with
  ``SeaWrite``; an NC alarm answers ``BadOutOfRange`` for a value out of range,
  ``BadNotWritable`` where MD32750 disables the datum);
* ``/Channel/MachineAxis/actToolBasePos[u1,<k>]`` the machine axis position (Double, mm)
  and ``/Channel/MachineAxis/name[u1,<k>]`` its name (String); read-only
  (``BadNotWritable``).

These are nodes of the address space (browsable under ``Sinumerik``), their values read
from the machine when asked and, for subscriptions, sampled every 100 ms. The window's
paths are not sampled: the center polls the status with reads.

**Security.** The server offers Basic256Sha256 Sign and SignAndEncrypt beside None
(``security_modes``), with its own certificate: given, or the simulator's (made once and
kept in ``EDNC_SIM_PKI_DIR``, else ``$XDG_CACHE_HOME/ednc/sim-opcua``, so a simulated
controller shows the same certificate run after run, as a real one does and as a center
trusting it on first use expects). ``trusted_clients`` is its trust list: a client
certificate not on it gets ``BadCertificateUntrusted`` at CreateSession (as on the real
server, where the center's certificate must be trusted once). On the None endpoint the
password is taken as sent, in clear (an old controller's configuration: the worst case a
center must not fall into silently); on Sign it is encrypted with the server's key.

**Busy.** With ``busy`` > 0 that fraction of CreateSession requests answers
``BadTooManySessions`` and of Read and Write requests ``BadResourceUnavailable`` (a
controller whose server is loaded by the HMI and other clients). When its 10 sessions
are taken, a CreateSession first closes the oldest session that was created and never
activated (a real server frees such a session; asyncua would keep it until its
timeout, so ten half-open logins would lock everyone out); only when all 10 are active
does it answer ``BadTooManySessions``. Not simulated: the limit of 1,000 samples/s.

The server runs in the machine's event loop (:class:`SinumerikOpcuaServer` is a
``ControllerServer``: ``port``, ``start()``, ``stop()``; port 0 binds a free port, read
back after start). Servers in one process share asyncua's standard address space, each
copying a node the first time it touches it (:class:`_CopyOnAccess`), so a fleet of them
starts in tens of milliseconds each. Build it with :func:`sinumerik_server`::

    cnc = WindowCNC(machine, sinumerik_server({"ednc": OpcuaUser("pw", PLC_WRITER)}))
"""

from __future__ import annotations

import asyncio
import contextlib
import copy
import functools
import os
import random
import re
import socket
import struct
from collections.abc import Callable, Iterator, Mapping, MutableMapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from asyncua import ua
from asyncua.common.utils import ServiceError
from asyncua.crypto import cert_gen, uacrypto
from asyncua.crypto.permission_rules import User, UserRole
from asyncua.server.address_space import NodeData
from asyncua.server.internal_server import InternalServer
from asyncua.server.internal_session import InternalSession
from asyncua.server.server import Server
from asyncua.ua.attribute_ids import AttributeIds
from asyncua.ua.status_codes import StatusCodes
from cryptography import x509
from cryptography.hazmat.primitives.serialization import Encoding
from cryptography.x509.oid import ExtendedKeyUsageOID

from .siemens import SD_ABS_VALUE, SD_REF_POSITION, SD_SLOPE, SiemensAlarm, SiemensNC

if TYPE_CHECKING:
    from .windowcnc import WindowCNC

__all__ = [
    "ADMIN",
    "PLC_WRITER",
    "READER",
    "OpcuaUser",
    "SinumerikOpcuaServer",
    "plc_path",
    "position_path",
    "sd_path",
    "sinumerik_server",
]

NAMESPACE: Final = "urn:ednc:sim:sinumerik"
SERVER_URI: Final = "urn:ednc:sim:sinumerik:server"
"""The simulated controllers' ApplicationUri (in their certificate's subjectAltName)."""
SIM_PKI_ENV: Final = "EDNC_SIM_PKI_DIR"
SECURITY_MODES: Final = ("None", "Sign", "SignAndEncrypt")
PLC_WRITE_LIMIT: Final = {"s7-300": 240, "s7-1500": 960}
"""PLC bytes one Write request may carry, by the PLC's class: the data of one PDU (an
S7-300-class PLC, the 840D sl's, 240 bytes; an S7-1500, SINUMERIK ONE's, 960). The
simulated server refuses more (``BadRequestTooLarge``) rather than splitting it into PDUs
the PLC program could read between."""
_POLICY: Final = {"None": ua.SecurityPolicyType.NoSecurity,
                  "Sign": ua.SecurityPolicyType.Basic256Sha256_Sign,
                  "SignAndEncrypt": ua.SecurityPolicyType.Basic256Sha256_SignAndEncrypt}
"""Registered first, so it is namespace 2 as on the real server."""
MAX_SESSIONS: Final = 10
MAX_SUBSCRIPTIONS: Final = 10
MIN_INTERVAL_MS: Final = 100.0
SESSION_TIMEOUT_MS: Final = 60_000.0

READER: Final = frozenset({"SinuReadAll"})
PLC_WRITER: Final = frozenset({"SinuReadAll", "PlcWrite"})
ADMIN: Final = frozenset({"SinuReadAll", "SinuWriteAll"})

SD_NAMES: Final = {SD_ABS_VALUE: "TEMP_COMP_ABS_VALUE", SD_SLOPE: "TEMP_COMP_SLOPE",
                   SD_REF_POSITION: "TEMP_COMP_REF_POSITION"}
_SD_BY_NAME: Final = {v: k for k, v in SD_NAMES.items()}

_PLC = re.compile(r"^/Plc/DB(\d+)\.DB([BWD])(\d+)(?::\[(\d+)\])?$")
_SD = re.compile(r"^/NC/_N_AX_SEA_ACX/\$SA_([A-Z_]+)\[u(\d+)\]$")
_AXIS = re.compile(r"^/Channel/MachineAxis/(actToolBasePos|name)\[u1,(\d+)\]$")
_WIDTH: Final = {"B": 1, "W": 2, "D": 4}
_STANDARD: dict[ua.NodeId, NodeData] | None = None
"""asyncua's standard address space, built once per process and never changed (every
server works on its own copies of the nodes it touches, :class:`_CopyOnAccess`)."""
_S = StatusCodes
_ANONYMOUS: Final = User(role=UserRole.Anonymous)
_NONE_URI: Final = "http://opcfoundation.org/UA/SecurityPolicy#None"


def plc_path(db: int, offset: int, width: int, count: int | None = None) -> str:
    """The BTSS path of ``count`` (None: one, scalar) elements of ``width`` bytes (1, 2,
    4) at byte ``offset`` of data block ``db``: ``/Plc/DB900.DBD512:[240]``."""
    letter = {1: "B", 2: "W", 4: "D"}[width]
    return f"/Plc/DB{db}.DB{letter}{offset}" + ("" if count is None else f":[{count}]")


def sd_path(number: int, axis: int) -> str:
    """The BTSS path of axis setting datum SD``number`` of machine axis ``axis``
    (1-based): ``/NC/_N_AX_SEA_ACX/$SA_TEMP_COMP_ABS_VALUE[u1]``."""
    return f"/NC/_N_AX_SEA_ACX/$SA_{SD_NAMES[number]}[u{axis}]"


def position_path(axis: int) -> str:
    """The BTSS path of machine axis ``axis``'s (1-based) position, mm."""
    return f"/Channel/MachineAxis/actToolBasePos[u1,{axis}]"


def sim_pki_dir() -> Path:
    """Where the simulated controllers keep their certificate (module docstring)."""
    given = os.environ.get(SIM_PKI_ENV)
    if given:
        return Path(given)
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "ednc" / "sim-opcua"


@functools.cache
def sim_certificate(root: Path | None = None) -> tuple[bytes, bytes]:
    """The simulated controllers' certificate (DER) and key (PEM): read from ``root``
    (default :func:`sim_pki_dir`), or made there once. One for every simulated
    controller of a process: an RSA key costs ~0.1 CPU-s, a fleet of 100 would spend 10 s
    making keys no center tells apart (it keeps certificates per endpoint)."""
    root = root if root is not None else sim_pki_dir()
    path = root / "server.pem"  # certificate and key in one file: one atomic replace
    try:
        return _split_pem(path.read_bytes())
    except (OSError, ValueError):
        pass
    try:  # kept by an earlier version as two files: the same certificate, centers trust it
        old = (root / "server.der").read_bytes(), (root / "server.key.pem").read_bytes()
        cert = x509.load_der_x509_certificate(old[0])
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_bytes(cert.public_bytes(Encoding.PEM) + old[1])
        tmp.chmod(0o600)
        tmp.replace(path)
        return _split_pem(path.read_bytes())
    except (OSError, ValueError):
        pass
    key = cert_gen.generate_private_key()
    cert = cert_gen.generate_self_signed_app_certificate(
        key, SERVER_URI, {"organizationName": "EDNC simulated SINUMERIK"},
        [x509.UniformResourceIdentifier(SERVER_URI), x509.DNSName(socket.gethostname()),
         x509.DNSName("localhost")],
        [ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH], days=3650)
    der, pem = cert.public_bytes(Encoding.DER), cert_gen.dump_private_key_as_pem(key)
    try:
        root.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_bytes(cert.public_bytes(Encoding.PEM) + pem)
        tmp.chmod(0o600)
        tmp.replace(path)
        return _split_pem(path.read_bytes())  # another process's, if it won the race
    except (OSError, ValueError):
        return der, pem  # not kept: this process's controllers still share it


def _split_pem(data: bytes) -> tuple[bytes, bytes]:
    """(certificate DER, private key PEM) of a file holding both, PEM."""
    at = data.find(b"-----BEGIN PRIVATE KEY-----")
    if at < 0:
        raise ValueError("no private key")
    cert = x509.load_pem_x509_certificate(data[:at])
    return cert.public_bytes(Encoding.DER), data[at:]


@dataclass(frozen=True)
class OpcuaUser:
    """A user of the server: password and rights (realm names, see module docstring)."""

    password: str
    rights: frozenset[str]


class _Users:
    """asyncua's user manager: who may log in (rights are looked up per request)."""

    def __init__(self, users: Mapping[str, OpcuaUser]) -> None:
        self.users = dict(users)

    def get_user(self, iserver: Any, username: str | None = None, password: str | None = None,
                 certificate: Any = None) -> User | None:
        if username is None:
            return User(role=UserRole.Anonymous)  # may browse; no NC or PLC data
        known = self.users.get(username)
        if known is None or password != known.password:
            return None  # ActivateSession answers BadUserAccessDenied
        return User(role=UserRole.User, name=username)


def _status(code: int) -> ua.StatusCode:
    return ua.StatusCode(ua.UInt32(code))


def _nid(path: str, ns: int) -> ua.NodeId:
    return ua.NodeId(ua.String(path), ua.Int16(ns))


def _bad(code: int) -> ua.DataValue:
    return ua.DataValue(StatusCode=_status(code))


class _Sinumerik:
    """The NC and PLC data of one machine behind the server: reads and writes of the
    ``ns=2`` BTSS paths with rights checks (no asyncua state here)."""

    def __init__(self, cnc: WindowCNC, users: Mapping[str, OpcuaUser], db: int) -> None:
        self.cnc = cnc
        self.users = users
        self.db = db

    def rights(self, user: User) -> frozenset[str]:
        if user.role is UserRole.Admin:  # the server's own internal session
            return ADMIN
        known = self.users.get(user.name or "") if user.role is UserRole.User else None
        return known.rights if known is not None else frozenset()

    @staticmethod
    def _may(rights: frozenset[str], area: str, write: bool) -> bool:
        if write:
            return "SinuWriteAll" in rights or f"{area}Write" in rights
        return bool({"SinuReadAll", "SinuWriteAll", f"{area}Read", f"{area}Write"} & rights)

    def _nc(self) -> SiemensNC:
        ctl = self.cnc.runtime.controller  # looked up each time: a PLC restart replaces it
        if not isinstance(ctl, SiemensNC):
            raise ServiceError(_S.BadNodeIdUnknown)
        return ctl

    def _axis(self, k: str) -> int:
        j = int(k) - 1
        if not 0 <= j < len(self.cnc.machine.axis_names):
            raise ServiceError(_S.BadNodeIdUnknown)
        return j

    # -- reads

    def read(self, path: str, user: User, index_range: str | None) -> ua.DataValue:
        """The value of ``path`` for ``user`` (a bad status when refused)."""
        try:
            return self._read(path, self.rights(user), index_range)
        except ServiceError as e:
            return _bad(e.code)

    def _read(self, path: str, rights: frozenset[str], index_range: str | None
              ) -> ua.DataValue:
        if (m := _PLC.match(path)) is not None:
            if not self._may(rights, "Plc", False):
                raise ServiceError(_S.BadUserAccessDenied)
            at, width, count = self._plc(m, index_range)
            data = bytes(self.cnc.window[at:at + width * (count or 1)])
            values = [int.from_bytes(data[i:i + width], "big")
                      for i in range(0, len(data), width)]
            if count is None:
                return ua.DataValue(ua.Variant(values[0], ua.VariantType.UInt32))
            return ua.DataValue(ua.Variant(values, ua.VariantType.UInt32, is_array=True))
        if index_range:
            raise ServiceError(_S.BadIndexRangeInvalid)
        if (m := _SD.match(path)) is not None:
            if not self._may(rights, "Sea", False):
                raise ServiceError(_S.BadUserAccessDenied)
            number, j = self._sd(m)
            value = self._nc().read_sd(number, self.cnc.machine.axis_names[j])
            return ua.DataValue(ua.Variant(value, ua.VariantType.Double))
        if (m := _AXIS.match(path)) is not None:
            if not self._may(rights, "Sinu", False):
                raise ServiceError(_S.BadUserAccessDenied)
            j = self._axis(m.group(2))
            if m.group(1) == "name":
                return ua.DataValue(ua.Variant(self.cnc.machine.axis_names[j],
                                               ua.VariantType.String))
            pos = float(self.cnc.runtime.positions[j])
            return ua.DataValue(ua.Variant(pos, ua.VariantType.Double))
        raise ServiceError(_S.BadNodeIdUnknown)

    def _plc(self, m: re.Match[str], index_range: str | None) -> tuple[int, int, int | None]:
        """(byte offset, element width, element count or None) of a PLC path in the
        window's data block; refuses other blocks, index ranges and bytes outside."""
        if int(m.group(1)) != self.db:
            raise ServiceError(_S.BadNodeIdUnknown)
        if index_range:
            raise ServiceError(_S.BadIndexRangeInvalid)
        width = _WIDTH[m.group(2)]
        at = int(m.group(3))
        count = None if m.group(4) is None else int(m.group(4))
        if count == 0:
            raise ServiceError(_S.BadNodeIdInvalid)
        if at + width * (count or 1) > len(self.cnc.window):
            raise ServiceError(_S.BadOutOfRange)
        return at, width, count

    def _sd(self, m: re.Match[str]) -> tuple[int, int]:
        number = _SD_BY_NAME.get(m.group(1))
        if number is None:
            raise ServiceError(_S.BadNodeIdUnknown)
        return number, self._axis(m.group(2))

    # -- writes

    def write(self, path: str, user: User, value: ua.DataValue, index_range: str | None
              ) -> ua.StatusCode:
        """Write ``value`` to ``path`` for ``user``; the status says why not."""
        try:
            self._write(path, self.rights(user), value, index_range)
        except ServiceError as e:
            return _status(e.code)
        return ua.StatusCode()

    def _write(self, path: str, rights: frozenset[str], dv: ua.DataValue,
               index_range: str | None) -> None:
        variant = dv.Value
        if (m := _PLC.match(path)) is not None:
            if not self._may(rights, "Plc", True):
                raise ServiceError(_S.BadUserAccessDenied)
            at, width, count = self._plc(m, index_range)
            data = self._plc_bytes(variant, width, count)
            self.cnc.window[at:at + len(data)] = data
            return
        if index_range:
            raise ServiceError(_S.BadIndexRangeInvalid)
        if (m := _SD.match(path)) is not None:
            if not self._may(rights, "Sea", True):
                raise ServiceError(_S.BadUserAccessDenied)
            number, j = self._sd(m)
            if variant is None or variant.VariantType is not ua.VariantType.Double \
                    or variant.is_array:
                raise ServiceError(_S.BadTypeMismatch)
            try:
                self._nc().write_sd(number, self.cnc.machine.axis_names[j], variant.Value)
            except SiemensAlarm as e:
                raise ServiceError(_S.BadNotWritable if e.code.endswith("_DISABLED")
                                   else _S.BadOutOfRange) from None
            return
        if _AXIS.match(path) is not None:
            raise ServiceError(_S.BadNotWritable)
        raise ServiceError(_S.BadNodeIdUnknown)

    @staticmethod
    def _plc_bytes(variant: ua.Variant | None, width: int, count: int | None) -> bytes:
        """The data block bytes a UInt32 value (scalar for ``count`` None, else an array of
        exactly ``count``) stands for, each element big-endian in ``width`` bytes."""
        if variant is None or variant.VariantType is not ua.VariantType.UInt32:
            raise ServiceError(_S.BadTypeMismatch)
        if count is None:
            if variant.is_array or isinstance(variant.Value, list):
                raise ServiceError(_S.BadTypeMismatch)
            values = [variant.Value]
        else:
            if not isinstance(variant.Value, list) or len(variant.Value) != count:
                raise ServiceError(_S.BadTypeMismatch)
            values = variant.Value
        limit = 1 << (8 * width)
        if any(not 0 <= v < limit for v in values):
            raise ServiceError(_S.BadOutOfRange)
        if width == 4:
            return struct.pack(f">{len(values)}I", *values)
        if width == 2:
            return struct.pack(f">{len(values)}H", *values)
        return bytes(values)


class _Session(InternalSession):
    """A client's session: NC and PLC paths answered by the machine, subscriptions no
    faster than the SINUMERIK's 100 ms."""

    def _ours(self, node: ua.NodeId, attr: int) -> str | None:
        if attr != AttributeIds.Value or node.NamespaceIndex != 2 \
                or not isinstance(node.Identifier, str):
            return None
        return node.Identifier

    def _user(self) -> User:
        return self.user if self.user is not None else User()

    async def read(self, params: ua.ReadParameters) -> list[ua.DataValue]:
        if self.iserver.is_busy():  # type: ignore[attr-defined]
            raise ServiceError(_S.BadResourceUnavailable)
        nc: _Sinumerik = self.iserver.sinumerik  # type: ignore[attr-defined]
        out: list[ua.DataValue | None] = []
        rest = ua.ReadParameters()
        rest.MaxAge, rest.TimestampsToReturn = params.MaxAge, params.TimestampsToReturn
        for rv in params.NodesToRead:
            path = self._ours(rv.NodeId, rv.AttributeId)
            if path is None:
                out.append(None)
                rest.NodesToRead.append(rv)
            else:
                out.append(nc.read(path, self._user(), rv.IndexRange))
        others = iter(await super().read(rest) if rest.NodesToRead else [])
        return [v if v is not None else next(others) for v in out]

    async def write(self, params: ua.WriteParameters) -> list[ua.StatusCode]:
        if self.iserver.is_busy():  # type: ignore[attr-defined]
            raise ServiceError(_S.BadResourceUnavailable)
        limit: int = self.iserver.plc_write_limit  # type: ignore[attr-defined]
        plc = 0
        for wv in params.NodesToWrite:
            path = self._ours(wv.NodeId, wv.AttributeId)
            m = _PLC.match(path) if path is not None else None
            if m is not None:
                plc += _WIDTH[m.group(2)] * int(m.group(4) or 1)
        if plc > limit:  # more than one PDU of the PLC in one request
            raise ServiceError(_S.BadRequestTooLarge)
        nc: _Sinumerik = self.iserver.sinumerik  # type: ignore[attr-defined]
        out: list[ua.StatusCode | None] = []
        rest = ua.WriteParameters()
        for wv in params.NodesToWrite:  # no await between ours: one step of the loop
            path = self._ours(wv.NodeId, wv.AttributeId)
            if path is None:
                out.append(None)
                rest.NodesToWrite.append(wv)
            else:
                out.append(nc.write(path, self._user(), wv.Value, wv.IndexRange))
        others = iter(await super().write(rest) if rest.NodesToWrite else [])
        return [v if v is not None else next(others) for v in out]

    async def create_subscription(self, params: ua.CreateSubscriptionParameters,
                                  callback: Callable[..., Any],
                                  request_callback: Callable[..., Any] | None = None
                                  ) -> ua.CreateSubscriptionResult:
        params.RequestedPublishingInterval = max(MIN_INTERVAL_MS,
                                                 params.RequestedPublishingInterval)
        return await super().create_subscription(params, callback, request_callback)

    async def create_monitored_items(self, params: ua.CreateMonitoredItemsParameters
                                     ) -> list[ua.MonitoredItemCreateResult]:
        results = await super().create_monitored_items(params)
        for r in results:
            r.RevisedSamplingInterval = max(MIN_INTERVAL_MS, r.RevisedSamplingInterval)
        return results

    async def modify_monitored_items(self, params: ua.ModifyMonitoredItemsParameters
                                     ) -> list[ua.MonitoredItemModifyResult]:
        for item in params.ItemsToModify:
            sp = item.RequestedParameters
            sp.SamplingInterval = max(MIN_INTERVAL_MS, sp.SamplingInterval)
        return await super().modify_monitored_items(params)


class _CopyOnAccess(MutableMapping[ua.NodeId, NodeData]):
    """One server's nodes over the process's standard address space: a standard node is
    copied the first time this server touches it, so a server changes only its own copies.
    asyncua builds the standard space in about a CPU second and 45 MB per server; shared,
    a further server starts in tens of milliseconds and copies a few dozen nodes (a fleet
    of simulated controllers in one process; asyncua's own shelf loader is the model)."""

    def __init__(self, source: dict[ua.NodeId, NodeData]) -> None:
        self.source = source
        self.own: dict[ua.NodeId, NodeData] = {}
        self.deleted: set[ua.NodeId] = set()

    def __getitem__(self, key: ua.NodeId) -> NodeData:
        try:
            return self.own[key]
        except KeyError:
            if key in self.deleted:
                raise
        node = self.own[key] = copy.deepcopy(self.source[key])
        return node

    def __setitem__(self, key: ua.NodeId, value: NodeData) -> None:
        self.deleted.discard(key)
        self.own[key] = value

    def __delitem__(self, key: ua.NodeId) -> None:
        if key not in self:
            raise KeyError(key)
        self.own.pop(key, None)
        if key in self.source:
            self.deleted.add(key)

    def __contains__(self, key: object) -> bool:
        return key in self.own or (key in self.source and key not in self.deleted)

    def __iter__(self) -> Iterator[ua.NodeId]:
        yield from self.own
        yield from (k for k in self.source if k not in self.own and k not in self.deleted)

    def __len__(self) -> int:
        return sum(1 for _ in self)


class _Internal(InternalServer):
    """asyncua's internal server with the SINUMERIK's session limit (asyncua counts
    activated sessions over the whole process, so the limit per server is kept here)."""

    def __init__(self, users: _Users, sinumerik: _Sinumerik, max_sessions: int,
                 busy: float = 0.0, seed: int | None = None) -> None:
        super().__init__(user_manager=users)  # type: ignore[arg-type]
        self.sinumerik = sinumerik
        self.max_sessions = max_sessions
        self.busy = busy
        self._rng = random.Random(seed)
        self.evicted = 0
        """Sessions closed unactivated to make room (for tests)."""
        self.plc_write_limit = PLC_WRITE_LIMIT["s7-1500"]
        self.busy_answers = 0

    def is_busy(self) -> bool:
        """Whether this request gets a busy answer (``busy`` of them, at random)."""
        if self.busy > 0.0 and self._rng.random() < self.busy:
            self.busy_answers += 1
            return True
        return False

    async def load_standard_address_space(self, shelf_file: Path | None = None) -> None:
        global _STANDARD
        if _STANDARD is None:
            await super().load_standard_address_space(None)
            _STANDARD = dict(self.aspace._nodes)
        self.aspace._nodes = _CopyOnAccess(_STANDARD)  # type: ignore[assignment]

    def create_session(self, name: str, user: User = _ANONYMOUS,
                       external: bool = False) -> InternalSession:
        if external and self.is_busy():
            raise ServiceError(_S.BadTooManySessions)
        if external and len(self._external_sessions) >= self.max_sessions:
            idle = [x for x in self._external_sessions.values() if not x.is_activated()]
            if not idle:
                raise ServiceError(_S.BadTooManySessions)
            oldest = idle[0]  # the dict keeps creation order
            self.unregister_external_session(oldest)  # its place is free now
            asyncio.get_running_loop().create_task(oldest.close_session())
            self.evicted += 1
        return _Session(self, self.aspace, self.subscription_service, name, user=user,
                        external=external)


class SinumerikOpcuaServer:
    """The OPC UA server of one simulated SINUMERIK (a ``ControllerServer``).

    Parameters
    ----------
    cnc : WindowCNC
        The machine: its window is data block ``db``; NC data come from its controller.
    users : mapping of str to OpcuaUser
    host : str
    port : int
        0: a free port, in :attr:`port` after :meth:`start`.
    db : int
        The data block holding the window.
    max_sessions : int
    session_timeout_s : float
        A session idle this long is closed (every session gets this timeout, whatever it
        asks; asyncua does not go below 5 s).
    certificate, private_key : Path, optional
        PEM or DER files of the server's certificate; default :func:`sim_certificate`.
    trusted_clients : sequence of Path, optional
        Client certificates (PEM or DER) the server trusts; None trusts any.
    security_modes : sequence of str
        Endpoints offered: ``None`` (password in clear), ``Sign``, ``SignAndEncrypt``
        (Basic256Sha256).
    busy : float
        Fraction of CreateSession, Read and Write requests answered busy (module
        docstring); ``seed`` makes the draw repeatable.
    plc_class : {"s7-300", "s7-1500"}
        The PLC's class: PLC bytes per Write request (:data:`PLC_WRITE_LIMIT`).
    """

    def __init__(self, cnc: WindowCNC, users: Mapping[str, OpcuaUser], *,
                 host: str = "127.0.0.1", port: int = 0, db: int = 900,
                 max_sessions: int = MAX_SESSIONS,
                 session_timeout_s: float = SESSION_TIMEOUT_MS / 1000,
                 certificate: Path | None = None,
                 private_key: Path | None = None,
                 trusted_clients: Sequence[Path] | None = None,
                 security_modes: Sequence[str] = SECURITY_MODES, busy: float = 0.0,
                 seed: int | None = None, plc_class: str = "s7-1500") -> None:
        if plc_class not in PLC_WRITE_LIMIT:
            raise ValueError(f"plc_class: s7-300 or s7-1500, got {plc_class!r}")
        unknown = set(security_modes) - set(SECURITY_MODES)
        if unknown or not security_modes:
            raise ValueError(f"security_modes: some of {', '.join(SECURITY_MODES)}, got "
                             f"{list(security_modes)}")
        if not 0.0 <= busy < 1.0:
            raise ValueError(f"busy: a fraction in [0, 1), got {busy}")
        self.security_modes = tuple(security_modes)
        self.cnc = cnc
        self.host = host
        self.port = port
        self.db = db
        self.certificate, self.private_key = certificate, private_key
        self.session_timeout_ms = max(5_000.0, 1000 * float(session_timeout_s))
        self.trusted_clients = None if trusted_clients is None else list(trusted_clients)
        self.sinumerik = _Sinumerik(cnc, users, db)
        self._internal = _Internal(_Users(users), self.sinumerik, max_sessions, busy, seed)
        self._internal.plc_write_limit = PLC_WRITE_LIMIT[plc_class]
        self.plc_class = plc_class
        self.server: Server | None = None
        self._sampled: list[tuple[ua.NodeId, str]] = []
        self._sampler: asyncio.Task[None] | None = None

    @property
    def endpoint(self) -> str:
        """``opc.tcp://host:port`` (the bound port once started)."""
        return f"opc.tcp://{self.host}:{self.port}"

    async def start(self) -> None:
        """Build the address space and listen."""
        srv = Server(iserver=self._internal)
        await srv.init()
        srv.disable_clock()  # a fleet of servers need not rewrite CurrentTime every second
        srv.set_endpoint(f"opc.tcp://{self.host}:{self.port}")
        srv.set_server_name(f"SINUMERIK {self.cnc.machine.name} (simulated)")
        srv.set_identity_tokens([ua.AnonymousIdentityToken, ua.UserNameIdentityToken])
        if self.certificate is not None and self.private_key is not None:
            await srv.load_certificate(str(self.certificate))
            await srv.load_private_key(str(self.private_key))
        else:
            der, pem = sim_certificate()
            await srv.set_application_uri(SERVER_URI)
            await srv.load_certificate(der, "der")
            await srv.load_private_key(pem, None, "pem")
        srv.set_security_policy([_POLICY[m] for m in self.security_modes])
        if self.trusted_clients is not None:
            trusted = {(await uacrypto.load_certificate(str(p))).public_bytes(Encoding.DER)
                       for p in self.trusted_clients}

            async def validate(cert: Any, _app: Any) -> None:
                if cert.public_bytes(Encoding.DER) not in trusted:
                    raise ServiceError(_S.BadCertificateUntrusted)

            srv.set_certificate_validator(validate)
        iserver = srv.iserver
        iserver.max_session_timeout_ms = self.session_timeout_ms
        iserver.min_session_timeout_ms = self.session_timeout_ms
        iserver.max_subscriptions = MAX_SUBSCRIPTIONS
        iserver.allow_remote_admin = False
        ns = await srv.register_namespace(NAMESPACE)
        await self._nodes(srv, ns)
        await srv.start()
        for edp in srv.iserver.endpoints:  # None takes the password in clear (docstring)
            if edp.SecurityMode == ua.MessageSecurityMode.None_:
                for token in edp.UserIdentityTokens:
                    if token.TokenType == ua.UserTokenType.UserName:
                        token.SecurityPolicyUri = _NONE_URI
        assert srv.bserver is not None
        self.port = srv.bserver.port  # the bound one when asked for 0
        self.server = srv
        self._sampler = asyncio.create_task(self._sample(srv),
                                            name=f"{self.cnc.machine.name}:opcua-sampling")

    async def _sample(self, srv: Server) -> None:
        """The SINUMERIK's sampling for monitored items: every 100 ms, while any
        subscription exists, the NC values of the address space's nodes are read from the
        machine into the nodes (asyncua reports data changes on writes, it samples
        nothing itself). Reads by clients are answered from the machine anyway."""
        last: dict[str, object] = {}
        admin = User(role=UserRole.Admin)
        while True:
            await asyncio.sleep(MIN_INTERVAL_MS / 1000)
            if not srv.iserver.subscription_service.subscriptions:
                last.clear()
                continue
            for node, path in self._sampled:
                dv = self.sinumerik.read(path, admin, None)
                value = dv.Value.Value if dv.Value is not None else None
                if value is None or last.get(path) == value:
                    continue
                last[path] = value
                await srv.write_attribute_value(node, dv)

    async def _nodes(self, srv: Server, ns: int) -> None:
        """Browsable nodes: the window's data block and, per axis, position, name and the
        temperature compensation setting data (values served by :class:`_Sinumerik`)."""
        root = await srv.nodes.objects.add_folder(_nid("/Sinumerik", ns), "Sinumerik")
        plc = await root.add_folder(_nid("/Sinumerik/Plc", ns), "Plc")
        await plc.add_variable(_nid(f"/Plc/DB{self.db}", ns), f"DB{self.db}",
                               ua.Variant([], ua.VariantType.UInt32, is_array=True))
        axes = await root.add_folder(_nid("/Sinumerik/Channel/MachineAxis", ns),
                                     "MachineAxis")
        sea = await root.add_folder(_nid("/Sinumerik/SEA", ns), "SEA")
        for k, name in enumerate(self.cnc.machine.axis_names, start=1):
            await axes.add_variable(_nid(position_path(k), ns), f"actToolBasePos{k}",
                                    ua.Variant(0.0, ua.VariantType.Double))
            self._sampled.append((_nid(position_path(k), ns), position_path(k)))
            await axes.add_variable(_nid(f"/Channel/MachineAxis/name[u1,{k}]", ns),
                                    f"name{k}", ua.Variant(name, ua.VariantType.String))
            for number in SD_NAMES:
                node = await sea.add_variable(_nid(sd_path(number, k), ns),
                                              f"SD{number}[{name}]",
                                              ua.Variant(0.0, ua.VariantType.Double))
                await node.set_writable()
                self._sampled.append((_nid(sd_path(number, k), ns), sd_path(number, k)))

    async def stop(self) -> None:
        """Close every session and stop listening."""
        if self._sampler is not None:
            self._sampler.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._sampler
            self._sampler = None
        if self.server is not None:
            await self.server.stop()
            self.server = None


def sinumerik_server(users: Mapping[str, OpcuaUser], **kw: Any
                     ) -> Callable[[WindowCNC], SinumerikOpcuaServer]:
    """A ``server_factory`` for :class:`~machine_sim.windowcnc.WindowCNC` (keywords as
    :class:`SinumerikOpcuaServer`'s)."""
    def build(cnc: WindowCNC) -> SinumerikOpcuaServer:
        return SinumerikOpcuaServer(cnc, users, **kw)
    return build
