"""Repository: the ``temperature_readings`` table (every accepted temperature reading).

Written in batches by :class:`server.intake.TemperatureIntake` (one multi-row INSERT per
flush: a plant sends hundreds of readings a second, a transaction each would be the
bottleneck), read per machine for the REST API, pruned by age and by count, in batches.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass

from sqlalchemy import delete, func, insert, select
from sqlalchemy.orm import Session

from server.db.tables import TemperatureReadingRow


@dataclass(frozen=True, slots=True)
class NewReading:
    """A reading to store: machine id, model column, °C, when taken (UTC), source."""

    machine_id: int
    sensor: str
    celsius: float
    time: dt.datetime
    source: str


def add_readings(session: Session, readings: Sequence[NewReading]) -> int:
    """Insert ``readings`` in one statement; returns how many."""
    if not readings:
        return 0
    session.execute(insert(TemperatureReadingRow), [
        {"machine_id": r.machine_id, "sensor": r.sensor, "celsius": r.celsius,
         "time": r.time, "source": r.source} for r in readings])
    return len(readings)


def list_readings(session: Session, machine_id: int, *, sensor: str | None = None,
                  since: dt.datetime | None = None, until: dt.datetime | None = None,
                  limit: int = 1000) -> list[TemperatureReadingRow]:
    """A machine's readings, newest first, optionally of one column and a time window
    (``since`` inclusive, ``until`` exclusive), at most ``limit``."""
    query = select(TemperatureReadingRow).where(TemperatureReadingRow.machine_id == machine_id)
    if sensor is not None:
        query = query.where(TemperatureReadingRow.sensor == sensor)
    if since is not None:
        query = query.where(TemperatureReadingRow.time >= since)
    if until is not None:
        query = query.where(TemperatureReadingRow.time < until)
    order = (TemperatureReadingRow.time.desc(), TemperatureReadingRow.id.desc())
    return list(session.scalars(query.order_by(*order).limit(limit)))


def delete_readings_before(session: Session, time: dt.datetime, *,
                           limit: int | None = None) -> int:
    """Delete readings taken before ``time``, at most ``limit`` of them (the oldest ids
    first; all without a limit); return how many (retention).

    A plant writes hundreds of rows a second, so a day's expiry is tens of millions of
    rows: deleting them in one statement would hold SQLite's write lock (and the intake's
    and the push's writes behind it) for minutes. The caller deletes in batches, one
    transaction each.
    """
    if limit is None:
        doomed = delete(TemperatureReadingRow).where(TemperatureReadingRow.time < time)
    else:
        ids = (select(TemperatureReadingRow.id).where(TemperatureReadingRow.time < time)
               .order_by(TemperatureReadingRow.id).limit(limit))
        doomed = delete(TemperatureReadingRow).where(
            TemperatureReadingRow.id.in_(ids.scalar_subquery()))
    result = session.execute(doomed)
    return int(getattr(result, "rowcount", 0) or 0)


def delete_readings_beyond(session: Session, keep: int, *, limit: int) -> int:
    """Delete the oldest readings beyond the newest ``keep`` (by id, which grows with
    every insert), at most ``limit`` of them; return how many. Bounds the table whatever
    the rate: counting rows would scan it, the ids tell without a scan."""
    newest = session.scalar(select(func.max(TemperatureReadingRow.id)))
    oldest = session.scalar(select(func.min(TemperatureReadingRow.id)))
    if newest is None or oldest is None:
        return 0
    first_kept = int(newest) - keep + 1
    if oldest >= first_kept:
        return 0
    result = session.execute(delete(TemperatureReadingRow).where(
        TemperatureReadingRow.id < min(first_kept, int(oldest) + limit)))
    return int(getattr(result, "rowcount", 0) or 0)
