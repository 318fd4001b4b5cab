"""The temperature intake (server/intake.py, server/forward.py, the REST route), with the
real machine services on SQLite and PostgreSQL: every refusal reason, the last good value
kept, the time series stored and pruned, coalesced forwarding, and over real Mosquitto and
TCP a published temperature reaching a simulated machine's ``controller.temperatures``
without any map being built for it."""

from __future__ import annotations

import asyncio
import datetime as dt
import json
import math
import uuid
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from protocol import Temperatures
from server.center import Center
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db import temperatures as reading_repo
from server.db.temperatures import NewReading
from server.events import EventKind
from server.forward import TemperatureForwarder, sensor_name
from server.intake import TemperatureIntake, description_columns, model_columns
from server.settings import load_settings
from tests.support.api import API_KEY, WRITE, running
from tests.support.intake import _app, client_of
from tests.support.link import (
    DEADLINE_S,
    SECRET,
    description,
    model_body,
    rig,
    simulator,
    until,
)
from tests.support.mqtt import publisher
from volumetric.model.lag import first_order_lag


def intake_of(center: Center) -> TemperatureIntake:
    assert center.intake is not None
    return center.intake


def test_known_columns_from_model_and_description() -> None:
    body = model_body(thermal_sensor="T_spindle_C")
    body["terms"].append({"effect": "backlash", "axis": "x", "sensor": None,
                          "reversal_um": 4.0})
    assert model_columns(body) == {"T_spindle_C"}
    assert description_columns({"sensors": ["air", "T_bed_C", "bad name", 3]}) == {
        "T_air_C", "T_bed_C"}
    assert description_columns({}) == frozenset()
    assert sensor_name("T_x_screw_C") == "x_screw"


async def test_every_refusal_keeps_the_last_good_value(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.db.run(machine_repo.create_machine, name="vmc-01", ip="127.0.0.1",
                       controller="fanuc", secret=SECRET,
                       description={**description("vmc-01", "fanuc", "127.0.0.1"),
                                    "sensors": ["air"]})
        intake = intake_of(r.center)
        board = r.services.temperatures
        registry = r.center.metrics.registry
        for reason in ("not_finite", "out_of_range", "unknown_sensor", "too_fast",
                       "unknown_machine"):  # on the metrics endpoint from the start, at 0
            assert registry.get_sample_value("ednc_temperatures_refused_total",
                                              {"reason": reason}) == 0, reason
        assert await intake.lookup("vmc-01") == frozenset({"T_air_C"})
        assert intake.take("vmc-01", "air", 20.0) is None
        cases = [("air", math.nan, "not_finite"), ("air", 150.0, "out_of_range"),
                 ("air", -40.0, "out_of_range"), ("bed", 20.0, "unknown_sensor"),
                 ("air", 35.0, "too_fast"), ("bad name", 20.0, "unknown_sensor")]
        for sensor, celsius, reason in cases:
            refusal = intake.take("vmc-01", sensor, celsius)
            assert refusal is not None and refusal.reason == reason, (sensor, celsius)
            assert board.readings("vmc-01")["T_air_C"].celsius == 20.0
        refusal = intake.take("nobody", "air", 20.0)
        assert refusal is None  # held while "nobody" is looked up ...
        await until(lambda: intake.refusals[-1].machine == "nobody")
        assert intake.refusals[-1].reason == "unknown_machine"  # ... and then refused
        assert not board.readings("nobody")
        assert intake.take("vmc-01", "air", 21.5) is None  # within the allowance
        for reason in ("not_finite", "out_of_range", "unknown_sensor", "too_fast",
                       "unknown_machine"):
            assert registry.get_sample_value("ednc_temperatures_refused_total",
                                              {"reason": reason}), reason
        assert registry.get_sample_value("ednc_temperatures_refused_total",
                                          {"reason": "out_of_range"}) == 2

        async def evented() -> bool:  # the events are stored in the background
            errors = await r.events(EventKind.ERROR)
            return any("T_air_C refused" in e.detail and "outside" in e.detail
                       for e in errors)

        await until(evented)
        # a machine registered and given a model after start-up is known at once
        await r.register("vmc-02", ip="127.0.0.2",
                         model=model_body("vmc-02", thermal_sensor="T_spindle_C"))
        assert intake.take("vmc-02", "spindle", 22.0) is None
        await until(lambda: "T_spindle_C" in board.readings("vmc-02"))


async def test_telemetry_is_screened_too(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        await r.register("sie-01", controller="siemens", model=model_body("sie-01"))
        board = r.services.temperatures
        await intake_of(r.center).lookup("sie-01")
        # a machine's own Telemetry names its sensors: no model column needed
        assert board.update("sie-01", "column", 21.0, source="telemetry")
        assert not board.update("sie-01", "column", 500.0, source="telemetry")
        assert board.readings("sie-01")["T_column_C"].celsius == 21.0


async def test_readings_are_stored_listed_and_pruned(tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body(thermal_sensor="T_spindle_C"))
        intake = intake_of(r.center)
        await intake.lookup("vmc-01")
        t0 = 1_763_820_000.0
        for k in range(5):
            assert intake.take("vmc-01", "spindle", 20.0 + 0.1 * k, source="mqtt",
                               at=t0 + k) is None
        assert await intake.flush() == 5
        rows = await r.db.run(reading_repo.list_readings, mid)
        assert [round(x.celsius, 3) for x in rows] == [20.4, 20.3, 20.2, 20.1, 20.0]
        assert rows[0].time == dt.datetime.fromtimestamp(t0 + 4, dt.UTC)
        assert {x.source for x in rows} == {"mqtt"} and {x.sensor for x in rows} == {
            "T_spindle_C"}
        window = await r.db.run(reading_repo.list_readings, mid,
                                since=dt.datetime.fromtimestamp(t0 + 1, dt.UTC),
                                until=dt.datetime.fromtimestamp(t0 + 3, dt.UTC))
        assert [round(x.celsius, 3) for x in window] == [20.2, 20.1]
        old = dt.datetime.now(dt.UTC) - dt.timedelta(days=intake.retention_days + 1)
        await r.db.run(reading_repo.add_readings,
                       [NewReading(mid, "T_spindle_C", 19.0, old, "rest")])
        assert await intake.prune_once() == 6  # the 2025 readings are old too
        assert await r.db.run(reading_repo.list_readings, mid) == []


async def test_pruning_bounds_the_table_by_age_and_by_count_in_batches(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=model_body(thermal_sensor="T_spindle_C"))
        intake = intake_of(r.center)
        now = dt.datetime.now(dt.UTC)
        old = now - dt.timedelta(days=intake.retention_days + 1)
        rows = [NewReading(mid, "T_spindle_C", 10.0 + k, old, "rest") for k in range(7)]
        rows += [NewReading(mid, "T_spindle_C", 20.0 + k, now - dt.timedelta(seconds=30 - k),
                            "mqtt") for k in range(25)]
        await r.db.run(reading_repo.add_readings, rows)
        intake.max_rows = 10
        # 7 too old, then 15 beyond the newest 10, three rows per transaction
        assert await intake.prune_once(batch=3) == 22
        kept = await r.db.run(reading_repo.list_readings, mid)
        assert [x.celsius for x in kept] == [20.0 + k for k in range(24, 14, -1)]
        assert await intake.prune_once(batch=3) == 0
        with pytest.raises(ValueError, match="max_rows"):
            TemperatureIntake(r.center, r.services.temperatures, max_rows=0)


class FakeSession:
    """Collects what the forwarder sends (the sans-I/O message, not bytes)."""

    def __init__(self) -> None:
        self.sent: list[Temperatures] = []

    def send(self, msg: Temperatures) -> None:
        self.sent.append(msg)


async def test_forwarding_coalesces_per_machine_last_value_wins() -> None:
    a, b = FakeSession(), FakeSession()
    fwd = TemperatureForwarder({"a": a, "b": b}, interval_s=0.05,  # type: ignore[dict-item]
                               clock=lambda: 1000.0)
    fwd.note("a", "T_spindle_C", 21.0, 999.5)       # sent at once
    for k in range(1, 5):                           # within the interval: coalesced
        fwd.note("a", "T_spindle_C", 21.0 + k, 1000.0)
    fwd.note("a", "T_air_C", 19.0, 1000.0)
    fwd.note("b", "T_spindle_C", 30.0, 1000.0)      # another machine: its own interval
    fwd.note("c", "T_spindle_C", 30.0, 1000.0)      # no session: skipped
    assert [m.readings for m in a.sent] == [(a.sent[0].readings[0],)]
    first = a.sent[0].readings[0]
    assert (first.name, first.celsius, first.age_ms) == ("spindle", 21.0, 500)
    assert len(b.sent) == 1 and fwd.stats.no_session == 1
    await until(lambda: len(a.sent) == 2)
    second = {x.name: x.celsius for x in a.sent[1].readings}
    assert second == {"spindle": 25.0, "air": 19.0}
    assert fwd.stats.coalesced == 3  # 22, 23 and 24 °C were overtaken before they left
    assert a.sent[1].timestamp_ms == 1_000_000
    fwd.note("a", "T_" + "n" * 17 + "_C", 20.0, 1000.0)  # too long for the wire
    assert fwd.stats.unsendable == 1
    fwd.close()


@pytest.mark.services
async def test_published_temperature_reaches_the_machine_without_a_map_build(
        tmp_path: Path, mqtt_broker: tuple[str, int]) -> None:
    top = f"ednc-test-{uuid.uuid4().hex[:12]}"
    async with asyncio.timeout(DEADLINE_S), \
            rig(tmp_path, mqtt=mqtt_broker, prefix=top,
                mqtt_options={"stale_check_s": 0.05}) as r, \
            publisher(mqtt_broker) as pub:
        # a model without thermal terms: the push scheduler has nothing to rebuild for
        # a temperature, so whatever reaches the machine came as Temperatures
        mid = await r.register(model=model_body())
        await r.db.run(machine_repo.update_machine, "vmc-01", description={
            **description("vmc-01", "fanuc", "127.0.0.1"), "sensors": ["spindle"]})
        assert r.services.mqtt is not None
        await r.services.mqtt.connected.wait()
        await pub.publish(f"{top}/vmc-01/temperature/spindle", "22.5")  # before it connects
        await until(lambda: "T_spindle_C" in r.services.temperatures.readings("vmc-01"))
        async with simulator(r.port) as sim:
            store = sim.runtime.controller.temperatures
            await until(lambda: store.values().get("T_spindle_C") == 22.5)  # at connect
            await until(lambda: sim.runtime.controller.store.version == 1)  # its one map
            for k in range(1, 6):
                celsius = 22.5 + 0.25 * k
                await pub.publish(f"{top}/vmc-01/temperature/spindle",
                                  json.dumps({"celsius": celsius}))
                await until(lambda c=celsius: store.values().get("T_spindle_C") == c)
            await pub.publish(f"{top}/vmc-01/temperature/spindle", "95.0")  # too fast
            await pub.publish(f"{top}/vmc-01/temperature/spindle", "24.0")
            await until(lambda: store.values().get("T_spindle_C") == 24.0)
            assert sim.stats.temperatures_received >= 6
            assert store.readings()["spindle"].source == "center"
        assert r.services.intake is not None
        assert any(f.reason == "too_fast" for f in r.services.intake.refusals)
        maps = await r.db.run(map_repo.list_map_versions, mid)
        assert len(maps) == 1  # the first map only: no rebuild for any temperature


async def test_rest_post_and_get(tmp_path: Path, database_url: str) -> None:
    app = _app(tmp_path, database_url)
    async with asyncio.timeout(DEADLINE_S), client_of(app) as client:
        desc = {**description("vmc-01", "fanuc", "10.0.0.21"), "sensors": ["air"]}
        r = await client.post("/api/machines", json={**desc, "secret": SECRET}, headers=WRITE)
        assert r.status_code == 201, r.text
        r = await client.post("/api/machines/vmc-01/models", headers=WRITE,
                              json={"body": model_body(thermal_sensor="T_spindle_C")})
        assert r.status_code == 201, r.text
        url = "/api/machines/vmc-01/temperatures"
        body = {"readings": [{"sensor": "spindle", "celsius": 23.0,
                              "time": "2026-11-24T10:00:00Z"},
                             {"sensor": "air", "celsius": 20.5},
                             {"sensor": "bed", "celsius": 20.0},
                             {"sensor": "spindle", "celsius": 150.0}]}
        assert (await client.post(url, json=body)).status_code == 401
        r = await client.post(url, json=body, headers=WRITE)
        assert r.status_code == 200, r.text
        taken = r.json()
        assert (taken["accepted"], taken["refused"]) == (2, 2)
        assert [v["reason"] for v in taken["verdicts"]] == [None, None, "unknown_sensor",
                                                             "out_of_range"]
        r = await client.post(url, json={"readings": [{"sensor": "bed", "celsius": 1}]},
                              headers=WRITE)
        assert r.status_code == 422 and r.json()["detail"][0]["type"] == "unknown_sensor"
        r = await client.post(url, headers=WRITE,
                              json={"readings": [{"sensor": "air", "celsius": "NaN"}]})
        assert r.status_code == 422
        assert (await client.post("/api/machines/nobody/temperatures", json=body,
                                  headers=WRITE)).status_code == 404
        center = app.state.center
        assert isinstance(center, Center) and center.intake is not None
        await center.intake.flush()
        r = await client.get(url)
        assert r.status_code == 200, r.text
        got = r.json()
        assert got["known_sensors"] == ["T_air_C", "T_spindle_C"]
        assert {x["sensor"]: x["celsius"] for x in got["latest"]} == {
            "T_air_C": 20.5, "T_spindle_C": 23.0}
        assert sorted((x["sensor"], x["celsius"]) for x in got["history"]) == [
            ("T_air_C", 20.5), ("T_spindle_C", 23.0)]
        assert {x["reason"] for x in got["refusals"]} == {"unknown_sensor", "out_of_range"}
        r = await client.get(url, params={"sensor": "spindle",
                                          "until": "2026-11-24T10:00:01Z"})
        assert [x["celsius"] for x in r.json()["history"]] == [23.0]
        assert (await client.get(url, params={"since": "2026-11-24T10:00:00"})
                ).status_code == 422


async def test_post_without_the_machine_services_says_why(tmp_path: Path) -> None:
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'api.db'}",
                             api_key=API_KEY)
    async with running(settings) as (_, client):  # an API-only process
        r = await client.post("/api/machines", headers=WRITE, json={
            **description("vmc-01", "fanuc", "10.0.0.21"), "secret": SECRET})
        assert r.status_code == 201, r.text
        url = "/api/machines/vmc-01/temperatures"
        r = await client.post(url, headers=WRITE,
                              json={"readings": [{"sensor": "spindle", "celsius": 20.0}]})
        assert r.status_code == 409 and "not running" in r.json()["detail"]
        r = await client.get(url)
        assert r.status_code == 200 and r.json()["known_sensors"] is None


async def test_a_connected_machines_telemetry_is_taken_at_once_and_stored(
        tmp_path: Path) -> None:
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(controller="siemens", model=model_body())  # after start-up
        intake = intake_of(r.center)
        assert intake.knows("vmc-01") is None
        async with simulator(r.port, controller="siemens") as sim:
            await sim.ready.wait()
            await until(lambda: "T_spindle_C" in r.services.temperatures.readings("vmc-01"))
            await until(lambda: intake.knows("vmc-01") is not None)
        await intake.flush()
        rows = await r.db.run(reading_repo.list_readings, mid, sensor="T_spindle_C")
        assert rows and {x.source for x in rows} == {"telemetry"}
        assert intake.stats.refused == 0


def lagged_body(tau_s: float) -> dict[str, Any]:
    """vmc-01's model with a lagged spindle drift along z (as ednc diagnose --out saves)."""
    body = model_body()
    body["terms"] = [{"effect": "thermal_dynamic", "axis": "z", "intercept_um": 0.0,
                      "t0_s": 0.0, "t_state_s": None,
                      "columns": [{"kind": "lag", "sensor": "T_spindle_C", "tau_s": tau_s,
                                   "coefficient": -2.0}]}]
    return body


async def test_a_lag_state_is_warmed_from_the_stored_readings(tmp_path: Path) -> None:
    """After a restart the center's first reading of a lag's sensor does not start the lag
    at rest: the stored readings before it give its state, as first_order_lag over the
    whole series does; readings after it step it on."""
    tau = 3600.0
    t0 = dt.datetime.now(dt.UTC).timestamp() - 6 * tau
    t = t0 + np.arange(0.0, 5 * tau, 60.0)
    ramp = 20.0 + 4.0 * (t - t0) / (5 * tau)  # warming 0.8 K/h: the lag trails by ~0.8 K
    live = [(t[-1] + 60.0, 24.0), (t[-1] + 120.0, 24.5)]
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=lagged_body(tau))
        intake = intake_of(r.center)
        await intake.lookup("vmc-01")
        assert intake.knows("vmc-01") == {"T_spindle_C", "T_lag1_C"}
        await r.db.run(reading_repo.add_readings, [
            NewReading(mid, "T_spindle_C", float(c), dt.datetime.fromtimestamp(s, dt.UTC),
                       "mqtt") for s, c in zip(t, ramp, strict=True)])
        when, celsius = live[0]
        assert intake.take("vmc-01", "spindle", celsius, source="mqtt", at=when) is None
        all_t = np.concatenate((t, [when]))
        expected = first_order_lag(all_t, np.concatenate((ramp, [celsius])), tau)[-1]

        def lag() -> float:
            reading = r.services.temperatures.reading("vmc-01", "T_lag1_C")
            return math.nan if reading is None else reading.celsius

        await until(lambda: bool(abs(lag() - expected) < 1e-9))
        assert abs(expected - celsius) > 0.5  # at rest it would have been the reading
        when, celsius = live[1]
        assert intake.take("vmc-01", "spindle", celsius, source="mqtt", at=when) is None
        all_t = np.concatenate((all_t, [when]))
        series = np.concatenate((ramp, [live[0][1], celsius]))
        assert lag() == pytest.approx(first_order_lag(all_t, series, tau)[-1], abs=1e-9)
        await intake.flush()
        stored = {x.sensor for x in await r.db.run(reading_repo.list_readings, mid,
                                                   limit=10_000)}
        assert stored == {"T_spindle_C"}  # the lag states are derived: not stored


async def test_a_lag_of_several_sensors_is_the_weighted_sum_of_their_lags(
        tmp_path: Path) -> None:
    """A lagged model that weighs two sensors at one time constant (an averaged model,
    as ednc diagnose saves it) is one state sent: each sensor's own lag, warmed from its
    stored readings and stepped by its own readings at their own times, summed with the
    weights. Nothing is sent until both sensors have a state."""
    tau = 1800.0
    body = model_body()
    body["terms"] = [{"effect": "thermal_dynamic", "axis": "z", "intercept_um": 0.0,
                      "t0_s": 0.0, "t_state_s": None, "columns": [
                          {"kind": "lag", "sensor": "T_spindle_C", "tau_s": tau,
                           "coefficient": 3.0},
                          {"kind": "lag", "sensor": "T_column_C", "tau_s": tau,
                           "coefficient": -1.0}]}]
    t0 = dt.datetime.now(dt.UTC).timestamp() - 4 * tau
    t = {"T_spindle_C": t0 + np.arange(0.0, 3 * tau, 60.0),
         "T_column_C": t0 + 7.0 + np.arange(0.0, 3 * tau, 90.0)}
    x = {"T_spindle_C": 20.0 + 5.0 * (t["T_spindle_C"] - t0) / (3 * tau),
         "T_column_C": 21.0 - 1.0 * (t["T_column_C"] - t0) / (3 * tau)}
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path) as r:
        mid = await r.register(model=body)
        intake = intake_of(r.center)
        await intake.lookup("vmc-01")
        assert intake.knows("vmc-01") == {"T_spindle_C", "T_column_C", "T_lag1_C"}
        await r.db.run(reading_repo.add_readings, [
            NewReading(mid, s, float(c), dt.datetime.fromtimestamp(w, dt.UTC), "mqtt")
            for s in t for w, c in zip(t[s], x[s], strict=True)])

        def lag() -> float:
            reading = r.services.temperatures.reading("vmc-01", "T_lag1_C")
            return math.nan if reading is None else reading.celsius

        def expected() -> float:
            y = {s: first_order_lag(t[s], x[s], tau)[-1] for s in t}
            return 20.0 + 0.75 * (y["T_spindle_C"] - 20.0) - 0.25 * (y["T_column_C"] - 20.0)

        live = [("spindle", 3 * tau + 30.0, 25.2), ("column", 3 * tau + 45.0, 19.9),
                ("spindle", 3 * tau + 90.0, 25.4), ("spindle", 3 * tau + 150.0, 25.5),
                ("column", 3 * tau + 160.0, 19.8)]
        for k, (sensor, dt_s, celsius) in enumerate(live):
            column = f"T_{sensor}_C"
            assert intake.take("vmc-01", sensor, celsius, source="mqtt",
                               at=t0 + dt_s) is None
            t[column] = np.append(t[column], t0 + dt_s)
            x[column] = np.append(x[column], celsius)
            if k == 0:  # the column sensor has no state yet: nothing to send
                await asyncio.sleep(0.2)
                assert math.isnan(lag())
                continue
            want = expected()
            await until(lambda want=want: bool(abs(lag() - want) < 1e-9))
        # the center's value is not either sensor's own lag nor their plain mean
        y = {s: first_order_lag(t[s], x[s], tau)[-1] for s in t}
        assert min(abs(lag() - v) for v in y.values()) > 0.5
        card = r.services.temperatures.notes[("vmc-01", "T_lag1_C")]
        assert card == "a weighted sum of 2 sensors through a 30 min lag"
        # dated by its stalest sensor: the spindle's last reading, not the column's later one
        sent = r.services.temperatures.reading("vmc-01", "T_lag1_C")
        assert sent is not None and sent.time == t["T_spindle_C"][-1] < t["T_column_C"][-1]
