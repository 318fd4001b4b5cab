"""Registrations that could never work are refused, and map versions never go back (issue
12): a model written for another machine is 422; a machine deleted and registered again
continues above the map version it still holds, over a real socket with a simulated PLC.
(Secrets, names, travels and tool lengths: tests/test_server_api.py, the 422 table.)"""

from __future__ import annotations

import asyncio
from pathlib import Path

from server.db import error_models as model_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.events import EventKind
from server.settings import load_settings
from tests.support.api import API_KEY as KEY
from tests.support.api import SECRET, VMC, WRITE, running
from tests.support.link import DEADLINE_S, model_body, rig, simulator, until


async def test_a_model_written_for_another_machine_is_422(tmp_path: Path) -> None:
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'c.db'}", api_key=KEY)
    async with running(settings) as (_, client):
        assert (await client.post("/api/machines", headers=WRITE,
                                  json={**VMC, "secret": SECRET})).status_code == 201
        url = "/api/machines/vmc-01/models"
        r = await client.post(url, headers=WRITE, json={"body": model_body("vmc-02")})
        assert r.status_code == 422
        (error,) = r.json()["detail"]
        assert error["loc"] == ["body", "body", "machine"] and "vmc-02" in error["msg"]
        assert (await client.get(url)).json() == []
        r = await client.post(url, headers=WRITE, json={"body": model_body("vmc-01")})
        assert r.status_code == 201


async def test_a_re_registered_machine_continues_above_the_version_it_holds(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S * 2), rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        async with simulator(r.port) as sim:
            await until(lambda: sim.runtime.controller.store.version == 1)
            # two more models, each waited for: two models stored at once may share one
            # build (one map version for both), so the versions would not reach 3
            for version, slope in ((2, 0.02), (3, 0.03)):
                await r.db.run(model_repo.add_model, mid, source="upload",
                               body=model_body(slope=slope))
                await until(lambda v=version: sim.runtime.controller.store.version == v)
            # the machine is deleted and registered again; the PLC keeps version 3
            await r.db.run(machine_repo.delete_machine, "vmc-01")
            await until(lambda: not r.center.registry.get("vmc-01").connected)
            new_id = await r.register(model=model_body(slope=0.04))
            await until(lambda: sim.runtime.controller.store.version == 4)

            async def acked() -> bool:  # the center stores the MapAck after the PLC sent it
                return await r.acked_version(new_id) == 4

            await until(acked)
        assert await r.events(EventKind.REJECTED) == []  # no STALE_VERSION on the way
        assert (await r.db.run(map_repo.next_map_version, new_id)) == 5
