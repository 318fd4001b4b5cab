"""The dashboard served for real (uvicorn on a thread, port 0) for the Chromium tests:
``serving`` and the ``live_server`` fixture, with machines that move and report
temperatures."""

from __future__ import annotations

import asyncio
import datetime as dt
import re
import threading
import time
from collections.abc import AsyncIterator, Callable, Coroutine, Iterator, Sequence
from contextlib import asynccontextmanager, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import pytest
import uvicorn
from fastapi import FastAPI

from server.app import ServiceFactory, create_app
from server.center import Center
from server.dashboard.live import LiveFeed
from server.settings import Settings
from tests.support.api import API_KEY

CHROMIUM = Path("/usr/bin/chromium")


MM = re.compile(r"^-?\d+\.\d{3} mm$")


T = TypeVar("T")


def keyed_telemetry(x: float, temperature: float | None) -> dict[str, Any]:
    """Telemetry as ``server.links.ednc.telemetry_fields`` keeps it (mm, °C)."""
    return {
        "timestamp_ms": int(dt.datetime.now(dt.UTC).timestamp() * 1000),
        "state": "compensating", "map_version": 1,
        "axes": {"X": {"position": x, "compensation": 0.0042},
                 "Y": {"position": 120.0, "compensation": -0.0013},
                 "Z": {"position": -80.0, "compensation": 0.0008}},
        "temperatures": {} if temperature is None else {"spindle": temperature},
    }


@dataclass
class Live:
    """The running server: its URL, loop and Center, and the machines it moves."""

    url: str = ""
    loop: asyncio.AbstractEventLoop | None = None
    center: Center | None = None
    moving: dict[str, float] = field(default_factory=dict)
    app: FastAPI | None = None
    server: uvicorn.Server | None = None
    thread: threading.Thread | None = None

    @property
    def stopped(self) -> bool:
        return self.thread is not None and not self.thread.is_alive()

    def stop(self) -> None:
        """Ask uvicorn to exit (as on Ctrl+C) and wait for it, at most 40 s."""
        assert self.server is not None and self.thread is not None
        self.server.should_exit = True
        self.thread.join(timeout=40)

    def feed(self) -> LiveFeed:
        """The app's live feed (made by the first ``/api/live``)."""
        assert self.app is not None
        feed = self.app.state.dashboard_feed
        assert isinstance(feed, LiveFeed)
        return feed

    def call(self, coro: Coroutine[Any, Any, T]) -> T:
        """Run a coroutine on the server's loop and wait for its result."""
        assert self.loop is not None
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(timeout=30)

    def do(self, fn: Callable[[], object]) -> None:
        """Run ``fn`` on the server's loop (the registry belongs to it)."""
        async def job() -> None:
            fn()
        self.call(job())


def driver(live: Live) -> Callable[[Center], Any]:
    """A service for ``create_app``: telemetry for the machines in ``live.moving``."""

    @asynccontextmanager
    async def service(center: Center) -> AsyncIterator[None]:
        live.loop, live.center = asyncio.get_running_loop(), center

        async def tick() -> None:
            while True:
                for name in list(live.moving):
                    live.moving[name] += 1.25
                    temperature = None if name == "vmc-01" else 22.4
                    center.registry.seen(name, keyed_telemetry(live.moving[name], temperature))
                await asyncio.sleep(0.3)

        task = asyncio.create_task(tick(), name="test-telemetry")
        try:
            yield
        finally:
            task.cancel()

    return service


@contextmanager
def serving(settings: Settings, services: Sequence[ServiceFactory], live: Live) -> Iterator[Live]:
    """The app on a real uvicorn (127.0.0.1, port 0) in a thread; stopped on exit."""
    app = create_app(settings, services=services)
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=0, log_level="warning"))
    thread = threading.Thread(target=server.run, name="uvicorn", daemon=True)
    live.app, live.server, live.thread = app, server, thread
    thread.start()
    while not server.started and thread.is_alive():
        time.sleep(0.05)
    assert server.started, "uvicorn did not start"
    port = server.servers[0].sockets[0].getsockname()[1]
    live.url = f"http://127.0.0.1:{port}"
    try:
        yield live
    finally:
        if not live.stopped:
            live.stop()
        assert live.stopped, "uvicorn did not stop (an open stream held it?)"


@pytest.fixture
def live_server(tmp_path: Path) -> Iterator[Live]:
    live = Live()
    settings = Settings(database_url=f"sqlite:///{tmp_path / 'ednc.db'}", api_key=API_KEY)
    with serving(settings, [driver(live)], live):
        yield live
