"""Shared fixtures. Tests that need a real service use the one on loopback; when it is not
reachable they skip, except under CI (``EDNC_REQUIRE_SERVICES=1``) where they fail."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.browser import live_server  # noqa: F401  (fixture, by name)
from tests.support.data import unpack_real_data
from tests.support.db import database_url, postgres_url  # noqa: F401  (fixtures, by name)
from tests.support.services import reachable, require


@pytest.fixture(scope="session")
def real_data(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The directory holding tests/data's real measured files, unpacked and checked."""
    return unpack_real_data(tmp_path_factory.mktemp("real_data"))


@pytest.fixture
def mqtt_broker() -> tuple[str, int]:
    require("Mosquitto", reachable("127.0.0.1", 1883), "start it with "
            "`mosquitto -d -c /etc/mosquitto/mosquitto.conf`")
    return ("127.0.0.1", 1883)
