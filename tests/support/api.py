"""The REST API in-process for tests: ``running`` starts the app with its lifespan and an
httpx client on it; the key, a machine description and measurement CSV builders."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import httpx
import numpy as np
from fastapi import FastAPI

from server.app import create_app
from server.center import Center
from server.settings import Settings
from tests.support.db import database_url, postgres_url  # noqa: F401  (fixtures)

API_KEY = "test-api-key-0123"


WRITE = {"X-API-Key": API_KEY}


SECRET = "machine-secret-4711"


VMC = {
    "name": "vmc-01",
    "controller": "fanuc",
    "ip": "10.0.0.21",
    "chain": "w X Y b Z t",
    "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
    "tool_length_mm": 100.0,
}


CSV_HEADER = "test,run,time_s,x_mm,y_mm,z_mm,dir_x,dir_y,dir_z,tool_mm,quantity,ux,uy,uz,value"


@asynccontextmanager
async def running(settings: Settings) -> AsyncIterator[tuple[FastAPI, httpx.AsyncClient]]:
    """The app with its lifespan running, and a client talking to it in-process."""
    app = create_app(settings)
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://test") as client:
            yield app, client


def center_of(app: FastAPI) -> Center:
    center = app.state.center
    assert isinstance(center, Center)
    return center


def backlash_csv(reversal_um: float) -> str:
    """Four runs of an X positioning test, alternately approached from below and above,
    whose readings differ by ``reversal_um`` between the two approach directions."""
    rng = np.random.default_rng(7)  # fixed: the same readings every time
    lines, t = [CSV_HEADER], 0
    for run in range(1, 5):
        d = 1 if run % 2 else -1
        for i in range(21) if d > 0 else range(20, -1, -1):
            t, x = t + 1, 25.0 * i
            value = 0.02 * x - d * reversal_um / 2 + rng.normal(0.0, 0.1)
            lines.append(f"X-positioning,{run},{t},{x},150,-150,{d},0,0,100,displacement,"
                         f"1,0,0,{value:.4f}")
    return "\n".join(lines) + "\n"
