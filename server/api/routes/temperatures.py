"""``/api/machines/{name}/temperatures``: a machine's temperatures for the dashboard (the
latest per sensor, the stored time series, recent refusals) and a way in for plant
systems that post readings instead of publishing them on MQTT (:mod:`server.intake`)."""

from __future__ import annotations

import datetime as dt
import math
import time
from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Query, status

from server.api.deps import CenterDep, MachineDep, WriteAccess
from server.api.errors import NOT_FOUND, WRITE, Problem
from server.db import temperatures as reading_repo
from server.intake import TemperatureIntake
from server.schemas.temperature import (
    TemperatureLatest,
    TemperaturePoint,
    TemperatureRefusal,
    TemperaturesIn,
    TemperaturesPublic,
    TemperaturesTaken,
    TemperatureVerdict,
)
from server.temperatures import column_of

router = APIRouter(prefix="/machines/{name}/temperatures", tags=["temperatures"],
                   responses=NOT_FOUND)

_OFF: dict[int | str, dict[str, Any]] = {
    409: {"model": Problem, "description": "The machine services (and with them the "
          "temperature intake) are not running in this process."}}


def _utc(seconds: float) -> dt.datetime:
    return dt.datetime.fromtimestamp(seconds, dt.UTC)


def _intake(center: CenterDep) -> TemperatureIntake:
    if center.intake is None:
        # 409, not 503: the request cannot succeed in this process's configuration
        # (an API-only process), retrying does not help, and 5xx are kept for faults
        raise HTTPException(status.HTTP_409_CONFLICT,
                            "the temperature intake is not running in this process")
    return center.intake


@router.get("")
async def get_temperatures(
    center: CenterDep, machine: MachineDep,
    sensor: Annotated[str | None, Query(pattern=r"^[A-Za-z0-9_]{1,64}$",
                                        description="Only this sensor or column.")] = None,
    since: Annotated[dt.datetime | None, Query(description="Readings taken at or after "
                                               "this time (ISO 8601 with a zone).")] = None,
    until: Annotated[dt.datetime | None, Query(description="Readings taken before this "
                                               "time.")] = None,
    limit: Annotated[int, Query(ge=0, le=10_000, description="Most readings of the "
                                "series (newest first).")] = 1000,
) -> TemperaturesPublic:
    """The latest reading per sensor, the stored series newest first, recent refusals."""
    for when in (since, until):
        if when is not None and when.tzinfo is None:
            raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT,
                                "since and until need a time zone (e.g. Z)")
    column = column_of(sensor) if sensor is not None else None
    rows = await center.db.run(reading_repo.list_readings, machine.id, sensor=column,
                               since=since, until=until, limit=limit) if limit else []
    intake = center.intake
    latest: list[TemperatureLatest] = []
    refusals: list[TemperatureRefusal] = []
    known: list[str] | None = None
    if intake is not None:
        board, now = intake.board, time.monotonic()
        for col, r in sorted(board.readings(machine.name).items()):
            age = max(0.0, now - r.received)
            latest.append(TemperatureLatest(
                sensor=col, celsius=r.celsius, time=_utc(r.time), age_s=round(age, 3),
                source=r.source, stale=r.stale or age > board.stale_after_s))
        refusals = [TemperatureRefusal(
            sensor=f.sensor, celsius=f.celsius if math.isfinite(f.celsius) else None,
            source=f.source, reason=f.reason, detail=f.text, time=_utc(f.time))
            for f in reversed(intake.refusals) if f.machine == machine.name]
        columns = intake.knows(machine.name)
        known = None if columns is None else sorted(columns)
    return TemperaturesPublic(
        machine=machine.name, known_sensors=known, latest=latest,
        history=[TemperaturePoint(sensor=r.sensor, celsius=r.celsius, time=r.time,
                                  source=r.source) for r in rows],
        refusals=refusals)


@router.post("", dependencies=[WriteAccess], responses={**WRITE, **_OFF})
async def post_temperatures(center: CenterDep, machine: MachineDep,
                            body: TemperaturesIn) -> TemperaturesTaken:
    """Take readings of the machine's sensors: each is checked like an MQTT reading,
    kept, stored and forwarded to the machine. 422 when every reading was refused (the
    verdicts say why), else 200 with a verdict per reading."""
    intake = _intake(center)
    known = intake.knows(machine.name)
    if known is None or any(column_of(r.sensor) not in known for r in body.readings):
        await intake.lookup(machine.name)  # registered or given a model a moment ago
    verdicts = []
    for r in body.readings:
        if r.time is not None and r.time.tzinfo is None:
            refusal_text, reason = "time needs a time zone (e.g. Z)", "bad_time"
        else:
            at = r.time.timestamp() if r.time is not None else None
            refusal = intake.take(machine.name, r.sensor, r.celsius, source="rest", at=at)
            refusal_text = refusal.text if refusal else ""
            reason = refusal.reason if refusal else ""
        verdicts.append(TemperatureVerdict(sensor=r.sensor, accepted=not reason,
                                           reason=reason or None,
                                           detail=refusal_text or None))
    accepted = sum(v.accepted for v in verdicts)
    taken = TemperaturesTaken(machine=machine.name, accepted=accepted,
                              refused=len(verdicts) - accepted, verdicts=verdicts)
    if not accepted:
        raise HTTPException(status.HTTP_422_UNPROCESSABLE_CONTENT,
                            [{"loc": ["body", "readings", i], "msg": v.detail,
                              "type": v.reason} for i, v in enumerate(verdicts)])
    return taken
