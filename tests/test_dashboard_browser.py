"""The dashboard in a real headless browser (Debian's chromium driven by playwright).

A real uvicorn serves the app on 127.0.0.1 (port 0) in a thread, with a temporary SQLite
database. Machines are registered and verified through the REST API; their live links are
driven straight into the Center's registry by a small service running on the server's
event loop (telemetry in the shape the machine TCP server stores, ``telemetry_fields``),
moving X a little every 0.3 s. The browser must show every machine with its live values,
see the position change, show a refusal recorded after the page loaded, and draw the
machine page's map, diagonal plots and model.
"""

from __future__ import annotations

import datetime as dt
import re
from pathlib import Path
from typing import Any

import httpx
import pytest

from protocol.codes import MapEncoding
from server.db import corrections as correction_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db import temperatures as reading_repo
from server.db.corrections import NewSample
from server.db.temperatures import NewReading
from server.events import EventKind
from tests.support.api import SECRET, VMC, WRITE
from tests.support.browser import (
    CHROMIUM,
    MM,
    Live,
)
from tests.support.dashboard import DIAGNOSIS, OTHER, SIEMENS, diagonals_csv, example_map
from tests.support.services import require

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def seed(live: Live) -> None:
    """Three machines; vmc-01 (tolerance 25 µm) with a model, an applied map built from
    it, a verification after it, a diagnosis; an hour of history (vmc-01's corrections,
    dmu-02's temperatures) in the database."""
    with httpx.Client(base_url=live.url, headers=WRITE, timeout=30) as client:
        for description in ({**VMC, "accuracy_tolerance_um": 25.0}, SIEMENS, OTHER):
            r = client.post("/api/machines", json={**description, "secret": SECRET})
            assert r.status_code == 201, r.text
        body = {"format": "ednc-model/1", "machine": "vmc-01",
                "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 4.0, 1.5],
                                       "origin": 250.0, "scale": 250.0},
                               "EYY": {"type": "polynomial", "coefficients": [1.0, -2.0],
                                       "origin": 150.0, "scale": 150.0}},
                "locations": {"EC0Y": 12.0}, "terms": [], "info": {"rms_um": 0.42}}
        r = client.post("/api/machines/vmc-01/models", json={"body": body})
        assert r.status_code == 201, r.text
        for set_name, scale in (("diag-before", 10.0), ("diag-after", 2.0)):
            r = client.post("/api/machines/vmc-01/measurements", params={"set_name": set_name},
                            content=diagonals_csv(scale).encode(),
                            headers={"content-type": "text/csv"})
            assert r.status_code == 201, r.text
        r = client.post("/api/machines/vmc-01/verifications",
                        json={"before": "diag-before", "after": "diag-after"})
        assert r.status_code == 201, r.text
        assert client.post("/api/machines/vmc-01/diagnoses", json=DIAGNOSIS).status_code == 201

    async def stored() -> None:
        assert live.center is not None
        db = live.center.db
        row = await db.run(machine_repo.get_machine, "vmc-01")
        dmu = await db.run(machine_repo.get_machine, "dmu-02")
        assert row is not None and dmu is not None
        await db.run(map_repo.add_map_version, row.id, model_version=1,
                     payload=example_map("vmc-01", 1, MapEncoding.INT32_INCREMENTS))
        sent = await db.run(map_repo.record_sent, row.id, 1)
        assert sent is not None
        await db.run(map_repo.record_answer, sent.id, acked=True)
        now = dt.datetime.now(dt.UTC)
        minutes = [now - dt.timedelta(minutes=60 - k) for k in range(60)]
        await db.run(reading_repo.add_readings, [
            NewReading(dmu.id, "T_spindle_C", 21.0 + k / 60, t, "mqtt")
            for k, t in enumerate(minutes)])
        await db.run(correction_repo.add_samples, [
            NewSample(row.id, axis, t, mean, mean - 0.5, mean + 0.5, 60)
            for t in minutes for axis, mean in (("X", 4.2), ("Y", -1.3))])

    live.call(stored())
    assert live.center is not None
    registry = live.center.registry
    live.do(lambda: registry.connected("vmc-01", "10.0.0.21:50123"))
    live.do(lambda: registry.connected("dmu-02", "10.0.0.22:50124"))
    live.moving.update({"vmc-01": 100.0, "dmu-02": 10.0})


def expect_trend(row: Any, field: str, series: str) -> None:
    """A uPlot chart with both axes and ``series`` in its legend, from the server's history."""
    from playwright.sync_api import expect
    chart = row.locator(f'.trend-chart[data-field="{field}"]')
    expect(chart).to_have_attribute("data-points", re.compile(r"^[1-9]\d*$"), timeout=10_000)
    expect(chart.locator("canvas")).to_have_count(1)
    expect(chart.locator(".u-axis")).to_have_count(2)  # time and value
    expect(chart.locator(".u-legend")).to_contain_text(series)


def test_dashboard_and_machine_page_in_chromium(live_server: Live, tmp_path: Path) -> None:
    require("chromium", CHROMIUM.exists(), f"install Debian's chromium ({CHROMIUM})")
    from playwright.sync_api import expect, sync_playwright

    live = live_server
    seed(live)
    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=str(CHROMIUM),
            args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = browser.new_page(viewport={"width": 1700, "height": 1000})
            errors: list[str] = []
            page.on("pageerror", lambda exc: errors.append(str(exc)))
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("response", lambda r: errors.append(f"{r.status} {r.url}")
                    if r.status >= 400 else None)
            page.goto(live.url + "/")

            rows = page.locator("#machines > tbody > tr")
            expect(rows).to_have_count(3)
            vmc = page.locator('#machines > tbody > tr[data-machine="vmc-01"]')
            dmu = page.locator('#machines > tbody > tr[data-machine="dmu-02"]')
            other = page.locator('#machines > tbody > tr[data-machine="vmc-03"]')
            expect(page.locator("#live")).to_have_text("● live")
            expect(vmc).to_have_class("health-ok")
            expect(other).to_have_class("health-offline")
            expect(dmu).to_have_class("health-unknown")  # never verified, no model

            # the first screen: which machines are out of tolerance, and why, worst first
            accuracy = page.locator("#accuracy > tbody > tr")
            expect(accuracy).to_have_count(3)
            expect(accuracy.first).to_have_attribute("data-machine", "vmc-03")  # offline
            expect(page.locator('#accuracy tr[data-machine="vmc-01"] [data-field="reasons"]'
                                )).to_contain_text("within the 25 µm tolerance; map v1 applied")
            expect(page.locator('#accuracy tr[data-machine="dmu-02"] [data-field="reasons"]'
                                )).to_contain_text("never verified")
            expect(page.locator('#accuracy tr[data-machine="dmu-02"] li')).to_have_count(2)
            expect(page.locator('#accuracy tr[data-machine="vmc-01"] [data-field="map-facts"]'
                                )).to_contain_text("grid map")
            expect(vmc.locator('[data-field="health"]')).to_have_text("OK")
            expect(dmu.locator('[data-field="health"]')).to_have_text("UNKNOWN")
            expect(vmc.locator('[data-field="map-kind"]')).to_contain_text("grid map")
            expect(vmc.locator('[data-field="chain"]')).to_have_text("w X Y b Z t")
            expect(vmc.locator('[data-field="maps"]')).to_have_text("v1 / v1 / v1")
            expect(vmc.locator('[data-field="comp-X"]')).to_have_text("+4.2 µm")
            expect(vmc.locator('[data-field="comp-Y"]')).to_have_text("-1.3 µm")
            expect(dmu.locator('[data-field="temp-spindle"]')).to_have_text("22.4 °C")
            expect(vmc.locator('[data-field="verification"]')).to_contain_text("80 % better")
            expect(vmc.locator('[data-field="diagnosis"]')).to_contain_text("backlash on x")
            expect(vmc.locator('[data-field="diagnosis"]')).to_contain_text("reversal 9.80 µm")

            position = vmc.locator('[data-field="pos-X"]')
            expect(position).to_have_text(MM)
            first = position.inner_text()
            expect(position).not_to_have_text(first, timeout=10_000)  # it moves on screen

            # fleet health at a glance: one segment per machine, coloured by its health
            strip = page.locator("#health-strip .seg")
            expect(strip).to_have_count(3)
            expect(page.locator('#health-strip .seg[data-machine="vmc-01"]')).to_have_class(
                "seg health-ok")
            expect(page.locator('#health-strip .seg[data-machine="vmc-03"]')).to_have_class(
                "seg health-offline")
            # trends with axes, drawn from the server's history: still there after a reload
            expect_trend(vmc, "trend-comp", "X")
            expect_trend(dmu, "trend-temp", "spindle")
            page.reload()  # the same rows, drawn again from the server's history
            expect_trend(dmu, "trend-temp", "spindle")
            expect_trend(vmc, "trend-comp", "Y")
            page.select_option("#window", str(7 * 86400))  # a week: kept in the address
            expect(page).to_have_url(re.compile(r"\?window=604800$"))
            expect_trend(dmu, "trend-temp", "spindle")

            live.call(_refuse(live))
            refusal = page.locator('#events tr[data-kind="refused"]')
            expect(refusal).to_have_count(1, timeout=10_000)
            expect(refusal).to_contain_text("10.9.9.9:5555")
            expect(refusal).to_contain_text("unknown address")
            page.screenshot(path=str(tmp_path / "dashboard.png"), full_page=True)

            page.goto(live.url + "/machines/vmc-01")
            for output in ("X", "Y", "Z"):
                cells = page.locator(f'svg.heatmap[data-output="{output}"] rect[fill]')
                expect(cells).to_have_count(11 * 7)  # the X-Y slice of an 11 x 7 x 4 grid
            expect(page.locator("#map figcaption").first).to_contain_text("Correction of X")
            expect(page.locator('[data-field="map-caption"]')).to_contain_text(
                "grid of X×11 Y×7 Z×4 nodes")
            expect(page.locator('[data-field="map-caption"]')).to_contain_text(
                "no thermal terms")
            expect(page.locator('#accuracy [data-field="reasons"]')).to_contain_text(
                "within the 25 µm tolerance")
            expect_trend(page.locator(".history"), "history-comp", "X")
            expect(page.locator('.history [data-field="history-temp"]')).to_have_attribute(
                "data-points", "0")  # vmc-01 reports no temperature
            expect(page.locator("#delivery-table")).to_contain_text("applied")
            expect(page.locator('[data-field="diagonal-offsets"]')).to_contain_text(
                "does not enter the range")
            expect(page.locator("#diagonals figcaption").first).to_contain_text(
                "offset at the start")
            diagonals = page.locator("#diagonals figure")
            expect(diagonals).to_have_count(4)
            expect(diagonals.first.locator("path.series.before")).to_have_count(1)
            expect(diagonals.first.locator("path.series.after")).to_have_count(1)
            expect(page.locator('[data-field="improvement"]')).to_contain_text("+80.0 %")
            expect(page.locator('#components tr[data-component="EXX"]')).to_contain_text("µm")
            expect(page.locator('[data-field="effect"]')).to_have_text("backlash on x")
            expect(page.locator("#model")).to_contain_text("RMS 0.42 µm")
            machine_position = page.locator('#live-values [data-field="pos-X"]')
            expect(machine_position).to_have_text(MM)
            shown = machine_position.inner_text()
            expect(machine_position).not_to_have_text(shown, timeout=10_000)
            expect(page.locator("main")).not_to_contain_text("null")  # no absent value as text
            page.screenshot(path=str(tmp_path / "machine.png"), full_page=True)
            assert errors == []
        finally:
            browser.close()


async def _refuse(live: Live) -> None:
    assert live.center is not None
    await live.center.record_event(EventKind.REFUSED, "10.9.9.9:5555", "unknown address",
                                   reason="unknown")


def test_api_docs_render_with_every_other_host_blocked(live_server: Live) -> None:
    """/docs and /redoc on a plant network without internet: every request to a host
    other than the app's is refused, and both pages still show the API."""
    require("chromium", CHROMIUM.exists(), f"install Debian's chromium ({CHROMIUM})")
    from playwright.sync_api import Route, expect, sync_playwright

    live = live_server
    outside: list[str] = []

    def gate(route: Route) -> None:
        if route.request.url.startswith(live.url + "/"):
            route.continue_()
        else:
            outside.append(route.request.url)
            route.abort()

    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=str(CHROMIUM),
            args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"])
        try:
            page = browser.new_page(viewport={"width": 1400, "height": 900})
            page.route("**/*", gate)
            errors: list[str] = []
            page.on("pageerror", lambda exc: errors.append(str(exc)))
            page.goto(live.url + "/docs")
            expect(page.locator(".swagger-ui .info .title")).to_contain_text(
                "EDNC control center", timeout=20_000)
            expect(page.locator(".opblock-tag-section").first).to_be_visible()
            expect(page.locator("#operations-history-history_api_machines__name__history_get")
                   ).to_have_count(1)
            page.goto(live.url + "/redoc")
            expect(page.locator("h1").first).to_contain_text("EDNC control center",
                                                             timeout=20_000)
            expect(page.locator("body")).to_contain_text("/api/machines/{name}/history")
            assert outside == []
            assert errors == []
        finally:
            browser.close()
