"""``/api/machines/{name}/history`` and ``/api/history``: time series over a window,
downsampled by the database (:mod:`server.dashboard.history`).

The dashboard's trend charts read them; they are also what a plant's own tools read to
plot a machine's temperatures, applied corrections, map deliveries and verifications
without scraping the live stream. How long the data is kept: README, "History".
"""

from __future__ import annotations

import datetime as dt
from typing import Annotated

from fastapi import APIRouter, Query
from sqlalchemy.orm import Session

from server.api.deps import DatabaseDep, MachineDep
from server.api.errors import NOT_FOUND, unprocessable
from server.dashboard.history import (
    MAX_POINTS,
    MAX_WINDOW_S,
    MIN_WINDOW_S,
    FleetHistory,
    MachineHistory,
    fleet_history,
    machine_history,
)
from server.db import machines as machine_repo

router = APIRouter(tags=["history"])

EARLIEST = dt.datetime(1970, 1, 2, tzinfo=dt.UTC)
LATEST = dt.datetime(9000, 1, 1, tzinfo=dt.UTC)

WindowQuery = Annotated[float, Query(
    ge=MIN_WINDOW_S, le=MAX_WINDOW_S,
    description="Length of the window, s, ending at `until` (60 s to 366 days).")]
PointsQuery = Annotated[int, Query(
    ge=10, le=MAX_POINTS, description="Buckets the window is cut into: at most this many "
                                      "points per series.")]
UntilQuery = Annotated[dt.datetime | None, Query(
    description="End of the window (ISO 8601; UTC when no offset is given), 1970-01-02 "
                "to 9000-01-01; default now.")]


def _until(until: dt.datetime | None, window_s: float) -> dt.datetime | None:
    """``until`` as UTC, refused (422) outside the range a window can end in."""
    if until is None:
        return None
    until = until if until.tzinfo is not None else until.replace(tzinfo=dt.UTC)
    if not EARLIEST + dt.timedelta(seconds=window_s) <= until <= LATEST:
        raise unprocessable(["query", "until"], f"until must lie between "
                            f"{(EARLIEST + dt.timedelta(seconds=window_s)).isoformat()} and "
                            f"{LATEST.isoformat()} for a window of {window_s:g} s",
                            "until_range")
    return until


@router.get("/machines/{name}/history", responses=NOT_FOUND)
async def history(db: DatabaseDep, machine: MachineDep, window_s: WindowQuery = 86400.0,
                  points: PointsQuery = 300, until: UntilQuery = None) -> MachineHistory:
    """The machine's temperatures (°C) and applied corrections per axis (µm, µrad for a
    rotary axis) downsampled to at most `points` buckets (mean, min, max each), its map
    deliveries, verifications and events in the window."""
    return await db.run(machine_history, machine, _until(until, window_s), window_s, points)


@router.get("/history")
async def fleet(db: DatabaseDep, window_s: WindowQuery = 86400.0, points: PointsQuery = 300,
                until: UntilQuery = None) -> FleetHistory:
    """Every machine's temperature and correction trends over the window (as above)."""

    end = _until(until, window_s)

    def job(session: Session) -> FleetHistory:
        return fleet_history(session, machine_repo.list_machines(session), end, window_s,
                             points)

    return await db.run(job)
