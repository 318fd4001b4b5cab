"""The error as sent of a machine's newest map (server/dashboard/mapcheck.py): the center
rebuilds the stored map the way the push built it and takes the build's report only when
the rebuild is the stored map, byte for byte."""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi import FastAPI

from server import mapcodec
from server.dashboard.mapcheck import checks_of
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.push.adapter import build_for
from server.settings import Settings
from tests.support.api import API_KEY, SECRET, VMC, WRITE, center_of, running
from tests.support.dashboard import MODEL, SIEMENS


@pytest.fixture
async def api(tmp_path: Path) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}", api_key=API_KEY)
    async with running(settings) as pair:
        yield pair


async def store(app: FastAPI, client: httpx.AsyncClient, description: dict[str, Any],
                tolerance_um: float) -> Any:
    """Register the machine and its model, store the map built at ``tolerance_um``."""
    name = description["name"]
    r = await client.post("/api/machines", json={**description, "secret": SECRET},
                          headers=WRITE)
    assert r.status_code == 201, r.text
    body = {**MODEL, "machine": name}
    r = await client.post(f"/api/machines/{name}/models", json={"body": body}, headers=WRITE)
    assert r.status_code == 201, r.text
    built = build_for(description, description["controller"], body, {}, tolerance_um)
    db = center_of(app).db
    row = await db.run(machine_repo.get_machine, name)
    assert row is not None
    await db.run(map_repo.add_map_version, row.id, model_version=1,
                 payload=mapcodec.encode(mapcodec.with_version(built, 1)))
    return built


async def cards(app: FastAPI, client: httpx.AsyncClient) -> dict[str, dict[str, Any]]:
    await client.get("/api/dashboard")  # schedules the checks
    checks = checks_of(center_of(app))
    assert checks is not None
    await checks.wait()
    machines = (await client.get("/api/dashboard")).json()["machines"]
    return {c["name"]: c for c in machines}


async def test_the_error_as_sent_is_the_stored_maps_own(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    fanuc = await store(app, client, VMC, 0.5)  # as the push builds it
    other = await store(app, client, SIEMENS, 3.0)  # not at the push's tolerance
    found = await cards(app, client)
    maps = found["vmc-01"]["maps"]
    assert fanuc.report is not None
    assert (maps["error_um"], maps["tolerance_um"]) == (
        pytest.approx(fanuc.report.worst_error_um), fanuc.report.tolerance_um)
    assert maps["kind"] == mapcodec.kind_of(fanuc)
    assert maps["bytes"] == fanuc.report.bytes
    codes = [r["code"] for r in found["vmc-01"]["accuracy"]["reasons"]]
    over = fanuc.report.worst_error_um > fanuc.report.tolerance_um
    assert ("map_over_tolerance" in codes) is over
    # a rebuild that is not the stored map says nothing about it: unknown, not guessed
    assert other.report is not None and mapcodec.encode(mapcodec.with_version(
        build_for(SIEMENS, "siemens", {**MODEL, "machine": "dmu-02"}, {}, 0.5), 1)) != \
        mapcodec.encode(mapcodec.with_version(other, 1))
    assert found["dmu-02"]["maps"]["error_um"] is None
    metrics = (await client.get("/metrics")).text
    assert f'ednc_machine_map_error_um{{machine="vmc-01"}} {fanuc.report.worst_error_um}' \
        in metrics
    assert 'ednc_machine_map_error_um{machine="dmu-02"}' not in metrics
    detail = (await client.get("/api/machines/vmc-01/dashboard")).json()
    assert detail["card"]["maps"]["error_um"] == pytest.approx(fanuc.report.worst_error_um)
