"""Read queries: a machine's (or every machine's) time series over a window, downsampled
in the database.

The dashboard's trends span minutes to months; a month of one sensor is millions of
readings at a plant's rates. The database groups them into ``bucket_s`` wide buckets
(``floor((epoch(time) - epoch(since) + 1 ms) / bucket_s)``) and returns per bucket the mean
time, mean, smallest and largest value and the count, so that a trend costs at most
``window / bucket_s`` points per series whatever the rate. Seconds since the epoch are
``extract(epoch ...)`` on PostgreSQL and ``julianday`` on SQLite (which stores UTC
timestamps as text).
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass
from typing import Any

from sqlalchemy import Float, cast, extract, func, select
from sqlalchemy.orm import Session, defer
from sqlalchemy.sql.elements import ColumnElement

from server.db.tables import (
    AppliedRow,
    CorrectionSampleRow,
    DiagnosisRow,
    EventRow,
    MachineRow,
    MapVersionRow,
    TemperatureReadingRow,
)

UNIX_EPOCH_JULIAN_DAY = 2440587.5
EDGE_S = 1e-3
"""Bucket edges are this much early, s (see :func:`_buckets`)."""


@dataclass(frozen=True, slots=True)
class Bucket:
    """One downsampled point of one series.

    Attributes
    ----------
    machine_id : int
    series : str
        The sensor (model column) or the axis.
    t : float
        Mean time of the values in the bucket, s since the Unix epoch (UTC).
    mean, low, high : float
        Mean, smallest and largest value in the bucket (the series' unit).
    count : int
        Values (or stored periods) in the bucket.
    """

    machine_id: int
    series: str
    t: float
    mean: float
    low: float
    high: float
    count: int


def epoch(session: Session, column: Any) -> ColumnElement[float]:
    """Seconds since the Unix epoch of a timestamp column, on this session's backend."""
    if session.get_bind().dialect.name == "sqlite":
        return (func.julianday(column) - UNIX_EPOCH_JULIAN_DAY) * 86400.0
    return cast(extract("epoch", column), Float)


def _buckets(session: Session, row: Any, series: Any, value: Any, low: Any, high: Any,
             count: Any, machine_ids: list[int] | None, since: dt.datetime,
             until: dt.datetime, bucket_s: float) -> list[Bucket]:
    t = epoch(session, row.time)
    # + EDGE_S: SQLite's julianday carries ~50 µs of rounding, which would put a reading
    # taken exactly on a bucket's edge into the bucket before
    index = func.floor((t - since.timestamp() + EDGE_S) / bucket_s)
    query = select(row.machine_id, series, func.avg(t), value, low, high, count).where(
        row.time >= since, row.time < until)
    if machine_ids is not None:
        query = query.where(row.machine_id.in_(machine_ids))
    query = query.group_by(row.machine_id, series, index).order_by(
        row.machine_id, series, index)
    return [Bucket(int(m), str(s), float(tt), float(v), float(lo), float(hi), int(n))
            for m, s, tt, v, lo, hi, n in session.execute(query)]


def temperature_buckets(session: Session, machine_ids: list[int] | None, since: dt.datetime,
                        until: dt.datetime, bucket_s: float) -> list[Bucket]:
    """Accepted temperature readings per machine and sensor (°C), downsampled."""
    r = TemperatureReadingRow
    return _buckets(session, r, r.sensor, func.avg(r.celsius), func.min(r.celsius),
                    func.max(r.celsius), func.count(), machine_ids, since, until, bucket_s)


def correction_buckets(session: Session, machine_ids: list[int] | None, since: dt.datetime,
                       until: dt.datetime, bucket_s: float) -> list[Bucket]:
    """Applied compensation per machine and axis (µm; µrad rotary), downsampled: the
    mean of the stored periods' means weighted by their readings, the extremes of theirs."""
    r = CorrectionSampleRow
    mean = func.sum(r.mean * r.samples) / func.sum(r.samples)
    return _buckets(session, r, r.axis, mean, func.min(r.low), func.max(r.high),
                    func.sum(r.samples), machine_ids, since, until, bucket_s)


def deliveries(session: Session, machine_id: int, since: dt.datetime, until: dt.datetime,
               limit: int = 1000) -> list[tuple[AppliedRow, MapVersionRow]]:
    """The machine's map deliveries sent in the window with their maps (no payload),
    oldest first, and the last one before the window (what was applied when it began)."""
    base = (select(AppliedRow, MapVersionRow).join(MapVersionRow,
                                                   MapVersionRow.id == AppliedRow.map_id)
            .where(AppliedRow.machine_id == machine_id)
            .options(defer(MapVersionRow.payload, raiseload=True)))
    inside = session.execute(base.where(AppliedRow.applied_at >= since,
                                        AppliedRow.applied_at < until)
                             .order_by(AppliedRow.id.desc()).limit(limit)).all()
    before = session.execute(base.where(AppliedRow.applied_at < since, AppliedRow.acked)
                             .order_by(AppliedRow.id.desc()).limit(1)).all()
    rows = list(reversed(inside)) if not before else list(before) + list(reversed(inside))
    return [(a, m) for a, m in rows]


def reports(session: Session, machine_id: int, kind: str, since: dt.datetime,
            until: dt.datetime, limit: int = 1000) -> list[DiagnosisRow]:
    """The machine's reports of ``kind`` made in the window, oldest first."""
    query = select(DiagnosisRow).where(
        DiagnosisRow.machine_id == machine_id, DiagnosisRow.kind == kind,
        DiagnosisRow.created_at >= since, DiagnosisRow.created_at < until)
    return list(reversed(session.scalars(query.order_by(DiagnosisRow.id.desc()).limit(limit))
                         .all()))


def events(session: Session, machine: str, since: dt.datetime, until: dt.datetime,
           limit: int = 500) -> list[EventRow]:
    """The machine's events in the window, newest ``limit``, oldest first."""
    query = select(EventRow).where(EventRow.machine == machine, EventRow.time >= since,
                                   EventRow.time < until)
    return list(reversed(session.scalars(query.order_by(EventRow.id.desc()).limit(limit))
                         .all()))


def rejects_by_machine(session: Session) -> dict[str, int]:
    """Stored rejected deliveries per machine name (every one the table still holds)."""
    query = (select(MachineRow.name, func.count()).join(AppliedRow,
                                                         AppliedRow.machine_id == MachineRow.id)
             .where(AppliedRow.reject_reason.is_not(None)).group_by(MachineRow.name))
    return {str(name): int(n) for name, n in session.execute(query)}
