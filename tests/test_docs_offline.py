"""``/docs`` and ``/redoc`` come from the project's own files: their HTML names no other
host, and every script and style it names is served by the app (a plant network often has
no internet; the CDN defaults rendered blank pages there). The pages rendering in Chromium
with every other host blocked is in ``test_dashboard_browser.py``."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from pathlib import Path

import httpx
import pytest
from fastapi import FastAPI

from server.settings import Settings
from tests.support.api import running

VENDOR = Path(__file__).resolve().parent.parent / "server" / "static" / "vendor"
ASSET = re.compile(r"""(?:src|href|spec-url)\s*=\s*["']([^"']+)["']""")


@pytest.fixture
async def client(tmp_path: Path) -> AsyncIterator[httpx.AsyncClient]:
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}")
    pair: tuple[FastAPI, httpx.AsyncClient]
    async with running(settings) as pair:
        yield pair[1]


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
async def test_api_docs_load_only_what_the_app_serves(client: httpx.AsyncClient,
                                                      page: str) -> None:
    r = await client.get(page)
    assert r.status_code == 200
    assert r.headers["content-security-policy"].startswith("default-src 'self';")
    html = r.text
    assert re.search(r"https?://|[\"'(]//", html) is None, "a host outside the app"
    assets = ASSET.findall(html)
    scripts = [a for a in assets if a.endswith(".js")]
    assert scripts and all(a.startswith("/static/vendor/") for a in scripts), assets
    for asset in assets:
        got = await client.get(asset)
        assert got.status_code == 200, asset
        assert len(got.content) > 100, asset
    if page == "/docs":  # the validator badge would ask validator.swagger.io
        assert '"validatorUrl": null' in html


async def test_the_openapi_document_lists_history_and_leaves_the_doc_pages_out(
        client: httpx.AsyncClient) -> None:
    paths = (await client.get("/openapi.json")).json()["paths"]
    assert {"/api/machines/{name}/history", "/api/history"} <= set(paths)
    assert not {"/docs", "/redoc"} & set(paths)


def test_every_vendored_package_ships_its_licence() -> None:
    for package in ("uplot", "swagger-ui", "redoc"):
        licence = (VENDOR / package / "LICENSE").read_text(encoding="utf-8")
        assert "Apache License" in licence or "MIT License" in licence or \
            "Permission is hereby granted" in licence, package
    listed = (VENDOR / "README.md").read_text(encoding="utf-8")
    for path in VENDOR.glob("*/*"):
        assert f"{path.parent.name}/{path.name}" in listed, f"{path} not listed with its hash"
