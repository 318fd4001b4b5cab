"""``/api/live`` over a real socket: a viewer that leaves is noticed, and an open stream does
not hold the server's shutdown (uvicorn waits for open responses and does not tell the app
it is stopping, so the stream must end by itself)."""

from __future__ import annotations

import time
from collections.abc import Iterator

import httpx
import pytest

from server.dashboard import live as live_module
from tests.support.api import SECRET, VMC, WRITE
from tests.support.browser import Live


def first_event(lines: Iterator[str]) -> str:
    """Read the stream's lines up to its first ``snapshot`` event; return that event's data."""
    block: list[str] = []
    for line in lines:
        if line:
            block.append(line)
            continue
        if "event: snapshot" in block:
            return next(b for b in block if b.startswith("data: "))
        block = []
    raise AssertionError("the stream ended without a snapshot")


def test_a_viewer_that_leaves_is_let_go(live_server: Live) -> None:
    live = live_server
    with httpx.Client(base_url=live.url, headers=WRITE, timeout=10) as client:
        r = client.post("/api/machines", json={**VMC, "secret": SECRET})
        assert r.status_code == 201
        with client.stream("GET", "/api/live") as response:
            assert response.headers["content-type"].startswith("text/event-stream")
            # Keep the line iterator: dropping it mid-stream makes httpx close the connection.
            lines = response.iter_lines()
            assert '"name":"vmc-01"' in first_event(lines)
            assert live.feed().viewers == 1
        deadline = time.monotonic() + 10  # a bound on waiting, not a speed requirement
        while live.feed().viewers and time.monotonic() < deadline:
            time.sleep(0.05)
        assert live.feed().viewers == 0


def test_an_open_stream_does_not_hold_the_shutdown(
    live_server: Live, monkeypatch: pytest.MonkeyPatch
) -> None:
    live = live_server
    monkeypatch.setattr(live_module, "MAX_STREAM_S", 2.0)
    with httpx.Client(base_url=live.url, timeout=30) as client, \
            client.stream("GET", "/api/live") as response:
        lines = response.iter_lines()
        first_event(lines)
        live.stop()  # asks uvicorn to exit while the stream is open; waits for it to stop
        assert live.stopped
        rest = list(lines)  # the stream ended by itself, after whole events
    assert rest == [] or rest[-1] == ""
