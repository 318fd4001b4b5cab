"""Shared fixtures. Tests that need a real service use the one on loopback; when it is not
reachable they skip, except under CI (``EDNC_REQUIRE_SERVICES=1``) where they fail."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.browser import live_server  # noqa: F401  (fixture, by name)
from tests.support.data import unpack_real_data
from tests.support.db import database_url, db, postgres_url  # noqa: F401  (fixtures, by name)
from tests.support.services import reachable, require


@pytest.fixture(scope="session", autouse=True)
def opcua_pki(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """The center's OPC UA certificate and trusted controllers, and the simulated NCs'
    certificate, in folders of this run (tests that need their own set them): the
    user's home keeps nothing from the tests, and a controller certificate trusted on
    first use by an earlier run cannot refuse this run's on a reused port."""
    root = tmp_path_factory.mktemp("opcua")
    names = {"EDNC_OPCUA_PKI_DIR": root / "center", "EDNC_SIM_PKI_DIR": root / "sim"}
    before = {k: os.environ.get(k) for k in names}
    os.environ.update({k: str(v) for k, v in names.items()})
    yield root
    for k, v in before.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.fixture(scope="session")
def real_data(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The directory holding tests/data's real measured files, unpacked and checked."""
    return unpack_real_data(tmp_path_factory.mktemp("real_data"))


@pytest.fixture
def mqtt_broker() -> tuple[str, int]:
    require("Mosquitto", reachable("127.0.0.1", 1883), "start it with "
            "`mosquitto -d -c /etc/mosquitto/mosquitto.conf`")
    return ("127.0.0.1", 1883)
