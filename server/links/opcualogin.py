"""Logging in to a SINUMERIK's OPC UA server, and what its failures mean, for every OPC UA link.

Two links talk OPC UA to a SINUMERIK: the window link (:mod:`server.links.opcua`, the PLC
data block holding the map window) and the native link (:mod:`server.links.sinumerik_sd`,
the NC's temperature compensation setting data). They log in the same way and must fail
the same way, so that a plant engineer who mistypes a password, runs a controller that
does not trust the center or gives a wrong node sees the same state and reason
(:mod:`server.links.state`) whichever link the machine has:

============================================== =========== ==========================
failure                                        state       reason
============================================== =========== ==========================
wrong user or password                         refused     ``login``
password reference not set                     refused     ``password_ref``
no Basic256Sha256 endpoint of the mode asked   refused     ``security``
controller's certificate changed / not listed  refused     ``server_certificate``
the controller refuses the center's            refused     ``BadCertificateUntrusted``
certificate, or another status code            refused     the status code's name
a user without the right for a request         refused     ``rights``
no such node                                   refused     ``BadNodeIdUnknown``
busy (:data:`TRANSIENT`), retried first        failed      the status code's name
nothing listens (connection refused, no route) unreachable ``connect``
nothing answers in time                        unreachable ``no_answer``
the connection dropped during a request        unreachable ``connection_lost``
============================================== =========== ==========================

Here: the channel's security (:class:`OpcuaSecurity`, :func:`secure_client`), one login
with its retries on busy answers (:func:`open_session`) and its end (:func:`close_client`),
what both links' clients hold (:class:`OpcuaClient`: the session, the operator's
warnings), and the classification of a failed login (:func:`login_error`), of a failed request
(:func:`request_error`) and of a node's bad status (:func:`status_error`).
"""

from __future__ import annotations

import asyncio
import logging
import random
from collections.abc import Awaitable, Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

from asyncua import ua
from asyncua.client.client import Client
from asyncua.crypto import security_policies, uacrypto
from cryptography.hazmat.primitives import serialization

from server.links.opcuapki import CENTER_URI, Pki, TrustMode, pki_at, thumbprint
from server.links.window.memory import LinkError

if TYPE_CHECKING:
    from server.schemas.link import OpcuaLogin

__all__ = ["HINTS", "RETRY_DELAYS_S", "TRANSIENT", "OpcuaClient", "OpcuaSecurity", "close_client",
           "jittered", "login_error", "open_session", "recheck_certificate",
           "request_error", "secure_client", "status_error", "status_name"]

log = logging.getLogger(__name__)

TRANSIENT: Final = frozenset({"BadTooManySessions", "BadResourceUnavailable", "BadTimeout"})
"""Answers that mean "busy, ask again": retried, not a reason to end the session."""
RETRY_DELAYS_S: Final = (0.05, 0.1, 0.2, 0.4, 0.8, 0.8, 0.8, 0.8, 0.8)
"""Waits before the retries of one request: 9 retries over 4.75 s (up to 1.5x with the
jitter, so a fleet does not retry in step). A controller busy for 30 % of its answers
fails one request in 0.3^10 = 6e-6: a status poll every 200 ms ends the session about
once in 9 hours instead of every 5 minutes with 5 retries; one busy for good is given up
within the time a push has anyway."""
HINTS: Final = {
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
"""What a status code asks the operator to fix (a link adds its own for its nodes)."""

_warned_insecure: set[tuple[str, str]] = set()


def status_name(e: BaseException) -> str | None:
    """The OPC UA status code's name an asyncua exception carries (None: not an answer)."""
    code = getattr(e, "code", None)
    if isinstance(code, int):
        return ua.StatusCode(ua.UInt32(code)).name
    return None


def jittered(delay_s: float) -> float:
    """``delay_s`` stretched by up to half at random (a fleet does not retry in step)."""
    return delay_s * (1.0 + 0.5 * random.random())


@dataclass(frozen=True, slots=True)
class OpcuaSecurity:
    """How an OPC UA link secures its channel (the link's security fields).

    Attributes
    ----------
    policy, mode : str
        ``Basic256Sha256`` with ``SignAndEncrypt`` (the default) or ``Sign``; ``None`` in
        either (and nothing else in the other) is no security at all: the password in
        clear. Normalised: both ``None`` then.
    trust : {"first_use", "list"}
        How the controller's certificate is trusted (:mod:`server.links.opcuapki`).
    certificate, private_key : str, optional
        Another application certificate and key (files) than the center's own, both or
        neither.

    Raises
    ------
    LinkError
        A combination that is not one of those.
    """

    policy: str = "Basic256Sha256"
    mode: str = "SignAndEncrypt"
    trust: TrustMode = "first_use"
    certificate: str | None = None
    private_key: str | None = None

    def __post_init__(self) -> None:
        if self.policy not in ("None", "Basic256Sha256") \
                or self.mode not in ("None", "Sign", "SignAndEncrypt") \
                or (self.policy == "None" and self.mode == "Sign"):
            raise LinkError(f"security policy {self.policy} with mode {self.mode}: "
                            "Basic256Sha256 with Sign or SignAndEncrypt, or None")
        if (self.certificate is None) != (self.private_key is None):
            raise LinkError("client_certificate and client_private_key go together")
        if "None" in (self.policy, self.mode):  # None in either is no security
            object.__setattr__(self, "policy", "None")
            object.__setattr__(self, "mode", "None")

    @classmethod
    def of(cls, link: OpcuaLogin) -> OpcuaSecurity:
        """The security a registration's link asks for."""
        return cls(link.security_policy, link.security_mode, link.trust,
                   link.client_certificate, link.client_private_key)

    @property
    def insecure(self) -> bool:
        """Security policy None: the password travels in clear."""
        return self.policy == "None"

    def notice(self, endpoint: str, user: str) -> str | None:
        """The warning an insecure link owes its operator, once per controller, user and
        process (a link makes a session per attempt to connect, and a warning per attempt
        would be a storm of events); logged. None: nothing (more) to say."""
        if not self.insecure or (endpoint, user) in _warned_insecure:
            return None
        _warned_insecure.add((endpoint, user))
        text = (f"{endpoint}: OPC UA security None: the password of user {user!r} crosses "
                "the network in clear text; set the link's security_policy Basic256Sha256 "
                "(the default)")
        log.warning("%s", text)
        return text


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
    (:meth:`Pki.check_server`).

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


def login_error(e: BaseException, endpoint: str, user: str, waited_s: float) -> LinkError:
    """A failed login (any exception asyncua raised, ``waited_s`` the time allowed) as a
    classified :class:`LinkError` (module docstring's table: a status code's name is its
    reason)."""
    name = status_name(e)
    if name == "BadUserAccessDenied":
        return LinkError(f"{endpoint}: login as {user!r} refused (BadUserAccessDenied): "
                         "wrong user or password", state="refused", reason="login")
    if name in TRANSIENT:
        return LinkError(f"{endpoint}: {HINTS.get(name, 'busy')} ({name})", state="failed",
                         reason=name, transient=True)
    if name is not None:
        return LinkError(f"{endpoint}: {HINTS.get(name, 'refused')} ({name})",
                         state="refused", reason=name)
    if isinstance(e, TimeoutError):
        return LinkError(f"{endpoint}: no answer within {waited_s:g} s",
                         state="unreachable", reason="no_answer")
    if isinstance(e, OSError):
        return LinkError(f"{endpoint}: cannot connect ({e.strerror or e.__class__.__name__})",
                         state="unreachable", reason="connect")
    return LinkError(f"{endpoint}: {e.__class__.__name__}: {e}", reason="login_failed")


def status_error(name: str, where: str, *, user: str, right: str,
                 hints: Mapping[str, str] = HINTS) -> LinkError:
    """A request (or one node of it) answered with status ``name``, classified: a missing
    ``right`` of ``user`` (``BadUserAccessDenied``) is ``refused`` for ``rights``, a busy
    answer ``failed`` and transient, any other ``refused`` with the status as reason.
    ``where``: what was asked of which controller; ``hints``: what each status asks the
    operator to fix."""
    if name == "BadUserAccessDenied":
        return LinkError(f"{where}: user {user!r} lacks {right} (BadUserAccessDenied)",
                         state="refused", reason="rights")
    busy = name in TRANSIENT
    return LinkError(f"{where}: {hints.get(name, 'refused')} ({name})",
                     state="failed" if busy else "refused", reason=name, transient=busy)


def request_error(e: BaseException, where: str, waited_s: float, *, user: str, right: str,
                  hints: Mapping[str, str] = HINTS) -> LinkError:
    """A request that raised ``e`` (not answered within ``waited_s``, the connection
    lost, or refused as a whole) as a classified :class:`LinkError`."""
    if isinstance(e, LinkError):
        return e
    name = status_name(e)
    if name is not None:
        return status_error(name, where, user=user, right=right, hints=hints)
    if isinstance(e, TimeoutError):
        return LinkError(f"{where}: no answer within {waited_s:g} s", state="unreachable",
                         reason="no_answer")
    return LinkError(f"{where}: connection lost ({e.__class__.__name__})",
                     state="unreachable", reason="connection_lost")


async def _login(endpoint: str, user: str, password: str, security: OpcuaSecurity, pki: Pki,
                 timeout_s: float, notices: list[str]) -> Client:
    """One login; raises :class:`LinkError` (``transient``: worth trying again now)."""
    # no asyncua watchdog: it reads the server state every interval and drops the
    # connection on any error, a busy answer (BadResourceUnavailable) included, which is
    # exactly what must not end a session here. A link's own requests (the window's
    # status polls, the setting data's read-back) find a dead connection within timeout_s.
    client = Client(endpoint, timeout=timeout_s, watchdog_intervall=86_400.0)
    client.session_timeout = 60_000  # the SINUMERIK's; it revises longer ones to this
    client.set_user(user)
    client.set_password(password)
    pinned = False
    try:
        async with asyncio.timeout(timeout_s * 2):
            if not security.insecure:
                pinned, seen = await secure_client(
                    client, endpoint, mode=security.mode, trust=security.trust, pki=pki,
                    certificate=security.certificate, private_key=security.private_key)
                notices += seen
            await client.connect()
    except LinkError:
        client.disconnect_socket()
        raise
    except Exception as e:  # asyncua raises many kinds; each becomes one clear line
        client.disconnect_socket()
        name = status_name(e)
        if pinned and name not in TRANSIENT | {"BadUserAccessDenied"} \
                and await recheck_certificate(endpoint, mode=security.mode,
                                              trust=security.trust, pki=pki,
                                              timeout_s=timeout_s):
            # the kept certificate is not the controller's any more, and its new one is
            # trusted (the refusal of an untrusted one was raised): again with it
            raise LinkError(f"{endpoint}: the controller's certificate was renewed",
                            transient=True) from None
        raise login_error(e, endpoint, user, timeout_s * 2) from None
    return client


async def open_session(endpoint: str, user: str, password: str, *,
                       security: OpcuaSecurity | None = None, pki: Pki | None = None,
                       timeout_s: float = 5.0,
                       retry_delays_s: Sequence[float] = RETRY_DELAYS_S,
                       on_busy: Callable[[LinkError], None] | None = None,
                       notices: list[str] | None = None) -> Client:
    """A session with ``endpoint`` as ``user``, secured as ``security`` asks.

    A controller answering busy (``BadTooManySessions``: a SINUMERIK frees a session that
    was never activated) is asked again after each of ``retry_delays_s`` (jittered),
    ``on_busy`` told of each; only a failure that persists is raised.

    Parameters
    ----------
    security : OpcuaSecurity, optional
        Default: Basic256Sha256 SignAndEncrypt, the controller trusted on first use.
    notices : list of str, optional
        Where warnings for the operator go (a certificate trusted on first use).

    Raises
    ------
    LinkError
        Classified as the module docstring's table says.
    """
    security = security if security is not None else OpcuaSecurity()
    pki = pki if pki is not None else pki_at()
    notices = notices if notices is not None else []
    for attempt in range(len(retry_delays_s) + 1):
        try:
            return await _login(endpoint, user, password, security, pki, timeout_s, notices)
        except LinkError as e:
            if not e.transient or attempt == len(retry_delays_s):
                raise
            if on_busy is not None:
                on_busy(e)
            await asyncio.sleep(jittered(retry_delays_s[attempt]))
    raise AssertionError("unreachable")  # the last attempt returned or raised


async def close_client(client: Client | None, timeout_s: float) -> None:
    """End ``client``'s session politely within ``timeout_s``, its socket in any case
    (never raises)."""
    if client is None:
        return
    try:
        async with asyncio.timeout(timeout_s):
            await client.disconnect()
    except Exception:  # a dead connection has nothing to close politely
        pass
    finally:
        client.disconnect_socket()


class OpcuaClient:
    """What every OPC UA link's client holds: at most one session with one controller as
    one user, and the warnings for the operator gathered on the way. A link adds its
    requests (the window's bytes, the setting data).

    Parameters
    ----------
    endpoint : str
        ``opc.tcp://host:port``.
    user : str
    security : OpcuaSecurity, optional
        Default: Basic256Sha256 SignAndEncrypt, the controller trusted on first use.
        Security None is warned once per controller and user (:meth:`take_notices`).
    pki : Pki, optional
        The center's certificates (default: :func:`~server.links.opcuapki.pki_at`).
    timeout_s : float
        Per request; the login may take twice this.
    retry_delays_s : sequence of float
        Waits before each new try of a request (or login) answered busy.
    """

    def __init__(self, endpoint: str, user: str, *, security: OpcuaSecurity | None = None,
                 pki: Pki | None = None, timeout_s: float = 5.0,
                 retry_delays_s: Sequence[float] = RETRY_DELAYS_S) -> None:
        self.endpoint = endpoint
        self.user = user
        self.security = security if security is not None else OpcuaSecurity()
        self._pki = pki
        self.timeout_s = float(timeout_s)
        self.retry_delays_s = tuple(retry_delays_s)
        self._client: Client | None = None
        self._notices: list[str] = []
        notice = self.security.notice(endpoint, user)
        if notice is not None:
            self._notices.append(notice)

    @property
    def pki(self) -> Pki:
        if self._pki is None:
            self._pki = pki_at()
        return self._pki

    @property
    def insecure(self) -> bool:
        """Security policy None: the password travels in clear."""
        return self.security.insecure

    def take_notices(self) -> list[str]:
        """Warnings for the operator gathered since the last call (security None, a
        controller certificate trusted on first use), each once."""
        out, self._notices = self._notices, []
        return out

    async def _open(self, password: str,
                    on_busy: Callable[[LinkError], None] | None = None) -> None:
        """Open the session (closing any before; :func:`open_session`)."""
        await self.close()
        self._client = await open_session(
            self.endpoint, self.user, password, security=self.security, pki=self.pki,
            timeout_s=self.timeout_s, retry_delays_s=self.retry_delays_s, on_busy=on_busy,
            notices=self._notices)

    async def close(self) -> None:
        """End the session (never raises)."""
        client, self._client = self._client, None
        await close_client(client, self.timeout_s)

    def _session(self) -> Client:
        if self._client is None:
            raise LinkError(f"{self.endpoint}: not connected", state="unreachable",
                            reason="connection_lost")
        return self._client

    async def _ask(self, request: Callable[[], Awaitable[Any]], where: str, right: str,
                   hints: Mapping[str, str] = HINTS) -> Any:
        """``request()``'s answer within :attr:`timeout_s`; raises the classified
        :class:`LinkError` (:func:`request_error`: ``where`` says what was asked, ``right``
        what a user refused lacks)."""
        try:
            async with asyncio.timeout(self.timeout_s):
                return await request()
        except Exception as e:  # asyncua raises many kinds; each becomes one clear line
            raise request_error(e, where, self.timeout_s, user=self.user, right=right,
                                hints=hints) from None
