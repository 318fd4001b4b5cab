"""The dashboard of a real center with real simulated machines, in chromium.

``ednc serve``'s services (machine TCP server, push scheduler) run in the app on uvicorn;
simulated Fanuc- and Siemens-style CNCs (``machine_sim.link.SimulatedCNC``) connect over
TCP, authenticate, get their maps pushed and send telemetry; one has the wrong secret and
is refused. The center knows a machine by its address and every simulator runs on this
host, so each reaches the center through a small relay that connects from its own
loopback address (127.0.0.2, .3, ...), as machines on a shop-floor network would.
"""

from __future__ import annotations

import asyncio
import contextlib
import re
import threading
from collections.abc import AsyncIterator, Iterator
from contextlib import AsyncExitStack, asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import pytest

from machine_sim.fanuc import FanucConfig
from machine_sim.link import SimulatedCNC
from machine_sim.runtime import MachineRuntime
from protocol.backoff import Backoff
from server.center import Center
from server.links.ednc import LinkTiming
from server.services import MachineServices, machine_services
from server.settings import load_settings
from tests.support.api import API_KEY, WRITE
from tests.support.browser import CHROMIUM, MM, Live, serving
from tests.support.link import model_body
from tests.support.services import require
from volumetric.model.machine import parse_machine

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SECRET = "machine-secret-0123456789"
NODE = "center-a"
TRAVEL = {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}
MACHINES = [  # name, controller, address, secret it uses
    ("vmc-01", "fanuc", "127.0.0.2", SECRET),
    ("dmu-02", "siemens", "127.0.0.3", SECRET),
    ("vmc-03", "fanuc", "127.0.0.4", "not-the-registered-secret"),
]


def description(name: str, controller: str, ip: str) -> dict[str, Any]:
    return {"name": name, "controller": controller, "ip": ip, "chain": "w X Y b Z t",
            "travel_mm": TRAVEL, "tool_length_mm": 100.0}


async def _pipe(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    try:
        while data := await reader.read(65536):
            writer.write(data)
            await writer.drain()
    except ConnectionError:
        pass
    finally:
        writer.close()


@asynccontextmanager
async def relay(center_port: int, source: str) -> AsyncIterator[int]:
    """Listen on 127.0.0.1 (port 0) and forward each connection to the center from
    ``source``; yields the port to give the simulator."""

    async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            up_reader, up_writer = await asyncio.open_connection(
                "127.0.0.1", center_port, local_addr=(source, 0))
        except OSError:
            writer.close()
            return
        try:
            await asyncio.gather(_pipe(reader, up_writer), _pipe(up_reader, writer))
        except asyncio.CancelledError:
            # The relay is closing with the connection still open: end it quietly (a
            # handler that ends cancelled is logged as an error by asyncio.start_server).
            writer.close()
            up_writer.close()

    server = await asyncio.start_server(handle, "127.0.0.1", 0)
    async with server:
        yield int(server.sockets[0].getsockname()[1])


@dataclass
class Fleet:
    """Simulated machines running on their own event loop in a thread."""

    center_port: int
    loop: asyncio.AbstractEventLoop | None = None
    stop: asyncio.Event | None = None
    started: threading.Event = field(default_factory=threading.Event)
    error: BaseException | None = None

    async def main(self) -> None:
        self.loop, self.stop = asyncio.get_running_loop(), asyncio.Event()
        async with AsyncExitStack() as stack:
            for i, (name, controller, ip, secret) in enumerate(MACHINES):
                port = await stack.enter_async_context(relay(self.center_port, ip))
                machine = parse_machine(description(name, controller, ip))
                runtime = MachineRuntime(machine, seed=i + 1,
                                         fanuc=FanucConfig(max_step_counts=1000))
                await stack.enter_async_context(SimulatedCNC(
                    machine, ("127.0.0.1", port), secret.encode(), runtime=runtime,
                    backoff=Backoff(initial_s=0.2, factor=2.0, cap_s=2.0)))
            self.started.set()
            await self.stop.wait()

    def run(self) -> None:
        try:
            asyncio.run(self.main())
        except BaseException as exc:  # reported by the test, not lost in the thread
            self.error = exc
        finally:
            self.started.set()

    def close(self) -> None:
        if self.loop is not None and self.stop is not None:
            self.loop.call_soon_threadsafe(self.stop.set)


@pytest.fixture
def center_with_fleet(tmp_path: Path) -> Iterator[Live]:
    require("loopback aliases", _can_bind("127.0.0.2"), "127.0.0.0/8 must be loopback")
    live = Live()
    found: dict[str, MachineServices] = {}

    @asynccontextmanager
    async def services(center: Center) -> AsyncIterator[None]:
        live.loop, live.center = asyncio.get_running_loop(), center
        timing = LinkTiming(heartbeat_s=1.0, telemetry_period_ms=250)
        async with machine_services(center, timing=timing) as svc:
            found["svc"] = svc
            assert center.temperatures is svc.temperatures  # handed over by the services
            yield

    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'center.db'}",
                             api_key=API_KEY, machine_host="127.0.0.1", machine_port=0,
                             heartbeat_s=1.0, node_id=NODE)
    with serving(settings, [services], live):
        with httpx.Client(base_url=live.url, headers=WRITE, timeout=30) as client:
            for name, controller, ip, _ in MACHINES:
                r = client.post("/api/machines", json={**description(name, controller, ip),
                                                       "secret": SECRET})
                assert r.status_code == 201, r.text
                r = client.post(f"/api/machines/{name}/models",
                                json={"body": model_body(name, slope=0.02)})
                assert r.status_code == 201, r.text
        fleet = Fleet(found["svc"].server.port)
        thread = threading.Thread(target=fleet.run, name="fleet", daemon=True)
        thread.start()
        fleet.started.wait(timeout=30)
        assert fleet.error is None, fleet.error
        try:
            yield live
        finally:
            fleet.close()
            thread.join(timeout=30)
            assert not thread.is_alive() and fleet.error is None, fleet.error


def _can_bind(address: str) -> bool:
    import socket

    with socket.socket() as s, contextlib.suppress(OSError):
        s.bind((address, 0))
        return True
    return False


def test_real_machines_on_the_dashboard(center_with_fleet: Live, tmp_path: Path) -> None:
    require("chromium", CHROMIUM.exists(), f"install Debian's chromium ({CHROMIUM})")
    from playwright.sync_api import expect, sync_playwright

    live = center_with_fleet
    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=str(CHROMIUM),
            args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = browser.new_page(viewport={"width": 1700, "height": 1000})
            errors: list[str] = []
            page.on("pageerror", lambda exc: errors.append(str(exc)))
            page.on("response", lambda r: errors.append(f"{r.status} {r.url}")
                    if r.status >= 400 else None)
            page.goto(live.url + "/")
            expect(page.locator("#machines > tbody > tr")).to_have_count(3)
            for name in ("vmc-01", "dmu-02"):
                row = page.locator(f'#machines > tbody > tr[data-machine="{name}"]')
                # Connected, authenticated, its first map pushed and acknowledged...
                expect(row.locator('[data-field="maps"]')).to_have_text("v1 / v1 / v1",
                                                                        timeout=30_000)
                expect(row.locator('[data-field="connected"]')).to_have_text("connected")
                # ... but delivered is not accurate: nobody verified it yet
                expect(row).to_have_class("health-unknown")
                expect(page.locator(f'#accuracy tr[data-machine="{name}"] li').first
                       ).to_contain_text("never verified")
                expect(row.locator('[data-field="owner"]')).to_have_text(
                    f"served by {NODE}")
                position = row.locator('[data-field="pos-X"]')
                expect(position).to_have_text(MM)
                first = position.inner_text()
                expect(position).not_to_have_text(first, timeout=10_000)  # the axis moves
            dmu = page.locator('#machines > tbody > tr[data-machine="dmu-02"]')
            temperature = dmu.locator('[data-field^="temp-"]').first
            expect(temperature).to_contain_text("°C")
            expect(temperature).to_have_attribute("title", re.compile(r"^telemetry, \d+ s ago$"))
            refused = page.locator('#machines > tbody > tr[data-machine="vmc-03"]')
            expect(refused).to_have_class("health-offline")
            # its first wrong answer is refused as such; the retries after it are throttled
            refusal = page.locator('#events tr[data-kind="refused"]').filter(
                has_text="authentication").first
            expect(refusal).to_contain_text("vmc-03", timeout=15_000)
            page.screenshot(path=str(tmp_path / "fleet.png"), full_page=True)

            # every machine has its own series in /metrics, in the state the page shows
            metrics = httpx.get(f"{live.url}/metrics").text
            for name, state in (("vmc-01", "unknown"), ("dmu-02", "unknown"),
                                ("vmc-03", "offline")):
                assert (f'ednc_machine_accuracy_state{{machine="{name}",state="{state}"}} 1.0'
                        in metrics), name
            assert 'ednc_machine_map_version_applied{machine="vmc-01"} 1.0' in metrics

            grid = httpx.get(f"{live.url}/api/machines/dmu-02/maps/latest/grid").json()
            page.goto(live.url + "/machines/dmu-02")
            for out in grid["outputs"]:
                figure = page.locator(f'#map figure[data-output="{out["output"]}"]')
                if grid["v"] is None:  # a map over one axis is drawn as a line, node by node
                    dots = figure.locator("svg.map-profile circle.dot")
                    expect(dots).to_have_count(len(out["values"][0]))
                else:
                    cells = figure.locator("svg.heatmap rect[fill]")
                    expect(cells).to_have_count(len(out["values"]) * len(out["values"][0]))
            expect(page.locator('#live-values [data-field="pos-X"]')).to_have_text(MM)
            page.screenshot(path=str(tmp_path / "fleet-machine.png"), full_page=True)
            # a map that is not a grid is not captioned as one (Fanuc-style factored maps)
            for name in ("vmc-01", "dmu-02"):
                kind = httpx.get(f"{live.url}/api/machines/{name}/maps/latest/grid").json()[
                    "kind"]
                page.goto(live.url + f"/machines/{name}")
                caption = page.locator('[data-field="map-caption"]')
                expect(caption).to_contain_text({"grid": "grid of", "tables": "component tables",
                                                 "factored": "factored map"}[kind])
                if kind != "grid":
                    expect(caption).not_to_contain_text("grid of")
                expect(page.locator('#accuracy [data-field="map-facts"]')).to_contain_text(
                    {"grid": "grid map", "tables": "component tables",
                     "factored": "factored map"}[kind])
            assert errors == []
        finally:
            browser.close()
