"""A machine's history for the trend charts: what ``/api/machines/{name}/history`` and
``/api/history`` return, assembled from the downsampled queries of
:mod:`server.db.history`.

Times are seconds since the Unix epoch (UTC) in the series, the form a chart's time axis
takes directly; units are named per series. The window is ``until - window_s`` to
``until`` and is cut into ``points`` buckets, so a series has at most ``points`` points
whatever the rate the data came in at.
"""

from __future__ import annotations

import datetime as dt
import math
from collections import defaultdict
from collections.abc import Mapping, Sequence
from typing import Literal

from pydantic import BaseModel, Field
from sqlalchemy.orm import Session

from server.dashboard.snapshot import residual, verification_summary
from server.dashboard.telemetry import ROTARY
from server.db import history as history_repo
from server.db.history import Bucket
from server.db.tables import MachineRow

MAX_POINTS = 2000
MIN_WINDOW_S = 60.0
MAX_WINDOW_S = 366 * 86400.0


class Series(BaseModel):
    """One downsampled series: per bucket its mean time, mean, smallest and largest value."""

    name: str = Field(description="Sensor (as the model names it, without T_ and _C) or axis.")
    unit: Literal["°C", "µm", "µrad"]
    t: list[float] = Field(description="Mean time of each bucket, s since the Unix epoch.")
    mean: list[float]
    low: list[float] = Field(description="Smallest value in each bucket.")
    high: list[float] = Field(description="Largest value in each bucket.")
    count: list[int] = Field(description="Readings (correction: telemetry readings) per "
                                         "bucket.")


class Delivery(BaseModel):
    """A map sent to the machine and its answer."""

    version: int
    sent_at: dt.datetime
    state: Literal["pending", "applied", "rejected"]
    reject_reason: str | None
    model_version: int | None
    bytes: int
    built_at_C: dict[str, float] = Field(description="Temperatures it was built at.")


class VerificationPoint(BaseModel):
    """One ISO 230-6 verification: its largest diagonal range."""

    id: int
    at: dt.datetime
    residual_um: float | None = Field(description="Largest diagonal range, compensated "
                                      "when the report has a compensated run, µm.")
    compensated: bool
    before_um: float | None = Field(description="Largest range without compensation, µm.")


class EventPoint(BaseModel):
    """An event of the machine (connected, pushed, rejected...)."""

    time: dt.datetime
    kind: str
    detail: str


class Window(BaseModel):
    """The window asked for and how it was cut."""

    since: dt.datetime
    until: dt.datetime
    bucket_s: float = Field(description="Width of one bucket, s.")


class MachineHistory(Window):
    """One machine's time series over the window."""

    machine: str
    temperatures: list[Series]
    corrections: list[Series] = Field(description="Compensation applied per axis, as its "
                                      "telemetry reported it (sampled by the center).")
    maps: list[Delivery] = Field(description="Deliveries in the window, oldest first, "
                                 "after the last one applied before it.")
    verifications: list[VerificationPoint]
    events: list[EventPoint] = Field(description="The newest 500 events in the window, "
                                     "oldest first.")


class MachineTrends(BaseModel):
    """A machine's trends on the fleet page."""

    machine: str
    temperatures: list[Series]
    corrections: list[Series]


class FleetHistory(Window):
    """Every machine's temperature and correction trends over the window."""

    machines: list[MachineTrends]


def window(until: dt.datetime | None, window_s: float, points: int
           ) -> tuple[dt.datetime, dt.datetime, float]:
    """``(since, until, bucket_s)``; ``until`` defaults to now.

    Buckets of a minute or more are whole minutes from the start of a minute (the window
    starts up to a minute early), so that the per-minute summaries serve them exactly
    (:func:`server.db.history.temperature_buckets`); still at most ``points`` of them.
    """
    end = until if until is not None else dt.datetime.now(dt.UTC)
    if end.tzinfo is None:
        end = end.replace(tzinfo=dt.UTC)
    since = end - dt.timedelta(seconds=window_s)
    if window_s / points < 60.0:
        return since, end, window_s / points
    since = since.replace(second=0, microsecond=0)
    span = (end - since).total_seconds()
    return since, end, 60.0 * math.ceil(span / points / 60.0)


def sensor_name(column: str) -> str:
    """``T_spindle_C`` → ``spindle`` (the name the machine's page shows)."""
    return column[2:-2] if column.startswith("T_") and column.endswith("_C") else column


def series(buckets: Sequence[Bucket], kind: Literal["temperature", "correction"]
           ) -> dict[int, list[Series]]:
    """Buckets (ordered by machine, series, time) as :class:`Series` by machine id."""
    grouped: dict[tuple[int, str], list[Bucket]] = defaultdict(list)
    for b in buckets:
        grouped[(b.machine_id, b.series)].append(b)
    out: dict[int, list[Series]] = defaultdict(list)
    for (machine_id, name), rows in grouped.items():
        if kind == "temperature":
            label, unit = sensor_name(name), "°C"
        else:
            label, unit = name, "µrad" if name[:1].upper() in ROTARY else "µm"
        out[machine_id].append(Series(
            name=label, unit=unit,
            t=[r.t for r in rows], mean=[r.mean for r in rows],
            low=[r.low for r in rows], high=[r.high for r in rows],
            count=[r.count for r in rows]))
    return out


def machine_history(session: Session, machine: MachineRow, until: dt.datetime | None,
                    window_s: float, points: int) -> MachineHistory:
    """One machine's history (blocking: run through ``Database.run``)."""
    since, end, bucket_s = window(until, window_s, points)
    temps = series(history_repo.temperature_buckets(session, [machine.id], since, end,
                                                    bucket_s), "temperature")
    comps = series(history_repo.correction_buckets(session, [machine.id], since, end,
                                                   bucket_s), "correction")
    maps = []
    for sent, row in history_repo.deliveries(session, machine.id, since, end):
        temperatures = row.temperatures if isinstance(row.temperatures, Mapping) else {}
        maps.append(Delivery(
            version=sent.map_version, sent_at=sent.applied_at,
            state="applied" if sent.acked else "rejected" if sent.reject_reason else "pending",
            reject_reason=sent.reject_reason, model_version=row.model_version,
            bytes=row.size_bytes,
            built_at_C={str(k): float(v) for k, v in temperatures.items()
                        if isinstance(v, int | float) and not isinstance(v, bool)}))
    verifications = []
    for report in history_repo.reports(session, machine.id, "verification", since, end):
        summary = verification_summary(report)
        value, compensated = residual(summary)
        before = max(summary.ranges_before_um.values()) if summary.ranges_before_um else None
        verifications.append(VerificationPoint(id=report.id, at=report.created_at,
                                               residual_um=value, compensated=compensated,
                                               before_um=before))
    events = [EventPoint(time=e.time, kind=e.kind, detail=e.detail)
              for e in history_repo.events(session, machine.name, since, end)]
    return MachineHistory(machine=machine.name, since=since, until=end, bucket_s=bucket_s,
                          temperatures=temps.get(machine.id, []),
                          corrections=comps.get(machine.id, []), maps=maps,
                          verifications=verifications, events=events)


def fleet_history(session: Session, machines: Sequence[MachineRow], until: dt.datetime | None,
                  window_s: float, points: int) -> FleetHistory:
    """Every machine's temperature and correction trends, in two grouped queries."""
    since, end, bucket_s = window(until, window_s, points)
    temps = series(history_repo.temperature_buckets(session, None, since, end, bucket_s),
                   "temperature")
    comps = series(history_repo.correction_buckets(session, None, since, end, bucket_s),
                   "correction")
    return FleetHistory(since=since, until=end, bucket_s=bucket_s, machines=[
        MachineTrends(machine=m.name, temperatures=temps.get(m.id, []),
                      corrections=comps.get(m.id, [])) for m in machines])
