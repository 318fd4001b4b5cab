"""The plausibility checks at the center's entry points (issue 32): REST temperatures and
uploads, MQTT payloads, a deleted machine's temperatures; the same limits and the same
words as the offline commands (:mod:`volumetric.plausible`)."""

from __future__ import annotations

import asyncio
from pathlib import Path

from server.center import Center
from server.db import machines as machine_repo
from server.db import measurements as measurement_repo
from tests.support.api import CSV_HEADER, WRITE, backlash_csv
from tests.support.intake import _app, client_of
from tests.support.link import DEADLINE_S, SECRET, description

READINGS = "/api/machines/vmc-01/temperatures"


async def _register(client: object, **extra: object) -> None:
    desc = {**description("vmc-01", "fanuc", "10.0.0.21"), "sensors": ["spindle", "air"],
            **extra}
    r = await client.post("/api/machines", json={**desc, "secret": SECRET},  # type: ignore[attr-defined]
                          headers=WRITE)
    assert r.status_code == 201, r.text


async def test_a_deleted_machines_temperatures_do_not_reach_a_new_one(tmp_path: Path) -> None:
    app = _app(tmp_path, f"sqlite:///{tmp_path / 'c.db'}")
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        await _register(client)
        r = await client.post(READINGS, headers=WRITE,
                              json={"readings": [{"sensor": "spindle", "celsius": 23.0}]})
        assert r.json()["accepted"] == 1, r.text
        assert (await client.delete("/api/machines/vmc-01", headers=WRITE)).status_code == 204
        await _register(client)  # a new machine of the same name
        got = (await client.get(READINGS)).json()
        assert got["latest"] == [] and got["refusals"] == []
        center = app.state.center
        assert isinstance(center, Center) and center.temperatures is not None
        assert center.temperatures.readings("vmc-01") == {}


async def test_rest_temperatures_name_the_unit(tmp_path: Path) -> None:
    app = _app(tmp_path, f"sqlite:///{tmp_path / 'c.db'}")
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        await _register(client)
        cases = [({"sensor": "spindle", "celsius": 295.15}, "out_of_range", "kelvin"),
                 ({"sensor": "spindle", "celsius": 22500}, "out_of_range", "m°C"),
                 ({"sensor": "spindle", "celsius": 1e6}, "out_of_range", "outside -20..100 °C"),
                 ({"sensor": "air", "celsius": 21.0, "time": "2286-11-20T17:46:40Z"},
                  "bad_time", "in the future")]
        for reading, reason, said in cases:
            r = await client.post(READINGS, headers=WRITE, json={"readings": [reading]})
            assert r.status_code == 422, r.text
            detail = r.json()["detail"][0]
            assert detail["type"] == reason and said in detail["msg"], (reading, detail)
        assert (await client.get(READINGS)).json()["latest"] == []  # nothing kept


async def test_uploads_read_utf16_and_refuse_a_spreadsheet_locale(tmp_path: Path) -> None:
    app = _app(tmp_path, f"sqlite:///{tmp_path / 'c.db'}")
    url = "/api/machines/vmc-01/measurements"
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        await _register(client)
        text = backlash_csv(8.0)
        german = text.replace(",", ";").replace(".", ",")
        r = await client.post(url, params={"set_name": "de"}, headers={
            **WRITE, "Content-Type": "text/csv"}, content=german.encode())
        assert r.status_code == 422 and "semicolons and decimal commas" in r.text, r.text
        r = await client.post(url, params={"set_name": "u16"}, headers={
            **WRITE, "Content-Type": "text/csv"}, content=text.encode("utf-16"))
        assert r.status_code == 201, r.text
        assert r.json()["row_count"] == text.count("\n") - 1 and r.json()["warnings"] == []
        mm = CSV_HEADER + "\n" + "\n".join(
            f"X-positioning,1,{i},{25.0 * i},150,-150,1,0,0,100,displacement,1,0,0,"
            f"{0.00002 * 25 * i:.6f}" for i in range(1, 21)) + "\n"
        r = await client.post(url, params={"set_name": "mm"}, headers={
            **WRITE, "Content-Type": "text/csv"}, content=mm.encode())
        assert r.status_code == 201, r.text
        assert "look like mm" in r.json()["warnings"][0]
        center = app.state.center
        assert isinstance(center, Center)
        sets = await center.db.run(measurement_repo.list_measurement_sets, 1)
        assert sorted(s.name for s in sets) == ["mm", "u16"]  # the refused one left nothing


async def test_rest_machine_descriptions_say_their_warnings(tmp_path: Path) -> None:
    # travels of 0.5 m written as 0.5: accepted (a spindle test moves no axis) but warned,
    # in the answer, as the CLI prints it on stderr
    app = _app(tmp_path, f"sqlite:///{tmp_path / 'c.db'}")
    metres = {"x": [0, 0.5], "y": [0, 0.3], "z": [-0.3, 0]}
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        desc = {**description("vmc-01", "fanuc", "10.0.0.21"), "travel_mm": metres}
        r = await client.post("/api/machines", json={**desc, "secret": SECRET}, headers=WRITE)
        assert r.status_code == 201, r.text
        assert any("metres" in w for w in r.json()["warnings"]), r.json()
        r = await client.patch("/api/machines/vmc-01", headers=WRITE,
                               json={"travel_mm": description()["travel_mm"]})
        assert r.status_code == 200, r.text
        assert r.json()["warnings"] == []
        r = await client.patch("/api/machines/vmc-01", headers=WRITE,
                               json={"travel_mm": metres})
        assert any("metres" in w for w in r.json()["warnings"]), r.json()


async def test_a_machine_deleted_through_another_node_is_forgotten_here(
        tmp_path: Path) -> None:
    # another center node deletes vmc-01 and registers a new vmc-01: this node hears of it
    # only through the database; the next look-up (a reading, a refresh) drops the old
    # machine's readings instead of showing them on the new one
    app = _app(tmp_path, f"sqlite:///{tmp_path / 'c.db'}")
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        await _register(client)
        r = await client.post(READINGS, headers=WRITE,
                              json={"readings": [{"sensor": "spindle", "celsius": 23.0}]})
        assert r.json()["accepted"] == 1, r.text
        center = app.state.center
        assert isinstance(center, Center) and center.intake is not None
        assert center.temperatures is not None
        assert set(center.temperatures.readings("vmc-01")) == {"T_spindle_C"}
        desc = {**description("vmc-01", "fanuc", "10.0.0.21"), "sensors": ["air"]}
        await center.db.run(machine_repo.delete_machine, "vmc-01")
        await center.db.run(lambda s: machine_repo.create_machine(
            s, name="vmc-01", ip="10.0.0.21", controller="fanuc", description=desc,
            secret=SECRET))
        assert await center.intake.lookup("vmc-01") == frozenset({"T_air_C"})
        assert center.temperatures.readings("vmc-01") == {}
        got = (await client.get(READINGS)).json()
        assert got["latest"] == [], got
