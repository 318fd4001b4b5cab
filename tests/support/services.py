"""Real services on loopback (Mosquitto, PostgreSQL, Chromium): find them, or skip or fail.

A developer machine without a service skips the tests that need it; CI sets
``EDNC_REQUIRE_SERVICES=1`` and the same test fails instead, so a missing service can
never pass CI in silence.
"""

from __future__ import annotations

import os
import socket

import pytest

REQUIRE_SERVICES = os.environ.get("EDNC_REQUIRE_SERVICES") == "1"


def reachable(host: str, port: int, timeout: float = 0.5) -> bool:
    try:
        with socket.create_connection((host, port), timeout=timeout):
            return True
    except OSError:
        return False


def require(name: str, ok: bool, how: str) -> None:
    """Skip (developer machine) or fail (CI) when a real service is missing."""
    if ok:
        return
    message = f"{name} is not available: {how}"
    if REQUIRE_SERVICES:
        pytest.fail(message)
    pytest.skip(message)
