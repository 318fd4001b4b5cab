"""A machine's history over a window, downsampled by the database (SQLite and PostgreSQL):
``/api/machines/{name}/history`` and ``/api/history``, and the correction sampler that
feeds the correction trends."""

from __future__ import annotations

import datetime as dt
from collections.abc import AsyncIterator
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi import FastAPI

from server.dashboard.sampler import CorrectionSampler
from server.db import history as history_repo
from server.db import maps as map_repo
from server.db import temperatures as reading_repo
from server.db.temperatures import NewReading
from server.events import EventKind
from server.settings import Settings
from tests.support.api import API_KEY, SECRET, VMC, WRITE, center_of, running
from tests.support.dashboard import OTHER, diagonals_csv

UNTIL = dt.datetime(2026, 11, 27, 12, 0, tzinfo=dt.UTC)
WINDOW_S = 1000.0


@pytest.fixture
async def api(database_url: str) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:
    async with running(Settings(database_url=database_url, api_key=API_KEY)) as pair:
        _, client = pair
        for description in (VMC, OTHER):
            r = await client.post("/api/machines", json={**description, "secret": SECRET},
                                  headers=WRITE)
            assert r.status_code == 201, r.text
        yield pair


async def machine_id(app: FastAPI, name: str) -> int:
    from server.db import machines as machine_repo
    row = await center_of(app).db.run(machine_repo.get_machine, name)
    assert row is not None
    return row.id


def readings(mid: int) -> tuple[list[NewReading], np.ndarray, np.ndarray]:
    """One reading a second over the window (and some outside it), a known ramp."""
    rng = np.random.default_rng(3)
    offsets = np.arange(-50.0, WINDOW_S + 50.0)  # s after the window's start
    celsius = 20.0 + offsets / 500.0 + rng.normal(0.0, 0.05, offsets.size)
    start = UNTIL - dt.timedelta(seconds=WINDOW_S)
    rows = [NewReading(mid, "T_spindle_C", float(c), start + dt.timedelta(seconds=float(o)),
                       "mqtt") for o, c in zip(offsets, celsius, strict=True)]
    return rows, offsets, celsius


async def test_temperatures_come_back_downsampled_to_the_buckets_asked_for(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    mid = await machine_id(app, "vmc-01")
    rows, offsets, celsius = readings(mid)
    await center_of(app).db.run(reading_repo.add_readings, rows)
    r = await client.get("/api/machines/vmc-01/history", params={
        "window_s": WINDOW_S, "points": 20, "until": UNTIL.isoformat()})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["bucket_s"] == 50.0
    [series] = body["temperatures"]
    assert (series["name"], series["unit"]) == ("spindle", "°C")
    inside = (offsets >= 0) & (offsets < WINDOW_S)
    bucket = (offsets[inside] // 50).astype(int)
    assert series["count"] == np.bincount(bucket).tolist()  # 50 per bucket, none outside
    means = np.bincount(bucket, weights=celsius[inside]) / np.bincount(bucket)
    assert series["mean"] == pytest.approx(means.tolist(), abs=1e-9)
    assert series["low"] == pytest.approx(
        [celsius[inside][bucket == k].min() for k in range(20)])
    assert series["high"] == pytest.approx(
        [celsius[inside][bucket == k].max() for k in range(20)])
    start = (UNTIL - dt.timedelta(seconds=WINDOW_S)).timestamp()
    assert series["t"] == pytest.approx([start + 50 * k + 24.5 for k in range(20)], abs=1e-3)
    # the other machine has none, and the fleet endpoint has both machines
    fleet = (await client.get("/api/history", params={
        "window_s": WINDOW_S, "points": 20, "until": UNTIL.isoformat()})).json()
    assert [(m["machine"], len(m["temperatures"])) for m in fleet["machines"]] == [
        ("vmc-01", 1), ("vmc-03", 0)]
    assert fleet["machines"][0]["temperatures"][0]["mean"] == series["mean"]


async def test_minute_summaries_give_the_same_buckets_as_the_readings(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    """Long windows read the per-minute summaries (and the readings after them): the
    buckets are those the readings give, whether the summaries reach the window's end,
    stop inside it, or do not exist yet."""
    app, client = api
    db = center_of(app).db
    rng = np.random.default_rng(5)
    rows = []
    for name, sensor in (("vmc-01", "T_spindle_C"), ("vmc-01", "T_bed_C"),
                         ("vmc-03", "T_spindle_C")):
        mid = await machine_id(app, name)
        stamps = np.sort(rng.uniform(-4 * 3600.0, 0.0, 3000))  # 4 h, irregular
        rows += [NewReading(mid, sensor, float(20 + rng.normal()),
                            UNTIL + dt.timedelta(seconds=float(t)), "mqtt") for t in stamps]
    await db.run(reading_repo.add_readings, rows)
    until = UNTIL + dt.timedelta(seconds=20)  # the window starts at 09:00:20
    params = {"window_s": 3 * 3600.0, "points": 30, "until": until.isoformat()}

    async def buckets() -> list[Any]:
        r = await client.get("/api/history", params=params)
        assert r.status_code == 200, r.text
        body = r.json()  # whole minutes from 09:00: 3 h 20 s in 30 buckets of 7 min
        assert (body["bucket_s"], body["since"]) == (420.0, "2026-11-27T09:00:00Z")
        return [(m["machine"], s["name"], s["count"], s["mean"], s["low"], s["high"], s["t"])
                for m in body["machines"] for s in m["temperatures"]]

    from_readings = await buckets()
    assert sum(sum(b[2]) for b in from_readings) > 6000
    rolled = 0
    for now in (UNTIL - dt.timedelta(minutes=50), UNTIL + dt.timedelta(minutes=5)):
        while n := await db.run(history_repo.roll_up, now, chunk_s=3600.0):
            rolled += n
        got = await buckets()
        assert [b[:3] for b in got] == [b[:3] for b in from_readings]  # same counts
        for a, b in zip(got, from_readings, strict=True):
            assert a[3] == pytest.approx(b[3], abs=1e-9)  # means
            assert (a[4], a[5]) == (b[4], b[5])  # extremes
            assert a[6] == pytest.approx(b[6], abs=2e-3)  # mean times
    assert rolled == 3 * 4 * 60  # every minute of every sensor, once
    assert await db.run(history_repo.roll_up, UNTIL + dt.timedelta(minutes=5)) == 0
    assert await db.run(history_repo.delete_minutes_before,
                        UNTIL - dt.timedelta(hours=1)) == 3 * 3 * 60


async def test_windows_and_points_out_of_range_are_refused(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = api
    for params in ({"window_s": 10}, {"points": 5}, {"points": 100000},
                   {"window_s": "nan"}, {"until": "yesterday"},
                   {"until": "0001-01-01T00:00:00"}, {"until": "9999-12-31T23:59:59Z"}):
        r = await client.get("/api/machines/vmc-01/history", params=params)
        assert r.status_code == 422, (params, r.text)
    r = await client.get("/api/machines/nope/history")
    assert r.status_code == 404
    r = await client.get("/api/history", params={"until": "1970-01-01T00:00:00"})
    assert r.status_code == 422 and "until must lie between" in r.text
    r = await client.get("/api/machines/vmc-01/history", params={
        "until": "2026-11-27T12:00:00", "window_s": 3600})  # no offset: UTC
    assert r.status_code == 200 and r.json()["until"] == "2026-11-27T12:00:00Z"


async def test_corrections_maps_verifications_and_events_are_in_the_history(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    center = center_of(app)
    mid = await machine_id(app, "vmc-01")
    sampler = CorrectionSampler(center)
    center.registry.connected("vmc-01", "10.0.0.21:1")
    for k, comp_mm in enumerate((0.001, 0.003, 0.002)):
        center.registry.seen("vmc-01", {
            "timestamp_ms": 1_800_000_000_000 + k, "state": "compensating", "map_version": 1,
            "axes": {"X": {"position": 1.0, "compensation": comp_mm},
                     "C": {"position": 0.0, "compensation": 1e-4}}})
        assert sampler.poll() == 1
        assert sampler.poll() == 0  # the same telemetry is counted once
    assert await sampler.flush() == 2  # one row per axis
    await center.db.run(map_repo.add_map_version, mid, payload=b"m", model_version=1,
                        temperatures={"T_spindle_C": 21.5})
    sent = await center.db.run(map_repo.record_sent, mid, 1)
    assert sent is not None
    await center.db.run(map_repo.record_answer, sent.id, acked=True)
    for set_name, scale in (("before", 10.0), ("after", 2.0)):
        r = await client.post("/api/machines/vmc-01/measurements", params={"set_name": set_name},
                              content=diagonals_csv(scale).encode(),
                              headers={**WRITE, "content-type": "text/csv"})
        assert r.status_code == 201, r.text
    report = (await client.post("/api/machines/vmc-01/verifications", headers=WRITE,
                                json={"before": "before", "after": "after"})).json()
    await center.record_event(EventKind.PUSHED, "vmc-01",
                              "map version 1 (1 bytes): test")
    body = (await client.get("/api/machines/vmc-01/history",
                             params={"window_s": 3600})).json()
    comps = {s["name"]: s for s in body["corrections"]}
    assert sorted(comps) == ["C", "X"]
    assert (comps["X"]["unit"], comps["C"]["unit"]) == ("µm", "µrad")
    assert comps["X"]["mean"] == pytest.approx([2.0])
    assert (comps["X"]["low"], comps["X"]["high"], comps["X"]["count"]) == (
        pytest.approx([1.0]), pytest.approx([3.0]), [3])
    assert comps["C"]["mean"][0] == pytest.approx(1e-4 * np.pi / 180 * 1e6)
    [delivery] = body["maps"]
    assert (delivery["version"], delivery["state"], delivery["built_at_C"]) == (
        1, "applied", {"T_spindle_C": 21.5})
    [verification] = body["verifications"]
    assert verification["id"] == report["id"] and verification["compensated"] is True
    assert verification["residual_um"] == pytest.approx(
        max(report["result"]["ranges_after_um"].values()))
    assert verification["before_um"] == pytest.approx(
        max(report["result"]["ranges_before_um"].values()))
    assert [e["kind"] for e in body["events"]] == ["pushed"]
    # the window ends now: an hour ago there was nothing
    past = (dt.datetime.now(dt.UTC) - dt.timedelta(hours=2)).isoformat()
    old: dict[str, Any] = (await client.get("/api/machines/vmc-01/history", params={
        "window_s": 3600, "until": past})).json()
    assert (old["corrections"], old["maps"], old["verifications"], old["events"]) == (
        [], [], [], [])


async def test_sampled_corrections_are_pruned_after_their_retention(
        api: tuple[FastAPI, httpx.AsyncClient]) -> None:
    app, client = api
    center = center_of(app)
    sampler = CorrectionSampler(center, retention_days=1.0)
    center.registry.connected("vmc-01", "10.0.0.21:1")
    center.registry.seen("vmc-01", {"timestamp_ms": 1, "axes": {"X": {"position": 0.0,
                                                                        "compensation": 0.001}}})
    sampler.poll()
    await sampler.flush(now=dt.datetime.now(dt.UTC) - dt.timedelta(days=2))
    center.registry.seen("vmc-01", {"timestamp_ms": 2, "axes": {"X": {"position": 0.0,
                                                                        "compensation": 0.001}}})
    sampler.poll()
    await sampler.flush()
    assert await sampler.prune_once() == 1
    body = (await client.get("/api/machines/vmc-01/history",
                             params={"window_s": 3 * 86400})).json()
    assert body["corrections"][0]["count"] == [1]
