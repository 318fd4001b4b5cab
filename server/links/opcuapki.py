"""The center's OPC UA certificates: its own application instance certificate and the
controllers' certificates it trusts.

OPC UA secures a channel (Basic256Sha256, Sign or SignAndEncrypt) with one certificate
per application: the center proves itself with its own, and checks the controller's. A
folder holds both sides (the layout of the OPC Foundation's reference stacks, flattened):

``own/center.der``, ``own/center.key.pem``
    The center's certificate (self-signed, RSA 2048, SHA-256, 10 years) and private key
    (mode 0600), made on first use and kept: the controller's operator trusts it once
    (on a SINUMERIK: copy ``center.der`` into the OPC UA server's trusted clients, or
    accept it in the HMI's certificate dialog); :func:`thumbprint` of it is what
    ``ednc serve`` prints and ``GET /api/opcua/certificate`` returns, so the operator
    can compare before trusting.
``trusted/``
    Controller certificates (DER or PEM, any file name) the operator trusts explicitly.
``servers/``
    Controller certificates trusted on first use: the first certificate seen at an
    endpoint is kept here (``<host>_<port>.der``) and from then on only that one is
    accepted there. A controller whose certificate changed is refused until the operator
    deletes the kept file or puts the new certificate into ``trusted/``.
``rejected/``
    Certificates refused (a changed one, or one not in the trust list): the operator can
    look at one and move it into ``trusted/``.

A link chooses ``trust: first_use`` (the default) or ``list`` (only ``trusted/``).

Where the folder is: ``EDNC_OPCUA_PKI_DIR``, else ``$XDG_DATA_HOME/ednc/opcua-pki``
(``~/.local/share/ednc/opcua-pki``). One :class:`Pki` per folder and process
(:func:`pki_at`); its certificate and key are read or made once and kept in memory, so
100 sessions cost no key generation and no file reads after the first.
"""

from __future__ import annotations

import datetime
import functools
import hashlib
import logging
import os
import re
import socket
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Final, Literal

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import rsa
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from server.links.window.memory import LinkError

__all__ = ["CENTER_URI", "PKI_ENV", "CenterIdentity", "Pki", "TrustMode", "certificate_line",
           "default_pki_dir", "pki_at", "sha256_fingerprint", "thumbprint"]

log = logging.getLogger(__name__)

PKI_ENV: Final = "EDNC_OPCUA_PKI_DIR"
CENTER_URI: Final = "urn:ednc:center"
"""The center's ApplicationUri: in its certificate's subjectAltName, as OPC UA requires
(a server compares it with the ApplicationDescription the client sends)."""
VALID_DAYS: Final = 3650
"""The center's certificate lives 10 years: renewing means every controller's operator
trusts the new one, which a plant does not want yearly."""

TrustMode = Literal["first_use", "list"]


def thumbprint(der: bytes) -> str:
    """The certificate's thumbprint as OPC UA shows it (SHA-1 of the DER bytes, hex,
    upper case): what a SINUMERIK's certificate dialog lists."""
    return hashlib.sha1(der).hexdigest().upper()


def sha256_fingerprint(der: bytes) -> str:
    """SHA-256 of the DER bytes, ``AB:CD:...`` (what ``openssl x509 -fingerprint
    -sha256`` prints)."""
    h = hashlib.sha256(der).hexdigest().upper()
    return ":".join(h[i:i + 2] for i in range(0, len(h), 2))


def default_pki_dir() -> Path:
    """``EDNC_OPCUA_PKI_DIR``, else the user's data dir (module docstring)."""
    given = os.environ.get(PKI_ENV)
    if given:
        return Path(given)
    data = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(data) / "ednc" / "opcua-pki"


@dataclass(frozen=True, slots=True)
class CenterIdentity:
    """The center's certificate and key, loaded.

    Attributes
    ----------
    certificate : x509.Certificate
    private_key : rsa.RSAPrivateKey
    der : bytes
        The certificate, DER (what goes on the wire).
    path : Path
        Where the certificate is (DER), for the operator to copy.
    created : bool
        Made by this process (first start).
    """

    certificate: x509.Certificate
    private_key: rsa.RSAPrivateKey
    der: bytes
    path: Path
    created: bool

    @property
    def thumbprint(self) -> str:
        return thumbprint(self.der)


def _make_certificate(uri: str, host: str) -> tuple[rsa.RSAPrivateKey, x509.Certificate]:
    """A self-signed application instance certificate (OPC 10000-6 §6.2.2: the URI and
    host in subjectAltName, digital signature, key and data encipherment, client and
    server authentication)."""
    key = rsa.generate_private_key(public_exponent=65537, key_size=2048)
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, f"EDNC center@{host}"),
                      x509.NameAttribute(NameOID.ORGANIZATION_NAME, "EDNC")])
    now = datetime.datetime.now(datetime.UTC)
    cert = (x509.CertificateBuilder().subject_name(name).issuer_name(name)
            .public_key(key.public_key()).serial_number(x509.random_serial_number())
            .not_valid_before(now - datetime.timedelta(days=1))
            .not_valid_after(now + datetime.timedelta(days=VALID_DAYS))
            .add_extension(x509.SubjectAlternativeName(
                [x509.UniformResourceIdentifier(uri), x509.DNSName(host)]), critical=False)
            .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()),
                           critical=False)
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.KeyUsage(
                digital_signature=True, content_commitment=True, key_encipherment=True,
                data_encipherment=True, key_agreement=False, key_cert_sign=False,
                crl_sign=False, encipher_only=False, decipher_only=False), critical=True)
            .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.CLIENT_AUTH,
                                                  ExtendedKeyUsageOID.SERVER_AUTH]),
                           critical=False)
            .sign(key, hashes.SHA256()))
    return key, cert


def _load_any(data: bytes) -> x509.Certificate | None:
    try:
        if data.lstrip().startswith(b"-----BEGIN"):
            return x509.load_pem_x509_certificate(data)
        return x509.load_der_x509_certificate(data)
    except ValueError:
        return None


def _endpoint_file(endpoint: str) -> str:
    """``opc.tcp://10.0.3.18:4840/x`` -> ``10.0.3.18_4840`` (a safe file name)."""
    where = endpoint.removeprefix("opc.tcp://").split("/", 1)[0]
    return re.sub(r"[^A-Za-z0-9.\-]", "_", where)


class Pki:
    """One PKI folder (module docstring). Use :func:`pki_at` for the shared instance."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self._lock = threading.Lock()
        self._identity: CenterIdentity | None = None
        self._trusted: tuple[float, frozenset[bytes]] | None = None

    @property
    def own_dir(self) -> Path:
        return self.root / "own"

    @property
    def trusted_dir(self) -> Path:
        return self.root / "trusted"

    @property
    def servers_dir(self) -> Path:
        return self.root / "servers"

    @property
    def rejected_dir(self) -> Path:
        return self.root / "rejected"

    # -- the center's own

    @property
    def pending(self) -> bool:
        """The certificate is not loaded yet (the next :meth:`identity` reads or makes
        it)."""
        return self._identity is None

    def identity(self) -> CenterIdentity:
        """The center's certificate and key: read once, or made (and kept) on first use.

        Raises
        ------
        LinkError
            The folder cannot be written, or holds a key or certificate that cannot be
            read (the text names the file).
        """
        with self._lock:  # two first sessions at once make one certificate, not two
            if self._identity is None:
                self._identity = self._load_or_make()
            return self._identity

    def _load_or_make(self) -> CenterIdentity:
        cert_path, key_path = self.own_dir / "center.der", self.own_dir / "center.key.pem"
        if cert_path.exists() and key_path.exists():
            try:
                key = serialization.load_pem_private_key(key_path.read_bytes(), None)
                der = cert_path.read_bytes()
                cert = x509.load_der_x509_certificate(der)
            except (OSError, ValueError, TypeError) as e:
                raise LinkError(f"the center's OPC UA certificate in {self.own_dir} cannot "
                                f"be read ({e.__class__.__name__}): move the folder away "
                                "to make a new one (controllers must then trust it again)",
                                reason="center_certificate") from None
            if not isinstance(key, rsa.RSAPrivateKey):
                raise LinkError(f"{key_path}: not an RSA key", reason="center_certificate")
            return CenterIdentity(cert, key, der, cert_path, False)
        host = socket.gethostname() or "localhost"
        key, cert = _make_certificate(CENTER_URI, host)
        der = cert.public_bytes(serialization.Encoding.DER)
        try:
            self.own_dir.mkdir(parents=True, exist_ok=True)
            fd = os.open(key_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            with os.fdopen(fd, "wb") as f:
                f.write(key.private_bytes(serialization.Encoding.PEM,
                                          serialization.PrivateFormat.PKCS8,
                                          serialization.NoEncryption()))
            cert_path.write_bytes(der)
        except OSError as e:
            raise LinkError(f"cannot keep the center's OPC UA certificate in "
                            f"{self.own_dir}: {e.strerror}; set {PKI_ENV} to a writable "
                            "folder", reason="center_certificate") from None
        log.info("made the center's OPC UA certificate %s (thumbprint %s): add it to "
                    "each controller's trusted clients", cert_path, thumbprint(der))
        return CenterIdentity(cert, key, der, cert_path, True)

    # -- the controllers'

    def _trusted_set(self) -> frozenset[bytes]:
        """DER bytes of every certificate in ``trusted/``, read again when the folder
        changes (the operator adds one without restarting the center)."""
        try:
            stamp = self.trusted_dir.stat().st_mtime
        except OSError:
            return frozenset()
        if self._trusted is not None and self._trusted[0] == stamp:
            return self._trusted[1]
        out: set[bytes] = set()
        for p in sorted(self.trusted_dir.iterdir()):
            try:
                cert = _load_any(p.read_bytes()) if p.is_file() else None
            except OSError:
                cert = None
            if cert is not None:
                out.add(cert.public_bytes(serialization.Encoding.DER))
        self._trusted = (stamp, frozenset(out))
        return self._trusted[1]

    def pinned(self, endpoint: str) -> bytes | None:
        """The certificate kept for ``endpoint`` on first use (None: none yet)."""
        try:
            return (self.servers_dir / f"{_endpoint_file(endpoint)}.der").read_bytes()
        except OSError:
            return None

    def known(self, endpoint: str, trust: TrustMode) -> bytes | None:
        """A certificate already trusted for ``endpoint`` (pinned), to connect with
        without asking the server for its endpoints first; None: ask."""
        return self.pinned(endpoint) if trust == "first_use" else None

    def check_server(self, endpoint: str, der: bytes, trust: TrustMode) -> bool:
        """Whether ``der`` (the controller's certificate at ``endpoint``) is trusted;
        returns True when it was trusted just now, on first use (kept in ``servers/``).

        Raises
        ------
        LinkError
            Not trusted: not in ``trusted/`` (``trust="list"``), or another certificate
            than the one kept for this endpoint (``first_use``). The certificate goes to
            ``rejected/`` and the text says what to do.
        """
        print_ = thumbprint(der)
        if der in self._trusted_set():
            kept = self.pinned(endpoint)
            if kept is not None and kept != der:  # renewed and trusted by the operator:
                self._pin(endpoint, der)  # connect with it directly from now on
            return False
        if trust == "list":
            where = self._reject(endpoint, der)
            raise LinkError(f"{endpoint}: the controller's certificate (thumbprint "
                            f"{print_}) is not in the trust list {self.trusted_dir}; if it "
                            f"is the controller's, move {where} there", state="refused",
                            reason="server_certificate")
        kept = self.pinned(endpoint)
        if kept is not None:
            if kept == der:
                return False
            where = self._reject(endpoint, der)
            raise LinkError(
                f"{endpoint}: the controller's certificate changed (thumbprint {print_}, "
                f"trusted on first use: {thumbprint(kept)}); refused, it may be another "
                f"machine or an interception. If the controller's certificate was renewed, "
                f"move {where} into {self.trusted_dir} or delete "
                f"{self.servers_dir / (_endpoint_file(endpoint) + '.der')}",
                state="refused", reason="server_certificate")
        self._pin(endpoint, der)
        return True

    def _pin(self, endpoint: str, der: bytes) -> None:
        try:
            self.servers_dir.mkdir(parents=True, exist_ok=True)
            (self.servers_dir / f"{_endpoint_file(endpoint)}.der").write_bytes(der)
        except OSError as e:
            raise LinkError(f"{endpoint}: cannot keep the controller's certificate in "
                            f"{self.servers_dir}: {e.strerror}",
                            reason="server_certificate") from None

    def _reject(self, endpoint: str, der: bytes) -> Path:
        path = self.rejected_dir / f"{_endpoint_file(endpoint)}-{thumbprint(der)[:16]}.der"
        try:
            self.rejected_dir.mkdir(parents=True, exist_ok=True)
            path.write_bytes(der)
        except OSError:
            pass  # the refusal stands; only the copy for the operator is missing
        return path


def certificate_line(pki: Pki) -> str:
    """What ``ednc serve`` prints at start: where the center's certificate is and its
    thumbprint (made now on a first start); a problem is said instead."""
    try:
        identity = pki.identity()
    except LinkError as exc:
        return f"OPC UA: no certificate for secured links: {exc}"
    made = "made now: " if identity.created else ""
    return (f"OPC UA: the center's certificate {identity.path} ({made}thumbprint "
            f"{identity.thumbprint}); add it to each controller's trusted clients "
            "(GET /api/opcua/certificate)")


@functools.cache
def _pki(root: Path) -> Pki:
    return Pki(root)


def pki_at(root: Path | None = None) -> Pki:
    """The process's :class:`Pki` of ``root`` (None: :func:`default_pki_dir`)."""
    return _pki((root if root is not None else default_pki_dir()).resolve())
