"""Shared fixtures. Tests that need a real service use the one on loopback; when it is not
reachable they skip, except under CI (``EDNC_REQUIRE_SERVICES=1``) where they fail."""

from __future__ import annotations

import os
import socket
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
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


@pytest.fixture
def shared_dir() -> Path:
    require("../shared", SHARED.is_dir(), f"expected the shared material at {SHARED}")
    return SHARED


@pytest.fixture
def mqtt_broker() -> tuple[str, int]:
    require("Mosquitto", reachable("127.0.0.1", 1883), "start it with "
            "`mosquitto -d -c /etc/mosquitto/mosquitto.conf`")
    return ("127.0.0.1", 1883)
