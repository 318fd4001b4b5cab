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

import re
from pathlib import Path

import httpx
import pytest

from protocol.codes import MapEncoding
from server.db import machines as machine_repo
from server.db import maps as map_repo
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
    """Three machines; vmc-01 with an applied map, a verification, a diagnosis, a model."""
    with httpx.Client(base_url=live.url, headers=WRITE, timeout=30) as client:
        for description in (VMC, SIEMENS, OTHER):
            r = client.post("/api/machines", json={**description, "secret": SECRET})
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
        body = {"format": "ednc-model/1", "machine": "vmc-01",
                "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 4.0, 1.5],
                                       "origin": 250.0, "scale": 250.0},
                               "EYY": {"type": "polynomial", "coefficients": [1.0, -2.0],
                                       "origin": 150.0, "scale": 150.0}},
                "locations": {"EC0Y": 12.0}, "terms": [], "info": {}}
        r = client.post("/api/machines/vmc-01/models", json={"body": body})
        assert r.status_code == 201, r.text

    async def maps() -> None:
        assert live.center is not None
        db = live.center.db
        row = await db.run(machine_repo.get_machine, "vmc-01")
        assert row is not None
        await db.run(map_repo.add_map_version, row.id, model_version=1,
                     payload=example_map("vmc-01", 1, MapEncoding.INT32_INCREMENTS))
        sent = await db.run(map_repo.record_sent, row.id, 1)
        await db.run(map_repo.record_answer, sent.id, acked=True)

    live.call(maps())
    assert live.center is not None
    registry = live.center.registry
    live.do(lambda: registry.connected("vmc-01", "10.0.0.21:50123"))
    live.do(lambda: registry.connected("dmu-02", "10.0.0.22:50124"))
    live.moving.update({"vmc-01": 100.0, "dmu-02": 10.0})


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
            vmc = page.locator('tr[data-machine="vmc-01"]')
            dmu = page.locator('tr[data-machine="dmu-02"]')
            other = page.locator('tr[data-machine="vmc-03"]')
            expect(page.locator("#live")).to_have_text("● live")
            expect(vmc).to_have_class("health-ok")
            expect(other).to_have_class("health-offline")
            expect(dmu).to_have_class("health-warn")  # no map built for it
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
            # trends drawn from the snapshots: a line once two or more have arrived
            spark = vmc.locator('svg[data-field="trend-comp"]')
            expect(spark).to_have_attribute("data-points", re.compile(r"^([2-9]|\d\d+)$"),
                                            timeout=10_000)
            expect(spark.locator("path.spark-line")).to_have_count(1)
            expect(dmu.locator('svg[data-field="trend-temp"] path.spark-line')).to_have_count(1)
            expect(vmc.locator('[data-field="trend-version"]')).to_contain_text("map v1")

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
            diagonals = page.locator("#diagonals figure")
            expect(diagonals).to_have_count(4)
            expect(diagonals.first.locator("path.series.before")).to_have_count(1)
            expect(diagonals.first.locator("path.series.after")).to_have_count(1)
            expect(page.locator('[data-field="improvement"]')).to_contain_text("+80.0 %")
            expect(page.locator('#components tr[data-component="EXX"]')).to_contain_text("µm")
            expect(page.locator('[data-field="effect"]')).to_have_text("backlash on x")
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
