"""``/metrics`` per machine (the accuracy state and what it rests on, as the dashboard says
it), pre-created outcome labels, build info, no ``*_created`` clutter; and the example
alert rules in ``deploy/alerts.yml`` name only series that ``/metrics`` exposes."""

from __future__ import annotations

import datetime as dt
import re
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import httpx
import pytest
import yaml
from fastapi import FastAPI
from prometheus_client.parser import text_string_to_metric_families

from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.health import STATES
from server.settings import Settings
from server.version import __version__
from tests.support.api import API_KEY, SECRET, VMC, WRITE, center_of, running
from tests.support.dashboard import MODEL, OTHER, SIEMENS, diagonals_csv

ALERTS = Path(__file__).resolve().parent.parent / "deploy" / "alerts.yml"


@pytest.fixture
async def plant(tmp_path: Path) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:
    """Three machines: vmc-01 connected, verified, map v1 applied; dmu-02 connected, its
    map rejected; vmc-03 offline."""
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}", api_key=API_KEY)
    async with running(settings) as (app, client):
        for description in ({**VMC, "accuracy_tolerance_um": 25.0}, SIEMENS, OTHER):
            r = await client.post("/api/machines", json={**description, "secret": SECRET},
                                  headers=WRITE)
            assert r.status_code == 201, r.text
        db = center_of(app).db
        for name, acked in (("vmc-01", True), ("dmu-02", False)):
            r = await client.post(f"/api/machines/{name}/models", headers=WRITE,
                                  json={"body": {**MODEL, "machine": name}})
            assert r.status_code == 201, r.text
            row = await db.run(machine_repo.get_machine, name)
            assert row is not None
            await db.run(map_repo.add_map_version, row.id, payload=b"m", model_version=1)
            sent = await db.run(map_repo.record_sent, row.id, 1)
            assert sent is not None
            await db.run(map_repo.record_answer, sent.id, acked=acked, reject_reason="CRC")
        for set_name, scale in (("before", 10.0), ("after", 2.0)):
            r = await client.post("/api/machines/vmc-01/measurements",
                                  params={"set_name": set_name},
                                  content=diagonals_csv(scale).encode(),
                                  headers={**WRITE, "content-type": "text/csv"})
            assert r.status_code == 201
        r = await client.post("/api/machines/vmc-01/verifications", headers=WRITE,
                              json={"before": "before", "after": "after"})
        assert r.status_code == 201
        registry = center_of(app).registry
        now_ms = int(dt.datetime.now(dt.UTC).timestamp() * 1000)
        telemetry = {"timestamp_ms": now_ms, "state": "compensating", "map_version": 1,
                     "axes": {"X": {"position": 1.0, "compensation": 0.001}},
                     "temperatures": {"spindle": 21.5}}
        for name in ("vmc-01", "dmu-02"):
            registry.connected(name, "10.0.0.9:1")
            registry.seen(name, telemetry)
        yield app, client


def samples(text: str) -> dict[tuple[str, frozenset[tuple[str, str]]], float]:
    return {(s.name, frozenset(s.labels.items())): s.value
            for family in text_string_to_metric_families(text) for s in family.samples}


def value(found: dict[tuple[str, frozenset[tuple[str, str]]], float], name: str,
          **labels: str) -> float | None:
    return found.get((name, frozenset(labels.items())))


async def test_every_machine_has_its_series(plant: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = plant
    r = await client.get("/metrics")
    assert r.status_code == 200
    found = samples(r.text)
    dashboard = (await client.get("/api/dashboard")).json()["machines"]
    for card in dashboard:
        name = card["name"]
        states = {s: value(found, "ednc_machine_accuracy_state", machine=name, state=s)
                  for s in STATES}
        assert states == {s: 1.0 if s == card["health"] else 0.0 for s in STATES}, name
        assert value(found, "ednc_machine_connected", machine=name) == float(card["connected"])
        assert value(found, "ednc_machine_accuracy_tolerance_um", machine=name) == \
            card["accuracy"]["tolerance_um"]
    assert [c["health"] for c in dashboard] == ["alarm", "ok", "offline"]
    vmc = {"machine": "vmc-01"}
    assert value(found, "ednc_machine_map_version_applied", **vmc) == 1.0
    residual = dashboard[1]["accuracy"]["residual_um"]
    assert value(found, "ednc_machine_verification_residual_um", **vmc) == pytest.approx(residual)
    assert value(found, "ednc_machine_map_age_seconds", **vmc) is not None
    assert value(found, "ednc_machine_telemetry_age_seconds", **vmc) is not None
    assert value(found, "ednc_machine_temperature_celsius", sensor="spindle", **vmc) == 21.5
    thermal = value(found, "ednc_machine_thermal_state_age_seconds", **vmc)
    assert thermal == value(found, "ednc_machine_telemetry_age_seconds", **vmc)
    assert value(found, "ednc_machine_map_rejects_total", machine="dmu-02") == 1.0
    assert value(found, "ednc_machine_map_rejects_total", **vmc) == 0.0
    # no value, no series: vmc-03 never had a map or telemetry
    assert value(found, "ednc_machine_map_version_applied", machine="vmc-03") is None
    assert value(found, "ednc_machine_telemetry_age_seconds", machine="vmc-03") is None


async def test_service_series_are_there_before_the_first_event(
        plant: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = plant
    text = (await client.get("/metrics")).text
    found = samples(text)
    for outcome in ("applied", "rejected", "failed"):
        assert value(found, "ednc_map_pushes_total", outcome=outcome) == 0.0
    assert value(found, "ednc_connections_refused_total", reason="auth") == 0.0
    build = [k for k in found if k[0] == "ednc_build_info"]
    assert len(build) == 1 and ("version", __version__) in build[0][1]
    assert "_created" not in text


async def test_a_deleted_machine_leaves_the_metrics(
        plant: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = plant
    assert 'machine="vmc-03"' in (await client.get("/metrics")).text
    r = await client.delete("/api/machines/vmc-03", headers=WRITE)
    assert r.status_code == 204, r.text
    assert 'machine="vmc-03"' not in (await client.get("/metrics")).text


def rules() -> list[dict[str, Any]]:
    loaded = yaml.safe_load(ALERTS.read_text(encoding="utf-8"))
    return [rule for group in loaded["groups"] for rule in group["rules"]]


async def test_the_alert_rules_load_and_name_only_exposed_series(
        plant: tuple[FastAPI, httpx.AsyncClient]) -> None:
    _, client = plant
    exposed = {name for name, _ in samples((await client.get("/metrics")).text)}
    loaded = rules()
    names = {r["alert"] for r in loaded}
    assert {"EdncMachineOutOfTolerance", "EdncMapOld", "EdncTelemetryStale"} <= names
    assert len(names) == len(loaded)  # unique
    for rule in loaded:
        assert set(rule) <= {"alert", "expr", "for", "labels", "annotations"}, rule["alert"]
        assert rule["labels"]["severity"] in ("critical", "warning", "info")
        assert rule["annotations"]["summary"]
        if "for" in rule:
            assert re.fullmatch(r"\d+[smhd]", rule["for"]), rule["for"]
        metrics = re.findall(r"\b(ednc_[a-z_]+)\b", rule["expr"])
        assert metrics, rule["alert"]
        for metric in metrics:
            assert metric in exposed, f"{rule['alert']}: {metric} is not in /metrics"
        for state in re.findall(r'state="([a-z_]+)"', rule["expr"]):
            assert state in STATES, rule["alert"]
        for template in re.findall(r'"ednc_[a-z_]+\{', str(rule["annotations"])):
            assert template[1:-1] in exposed


async def test_the_out_of_tolerance_rule_fires_on_the_machine_that_is(
        tmp_path: Path) -> None:
    """The rule's expression, evaluated on a scrape: only the machine whose verification
    leaves more than its tolerance matches it."""
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}", api_key=API_KEY)
    async with running(settings) as (_, client):
        for description in ({**VMC, "accuracy_tolerance_um": 1.0}, OTHER):
            r = await client.post("/api/machines", json={**description, "secret": SECRET},
                                  headers=WRITE)
            assert r.status_code == 201
        for set_name, scale in (("before", 10.0), ("after", 2.0)):
            await client.post("/api/machines/vmc-01/measurements", params={"set_name": set_name},
                              content=diagonals_csv(scale).encode(),
                              headers={**WRITE, "content-type": "text/csv"})
        r = await client.post("/api/machines/vmc-01/verifications", headers=WRITE,
                              json={"before": "before", "after": "after"})
        assert r.status_code == 201
        found = samples((await client.get("/metrics")).text)
    [rule] = [r for r in rules() if r["alert"] == "EdncMachineOutOfTolerance"]
    metric, selector, threshold = re.fullmatch(
        r'(\w+)\{(\w+="\w+")\} == (\d+)', rule["expr"]).groups()  # type: ignore[union-attr]
    key, wanted = selector.split("=")
    firing = sorted(dict(labels)["machine"] for (name, labels), v in found.items()
                    if name == metric and dict(labels).get(key) == wanted.strip('"')
                    and v == float(threshold))
    assert firing == ["vmc-01"]
