"""Garbage through the center's entry points (issue 32): REST uploads (measurement CSVs,
temperature readings, machine descriptions), MQTT temperature messages and fleet files.
The CLI's share is ``tests/test_cli_fuzz.py``; the two together are >= 10,000 cases per
run (``CASES`` here and there, derandomised so CI sees the same ones).

A case is fine when the input is taken, or refused with a reason: an HTTP status below
500 (never a 5xx, never an exception out of the app), an MQTT message refused and
counted, a fleet file refused with :class:`~machine_sim.fleet.FleetSpecError`. And a
refused input leaves nothing behind: no measurement set, no machine, no reading on the
board or in the database's buffer.

The app runs once for the module (SQLite, the machine services, in-process through
httpx's ASGI transport) on an event loop of its own thread; each hypothesis example
hands its requests to that loop.
"""

from __future__ import annotations

import asyncio
import json
import shutil
import string
import tempfile
import threading
from collections.abc import AsyncIterator, Coroutine, Iterator
from concurrent.futures import Future
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import httpx
import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sqlalchemy import func, select
from sqlalchemy.orm import Session

from machine_sim.fleet import FleetSpecError, generated_fleet, load_fleet
from server.app import create_app
from server.center import Center
from server.db.tables import MachineRow, MeasurementSetRow
from server.links.ednc import LinkTiming
from server.mqtt import MqttBridge
from server.services import MachineServices, machine_services
from server.settings import load_settings
from tests.support.api import API_KEY, WRITE, backlash_csv
from tests.support.fuzz import JSON, NUMBERS, TEXT, mutate, readings_csv
from tests.support.link import SECRET, description

pytestmark = pytest.mark.slow

CASES = {"uploads": 1000, "temperatures": 800, "machines": 600, "mqtt": 1600,
         "fleet": 1000}
SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow,
                                       HealthCheck.function_scoped_fixture,
                                       HealthCheck.data_too_large])
T = TypeVar("T")
MACHINE = "vmc-01"


@dataclass
class Center_:
    """The running app: its client, center and services, on the loop of its thread."""

    loop: asyncio.AbstractEventLoop
    client: httpx.AsyncClient
    center: Center
    services: MachineServices
    bridge: MqttBridge

    def run(self, coro: Coroutine[Any, Any, T]) -> T:
        future: Future[T] = asyncio.run_coroutine_threadsafe(coro, self.loop)
        return future.result(timeout=120)

    def state(self) -> tuple[int, int, int, int]:
        """What a refused input must not change: machines, measurement sets, readings on
        the board and readings accepted (each accepted one goes to the database)."""
        # on the loop's own thread: a few ms of SQLite, cheaper than the thread hop
        names, sets = self.center.db.call(_counts)
        board = sum(len(self.services.temperatures.readings(n)) for n in names)
        intake = self.services.intake
        accepted = intake.stats.accepted if intake is not None else 0
        return len(names), sets, board, accepted


def _counts(session: Session) -> tuple[list[str], int]:
    names = list(session.scalars(select(MachineRow.name)))
    return names, int(session.scalar(select(func.count(MeasurementSetRow.id))) or 0)


@pytest.fixture(scope="module")
def center(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Center_]:
    d = tmp_path_factory.mktemp("entry-fuzz")
    shm = Path("/dev/shm")
    if shm.is_dir():  # no fsync per commit: the cases are about answers, not the disk
        d = Path(tempfile.mkdtemp(prefix="ednc-entry-fuzz-", dir=shm))
    settings = load_settings(database_url=f"sqlite:///{d / 'c.db'}", api_key=API_KEY,
                             machine_host="127.0.0.1", machine_port=0)
    held: dict[str, MachineServices] = {}

    @asynccontextmanager
    async def services(center: Center) -> AsyncIterator[MachineServices]:
        async with machine_services(center, timing=LinkTiming(heartbeat_s=1.0)) as svc:
            held["svc"] = svc
            yield svc

    app = create_app(settings, services=[services])
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, name="entry-fuzz", daemon=True)
    thread.start()
    stop = asyncio.Event()
    ready: Future[Center_] = Future()

    async def serve() -> None:
        try:
            async with app.router.lifespan_context(app):
                transport = httpx.ASGITransport(app=app, raise_app_exceptions=True)
                async with httpx.AsyncClient(transport=transport,
                                             base_url="http://test") as client:
                    svc = held["svc"]
                    c = app.state.center
                    bridge = MqttBridge(c, svc.feed, svc.temperatures, host="127.0.0.1")
                    ready.set_result(Center_(loop, client, c, svc, bridge))
                    await stop.wait()
        except BaseException as exc:  # start-up failed: say so to the test
            if not ready.done():
                ready.set_exception(exc)
            raise

    served = asyncio.run_coroutine_threadsafe(serve(), loop)
    c = ready.result(timeout=120)
    r = c.run(c.client.post("/api/machines", headers=WRITE, json={
        **description(MACHINE, "fanuc", "10.0.0.21"), "sensors": ["spindle", "air"],
        "secret": SECRET}))
    assert r.status_code == 201, r.text
    try:
        yield c
    finally:
        loop.call_soon_threadsafe(stop.set)
        served.result(timeout=120)
        loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout=30)
        if d.parent == shm:
            shutil.rmtree(d, ignore_errors=True)


def _fine(r: httpx.Response, case: Any) -> bool:
    """The app answered without a fault; True when it took the input."""
    assert r.status_code < 500, (case, r.status_code, r.text[:500])
    return r.status_code < 300


# -- REST: measurement uploads

UPLOAD = st.one_of(
    readings_csv().map(lambda t: t.encode("utf-8", "surrogatepass")),
    st.binary(max_size=300),
    st.builds(lambda t, enc: t.encode(enc, "surrogatepass" if enc == "utf-8" else "replace"),
              readings_csv(), st.sampled_from(["utf-16", "utf-16-le", "latin-1", "utf-8"])),
    st.just(backlash_csv(5.0).encode()),
)


@settings(max_examples=CASES["uploads"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_measurement_uploads(center: Center_, data: st.DataObject) -> None:
    body = data.draw(UPLOAD)
    media = data.draw(st.sampled_from(["text/csv", "text/csv", "multipart", "image/png"]))
    name = data.draw(st.one_of(st.none(), st.text(alphabet=string.ascii_letters + "-_.",
                                                  min_size=1, max_size=20)))

    async def case() -> None:
        before = center.state()
        url = f"/api/machines/{MACHINE}/measurements"
        params = {"set_name": name} if name is not None else {}
        if media == "multipart":
            r = await center.client.post(url, headers=WRITE, params=params,
                                         files={"file": (name or "u.csv", body)})
        else:
            r = await center.client.post(url, headers={**WRITE, "Content-Type": media},
                                         params=params, content=body)
        after = center.state()
        if _fine(r, (media, body[:200])):
            assert after[1] == before[1] + 1
        else:
            assert after == before, (media, body[:200], r.text[:300])

    center.run(case())


# -- REST: temperature readings

READING = st.fixed_dictionaries(
    {"sensor": st.one_of(st.sampled_from(["spindle", "air", "T_spindle_C", "bed"]), TEXT),
     "celsius": st.one_of(st.floats(allow_nan=False, allow_infinity=False),
                          st.sampled_from([20.5, 293.15, 21500, 72.0, -40.0, 1e6]),
                          TEXT, st.none())},
    optional={"time": st.one_of(st.sampled_from(["2026-11-29T10:00:00Z", "yesterday",
                                                 "1763820000500", "2026-11-29T10:00:00"]),
                                st.floats(allow_nan=False, allow_infinity=False),
                                st.integers(-10**15, 10**15))})


@settings(max_examples=CASES["temperatures"], **SETTINGS)  # type: ignore[arg-type]
@given(body=st.one_of(st.fixed_dictionaries({"readings": st.lists(READING, max_size=4)}),
                      JSON))
def test_garbage_temperature_posts(center: Center_, body: Any) -> None:
    async def case() -> None:
        before = center.state()
        r = await center.client.post(f"/api/machines/{MACHINE}/temperatures",
                                     headers=WRITE, json=body)
        after = center.state()
        if not _fine(r, body):  # nothing kept: not on the board, not for the database
            assert after == before, (body, r.text[:300])

    center.run(case())


# -- REST: machine descriptions

@settings(max_examples=CASES["machines"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_machine_descriptions(center: Center_, data: st.DataObject) -> None:
    base = {**description("fz-01", "siemens", "10.0.9.1"), "secret": SECRET}
    body = mutate(base, data.draw) if data.draw(st.integers(0, 4)) else data.draw(JSON)
    patch = data.draw(st.booleans())

    async def case() -> None:
        before = center.state()
        if patch:
            r = await center.client.patch(f"/api/machines/{MACHINE}", headers=WRITE,
                                          json=body)
        else:
            r = await center.client.post("/api/machines", headers=WRITE, json=body)
        after = center.state()
        if _fine(r, body):
            name = r.json()["name"]
            if patch:  # put it back as it was
                r = await center.client.patch(f"/api/machines/{name}", headers=WRITE, json={
                    **description(MACHINE, "fanuc", "10.0.0.21"),
                    "sensors": ["spindle", "air"]})
                assert r.status_code == 200, r.text
            else:
                assert after[0] == before[0] + 1
                r = await center.client.delete(f"/api/machines/{name}", headers=WRITE)
                assert r.status_code == 204, r.text
        else:
            assert after[:2] == before[:2], (body, r.text[:300])

    center.run(case())


# -- MQTT temperature messages

PAYLOAD = st.one_of(
    NUMBERS.map(str.encode),
    st.binary(max_size=64),
    JSON.map(lambda v: json.dumps(v).encode()),
    st.builds(lambda c, t, k: json.dumps({"celsius": c, k: t}).encode(),
              st.one_of(st.floats(), st.sampled_from([21.0, 293.15, 21500, 72.0])),
              st.one_of(st.integers(-10**15, 10**15), st.floats(), TEXT,
                        st.sampled_from([1763820000, 1763820000500])),
              st.sampled_from(["time", "timestamp_ms"])),
)
TOPIC = st.one_of(
    st.builds(lambda m, s: f"ednc/{m}/temperature/{s}",
              st.sampled_from([MACHINE, "nobody", "", "x" * 70]),
              st.one_of(st.sampled_from(["spindle", "air", "bed", "T_air_C"]), TEXT)),
    TEXT, st.just("ednc/vmc-01/status"))


@settings(max_examples=CASES["mqtt"], **SETTINGS)  # type: ignore[arg-type]
@given(topic=TOPIC, payload=PAYLOAD)
def test_garbage_mqtt_temperatures(center: Center_, topic: str, payload: bytes) -> None:
    async def case() -> None:
        before = center.state()
        taken = center.bridge.handle(topic, payload)
        after = center.state()
        if not taken:
            assert after == before, (topic, payload)

    center.run(case())


# -- fleet files

FLEET_ENTRY = st.fixed_dictionaries({
    "machine": st.one_of(st.just(description("fl-01", "fanuc", "127.0.9.1")),
                         st.sampled_from(["m.json", "missing.json", "../m.json", ""]),
                         JSON),
    "secret": st.one_of(st.just(SECRET), TEXT, st.integers())},
    optional={"seed": st.one_of(st.integers(), TEXT), "ip": st.one_of(TEXT, st.integers()),
              "link": JSON})


@settings(max_examples=CASES["fleet"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_fleet_files(tmp_path_factory: pytest.TempPathFactory,
                             data: st.DataObject) -> None:
    d = tmp_path_factory.getbasetemp() / "fleet-fuzz"
    d.mkdir(exist_ok=True)
    (d / "m.json").write_text(json.dumps({**description("fm-01", "siemens", "127.0.9.2"),
                                          "link": data.draw(st.one_of(JSON, st.just(
                                              {"kind": "modbus", "port": 502})))}))
    good = {"machines": [{"machine": "m.json", "secret": SECRET}]}
    doc = data.draw(st.one_of(
        st.fixed_dictionaries({"machines": st.lists(FLEET_ENTRY, max_size=3)},
                              optional={"center": st.one_of(TEXT, JSON),
                                        "mqtt": JSON}),
        st.just(good), JSON))
    if data.draw(st.integers(0, 2)) == 0:
        doc = mutate(good, data.draw)
    suffix = data.draw(st.sampled_from([".json", ".yaml"]))
    path = d / f"fleet{suffix}"
    text = (yaml.safe_dump(doc) if suffix == ".yaml" and data.draw(st.booleans())
            else json.dumps(doc))
    if data.draw(st.integers(0, 9)) == 0:
        text = data.draw(st.text(alphabet=string.printable + "\x00µ", max_size=80))
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    try:
        entries, _ = load_fleet(path)
    except FleetSpecError as exc:
        assert str(exc).startswith(str(path)) or str(path.parent) in str(exc), exc
    else:
        assert entries and all(e.secret for e in entries)
    n = data.draw(st.integers(-2, 5))
    link = data.draw(st.sampled_from(["ednc", "modbus", "opcua", "carrier-pigeon"]))
    try:
        fleet = generated_fleet(n, data.draw(st.sampled_from([SECRET, "short", ""])),
                                link=link, controller=data.draw(st.sampled_from(
                                    ["mixed", "fanuc", "siemens", "x"])))
    except FleetSpecError:
        pass
    else:
        assert len({e.machine.name for e in fleet}) == len(fleet) == n


def test_the_cases_add_up_with_the_cli_fuzz() -> None:
    from tests.support.fuzz import CASES as CLI

    assert sum(CASES.values()) + sum(CLI.values()) >= 10_000
