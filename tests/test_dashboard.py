"""The dashboard's JSON endpoints, its live stream and its pages, through the ASGI app with
its lifespan (the browser test is ``test_dashboard_browser.py``)."""

from __future__ import annotations

import asyncio
import datetime as dt
import json
import re
from collections.abc import AsyncIterator
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi import FastAPI

from protocol.codes import MapEncoding
from server.dashboard import live as live_module
from server.dashboard.live import LiveFeed, sse_stream
from server.dashboard.schemas import DashboardSnapshot
from server.dashboard.telemetry import URAD_PER_DEG, live_values
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.events import EventKind
from server.settings import Settings
from tests.support.api import API_KEY, CSV_HEADER, SECRET, VMC, WRITE, center_of, running
from tests.support.dashboard import (
    DIAGNOSIS,
    MODEL,
    OTHER,
    SIEMENS,
    correction_um,
    diagonal_error_um,
    diagonals_csv,
    example_map,
)


@pytest.fixture
async def api(tmp_path: Any) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}", api_key=API_KEY,
                        node_id="test-node")
    async with running(settings) as pair:
        yield pair


async def register(client: httpx.AsyncClient, description: dict[str, Any]) -> None:
    r = await client.post("/api/machines", json={**description, "secret": SECRET},
                          headers=WRITE)
    assert r.status_code == 201, r.text


def telemetry(x: float, *, comp_um: float = 3.0, temp: float = 21.5,
              at: dt.datetime | None = None) -> dict[str, Any]:
    """A Telemetry message as ``dataclasses.asdict`` spells it (mm, °C)."""
    at = at or dt.datetime.now(dt.UTC)
    return {"timestamp_ms": int(at.timestamp() * 1000), "state": "compensating",
            "map_version": 1,
            "axes": [{"name": "X", "position": x, "compensation": comp_um / 1000.0},
                     {"name": "Y", "position": 150.0, "compensation": -0.002},
                     {"name": "Z", "position": -50.0, "compensation": 0.0}],
            "temperatures": [{"name": "spindle", "celsius": temp}]}


# --- maps -------------------------------------------------------------------------------------


async def machine_id(app: FastAPI, name: str) -> int:
    row = await center_of(app).db.run(machine_repo.get_machine, name)
    assert row is not None
    return row.id


# --- verification -----------------------------------------------------------------------------


async def upload(client: httpx.AsyncClient, machine: str, set_name: str, text: str) -> None:
    r = await client.post(f"/api/machines/{machine}/measurements", params={"set_name": set_name},
                          content=text.encode(), headers={**WRITE, "content-type": "text/csv"})
    assert r.status_code == 201, r.text


async def verify(client: httpx.AsyncClient, machine: str) -> dict[str, Any]:
    await upload(client, machine, "diag-before", diagonals_csv(10.0))
    await upload(client, machine, "diag-after", diagonals_csv(2.0))
    r = await client.post(f"/api/machines/{machine}/verifications", headers=WRITE,
                          json={"before": "diag-before", "after": "diag-after"})
    assert r.status_code == 201, r.text
    result: dict[str, Any] = r.json()
    return result


# --- telemetry --------------------------------------------------------------------------------

def test_telemetry_is_read_in_both_spellings_with_units() -> None:
    listed = live_values(telemetry(12.5, comp_um=3.0, temp=22.25))
    keyed = live_values({"state": "idle", "map_version": 2,
                         "axes": {"X": {"position": 12.5, "compensation": 0.003},
                                  "B": {"position": 90.0, "compensation": 0.001}},
                         "temperatures": {"spindle": 22.25}})
    for values in (listed, keyed):
        x = values.axes[0]
        assert (x.name, x.rotary, x.position) == ("X", False, 12.5)
        assert x.compensation == pytest.approx(3.0)  # mm → µm
        assert [(t.name, t.celsius) for t in values.temperatures] == [("spindle", 22.25)]
    b = keyed.axes[1]
    assert b.rotary and b.compensation == pytest.approx(0.001 * URAD_PER_DEG)  # deg → µrad
    assert (keyed.state, keyed.map_version, keyed.measured_at) == ("idle", 2, None)


def test_telemetry_that_is_not_numbers_is_left_out() -> None:
    values = live_values({"state": 3, "map_version": True, "timestamp_ms": "soon",
                          "axes": [{"name": "X", "position": "far"}, {"position": 1.0},
                                   {"name": "Y", "position": float("nan")},
                                   {"name": "Z", "position": 5.0}],
                          "temperatures": {"a": None, "b": 20.0}})
    assert [a.name for a in values.axes] == ["Z"]
    assert [t.name for t in values.temperatures] == ["b"]
    assert (values.state, values.map_version, values.measured_at) == (None, None, None)
    assert live_values({}).axes == ()


# --- the snapshot -----------------------------------------------------------------------------

async def test_snapshot_shows_every_machine_with_live_values_and_health(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    app, client = api
    for description in (VMC, SIEMENS, OTHER):
        await register(client, description)
    center = center_of(app)
    vmc, dmu = await machine_id(app, "vmc-01"), await machine_id(app, "dmu-02")
    db = center.db
    await db.run(map_repo.add_map_version, vmc, payload=b"one", model_version=None)
    sent = await db.run(map_repo.record_sent, vmc, 1)
    await db.run(map_repo.record_answer, sent.id, acked=True)
    await db.run(map_repo.add_map_version, dmu, payload=b"one", model_version=None)
    sent = await db.run(map_repo.record_sent, dmu, 1)
    await db.run(map_repo.record_answer, sent.id, acked=False, reject_reason="checksum")
    report = await verify(client, "vmc-01")
    r = await client.post("/api/machines/vmc-01/diagnoses", json=DIAGNOSIS, headers=WRITE)
    assert r.status_code == 201
    await center.record_event(EventKind.REFUSED, "10.9.9.9:5555", "unknown address",
                              reason="unknown")
    registry = center.registry
    registry.connected("vmc-01", "10.0.0.21:50123")
    registry.seen("vmc-01", telemetry(12.5))
    registry.connected("dmu-02", "10.0.0.22:50124")
    old = dt.datetime.now(dt.UTC) - dt.timedelta(seconds=60)
    registry.seen("dmu-02", telemetry(1.0, at=old))

    r = await client.get("/api/dashboard")
    assert r.status_code == 200
    snap = DashboardSnapshot.model_validate(r.json())
    assert snap.node_id == "test-node"
    cards = {c.name: c for c in snap.machines}
    assert sorted(cards) == ["dmu-02", "vmc-01", "vmc-03"]

    vmc_card = cards["vmc-01"]
    # map applied, but the verification leaves more than the default 10 µm tolerance
    after = max(report["result"]["ranges_after_um"].values())
    assert after > 10.0
    assert (vmc_card.health, vmc_card.connected, vmc_card.state) == (
        "out_of_tolerance", True, "compensating")
    assert vmc_card.health_reason == (f"last verification: {after:.1f} µm diagonal range "
                                      "with compensation, over the 10 µm tolerance")
    assert vmc_card.accuracy is not None
    assert vmc_card.accuracy.residual_um == pytest.approx(after)
    assert [r.code for r in vmc_card.accuracy.reasons] == ["residual", "no_model"]
    assert vmc_card.chain == "w X Y b Z t"
    assert [(a.name, a.position) for a in vmc_card.axes] == [("X", 12.5), ("Y", 150.0),
                                                            ("Z", -50.0)]
    assert vmc_card.axes[0].compensation == pytest.approx(3.0)
    assert [(t.name, t.celsius, t.stale) for t in vmc_card.temperatures] == [
        ("spindle", 21.5, False)]
    assert (vmc_card.maps.latest, vmc_card.maps.sent, vmc_card.maps.applied,
            vmc_card.maps.sent_state, vmc_card.maps.reported) == (1, 1, 1, "applied", 1)
    v = vmc_card.verification
    assert v is not None and v.id == report["id"]
    assert v.ranges_before_um == report["result"]["ranges_before_um"]
    assert v.improvement_pct is not None
    assert v.improvement_pct["overall"] == pytest.approx(
        100 * report["result"]["improvement"]["overall"])
    assert v.accepted is report["result"]["accepted"]
    d = vmc_card.diagnosis
    assert d is not None and (d.effect, d.axis, d.estimate) == ("backlash", "x",
                                                               {"reversal_um": 9.8})

    dmu_card = cards["dmu-02"]  # connected, but a rejected map outranks stale telemetry
    assert dmu_card.accuracy is not None
    assert dmu_card.health == "alarm" and "checksum" in dmu_card.health_reason
    assert [r.code for r in dmu_card.accuracy.reasons] == [
        "map_rejected", "telemetry_stale", "not_verified", "no_model"]
    assert dmu_card.telemetry_stale and dmu_card.temperatures[0].stale
    assert dmu_card.telemetry_age_s is not None and dmu_card.telemetry_age_s >= 60
    assert cards["vmc-03"].health == "offline" and cards["vmc-03"].axes == []

    assert [(e.kind, e.machine, e.detail) for e in snap.events] == [
        (EventKind.REFUSED, "10.9.9.9:5555", "unknown address")]




async def test_health_is_the_accuracy_and_names_the_first_thing_to_act_on(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    app, client = api
    await register(client, {**VMC, "accuracy_tolerance_um": 25.0})
    registry = center_of(app).registry
    registry.connected("vmc-01", "10.0.0.21:1")

    async def health() -> tuple[str, str]:
        card = (await client.get("/api/dashboard")).json()["machines"][0]
        return card["health"], card["health_reason"]

    never = "never verified: no ISO 230-6 diagonal test recorded, accuracy unknown"
    assert await health() == ("warn", "telemetry stale: nothing received yet")
    registry.seen("vmc-01", telemetry(0.0))
    assert await health() == ("unknown", never)
    r = await client.post("/api/machines/vmc-01/models", json={"body": MODEL}, headers=WRITE)
    assert r.status_code == 201, r.text
    assert await health() == ("warn", "no error map built from the model yet")
    db, mid = center_of(app).db, await machine_id(app, "vmc-01")
    await db.run(map_repo.add_map_version, mid, payload=b"m", model_version=1)
    assert await health() == ("warn", "map v1 not applied yet")
    sent = await db.run(map_repo.record_sent, mid, 1)
    await db.run(map_repo.record_answer, sent.id, acked=True)
    assert await health() == ("unknown", never)  # delivered is not accurate
    report = await verify(client, "vmc-01")
    after = max(report["result"]["ranges_after_um"].values())
    assert await health() == ("ok", f"verified {after:.1f} µm, within the 25 µm tolerance; "
                                    "map v1 applied")
    r = await client.post("/api/machines/vmc-01/models", json={"body": MODEL}, headers=WRITE)
    assert await health() == ("warn", "model v2 is newer than the last verification: "
                                      "verify again")
    registry.seen("vmc-01", {**telemetry(0.0), "state": "alarm"})
    assert await health() == ("alarm", "machine reports alarm")
    registry.disconnected("vmc-01")
    assert await health() == ("offline", "not connected")


async def test_temperatures_from_the_service_board_join_the_telemetry(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    from server.temperatures import TemperatureBoard

    app, client = api
    await register(client, VMC)
    center = center_of(app)
    center.registry.connected("vmc-01", "10.0.0.21:1")
    center.registry.seen("vmc-01", telemetry(1.0, temp=21.5))  # sensor "spindle"
    board = TemperatureBoard(stale_after_s=30.0)
    board.update("vmc-01", "column", 19.25, source="mqtt")
    board.update("vmc-01", "spindle", 21.75, source="mqtt")  # newer than the telemetry's
    center.temperatures = board  # as the services hand it over

    async def temperatures() -> list[tuple[str, float, bool, str]]:
        card = (await client.get("/api/dashboard")).json()["machines"][0]
        return [(t["name"], t["celsius"], t["stale"], t["source"])
                for t in card["temperatures"]]

    assert await temperatures() == [("column", 19.25, False, "mqtt"),
                                    ("spindle", 21.75, False, "mqtt")]
    board.mark_stale(source="mqtt")  # the broker went away
    assert await temperatures() == [("column", 19.25, True, "mqtt"),
                                    ("spindle", 21.75, True, "mqtt")]
    detail = (await client.get("/api/machines/vmc-01/dashboard")).json()
    assert [t["name"] for t in detail["card"]["temperatures"]] == ["column", "spindle"]


async def test_stored_reports_with_odd_keys_do_not_break_the_dashboard(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    from server.db import reports as report_repo

    app, client = api
    await register(client, VMC)
    db, mid = center_of(app).db, await machine_id(app, "vmc-01")
    await db.run(report_repo.add_report, mid, kind="verification", result={"ok": True})
    await db.run(report_repo.add_report, mid, kind="diagnosis",
                 result={"effect": 7, "estimate": {"a": "x", "b": 1.5}})
    card = (await client.get("/api/dashboard")).json()["machines"][0]
    assert card["verification"]["ranges_before_um"] == {}
    assert card["verification"]["improvement_pct"] is None
    assert (card["diagnosis"]["effect"], card["diagnosis"]["estimate"]) == ("unknown",
                                                                           {"b": 1.5})
    r = await client.get("/api/machines/vmc-01/verifications/latest/diagonals")
    assert r.status_code == 409 and "before_set" in r.json()["detail"]


# --- map slices -------------------------------------------------------------------------------

@pytest.mark.parametrize("encoding", [MapEncoding.INT32_INCREMENTS, MapEncoding.FLOAT32_MM])
async def test_map_grid_is_the_map_over_two_axes_at_mid_travel(
    api: tuple[FastAPI, httpx.AsyncClient], encoding: MapEncoding
) -> None:
    app, client = api
    await register(client, VMC)
    mid = await machine_id(app, "vmc-01")
    await center_of(app).db.run(map_repo.add_map_version, mid, model_version=None,
                                payload=example_map("vmc-01", 1, encoding))
    r = await client.get("/api/machines/vmc-01/maps/latest/grid")
    assert r.status_code == 200, r.text
    grid = r.json()
    assert (grid["u"], grid["v"], grid["fixed"]) == ("X", "Y", {"Z": -200.0})
    assert [(g["name"], g["unit"], g["count"]) for g in grid["grid"]] == [
        ("X", "mm", 11), ("Y", "mm", 7), ("Z", "mm", 4)]
    for k, out in enumerate(grid["outputs"]):
        assert out["unit"] == "µm"
        values = np.array(out["values"])
        assert values.shape == (7, 11)  # rows follow v = Y, columns u = X
        want = [[correction_um(k, 50.0 * i, 50.0 * j, -200.0) for i in range(11)]
                for j in range(7)]
        np.testing.assert_allclose(values, want, atol=1e-3)
        assert (out["min"], out["max"]) == pytest.approx((np.min(want), np.max(want)),
                                                         abs=1e-3)
    assert grid["outputs"][0]["reversal"] == pytest.approx(4.0)
    assert grid["outputs"][1]["reversal"] is None

    r = await client.get("/api/machines/vmc-01/maps/1/grid", params={"u": "Z", "v": "X"})
    grid = r.json()
    assert (grid["u"], grid["v"], grid["fixed"]) == ("Z", "X", {"Y": 150.0})
    values = np.array(grid["outputs"][1]["values"])
    assert values.shape == (11, 4)
    assert values[2, 3] == pytest.approx(correction_um(1, 100.0, 150.0, 0.0), abs=1e-3)


async def test_map_grid_errors_say_what_is_wrong(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    await register(client, VMC)
    url = "/api/machines/vmc-01/maps"
    r = await client.get(f"{url}/latest/grid")
    assert r.status_code == 404 and "has no map" in r.json()["detail"]
    db, mid = center_of(app).db, await machine_id(app, "vmc-01")
    await db.run(map_repo.add_map_version, mid, model_version=None,
                 payload=example_map("vmc-01", 1, MapEncoding.FLOAT32_MM))
    r = await client.get(f"{url}/latest/grid", params={"u": "A"})
    assert r.status_code == 422
    assert "u='A' is not a grid axis" in r.json()["detail"][0]["msg"]
    r = await client.get(f"{url}/latest/grid", params={"u": "Y", "v": "Y"})
    assert r.status_code == 422 and "both 'Y'" in r.json()["detail"][0]["msg"]
    assert (await client.get(f"{url}/2/grid")).status_code == 404
    await db.run(map_repo.add_map_version, mid, payload=b"\x00map", model_version=None)
    r = await client.get(f"{url}/latest/grid")
    assert r.status_code == 409 and "map v2" in r.json()["detail"]
    assert "does not decode" in r.json()["detail"]


# --- verification diagonals -------------------------------------------------------------------

async def test_diagonal_profiles_match_the_report_and_the_readings(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    _, client = api
    await register(client, VMC)
    url = "/api/machines/vmc-01/verifications/latest/diagonals"
    assert (await client.get(url)).status_code == 404
    report = await verify(client, "vmc-01")
    r = await client.get(url)
    assert r.status_code == 200, r.text
    plots = r.json()
    assert (plots["report_id"], plots["before_set"], plots["after_set"]) == (
        report["id"], "diag-before", "diag-after")
    result = report["result"]
    assert [d["label"] for d in plots["diagonals"]] == list(result["ranges_before_um"])
    for i, d in enumerate(plots["diagonals"]):
        assert d["range_before_um"] == pytest.approx(result["ranges_before_um"][d["label"]])
        assert d["range_after_um"] == pytest.approx(result["ranges_after_um"][d["label"]])
        along = np.array(d["along_mm"])
        length = float(np.linalg.norm([480.0, 280.0, 280.0]))
        np.testing.assert_allclose(along, np.linspace(0.0, length, 11), atol=1e-6)
        want = [diagonal_error_um(i, t, 10.0) for t in np.linspace(0, 1, 11)]
        np.testing.assert_allclose(d["before_um"], want, atol=1e-9)
        want = [diagonal_error_um(i, t, 2.0) for t in np.linspace(0, 1, 11)]
        np.testing.assert_allclose(d["after_um"], want, atol=1e-9)
    same = await client.get(f"/api/machines/vmc-01/verifications/{report['id']}/diagonals")
    assert same.json() == plots
    r = await client.get(f"/api/machines/vmc-01/verifications/{report['id'] + 1}/diagonals")
    assert r.status_code == 404


def test_diagonal_profiles_agree_with_the_core_ranges_whatever_the_sensing_sign() -> None:
    import io

    from server.dashboard.diagonals import diagonal_profiles
    from volumetric.measure.measurement import read_measurements
    from volumetric.verify.iso230_6 import DiagonalTestError, diagonal_ranges

    def read(text: str) -> Any:
        return read_measurements(io.StringIO(text))

    rng = np.random.default_rng(3)
    text = diagonals_csv(7.0)
    lines = text.splitlines()
    flipped = [lines[0]]
    for line in lines[1:]:  # a laser reading against the run direction reads -value
        f = line.split(",")
        if rng.random() < 0.5:
            f[11:15] = [str(-float(v)) for v in f[11:15]]  # u and value: columns 11..14
        flipped.append(",".join(f))
    straight = diagonal_profiles(read(text))
    for data in (read(text), read("\n".join(flipped) + "\n")):
        profiles = diagonal_profiles(data)
        ranges = diagonal_ranges(data)
        assert list(profiles) == list(ranges)
        for label, profile in profiles.items():
            assert profile.range_um == pytest.approx(ranges[label])
            np.testing.assert_allclose(profile.mean_um, straight[label].mean_um, atol=1e-9)
    first_point = [row for row in lines[1:] if row.startswith("diag-PPP,1,0,")]
    single = "\n".join([CSV_HEADER, *first_point])
    with pytest.raises(DiagonalTestError, match="diag-PPP: only one target point"):
        diagonal_profiles(read(single + "\n"))
    with pytest.raises(DiagonalTestError, match="no body-diagonal readings"):
        diagonal_profiles(read(CSV_HEADER + "\nX-pos,1,0,0,0,0,1,0,0,100,displacement,1,0,0,1\n"))


# --- machine page data ------------------------------------------------------------------------

async def test_machine_detail_has_description_live_row_and_model_terms(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    _, client = api
    await register(client, VMC)
    body = {"format": "ednc-model/1", "machine": "vmc-01",
            "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 4.0],
                                   "origin": 250.0, "scale": 250.0}},
            "locations": {"EC0Y": 12.0},
            "terms": [{"effect": "backlash", "axis": "x", "reversal_um": 6.0}], "info": {}}
    r = await client.post("/api/machines/vmc-01/models", headers=WRITE, json={"body": body})
    assert r.status_code == 201, r.text
    r = await client.get("/api/machines/vmc-01/dashboard")
    assert r.status_code == 200, r.text
    detail = r.json()
    assert detail["description"]["chain"] == "w X Y b Z t"
    assert detail["card"]["name"] == "vmc-01" and detail["model_problem"] is None
    exx, ec0y = detail["model"]["components"]
    # EXX = 4 µm * (x - 250) / 250 over x in [0, 500]: -4 .. +4 µm.
    assert (exx["name"], exx["unit"], exx["location"]) == ("EXX", "µm", False)
    assert (exx["min"], exx["max"]) == pytest.approx((-4.0, 4.0))
    assert exx["positions"][0] == 0.0 and exx["positions"][-1] == 500.0
    assert (ec0y["name"], ec0y["unit"], ec0y["location"], ec0y["min"]) == (
        "EC0Y", "µrad", True, 12.0)
    assert detail["model"]["terms"] == body["terms"]
    assert (await client.get("/api/machines/nope/dashboard")).status_code == 404


# --- the live stream --------------------------------------------------------------------------

def sse_snapshots(text: str) -> list[dict[str, Any]]:
    """The ``snapshot`` events of an SSE body, in order."""
    out = []
    for block in text.split("\n\n"):
        lines = block.split("\n")
        if "event: snapshot" in lines:
            data = next(line for line in lines if line.startswith("data: "))
            out.append(json.loads(data.removeprefix("data: ")))
    return out


async def test_live_stream_sends_a_snapshot_then_changes_then_ends(
    api: tuple[FastAPI, httpx.AsyncClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    app, client = api
    await register(client, VMC)
    registry = center_of(app).registry
    registry.connected("vmc-01", "10.0.0.21:1")
    registry.seen("vmc-01", telemetry(1.0))
    monkeypatch.setattr(live_module, "MAX_STREAM_S", 2.5)
    monkeypatch.setattr(live_module, "PERIOD_S", 0.1)

    async def move() -> None:
        for i in range(2, 12):
            await asyncio.sleep(0.15)
            registry.seen("vmc-01", telemetry(float(i)))

    mover = asyncio.create_task(move())
    # The in-process transport hands the body over when the stream ends (after 2.5 s).
    r = await client.get("/api/live")
    await mover
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("text/event-stream")
    assert r.text.startswith("retry: ")
    snapshots = sse_snapshots(r.text)
    positions = [s["machines"][0]["axes"][0]["position"] for s in snapshots]
    assert positions[0] == 1.0  # the state at connect
    assert positions[-1] == 11.0 and len(set(positions)) > 2  # then the changes
    feed = app.state.dashboard_feed
    assert isinstance(feed, LiveFeed) and feed.viewers == 0  # the producer is gone too
    assert feed._producer is None


async def test_live_feed_builds_once_for_all_viewers_and_closes() -> None:
    calls = 0
    now = dt.datetime.now(dt.UTC)

    async def source() -> DashboardSnapshot:
        nonlocal calls
        calls += 1
        return DashboardSnapshot(generated_at=now, version="t", node_id=f"n{calls}",
                                 stale_after_s=10.0, machines=[], events=[])

    feed = LiveFeed(source, period_s=0.05)
    first, second = feed.subscribe(), feed.subscribe()
    a = await anext(first)
    b = await anext(second)
    assert a is not None and b is not None and a.node_id == b.node_id == "n1"
    assert feed.viewers == 2
    a2, b2 = await anext(first), await anext(second)
    assert a2 is b2 and a2 is not None and a2.node_id != "n1"  # one build, both viewers
    await first.aclose()
    assert feed.viewers == 1
    await feed.close()
    assert [s async for s in second] == []  # the open stream ends
    assert feed.viewers == 0 and feed.closed()
    assert [s async for s in sse_stream(feed)] == ["retry: 1000\n\n"]


async def test_live_feed_sends_a_keep_alive_when_nothing_changes(
    monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(live_module, "KEEPALIVE_S", 0.2)

    async def same() -> DashboardSnapshot:
        return DashboardSnapshot(generated_at=dt.datetime.now(dt.UTC), version="t",
                                 node_id="n", stale_after_s=10.0, machines=[], events=[])

    feed = LiveFeed(same, period_s=0.05)
    stream = sse_stream(feed, max_stream_s=0.5)
    parts = [part async for part in stream]
    assert parts[0] == "retry: 1000\n\n" and parts[1].startswith("event: snapshot\n")
    assert ": keep-alive\n\n" in parts[2:]  # only the timestamp changed: no new snapshot
    assert not any(p.startswith("event:") for p in parts[2:])
    assert feed.viewers == 0


# --- pages ------------------------------------------------------------------------------------

async def test_pages_load_only_what_the_app_serves(api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = api
    await register(client, VMC)
    for path in ("/", "/dashboard", "/machines/vmc-01"):
        r = await client.get(path)
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
        refs = re.findall(r'(?:src|href)="([^"]+)"', r.text)
        assert refs, path
        for ref in refs:
            assert ref.startswith("/"), f"{path} loads {ref} from elsewhere"
            if ref.startswith("/static/"):
                asset = await client.get(ref)
                assert asset.status_code == 200, ref
                text = asset.text.replace("http://www.w3.org/2000/svg", "")  # a name, not a URL
                text = re.sub(r"/\*!.*?\*/", "", text, flags=re.S)  # a licence banner's home
                assert "http://" not in text and "https://" not in text, ref
    r = await client.get("/machines/nope")
    assert r.status_code == 404 and "nope" in r.text
    r = await client.get("/machines/%3Cb%3E")
    assert r.status_code == 404 and "<b>" not in r.text and "&lt;b&gt;" in r.text
    for bad in ("/static/../app.py", "/static/%2e%2e/app.py", "/static/nothing.js"):
        assert (await client.get(bad)).status_code == 404, bad
    assert (await client.get("/static/dashboard.js")).headers["content-type"].startswith(
        "text/javascript")


async def test_pages_and_stream_stay_out_of_the_openapi_document(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    _, client = api
    paths = (await client.get("/openapi.json")).json()["paths"]
    assert "/api/dashboard" in paths and "/api/machines/{name}/maps/latest/grid" in paths
    assert not {"/", "/dashboard", "/api/live", "/machines/{name}"} & set(paths)


async def test_stale_temperatures_turn_an_applied_machine_warn(
    api: tuple[FastAPI, httpx.AsyncClient]
) -> None:
    """Temperatures that stop arriving (EDNC_TEMPERATURE_STALE_S, or the broker gone) show
    on the machine's row: the map is applied but the thermal part holds its last value."""
    from server.temperatures import TemperatureBoard

    app, client = api
    await register(client, {**VMC, "accuracy_tolerance_um": 25.0})
    center = center_of(app)
    center.registry.connected("vmc-01", "10.0.0.21:1")
    center.registry.seen("vmc-01", telemetry(0.0))
    r = await client.post("/api/machines/vmc-01/models", json={"body": MODEL}, headers=WRITE)
    assert r.status_code == 201, r.text
    db, mid = center.db, await machine_id(app, "vmc-01")
    await db.run(map_repo.add_map_version, mid, payload=b"m", model_version=1)
    sent = await db.run(map_repo.record_sent, mid, 1)
    await db.run(map_repo.record_answer, sent.id, acked=True)
    await verify(client, "vmc-01")
    board = TemperatureBoard(stale_after_s=60.0)
    board.update("vmc-01", "spindle", 24.5, source="rest")  # REST readings show too
    center.temperatures = board  # as the services hand it over

    async def row() -> tuple[str, str, list[tuple[str, bool, str]]]:
        card = (await client.get("/api/dashboard")).json()["machines"][0]
        return card["health"], card["health_reason"], [
            (t["name"], t["stale"], t["source"]) for t in card["temperatures"]]

    ok = await row()
    assert (ok[0], ok[2]) == ("ok", [("spindle", False, "rest")])
    board.stale_after_s = 0.01  # (EDNC_TEMPERATURE_STALE_S) no reading for longer
    await asyncio.sleep(0.02)
    health, reason, temps = await row()
    assert (health, temps) == ("warn", [("spindle", True, "rest")])
    assert reason.startswith("temperature stale (spindle ") and "holds the last good" \
        in reason, reason
    detail = (await client.get("/api/machines/vmc-01/dashboard")).json()["card"]
    assert detail["health"] == "warn" and "spindle" in detail["health_reason"]
    board.stale_after_s = 60.0
    board.update("vmc-01", "spindle", 24.6, source="mqtt")  # a fresh one: in order again
    assert (await row())[:2] == ok[:2]
    board.mark_stale(source="mqtt")  # the broker went away
    assert (await row())[0] == "warn"
    center.registry.disconnected("vmc-01")  # a worse state keeps its own reason
    assert (await row())[:2] == ("offline", "not connected")
