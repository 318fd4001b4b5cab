"""A center app with the machine services and an in-process HTTP client on it, for the tests
of the temperature intake and the entry points' plausibility."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import AbstractAsyncContextManager, asynccontextmanager
from pathlib import Path
from typing import Any

import httpx

from server.app import create_app
from server.center import Center
from server.links.ednc import LinkTiming
from server.services import machine_services
from server.settings import load_settings
from tests.support.api import API_KEY


def _app(tmp_path: Path, database_url: str) -> Any:
    settings = load_settings(database_url=database_url, api_key=API_KEY,
                             machine_host="127.0.0.1", machine_port=0)

    def services(center: Center) -> AbstractAsyncContextManager[object]:
        return machine_services(center, timing=LinkTiming(heartbeat_s=1.0))

    return create_app(settings, services=[services])


@asynccontextmanager
async def client_of(app: Any) -> AsyncIterator[httpx.AsyncClient]:
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://test") as client:
            yield client
