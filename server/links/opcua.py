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
session, bytes outside the data block, an untrusted certificate). Reconnecting is the
session's: :meth:`close`, then :meth:`connect` again.

:meth:`OpcuaMemory.read_axes` reads, per axis, the machine position and the NC's
temperature compensation setting data SD43900/43910/43920 in one request, for telemetry.
"""

from __future__ import annotations

import asyncio
import logging
import os
import random
import re
from collections.abc import Awaitable, Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import security_policies, uacrypto
from asyncua.ua.attribute_ids import AttributeIds
from cryptography.hazmat.primitives import serialization

from server.links.opcuapki import CENTER_URI, Pki, TrustMode, pki_at, thumbprint
from server.links.window.memory import LinkError
from server.schemas.link import OpcuaLink

__all__ = ["PLC_BLOCK", "RETRY_DELAYS_S", "SD_NUMBERS", "TRANSIENT", "AxisReading",
           "OpcuaMemory", "read_password", "recheck_certificate", "secure_client"]

log = logging.getLogger(__name__)

PLC_BLOCK: Final = {"s7-300": 240, "s7-1500": 960}
"""Bytes per write by PLC class: the payload an S7-300-class PLC (840D sl) takes in one
PDU (240-byte PDU) and an S7-1500's (960). The OPC UA server forwards a write to the PLC
in PDUs of its size; a block of one PDU is written in one PLC access."""
TRANSIENT: Final = frozenset({"BadTooManySessions", "BadResourceUnavailable", "BadTimeout"})
"""Answers that mean "busy, ask again": retried, not a reason to end the session."""
RETRY_DELAYS_S: Final = (0.05, 0.1, 0.2, 0.4, 0.8, 0.8, 0.8, 0.8, 0.8)
"""Waits before the retries of one request: 9 retries over 4.75 s (up to 1.5x with the
jitter, so a fleet does not retry in step). A controller busy for 30 % of its answers
fails one request in 0.3^10 = 6e-6: a status poll every 200 ms ends the session about
once in 9 hours instead of every 5 minutes with 5 retries; one busy for good is given up
within the time a push has anyway."""
_warned_insecure: set[tuple[str, str]] = set()

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
    "BadNodeIdUnknown": "no such node on the controller: its server does not resolve the "
                        "path (a SINUMERIK's resolves /Plc/DB<n>.DBD<x>:[k]; check "
                        "window_node / sd_nodes and that the data block exists)",
    "BadOutOfRange": "outside the controller's data block (window larger than the DB?)",
    "BadTypeMismatch": "the node holds another type than UInt32 words",
    "BadSecurityPolicyRejected": "the server does not offer this security policy",
    "BadCertificateUntrusted": "the controller does not trust the center's certificate "
                               "(add it to the controller's trusted clients: GET "
                               "/api/opcua/certificate)",
    "BadSecurityChecksFailed": "the secure channel was refused (does the controller trust "
                               "the center's certificate? GET /api/opcua/certificate)",
    "BadResourceUnavailable": "the controller is busy",
    "BadRequestTooLarge": "the controller takes smaller writes (an S7-300-class PLC: set "
                          "the link's plc_class s7-300)",
    "BadTimeout": "the controller timed out",
}


def read_password(ref: str, user: str) -> str:
    """The password ``ref`` points at (``env:NAME`` or ``file:/path``; a file's trailing
    newline dropped); raises :class:`LinkError` naming what is missing."""
    kind, _, where = ref.partition(":")
    if kind == "env":
        value = os.environ.get(where)
        if value is None:
            raise LinkError(f"password of OPC UA user {user!r}: environment variable "
                            f"{where} is not set", state="refused", reason="password_ref")
        return value
    if kind == "file":
        try:
            return Path(where).read_text(encoding="utf-8").rstrip("\r\n")
        except (OSError, UnicodeDecodeError) as e:
            raise LinkError(f"password of OPC UA user {user!r}: cannot read {where} "
                            f"({e.__class__.__name__})", state="refused",
                            reason="password_ref") from None
    raise LinkError(f"password of OPC UA user {user!r}: reference {ref!r} is neither "
                    "env:NAME nor file:/path", state="refused", reason="password_ref")


def _mode(mode: str) -> ua.MessageSecurityMode:
    return (ua.MessageSecurityMode.Sign if mode == "Sign"
            else ua.MessageSecurityMode.SignAndEncrypt)


async def secure_client(client: Client, endpoint: str, *, mode: str = "SignAndEncrypt",
                        trust: TrustMode = "first_use", pki: Pki | None = None,
                        certificate: str | None = None, private_key: str | None = None
                        ) -> tuple[bool, list[str]]:
    """Set Basic256Sha256 ``mode`` (``Sign`` or ``SignAndEncrypt``) on an asyncua
    ``client`` before its ``connect()``: the center's certificate from ``pki`` (or the
    ``certificate`` and ``private_key`` files), the controller's the one kept for
    ``endpoint`` or, at first use, fetched from its endpoint list and checked
    (:meth:`Pki.check_server`). Any OPC UA link of the center can use it (the window
    link here; a link writing setting data too).

    Returns
    -------
    pinned : bool
        The controller's certificate was the kept one (not fetched now): a failed login
        may mean it changed (:func:`recheck_certificate`).
    notices : list of str
        Warnings for the operator (a certificate trusted on first use).

    Raises
    ------
    LinkError
        The certificate files cannot be read, the controller offers no such endpoint, or
        its certificate is not trusted.
    """
    pki = pki if pki is not None else pki_at()
    policy = security_policies.SecurityPolicyBasic256Sha256
    if certificate is not None and private_key is not None:
        try:
            cert = await uacrypto.load_certificate(certificate)
            key = await uacrypto.load_private_key(private_key)
        except (OSError, ValueError) as e:
            raise LinkError(f"{endpoint}: client_certificate or client_private_key cannot "
                            f"be read ({e.__class__.__name__})",
                            reason="center_certificate") from None
    else:
        # made or read once per process (a thread: 0.1-1 s of key generation, once)
        identity = await asyncio.to_thread(pki.identity) if pki.pending else pki.identity()
        cert, key = identity.certificate, identity.private_key
    client.application_uri = CENTER_URI  # as in the certificate
    notices: list[str] = []
    server_der = pki.known(endpoint, trust)
    pinned = server_der is not None
    if server_der is None:
        server_der = await _server_certificate(client, endpoint, mode, policy.URI)
        if await asyncio.to_thread(pki.check_server, endpoint, server_der, trust):
            text = (f"{endpoint}: the controller's certificate (thumbprint "
                    f"{thumbprint(server_der)}) trusted on first use")
            notices.append(text)
            log.warning("%s", text)
    sp = policy(server_der, cert, key, _mode(mode))  # type: ignore[no-untyped-call]
    client.security_policy = sp  # type: ignore[assignment]
    client.uaclient.set_security(sp)
    return pinned, notices


async def _server_certificate(client: Client, endpoint: str, mode: str, uri: str) -> bytes:
    """The controller's certificate from its endpoint list (GetEndpoints over an
    unsecured channel, as every OPC UA client first does)."""
    endpoints = await client.connect_and_get_server_endpoints()
    offered = [e for e in endpoints if e.SecurityPolicyUri == uri
               and e.SecurityMode == _mode(mode)]
    if not offered or not offered[0].ServerCertificate:
        have = ", ".join(sorted({f"{e.SecurityPolicyUri.rsplit('#', 1)[-1]} "
                                 f"{e.SecurityMode.name.rstrip('_')}" for e in endpoints}))
        raise LinkError(f"{endpoint}: the controller does not offer Basic256Sha256 {mode} "
                        f"(it offers {have or 'nothing'}): enable it on the controller, or "
                        "set the link's security_mode", state="refused", reason="security")
    der = uacrypto.x509_from_der(  # type: ignore[no-untyped-call]
        offered[0].ServerCertificate)  # the first of a chain
    return bytes(der.public_bytes(serialization.Encoding.DER))


async def recheck_certificate(endpoint: str, *, mode: str = "SignAndEncrypt",
                              trust: TrustMode = "first_use", pki: Pki | None = None,
                              timeout_s: float = 5.0) -> bool:
    """After a failed login with the certificate kept for ``endpoint``: raise the trust
    store's refusal (:class:`LinkError`) if the controller now shows another one; True
    if it shows another that is trusted (the operator put it into the trust list: log in
    again), False if the certificate is not the reason."""
    pki = pki if pki is not None else pki_at()
    pinned = pki.pinned(endpoint)
    probe = Client(endpoint, timeout=timeout_s)
    try:
        async with asyncio.timeout(timeout_s):
            der = await _server_certificate(
                probe, endpoint, mode, security_policies.SecurityPolicyBasic256Sha256.URI)
    except Exception:  # the first error stands
        return False
    finally:
        probe.disconnect_socket()
    return await asyncio.to_thread(pki.check_server, endpoint, der, trust) or der != pinned


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


class _Transient(Exception):
    """A busy answer (:data:`TRANSIENT`): ask again after a while; ``error`` if not."""

    def __init__(self, error: LinkError) -> None:
        super().__init__(str(error))
        self.text = str(error)
        self.error = error


def _jittered(delay_s: float) -> float:
    return delay_s * (1.0 + 0.5 * random.random())


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
        # None in either is no security (the other then is its default, or None too)
        insecure = "None" in (security_policy, security_mode)
        if security_policy not in ("None", "Basic256Sha256") \
                or security_mode not in ("None", "Sign", "SignAndEncrypt") \
                or (security_policy == "None" and security_mode == "Sign"):
            raise LinkError(f"security policy {security_policy} with mode {security_mode}: "
                            "Basic256Sha256 with Sign or SignAndEncrypt, or None")
        if (client_certificate is None) != (client_private_key is None):
            raise LinkError("client_certificate and client_private_key go together")
        self.endpoint = endpoint
        self.user = user
        self.password_ref = password_ref
        self._password = password
        self.window_node = window_node
        self._ns = int(m.group(1))
        self._db = m.group(2)
        self.security_policy = "None" if insecure else security_policy
        self.security_mode = "None" if insecure else security_mode
        self.trust: TrustMode = trust
        self._pki = pki
        self.client_certificate = client_certificate
        self.client_private_key = client_private_key
        self.sd_nodes = dict(sd_nodes or {})
        self.timeout_s = float(timeout_s)
        self.block = block
        self.retry_delays_s = tuple(retry_delays_s)
        self.busy_retries = 0
        """Requests asked again after a transient answer (the window session shows the
        link busy while this grows)."""
        self.busy_note = ""
        """The last transient answer, for the operator."""
        self._notices: list[str] = []
        self._client: Client | None = None
        if insecure and (endpoint, user) not in _warned_insecure:
            # once per controller, user and process: the link's task makes a memory per
            # attempt to connect, and a warning per attempt would be a storm of events
            _warned_insecure.add((endpoint, user))
            text = (f"{endpoint}: OPC UA security None: the password of user {user!r} "
                    "crosses the network in clear text; set the link's security_policy "
                    "Basic256Sha256 (the default)")
            self._notices.append(text)
            log.warning("%s", text)

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

    @property
    def insecure(self) -> bool:
        """Security policy None: the password travels in clear."""
        return self.security_policy == "None"

    def take_notices(self) -> list[str]:
        """Warnings for the operator gathered since the last call (security None, a
        controller certificate trusted on first use), each once."""
        out, self._notices = self._notices, []
        return out

    @property
    def pki(self) -> Pki:
        if self._pki is None:
            self._pki = pki_at()
        return self._pki

    # -- connection

    async def connect(self) -> None:
        """Open a session as :attr:`user`; raises :class:`LinkError`.

        A controller answering ``BadTooManySessions`` (or busy) is asked again, within
        the retry budget: a SINUMERIK frees a session that was never activated."""
        await self.close()
        password = (self._password if self._password is not None
                    else read_password(self.password_ref, self.user))
        for attempt in range(len(self.retry_delays_s) + 1):
            try:
                self._client = await self._connect_once(password)
                return
            except _Transient as e:
                if attempt == len(self.retry_delays_s):
                    raise e.error from None
                self.busy_retries += 1
                self.busy_note = e.text
                await asyncio.sleep(_jittered(self.retry_delays_s[attempt]))

    async def _connect_once(self, password: str) -> Client:
        # no asyncua watchdog: it reads the server state every interval and drops the
        # connection on any error, a busy answer (BadResourceUnavailable) included, which
        # is exactly what must not end a session here. The window session's status polls
        # keep the session alive and find a dead connection within timeout_s.
        client = Client(self.endpoint, timeout=self.timeout_s, watchdog_intervall=86_400.0)
        client.session_timeout = 60_000  # the SINUMERIK's; it revises longer ones to this
        client.set_user(self.user)
        client.set_password(password)
        pinned = False
        try:
            async with asyncio.timeout(self.timeout_s * 2):
                if not self.insecure:
                    pinned = await self._secure(client)
                await client.connect()
        except LinkError:
            client.disconnect_socket()
            raise
        except Exception as e:  # asyncua raises many kinds; each becomes one clear line
            client.disconnect_socket()
            name = _status_name(e)
            if pinned and name not in TRANSIENT | {"BadUserAccessDenied"} \
                    and await self._recheck_certificate():
                # the kept certificate is not the controller's any more, and its new one
                # is trusted (the refusal of an untrusted one was raised): again with it
                raise _Transient(LinkError(f"{self.endpoint}: the controller's certificate "
                                           "was renewed", transient=True)) from None
            if name in TRANSIENT:
                raise _Transient(self._login_error(e)) from None
            raise self._login_error(e) from None
        return client

    async def _secure(self, client: Client) -> bool:
        """Set Basic256Sha256 on ``client``; returns whether the controller's certificate
        was the one kept for this endpoint (not fetched and checked now)."""
        pinned, notices = await secure_client(
            client, self.endpoint, mode=self.security_mode, trust=self.trust, pki=self.pki,
            certificate=self.client_certificate, private_key=self.client_private_key)
        self._notices += notices
        return pinned

    async def _recheck_certificate(self) -> bool:
        return await recheck_certificate(self.endpoint, mode=self.security_mode,
                                         trust=self.trust, pki=self.pki,
                                         timeout_s=self.timeout_s)

    def _login_error(self, e: BaseException) -> LinkError:
        """A failed login as a classified :class:`LinkError` (state and reason for the
        operator: a status code's name is its reason)."""
        name = _status_name(e)
        where = self.endpoint
        if name == "BadUserAccessDenied":
            return LinkError(f"{where}: login as {self.user!r} refused (BadUserAccessDenied): "
                             "wrong user or password", state="refused", reason="login")
        if name in TRANSIENT:
            return LinkError(f"{where}: {_HINTS.get(name, 'busy')} ({name})", state="failed",
                             reason=name, transient=True)
        if name is not None:
            return LinkError(f"{where}: {_HINTS.get(name, 'refused')} ({name})",
                             state="refused", reason=name)
        if isinstance(e, TimeoutError):
            return LinkError(f"{where}: no answer within {self.timeout_s * 2:g} s",
                             state="unreachable", reason="no_answer")
        if isinstance(e, OSError):
            return LinkError(f"{where}: cannot connect ({e.strerror or e.__class__.__name__})",
                             state="unreachable", reason="connect")
        return LinkError(f"{where}: {e.__class__.__name__}: {e}", reason="login_failed")

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
            raise LinkError(f"{self.endpoint}: not connected", state="unreachable",
                            reason="connection_lost")
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

    async def _call(self, request: Callable[[], Awaitable[Any]], what: str, offset: int,
                    size: int, codes: Callable[[Any], list[ua.StatusCode | None]]) -> Any:
        """``request()``'s answer, asked again while the controller answers busy (the
        whole service, or any node of it, with a :data:`TRANSIENT` code: a read or a
        write of the same bytes is safe to repeat), at most ``len(retry_delays_s)``
        times."""
        for attempt in range(len(self.retry_delays_s) + 1):
            last = attempt == len(self.retry_delays_s)
            try:
                answer = await self._call_once(request, what, offset, size)
            except _Transient as e:
                if last:
                    raise e.error from None
                self.busy_note = e.text
            else:
                busy = [c.name for c in codes(answer) if c is not None and c.name in TRANSIENT]
                if not busy or last:
                    return answer
                self.busy_note = str(self._refused(busy[0], what, offset, size))
            self.busy_retries += 1
            await asyncio.sleep(_jittered(self.retry_delays_s[attempt]))
        raise AssertionError("unreachable")  # the last attempt returned or raised

    async def _call_once(self, request: Callable[[], Awaitable[Any]], what: str, offset: int,
                         size: int) -> Any:
        try:
            async with asyncio.timeout(self.timeout_s):
                return await request()
        except LinkError:
            raise
        except Exception as e:
            name = _status_name(e)
            if name in TRANSIENT:
                raise _Transient(self._refused(name, what, offset, size)) from None
            if name is not None:
                raise self._refused(name, what, offset, size) from None
            if isinstance(e, TimeoutError):
                raise LinkError(f"{self.endpoint}: {what} of {self._db} byte {offset}: no "
                                f"answer within {self.timeout_s:g} s", state="unreachable",
                                reason="no_answer") from None
            raise LinkError(f"{self.endpoint}: {what} of {self._db} byte {offset}: "
                            f"connection lost ({e.__class__.__name__})", state="unreachable",
                            reason="connection_lost") from None

    def _good(self, code: ua.StatusCode | None, what: str, offset: int, size: int) -> None:
        if code is not None and not code.is_good():
            raise self._refused(code.name, what, offset, size)

    def _refused(self, name: str, what: str, offset: int, size: int) -> LinkError:
        """A request answered with status ``name``, classified: a missing right and the
        controller's other refusals are ``refused``, busy answers ``failed`` and
        transient."""
        where = f"{self.endpoint}: {what} of {self._db} bytes {offset}..{offset + size - 1}"
        if name == "BadUserAccessDenied":
            right = "PlcWrite" if what == "write" else "SinuReadAll"
            return LinkError(f"{where}: user {self.user!r} lacks {right} "
                             "(BadUserAccessDenied)", state="refused", reason="rights")
        busy = name in TRANSIENT
        return LinkError(f"{where}: {_HINTS.get(name, 'refused')} ({name})",
                         state="failed" if busy else "refused", reason=name, transient=busy)

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
                    name = dv.StatusCode.name
                    hint = (f"user {self.user!r} lacks SinuReadAll"
                            if name == "BadUserAccessDenied" else _HINTS.get(name, "refused"))
                    raise LinkError(f"{self.endpoint}: read of {node}: {hint} ({name})",
                                    state="refused",
                                    reason="rights" if name == "BadUserAccessDenied" else name)
                v = dv.Value.Value if dv.Value is not None else None
                if not isinstance(v, (int, float)) or isinstance(v, bool):
                    raise LinkError(f"{self.endpoint}: {node} holds {type(v).__name__}, "
                                    "not a number")
                got.append(float(v))
            out[axis] = AxisReading(*got)
        return out
