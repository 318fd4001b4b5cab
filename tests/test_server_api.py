"""The REST API, end to end through the ASGI app with its lifespan, on SQLite and PostgreSQL."""

from __future__ import annotations

import datetime as dt
import hashlib
import json
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi import FastAPI

from server.app import ServiceFactory, create_app
from server.center import Center
from server.db import Database, make_engine
from server.db import events as event_repo
from server.db import maps as map_repo
from server.db import reports as report_repo
from server.events import EventKind
from server.numeric import plain_json
from server.retention import EventRetention
from server.settings import Settings
from tests.support.api import (
    API_KEY,
    CSV_HEADER,
    SECRET,
    VMC,
    WRITE,
    backlash_csv,
    center_of,
    running,
)
from tests.support.db import database_url, postgres_url  # noqa: F401  (fixtures)
from volumetric.model.components import component_from_json


def csv_text(rows: int) -> str:
    lines = [CSV_HEADER]
    for i in range(rows):
        lines.append(f"X-positioning,1,{i * 2.0},{i * 50.0},0,0,1,0,0,100,displacement,1,0,0,"
                     f"{0.5 * i}")
    return "\n".join(lines) + "\n"


@pytest.fixture
async def api(database_url: str) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:  # noqa: F811
    async with running(Settings(database_url=database_url, api_key=API_KEY)) as pair:
        yield pair


@pytest.fixture
async def client(api: tuple[FastAPI, httpx.AsyncClient]) -> httpx.AsyncClient:
    return api[1]


async def add_vmc(client: httpx.AsyncClient, **changes: Any) -> dict[str, Any]:
    r = await client.post("/api/machines", json={**VMC, "secret": SECRET, **changes},
                          headers=WRITE)
    assert r.status_code == 201, r.text
    body: dict[str, Any] = r.json()
    return body


def errors(response: httpx.Response) -> list[dict[str, Any]]:
    assert response.status_code == 422, response.text
    detail: list[dict[str, Any]] = response.json()["detail"]
    return detail


# --- machines -------------------------------------------------------------------------------

async def test_machine_crud_round_trip(client: httpx.AsyncClient) -> None:
    created = await add_vmc(client)
    assert created["name"] == "vmc-01" and created["ip"] == "10.0.0.21"
    assert created["description"]["chain"] == "w X Y b Z t"
    assert created["description"]["travel_mm"]["z"] == [-300.0, 0.0]

    got = (await client.get("/api/machines/vmc-01")).json()
    assert got == created
    listed = (await client.get("/api/machines")).json()
    assert [m["name"] for m in listed] == ["vmc-01"]

    r = await client.patch("/api/machines/vmc-01", headers=WRITE,
                           json={"name": "vmc-07", "ip": "fd00::7", "tool_length_mm": 80})
    assert r.status_code == 200, r.text
    patched = r.json()
    assert (patched["name"], patched["ip"]) == ("vmc-07", "fd00::7")
    assert patched["description"]["tool_length_mm"] == 80.0
    assert patched["description"]["chain"] == "w X Y b Z t"  # untouched keys stay
    assert (await client.get("/api/machines/vmc-01")).status_code == 404

    r = await client.delete("/api/machines/vmc-07", headers=WRITE)
    assert r.status_code == 204
    assert (await client.get("/api/machines/vmc-07")).status_code == 404
    assert (await client.get("/api/machines")).json() == []


async def test_patch_null_switches_chain_to_type_numbers(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    r = await client.patch("/api/machines/vmc-01", headers=WRITE,
                           json={"chain": None, "translational_type": 1, "rotary_type": 0})
    assert r.status_code == 200, r.text
    description = r.json()["description"]
    assert "chain" not in description and description["translational_type"] == 1


async def test_patch_result_is_validated_as_a_whole(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    r = await client.patch("/api/machines/vmc-01", headers=WRITE, json={"chain": None})
    (error,) = errors(r)
    assert "chain" in error["msg"] and "translational_type" in error["msg"]
    assert (await client.get("/api/machines/vmc-01")).json()["description"]["chain"]


async def test_extension_keys_are_kept(client: httpx.AsyncClient) -> None:
    created = await add_vmc(client, site={"hall": 3, "cell": "B"})
    assert created["description"]["site"] == {"hall": 3, "cell": "B"}


@pytest.mark.parametrize(
    ("change", "where", "words"),
    [
        ({"ip": "10.0.0.256"}, ["body", "ip"], "IP"),
        ({"controller": "heidenhain"}, ["body", "controller"], "fanuc"),
        ({"name": "bad name/.."}, ["body", "name"], "pattern"),
        ({"chain": "w X Q b Z t"}, ["body", "chain"], "pattern"),
        ({"chain": None}, ["body"], "translational_type"),
        ({"travel_mm": {"x": [0, 500], "y": [0, 300]}}, ["body"], "'z'"),
        ({"travel_mm": {"x": [0, "far"]}}, ["body", "travel_mm", "x", 1], "number"),
        ({"tool_length_mm": "long"}, ["body", "tool_length_mm"], "number"),
        ({"secret": "short"}, ["body", "secret"], "16 bytes"),
        # registrations that could never log in or never get a map (issue 12)
        ({"secret": "fifteen-chars!!"}, ["body", "secret"], "16 bytes"),
        ({"secret": "é" * 7}, ["body", "secret"], "got 14"),  # 7 characters, 14 bytes
        ({"name": "m" * 33}, ["body", "name"], "31}"),  # the protocol's 32-byte name field
        ({"travel_mm": {"x": [0, 1e308], "y": [0, 300], "z": [-300, 0]}},
         ["body", "travel_mm", "x", 1], "100000"),
        ({"tool_length_mm": -1e308}, ["body", "tool_length_mm"], "greater than or equal to 0"),
        ({"tool_length_mm": -100}, ["body", "tool_length_mm"], "greater than or equal to 0"),
    ],
)
async def test_bad_description_is_422_naming_the_field(
    client: httpx.AsyncClient, change: dict[str, Any], where: list[Any], words: str
) -> None:
    body = {k: v for k, v in {**VMC, "secret": SECRET, **change}.items() if v is not None}
    r = await client.post("/api/machines", json=body, headers=WRITE)
    found = errors(r)
    assert any(e["loc"] == where and words in e["msg"] for e in found), found
    assert (await client.get("/api/machines")).json() == []


async def test_nan_is_not_json(client: httpx.AsyncClient) -> None:
    # Python's json writes (and reads) NaN and Infinity; they are not JSON.
    headers = {**WRITE, "content-type": "application/json"}
    body = json.dumps({**VMC, "secret": SECRET, "tool_length_mm": float("nan")})
    (error,) = errors(await client.post("/api/machines", content=body, headers=headers))
    assert error["loc"] == ["body", "tool_length_mm"] and "input" not in error
    body = json.dumps({**VMC, "secret": SECRET, "note": {"x": float("inf")}})
    found = errors(await client.post("/api/machines", content=body, headers=headers))
    assert any("NaN and Infinity" in e["msg"] for e in found)


@pytest.mark.parametrize("change", [{"name": "vmc-02"}, {"ip": "10.0.0.99"}])
async def test_duplicate_name_or_ip_is_409(client: httpx.AsyncClient,
                                           change: dict[str, str]) -> None:
    await add_vmc(client)
    duplicate = {**VMC, "secret": SECRET, "name": "vmc-01", "ip": "10.0.0.21", **change}
    r = await client.post("/api/machines", json=duplicate, headers=WRITE)
    assert r.status_code == 409
    field = "ip" if "name" in change else "name"
    assert f"{field} " in r.json()["detail"]
    await add_vmc(client, name="vmc-03", ip="10.0.0.23")
    r = await client.patch("/api/machines/vmc-03", json={"ip": "10.0.0.21"}, headers=WRITE)
    assert r.status_code == 409


async def test_link_machines_share_an_ip_an_ednc_machine_does_not(
        client: httpx.AsyncClient) -> None:
    """Two controllers behind one Modbus gateway at its address; an EDNC machine there is
    409 either way round (the machine port would admit the address for both)."""
    gateway = "10.0.0.50"
    for unit in (1, 2):
        r = await client.post("/api/machines", headers=WRITE, json={
            **VMC, "secret": SECRET, "name": f"pmc-{unit}", "ip": gateway,
            "link": {"kind": "modbus", "unit_id": unit}})
        assert r.status_code == 201, r.text
    r = await client.post("/api/machines", headers=WRITE,
                          json={**VMC, "secret": SECRET, "name": "vmc-09", "ip": gateway})
    assert r.status_code == 409 and "EDNC machine" in r.json()["detail"], r.text
    await add_vmc(client)  # an EDNC machine at 10.0.0.21
    r = await client.patch("/api/machines/pmc-2", json={"ip": "10.0.0.21"}, headers=WRITE)
    assert r.status_code == 409 and "EDNC machine" in r.json()["detail"], r.text
    listed = {m["name"]: m["ip"] for m in (await client.get("/api/machines")).json()}
    assert listed == {"pmc-1": gateway, "pmc-2": gateway, "vmc-01": "10.0.0.21"}


@pytest.mark.parametrize("path", [
    "/api/machines/ghost", "/api/machines/ghost/status", "/api/machines/ghost/models",
    "/api/machines/ghost/models/latest", "/api/machines/ghost/measurements",
    "/api/machines/ghost/maps", "/api/machines/ghost/maps/1/payload",
    "/api/machines/ghost/diagnoses", "/api/machines/ghost/verifications/1",
    "/api/machines/ghost/deliveries",
])
async def test_unknown_machine_is_404(client: httpx.AsyncClient, path: str) -> None:
    r = await client.get(path)
    assert r.status_code == 404
    assert "ghost" in r.json()["detail"]


# --- auth and secrets -----------------------------------------------------------------------

async def test_writes_need_the_api_key_reads_do_not(client: httpx.AsyncClient) -> None:
    body = {**VMC, "secret": SECRET}
    r = await client.post("/api/machines", json=body)
    assert r.status_code == 401 and "X-API-Key" in r.json()["detail"]
    r = await client.post("/api/machines", json=body, headers={"X-API-Key": "wrong-key-123"})
    assert r.status_code == 401 and r.json()["detail"] == "wrong API key"
    r = await client.post("/api/machines", json={"garbage": 1})
    assert r.status_code == 401  # the key is checked before the body is judged
    await add_vmc(client)
    for method, path in [("PATCH", "/api/machines/vmc-01"), ("DELETE", "/api/machines/vmc-01"),
                         ("POST", "/api/machines/vmc-01/models"),
                         ("POST", "/api/machines/vmc-01/measurements"),
                         ("POST", "/api/machines/vmc-01/diagnoses")]:
        r = await client.request(method, path, json={})
        assert r.status_code == 401, (method, path)
    for path in ["/api/machines", "/api/machines/vmc-01", "/api/status", "/api/events",
                 "/metrics", "/api/machines/vmc-01/models"]:
        assert (await client.get(path)).status_code == 200, path


async def test_without_a_key_the_api_is_read_only(database_url: str) -> None:  # noqa: F811
    async with running(Settings(database_url=database_url)) as (_, client):
        r = await client.post("/api/machines", json={**VMC, "secret": SECRET},
                              headers={"X-API-Key": "anything-at-all"})
        assert r.status_code == 403 and "EDNC_API_KEY" in r.json()["detail"]
        assert (await client.get("/api/status")).json()["writes_enabled"] is False


async def test_secret_is_stored_but_never_returned(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    seen: list[str] = []
    seen.append((await client.post("/api/machines", json={**VMC, "secret": SECRET},
                                   headers=WRITE)).text)
    # Error responses must not echo it either, even for a whole-body error.
    seen.append((await client.post("/api/machines", headers=WRITE, json={
        **VMC, "name": "vmc-02", "ip": "10.0.0.22", "chain": None, "secret": SECRET})).text)
    seen.append((await client.post("/api/machines", headers=WRITE, json={
        **VMC, "secret": SECRET + "\x07"})).text)
    seen.append((await client.patch("/api/machines/vmc-01", headers=WRITE,
                                    json={"secret": SECRET + "-new"})).text)
    for path in ["/api/machines", "/api/machines/vmc-01", "/api/status",
                 "/api/machines/vmc-01/status", "/openapi.json"]:
        seen.append((await client.get(path)).text)
    assert not any(SECRET in text for text in seen)
    row = await center_of(app).db.run(_get_machine, "vmc-01")
    # the center keeps it for the challenge-response, sealed (AES-GCM) at rest: with a key
    # file beside SQLite; on PostgreSQL only with EDNC_SECRET_KEY, which this app lacks
    box = center_of(app).db.secrets
    assert box.seals == (row.secret.startswith("aesgcm1:") and SECRET not in row.secret)
    assert box.seals or "postgresql" in center_of(app).settings.database_url
    assert box.open(row.secret, row.id) == SECRET + "-new"


def _get_machine(session: Any, name: str) -> Any:
    from server.db import machines

    return machines.get_machine(session, name)


# --- models ---------------------------------------------------------------------------------

def model_body(slope_um: float) -> dict[str, Any]:
    """A model in the numeric core's JSON form: a linear positioning error of X."""
    return {"format": "ednc-model/1", "machine": "vmc-01",
            "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, slope_um],
                                   "origin": 250.0, "scale": 250.0}},
            "locations": {}, "terms": [], "info": {}}


async def test_models_are_versioned(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    url = "/api/machines/vmc-01/models"
    assert (await client.get(f"{url}/latest")).status_code == 404
    for i in range(3):
        r = await client.post(url, headers=WRITE, json={"body": model_body(i)})
        assert r.status_code == 201, r.text
        assert (r.json()["version"], r.json()["source"]) == (i + 1, "upload")
    latest = (await client.get(f"{url}/latest")).json()
    assert latest["version"] == 3 and latest["body"] == model_body(2)
    assert (await client.get(f"{url}/1")).json()["body"] == model_body(0)
    listed = (await client.get(url)).json()
    assert [m["version"] for m in listed] == [3, 2, 1] and "body" not in listed[0]
    assert (await client.get(f"{url}/4")).status_code == 404
    assert (await client.get(f"{url}/0")).status_code == 422
    r = await client.post(url, headers=WRITE, json={"source": "guess", "body": model_body(1)})
    assert errors(r)[0]["loc"] == ["body", "source"]


@pytest.mark.parametrize(("change", "words"), [
    ({"format": "other/9"}, "ednc-model/1"),
    ({"components": {"EAA": {"type": "polynomial", "coefficients": [1.0]}}}, "EAA"),
    ({"components": {"EXC": {"type": "polynomial", "coefficients": [1.0]}}}, "no axis C"),
    ({"components": [1, 2]}, ""),
    ({"terms": [{"effect": "warp", "axis": "x"}]}, "warp"),
])
async def test_a_model_the_core_cannot_read_is_422(
    client: httpx.AsyncClient, change: dict[str, Any], words: str
) -> None:
    await add_vmc(client)
    r = await client.post("/api/machines/vmc-01/models", headers=WRITE,
                          json={"body": {**model_body(1.0), **change}})
    (error,) = errors(r)
    assert error["loc"] == ["body", "body"] and words in error["msg"]
    assert (await client.get("/api/machines/vmc-01/models")).json() == []


def positioning_csv(slope_um_per_mm: float) -> str:
    """Two runs of an X positioning test whose error grows linearly with x."""
    lines = [CSV_HEADER]
    for run in (1, 2):
        for i in range(11):
            x = 50.0 * i
            lines.append(f"X-positioning,{run},{i},{x},150,-150,1,0,0,100,displacement,"
                         f"1,0,0,{slope_um_per_mm * x}")
    return "\n".join(lines) + "\n"


async def test_fit_identifies_the_model_from_stored_sets(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    await client.post("/api/machines/vmc-01/measurements", params={"set_name": "x-pos"},
                      content=positioning_csv(0.02).encode(),
                      headers={**WRITE, "content-type": "text/csv"})
    r = await client.post("/api/machines/vmc-01/models/fit", headers=WRITE,
                          json={"measurement_sets": ["x-pos"]})
    assert r.status_code == 201, r.text
    model = r.json()
    assert (model["version"], model["source"]) == (1, "fit")
    # 0.02 µm/mm over the 500 mm travel: the fitted EXX rises by 10 µm end to end.
    exx = component_from_json(model["body"]["components"]["EXX"])
    ends = exx(np.array([0.0, 500.0]))
    assert ends[1] - ends[0] == pytest.approx(10.0, rel=1e-6)
    latest = (await client.get("/api/machines/vmc-01/models/latest")).json()
    assert latest == model


async def test_fit_errors_are_422(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    url = "/api/machines/vmc-01/models/fit"
    r = await client.post(url, headers=WRITE, json={"measurement_sets": ["missing"]})
    (error,) = errors(r)
    assert error["loc"] == ["body", "measurement_sets", 0] and "missing" in error["msg"]
    r = await client.post(url, headers=WRITE, json={"measurement_sets": []})
    assert errors(r)[0]["loc"] == ["body", "measurement_sets"]
    r = await client.post(url, headers=WRITE, json={"measurement_sets": ["a", "a"]})
    assert "twice" in errors(r)[0]["msg"]


# --- measurements ---------------------------------------------------------------------------

async def test_measurement_upload_as_csv_body_and_as_file(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    url = "/api/machines/vmc-01/measurements"
    text = csv_text(5)
    r = await client.post(url, params={"set_name": "x-axis"}, content=text.encode(),
                          headers={**WRITE, "content-type": "text/csv"})
    assert r.status_code == 201, r.text
    assert r.json()["row_count"] == 5 and r.json()["name"] == "x-axis"

    r = await client.post(url, files={"file": ("morning.csv", csv_text(3).encode(), "text/csv")},
                          headers=WRITE)
    assert r.status_code == 201, r.text
    assert (r.json()["name"], r.json()["row_count"]) == ("morning", 3)

    assert [s["name"] for s in (await client.get(url)).json()] == ["morning", "x-axis"]
    meta = (await client.get(f"{url}/x-axis")).json()
    assert meta["size_bytes"] == len(text.encode())
    download = await client.get(f"{url}/x-axis/csv")
    assert download.status_code == 200 and download.text == text
    assert download.headers["content-type"].startswith("text/csv")
    assert (await client.get(f"{url}/nope/csv")).status_code == 404

    r = await client.post(url, params={"set_name": "x-axis"}, content=text.encode(),
                          headers={**WRITE, "content-type": "text/csv"})
    assert r.status_code == 409


@pytest.mark.parametrize(("body", "words"), [
    (CSV_HEADER.replace("time_s,", "") + "\n", "time_s"),
    (CSV_HEADER + "\nX-positioning,1,0,0,0,0,1,0,0,100,displacement,1,0,0\n", "line 2"),
    ("", "empty"),
    (CSV_HEADER + "\n", "no readings"),
])
async def test_bad_measurement_csv_is_422_with_the_core_message(
    client: httpx.AsyncClient, body: str, words: str
) -> None:
    await add_vmc(client)
    r = await client.post("/api/machines/vmc-01/measurements", content=body.encode(),
                          headers={**WRITE, "content-type": "text/csv"})
    (error,) = errors(r)
    assert words in error["msg"]
    assert (await client.get("/api/machines/vmc-01/measurements")).json() == []


async def test_measurement_upload_media_and_encoding_errors(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    url = "/api/machines/vmc-01/measurements"
    r = await client.post(url, json={"csv": "no"}, headers=WRITE)
    assert r.status_code == 415
    r = await client.post(url, content=b"test,run\n\xff\xfe\n",
                          headers={**WRITE, "content-type": "text/csv"})
    assert "not UTF-8" in errors(r)[0]["msg"]
    r = await client.post(url, files={"other": ("a.csv", b"x")}, headers=WRITE)
    assert "'file'" in errors(r)[0]["msg"]


async def test_oversized_upload_is_413(
    client: httpx.AsyncClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    await add_vmc(client)
    monkeypatch.setattr("server.api.routes.measurements.MAX_UPLOAD_BYTES", 200)
    url = "/api/machines/vmc-01/measurements"
    big = csv_text(10).encode()
    r = await client.post(url, content=big, headers={**WRITE, "content-type": "text/csv"})
    assert r.status_code == 413
    r = await client.post(url, files={"file": ("big.csv", big)}, headers=WRITE)
    assert r.status_code == 413
    assert (await client.get(url)).json() == []


# --- maps, deliveries, status ---------------------------------------------------------------

async def test_maps_deliveries_and_status(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    machine = await add_vmc(client)
    db = center_of(app).db
    mid = (await db.run(_get_machine, machine["name"])).id
    payloads = [b"\x00map-one", b"\x01map-two\xff"]
    for p in payloads:
        await db.run(map_repo.add_map_version, mid, payload=p, model_version=1,
                     temperatures={"T_t1_C": 20.5})
    url = "/api/machines/vmc-01/maps"
    assert [m["version"] for m in (await client.get(url)).json()] == [2, 1]
    latest = (await client.get(f"{url}/latest")).json()
    assert latest["sha256"] == hashlib.sha256(payloads[1]).hexdigest()
    assert latest["temperatures"] == {"T_t1_C": 20.5}
    r = await client.get(f"{url}/1/payload")
    assert r.content == payloads[0]
    assert r.headers["etag"] == f'"{hashlib.sha256(payloads[0]).hexdigest()}"'
    assert (await client.get(f"{url}/3")).status_code == 404

    sent = await db.run(map_repo.record_sent, mid, 1)
    await db.run(map_repo.record_answer, sent.id, acked=True)
    sent = await db.run(map_repo.record_sent, mid, 2)
    await db.run(map_repo.record_answer, sent.id, acked=False, reject_reason="out of range")
    status = (await client.get("/api/machines/vmc-01/status")).json()
    assert (status["map_version_latest"], status["map_version_sent"],
            status["map_version_applied"]) == (2, 2, 1)
    assert status["last_reject_reason"] == "out of range"
    deliveries = (await client.get("/api/machines/vmc-01/deliveries")).json()
    assert [(d["map_version"], d["state"]) for d in deliveries] == [(2, "rejected"),
                                                                    (1, "applied")]


async def test_status_shows_the_live_link(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    await add_vmc(client)
    await add_vmc(client, name="vmc-02", ip="10.0.0.22")
    registry = center_of(app).registry
    registry.connected("vmc-01", "10.0.0.21:50123")
    registry.seen("vmc-01", telemetry={"x_mm": 12.5, "T_spindle_C": 24.0})
    overall = (await client.get("/api/status")).json()
    assert (overall["machines"], overall["connected"]) == (2, 1)
    one = (await client.get("/api/machines/vmc-01/status")).json()
    assert one["connected"] is True and one["address"] == "10.0.0.21:50123"
    assert one["telemetry"] == {"x_mm": 12.5, "T_spindle_C": 24.0}
    assert "ednc_machines_connected 1.0" in (await client.get("/metrics")).text
    registry.disconnected("vmc-01")
    one = (await client.get("/api/machines/vmc-01/status")).json()
    assert one["connected"] is False and one["telemetry"]["x_mm"] == 12.5
    assert "ednc_machines_connected 0.0" in (await client.get("/metrics")).text


# --- diagnoses and verification reports -----------------------------------------------------

DIAGNOSIS = {"effect": "backlash", "axis": "x", "sensor": None, "estimate": {"reversal_um": 9.8},
             "rms_before_um": 2.9, "rms_after_um": 0.27,
             "candidates": [{"effect": "backlash", "axis": "x", "rms_after_um": 0.27}]}


async def test_diagnoses_and_verifications(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    machine = await add_vmc(client)
    url = "/api/machines/vmc-01/diagnoses"
    r = await client.post(url, json=DIAGNOSIS, headers=WRITE)
    assert r.status_code == 201, r.text
    diag = r.json()
    assert diag["kind"] == "diagnosis" and diag["result"]["estimate"] == {"reversal_um": 9.8}
    assert (await client.get(f"{url}/{diag['id']}")).json() == diag
    assert [d["id"] for d in (await client.get(url)).json()] == [diag["id"]]
    r = await client.post(url, json={**DIAGNOSIS, "rms_before_um": -1}, headers=WRITE)
    assert errors(r)[0]["loc"] == ["body", "rms_before_um"]

    db = center_of(app).db
    mid = (await db.run(_get_machine, machine["name"])).id
    report = await db.run(report_repo.add_report, mid, kind="verification",
                          result={"improvement": 0.78})
    vurl = "/api/machines/vmc-01/verifications"
    assert (await client.get(f"{vurl}/{report.id}")).json()["result"] == {"improvement": 0.78}
    assert (await client.get(f"{vurl}/{diag['id']}")).status_code == 404
    assert (await client.get(f"{url}/{report.id}")).status_code == 404
    assert len((await client.get(vurl)).json()) == 1


def diagonal_csv(um_per_mm: float) -> str:
    """Two runs of the PPP body diagonal whose error grows linearly along it."""
    start, end = np.array([10.0, 10.0, -290.0]), np.array([490.0, 290.0, -10.0])
    length = float(np.linalg.norm(end - start))
    u = (end - start) / length
    lines = [CSV_HEADER]
    for run in (1, 2):
        for i in range(6):
            p = start + (end - start) * i / 5
            lines.append(f"diag-PPP,{run},{i},{p[0]},{p[1]},{p[2]},1,1,1,100,displacement,"
                         f"{u[0]},{u[1]},{u[2]},{um_per_mm * length * i / 5}")
    return "\n".join(lines) + "\n"


async def test_verification_of_a_compensation(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    for set_name, slope in (("diag-before", 0.05), ("diag-after", 0.01)):
        r = await client.post("/api/machines/vmc-01/measurements", params={"set_name": set_name},
                              content=diagonal_csv(slope).encode(),
                              headers={**WRITE, "content-type": "text/csv"})
        assert r.status_code == 201, r.text
    url = "/api/machines/vmc-01/verifications"
    r = await client.post(url, headers=WRITE, json={"before": "diag-before",
                                                    "after": "diag-after"})
    assert r.status_code == 201, r.text
    report = r.json()
    length = float(np.linalg.norm([480.0, 280.0, 280.0]))
    result = report["result"]
    assert result["ranges_before_um"]["diag-PPP"] == pytest.approx(0.05 * length)
    assert result["ranges_after_um"]["diag-PPP"] == pytest.approx(0.01 * length)
    assert result["improvement"]["overall"] == pytest.approx(0.8)
    assert result["accepted"] is True
    assert (await client.get(f"{url}/{report['id']}")).json() == report

    r = await client.post(url, headers=WRITE, json={"before": "diag-after",
                                                    "after": "diag-before"})
    assert r.json()["result"]["accepted"] is False  # worse is not accepted
    r = await client.post(url, headers=WRITE, json={"before": "diag-before"})
    assert "improvement" not in r.json()["result"]


async def test_verification_errors_are_422(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    await client.post("/api/machines/vmc-01/measurements", params={"set_name": "x-pos"},
                      content=positioning_csv(0.02).encode(),
                      headers={**WRITE, "content-type": "text/csv"})
    url = "/api/machines/vmc-01/verifications"
    r = await client.post(url, headers=WRITE, json={"before": "x-pos"})
    assert "diag-" in errors(r)[0]["msg"]
    r = await client.post(url, headers=WRITE, json={"before": "x-pos", "after": "nope"})
    assert errors(r)[0]["loc"] == ["body", "after"]
    assert (await client.get(url)).json() == []


async def test_diagnosis_run_names_backlash_and_stores_the_extended_model(
    client: httpx.AsyncClient,
) -> None:
    await add_vmc(client)
    await client.post("/api/machines/vmc-01/measurements", params={"set_name": "bidir"},
                      content=backlash_csv(8.0).encode(),
                      headers={**WRITE, "content-type": "text/csv"})
    r = await client.post("/api/machines/vmc-01/diagnoses/run", headers=WRITE,
                          json={"measurement_sets": ["bidir"]})
    assert r.status_code == 201, r.text
    result = r.json()["result"]
    assert (result["effect"], result["axis"]) == ("backlash", "x")
    estimate = result["estimate"]
    assert abs(estimate["reversal_um"] - 8.0) < 5 * estimate["reversal_um_std"]
    assert result["rms_after_um"] < result["rms_before_um"]
    assert result["measurement_sets"] == ["bidir"] and result["model_version"] == 1
    model = (await client.get("/api/machines/vmc-01/models/latest")).json()
    assert model["source"] == "diagnose"
    (term,) = model["body"]["terms"]
    assert term["effect"] == "backlash" and term["reversal_um"] == estimate["reversal_um"]

    # What the core prints (``ednc diagnose --json``) is also accepted as an upload.
    uploaded = {k: v for k, v in result.items() if k not in ("measurement_sets",
                                                              "model_version")}
    r = await client.post("/api/machines/vmc-01/diagnoses", json=uploaded, headers=WRITE)
    assert r.status_code == 201, r.text
    assert r.json()["result"]["estimate"] == estimate


def test_core_json_is_made_strict() -> None:
    out = plain_json({"a": np.float64("nan"), "b": np.int64(3), "c": [np.inf, 1.5], 1: (2,)})
    assert out == {"a": None, "b": 3, "c": [None, 1.5], "1": [2]}
    assert type(out["b"]) is int
    json.dumps(out, allow_nan=False)


async def test_diagnosis_run_errors_are_422(client: httpx.AsyncClient) -> None:
    await add_vmc(client)
    await client.post("/api/machines/vmc-01/measurements", params={"set_name": "small"},
                      content=csv_text(5).encode(), headers={**WRITE, "content-type": "text/csv"})
    url = "/api/machines/vmc-01/diagnoses/run"
    r = await client.post(url, headers=WRITE, json={"measurement_sets": ["small"]})
    assert "too few readings" in errors(r)[0]["msg"]
    r = await client.post(url, headers=WRITE, json={"measurement_sets": ["small", "gone"]})
    assert errors(r)[0]["loc"] == ["body", "measurement_sets", 1]
    assert (await client.get("/api/machines/vmc-01/diagnoses")).json() == []
    assert (await client.get("/api/machines/vmc-01/models")).json() == []


# --- events and metrics ---------------------------------------------------------------------

async def test_events_feed_the_refusal_list_and_metrics(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    app, client = api
    center = center_of(app)
    await center.record_event(EventKind.REFUSED, "10.9.9.9:5555", "unknown address",
                              reason="unknown")
    await center.record_event(EventKind.CONNECTED, "vmc-01")
    await center.record_event(EventKind.REFUSED, "vmc-01", "bad HMAC", reason="auth")
    refused = (await client.get("/api/events", params={"kind": "refused"})).json()
    assert [(e["machine"], e["detail"]) for e in refused] == [
        ("vmc-01", "bad HMAC"), ("10.9.9.9:5555", "unknown address")]
    every = (await client.get("/api/events")).json()
    assert [e["kind"] for e in every] == ["refused", "connected", "refused"]
    page = (await client.get("/api/events", params={"before_id": every[0]["id"],
                                                    "limit": 1})).json()
    assert [e["kind"] for e in page] == ["connected"]
    assert (await client.get("/api/events", params={"kind": "party"})).status_code == 422
    text = (await client.get("/metrics")).text
    assert 'ednc_connections_refused_total{reason="unknown"} 1.0' in text
    assert 'ednc_connections_refused_total{reason="auth"} 1.0' in text
    assert 'ednc_events_total{kind="connected"} 1.0' in text


async def test_two_apps_keep_their_own_metrics(tmp_path: Path) -> None:
    settings = [Settings(database_url=f"sqlite:///{tmp_path / f'{i}.db'}") for i in range(2)]
    async with running(settings[0]) as (app_a, client_a), \
            running(settings[1]) as (_, client_b):
        center_of(app_a).metrics.pushes.labels(outcome="applied").inc()
        assert 'ednc_map_pushes_total{outcome="applied"} 1.0' in (
            await client_a.get("/metrics")).text
        assert 'ednc_map_pushes_total{outcome="applied"} 0.0' in (  # pre-created at 0
            await client_b.get("/metrics")).text


# --- restart --------------------------------------------------------------------------------

async def test_a_restart_loses_nothing(database_url: str) -> None:  # noqa: F811
    settings = Settings(database_url=database_url, api_key=API_KEY)
    async with running(settings) as (app, client):
        await add_vmc(client)
        r = await client.post("/api/machines/vmc-01/models", headers=WRITE,
                              json={"body": model_body(4.0)})
        assert r.status_code == 201
        await client.post("/api/machines/vmc-01/measurements", content=csv_text(2).encode(),
                          params={"set_name": "s1"}, headers={**WRITE, "content-type": "text/csv"})
        await client.post("/api/machines/vmc-01/diagnoses", json=DIAGNOSIS, headers=WRITE)
        await center_of(app).record_event(EventKind.REFUSED, "10.1.2.3:4", "unknown")
        before = {p: (await client.get(p)).text for p in RESTART_PATHS}
    async with running(settings) as (_, client):
        after = {p: (await client.get(p)).text for p in RESTART_PATHS}
    assert after == before
    assert json.loads(before["/api/machines/vmc-01/models/latest"])["body"] == model_body(4.0)
    assert before["/api/machines/vmc-01/measurements/s1/csv"] == csv_text(2)
    assert len(json.loads(before["/api/events"])) == 1


RESTART_PATHS = [
    "/api/machines", "/api/machines/vmc-01/models/latest", "/api/machines/vmc-01/measurements",
    "/api/machines/vmc-01/measurements/s1/csv", "/api/machines/vmc-01/diagnoses", "/api/events",
]


def test_create_app_reads_and_validates_the_environment(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from server.settings import SettingsError

    monkeypatch.setenv("EDNC_HTTP_PORT", "99999")
    with pytest.raises(SettingsError, match="EDNC_HTTP_PORT"):
        create_app()
    monkeypatch.setenv("EDNC_HTTP_PORT", "8081")
    assert isinstance(create_app(), FastAPI)


# --- lifespan seams -------------------------------------------------------------------------

def recording_service(log: list[str], tag: str, fail: bool = False) -> ServiceFactory:
    @asynccontextmanager
    async def run(center: Center) -> AsyncIterator[None]:
        assert isinstance(center, Center) and center.db is not None
        if fail:
            raise OSError(f"{tag}: port in use")
        log.append(f"start {tag}")
        try:
            yield
        finally:
            log.append(f"stop {tag}")

    return run


async def test_services_start_in_the_lifespan_and_stop_in_reverse(tmp_path: Path) -> None:
    log: list[str] = []
    services = [recording_service(log, "tcp"), recording_service(log, "mqtt")]
    app = create_app(Settings(database_url=f"sqlite:///{tmp_path / 'a.db'}"), services=services)
    async with app.router.lifespan_context(app):
        assert log == ["start tcp", "start mqtt"]
        center_of(app)
    assert log == ["start tcp", "start mqtt", "stop mqtt", "stop tcp"]
    assert not hasattr(app.state, "center")


async def test_a_service_that_cannot_start_stops_the_ones_before(tmp_path: Path) -> None:
    log: list[str] = []
    services = [recording_service(log, "tcp"), recording_service(log, "mqtt", fail=True)]
    app = create_app(Settings(database_url=f"sqlite:///{tmp_path / 'a.db'}"), services=services)
    with pytest.raises(OSError, match="mqtt: port in use"):
        async with app.router.lifespan_context(app):
            pytest.fail("the lifespan must not start")
    assert log == ["start tcp", "stop tcp"]


async def test_events_past_retention_are_deleted_at_start_up(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'ednc.db'}"
    db = Database(make_engine(url))
    db.create_schema()
    now = dt.datetime.now(dt.UTC)
    for days in (10, 3, 1):
        db.call(event_repo.add_event, kind="refused", machine=f"{days}d",
                time=now - dt.timedelta(days=days))
    db.engine.dispose()
    async with running(Settings(database_url=url, event_retention_days=2)) as (app, client):
        assert [e["machine"] for e in (await client.get("/api/events")).json()] == ["1d"]
        await center_of(app).record_event(EventKind.CONNECTED, "vmc-01")
        assert await EventRetention(center_of(app)).prune_once() == 0
