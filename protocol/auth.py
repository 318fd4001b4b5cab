"""Challenge-response authentication: an address alone does not let a machine in.

The center sends a fresh 32-byte random nonce; the machine answers with
``HMAC-SHA256(key=secret, msg=nonce ‖ UTF-8 machine name)`` (RFC 2104, FIPS 180-4).
Binding the name stops a response for one machine being replayed for another; a fresh
nonce per connection stops replay of an old response. The secret never crosses the wire.
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
from typing import Final

from .messages import NONCE_BYTES

MIN_SECRET_BYTES: Final = 16
"""128 bits: the least per-machine secret worth having against offline guessing."""


def new_nonce() -> bytes:
    """32 bytes from the operating system's CSPRNG, for one Challenge."""
    return secrets.token_bytes(NONCE_BYTES)


def compute_mac(secret: bytes, nonce: bytes, machine: str) -> bytes:
    """The 32-byte AuthResponse.mac a machine named ``machine`` sends for ``nonce``."""
    if len(secret) < MIN_SECRET_BYTES:
        raise ValueError(f"machine secret is {len(secret)} bytes, at least "
                         f"{MIN_SECRET_BYTES} needed")
    if len(nonce) != NONCE_BYTES:
        raise ValueError(f"nonce must be {NONCE_BYTES} bytes, got {len(nonce)}")
    return hmac.new(secret, nonce + machine.encode("utf-8"), hashlib.sha256).digest()


def verify_mac(secret: bytes, nonce: bytes, machine: str, mac: bytes) -> bool:
    """True when ``mac`` is right for this secret, nonce and machine (constant time)."""
    return hmac.compare_digest(compute_mac(secret, nonce, machine), mac)
