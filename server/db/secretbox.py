"""Machine secrets at rest: sealed with AES-256-GCM, opened only for the challenge.

Why encryption and not a hash: the center must compute HMAC(secret, nonce ‖ name) for
every login (protocol README §5), so it needs the secret itself; a hash (or a key derived
from the secret and stored instead of it) would be just as good a login credential as the
secret, so it would protect nothing. Sealing with a key kept outside the database means a
copy of the database (a backup, a dump, a stolen file) does not let anyone log in as a
machine.

A sealed value is ``aesgcm1:`` + base64url(12-byte nonce ‖ ciphertext ‖ 16-byte tag); the
machine's id is bound in as associated data, so a sealed secret copied onto another
machine's row does not open. A value without the prefix is a secret in clear text (written
before this existed, or by a tool that bypasses the API); it still opens, and
:func:`seal_all` seals it at start-up.

The key: ``EDNC_SECRET_KEY`` (any text of 16 bytes or more, stretched with HKDF-SHA256), or,
on SQLite without it, 32 random bytes in ``<database file>.key`` created with mode 0600
(a copy of the database file alone then opens nothing; whoever can read both files could
read the process's memory anyway). Without either (PostgreSQL and no key), secrets stay in
clear text and start-up says so.
"""

from __future__ import annotations

import base64
import logging
import os
import secrets
from pathlib import Path
from typing import Final

from cryptography.exceptions import InvalidTag
from cryptography.hazmat.primitives import hashes
from cryptography.hazmat.primitives.ciphers.aead import AESGCM
from cryptography.hazmat.primitives.kdf.hkdf import HKDF
from sqlalchemy import select
from sqlalchemy.orm import Session

from server.db.tables import MachineRow

log = logging.getLogger(__name__)

PREFIX: Final = "aesgcm1:"
_INFO: Final = b"ednc machine secrets v1"


class SecretKeyError(RuntimeError):
    """A sealed secret cannot be opened: no key, or not the key it was sealed with."""


class SecretBox:
    """Seals and opens machine secrets; ``SecretBox(None)`` keeps them in clear text."""

    def __init__(self, key: bytes | None) -> None:
        self._aead = AESGCM(key) if key is not None else None

    @classmethod
    def from_text(cls, text: str) -> SecretBox:
        """A box keyed by ``text`` (``EDNC_SECRET_KEY``), stretched with HKDF-SHA256."""
        key = HKDF(algorithm=hashes.SHA256(), length=32, salt=None,
                   info=_INFO).derive(text.encode("utf-8"))
        return cls(key)

    @classmethod
    def from_key_file(cls, path: Path) -> SecretBox:
        """A box keyed by the 32 bytes in ``path``, created (mode 0600) if missing."""
        if not path.exists():
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            with os.fdopen(fd, "wb") as f:
                f.write(secrets.token_bytes(32))
            log.info("machine secrets are sealed with a new key in %s", path)
        key = path.read_bytes()
        if len(key) != 32:
            raise SecretKeyError(f"{path}: a secret key file holds 32 bytes, this one "
                                 f"{len(key)}; set EDNC_SECRET_KEY or restore the file")
        return cls(key)

    @property
    def seals(self) -> bool:
        return self._aead is not None

    def seal(self, secret: str, machine_id: int) -> str:
        """The stored form of ``secret`` for machine ``machine_id``."""
        if self._aead is None:
            return secret
        nonce = secrets.token_bytes(12)
        sealed = self._aead.encrypt(nonce, secret.encode("utf-8"), _aad(machine_id))
        return PREFIX + base64.urlsafe_b64encode(nonce + sealed).decode("ascii")

    def open(self, stored: str, machine_id: int) -> str:
        """The secret from its stored form.

        Raises
        ------
        SecretKeyError
            Sealed, and this box has no key or another one.
        """
        if not stored.startswith(PREFIX):
            return stored
        if self._aead is None:
            raise SecretKeyError("machine secrets in the database are encrypted: set "
                                 "EDNC_SECRET_KEY to the key they were sealed with")
        try:
            raw = base64.urlsafe_b64decode(stored[len(PREFIX):].encode("ascii"))
            return self._aead.decrypt(raw[:12], raw[12:], _aad(machine_id)).decode("utf-8")
        except (InvalidTag, ValueError) as exc:
            raise SecretKeyError("a machine secret does not open with this EDNC_SECRET_KEY "
                                 "(not the key it was sealed with)") from exc


def _aad(machine_id: int) -> bytes:
    return f"machine:{machine_id}".encode()


def is_sealed(stored: str) -> bool:
    return stored.startswith(PREFIX)


def seal_all(session: Session, box: SecretBox) -> int:
    """Seal every secret stored in clear text, and check that the sealed ones open with
    ``box`` (a wrong key stops start-up rather than every login). Returns how many were
    sealed."""
    sealed = 0
    for row in session.scalars(select(MachineRow)):
        plain = box.open(row.secret, row.id)
        if box.seals and not is_sealed(row.secret):
            row.secret = box.seal(plain, row.id)
            sealed += 1
    return sealed
