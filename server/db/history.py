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

from sqlalchemy import Float, cast, delete, extract, func, insert, select
from sqlalchemy.orm import Session, defer
from sqlalchemy.sql.elements import ColumnElement

from server.db.tables import (
    AppliedRow,
    CorrectionSampleRow,
    DiagnosisRow,
    EventRow,
    MachineRow,
    MapVersionRow,
    TemperatureMinuteRow,
    TemperatureReadingRow,
)

UNIX_EPOCH_JULIAN_DAY = 2440587.5
MINUTE = dt.timedelta(minutes=1)
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


def _grouped(session: Session, row: Any, series: Any, t: Any, value: Any, low: Any,
             high: Any, count: Any, machine_ids: list[int] | None, time_col: Any,
             origin: dt.datetime, start: dt.datetime, end: dt.datetime, bucket_s: float
             ) -> dict[tuple[int, str, int], Bucket]:
    """Buckets by (machine id, series, bucket index counted from ``origin``) of the rows
    whose ``time_col`` is in [start, end)."""
    # + EDGE_S: SQLite's julianday carries ~50 µs of rounding, which would put a reading
    # taken exactly on a bucket's edge into the bucket before
    index = func.floor((epoch(session, time_col) - origin.timestamp() + EDGE_S) / bucket_s)
    query = select(row.machine_id, series, index, t, value, low, high, count).where(
        time_col >= start, time_col < end)
    if machine_ids is not None:
        query = query.where(row.machine_id.in_(machine_ids))
    query = query.group_by(row.machine_id, series, index)
    return {(int(m), str(s), int(k)): Bucket(int(m), str(s), float(tt), float(v), float(lo),
                                             float(hi), int(n))
            for m, s, k, tt, v, lo, hi, n in session.execute(query)}


def _merged(*parts: dict[tuple[int, str, int], Bucket]) -> list[Bucket]:
    """Buckets of several sources, those of one key combined (weighted by their counts),
    ordered by machine, series and time."""
    out: dict[tuple[int, str, int], Bucket] = {}
    for part in parts:
        for key, b in part.items():
            a = out.get(key)
            if a is None:
                out[key] = b
                continue
            n = a.count + b.count
            out[key] = Bucket(a.machine_id, a.series, (a.t * a.count + b.t * b.count) / n,
                              (a.mean * a.count + b.mean * b.count) / n, min(a.low, b.low),
                              max(a.high, b.high), n)
    return [out[k] for k in sorted(out)]


def rolled_until(session: Session) -> dt.datetime | None:
    """The end of the last minute summarised in ``temperature_minutes`` (None: none yet)."""
    last = session.scalar(select(func.max(TemperatureMinuteRow.minute)))
    return None if last is None else last + MINUTE


def temperature_buckets(session: Session, machine_ids: list[int] | None, since: dt.datetime,
                        until: dt.datetime, bucket_s: float) -> list[Bucket]:
    """Accepted temperature readings per machine and sensor (°C), downsampled.

    Buckets of whole minutes starting on a minute read the per-minute summaries up to
    where they reach (:func:`roll_up`) and the readings after it; others read the
    readings. Both give the same buckets (tests/test_history.py).
    """
    whole_minutes = bucket_s % 60 == 0 and since.second == 0 and since.microsecond == 0
    reach = rolled_until(session) if whole_minutes else None
    if reach is None or reach <= since:
        return _merged(_raw_from(session, machine_ids, since, since, until, bucket_s))
    boundary = min(reach, until)
    m = TemperatureMinuteRow
    weight = func.sum(m.count)
    minutes = _grouped(session, m, m.sensor, func.sum(m.t_mean * m.count) / weight,
                       func.sum(m.mean * m.count) / weight, func.min(m.low), func.max(m.high),
                       weight, machine_ids, m.minute, since, since, boundary, bucket_s)
    if boundary >= until:
        return _merged(minutes)
    return _merged(minutes, _raw_from(session, machine_ids, since, boundary, until, bucket_s))


def _raw_from(session: Session, machine_ids: list[int] | None, since: dt.datetime,
              start: dt.datetime, end: dt.datetime, bucket_s: float
              ) -> dict[tuple[int, str, int], Bucket]:
    """Buckets (indexed from ``since``) of the readings in [start, end)."""
    r = TemperatureReadingRow
    t = epoch(session, r.time)
    return _grouped(session, r, r.sensor, func.avg(t), func.avg(r.celsius),
                    func.min(r.celsius), func.max(r.celsius), func.count(), machine_ids,
                    r.time, since, start, end, bucket_s)


def roll_up(session: Session, now: dt.datetime, *, chunk_s: float = 86400.0) -> int:
    """Summarise the readings of the complete minutes not summarised yet, at most
    ``chunk_s`` of them per call, into ``temperature_minutes``; returns the rows added.

    A minute is complete one minute after it ended (a reading is stamped when taken and
    may arrive a little later); a reading that arrives later still stays out of the
    summary (it is in the readings). Several nodes may run this at once: the loser's
    insert hits the primary key and it adds nothing (the caller rolls back).
    """
    start = rolled_until(session)
    first = session.scalar(select(func.min(TemperatureReadingRow.time)).where(
        *(() if start is None else (TemperatureReadingRow.time >= start,))))
    if first is None:
        return 0
    first = first.replace(second=0, microsecond=0)
    start = first if start is None else max(start, first)  # skip a silent stretch
    end = min(now.replace(second=0, microsecond=0) - MINUTE,
              start + dt.timedelta(seconds=chunk_s))
    if end <= start:
        return 0
    buckets = _raw_from(session, None, start, start, end, 60.0)
    rows = [{"machine_id": m, "sensor": s, "minute": start + k * MINUTE, "t_mean": b.t,
             "mean": b.mean, "low": b.low, "high": b.high, "count": b.count}
            for (m, s, k), b in buckets.items()]
    if rows:
        session.execute(insert(TemperatureMinuteRow), rows)
    return len(rows)


def delete_minutes_before(session: Session, time: dt.datetime) -> int:
    """Delete the minute summaries older than ``time``; returns how many (retention)."""
    result = session.execute(delete(TemperatureMinuteRow).where(
        TemperatureMinuteRow.minute < time))
    return int(getattr(result, "rowcount", 0) or 0)


def correction_buckets(session: Session, machine_ids: list[int] | None, since: dt.datetime,
                       until: dt.datetime, bucket_s: float) -> list[Bucket]:
    """Applied compensation per machine and axis (µm; µrad rotary), downsampled: the
    mean of the stored periods' means weighted by their readings, the extremes of theirs."""
    r = CorrectionSampleRow
    weight = func.sum(r.samples)
    return _merged(_grouped(session, r, r.axis, func.avg(epoch(session, r.time)),
                            func.sum(r.mean * r.samples) / weight, func.min(r.low),
                            func.max(r.high), weight, machine_ids, r.time, since, since,
                            until, bucket_s))


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
