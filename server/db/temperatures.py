"""Repository: the ``temperature_readings`` table (every accepted temperature reading).

Written in batches by :class:`server.intake.TemperatureIntake` (one multi-row INSERT per
flush: a plant sends hundreds of readings a second, a transaction each would be the
bottleneck), read per machine for the REST API, pruned by age.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass

from sqlalchemy import delete, insert, select
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


def delete_readings_before(session: Session, time: dt.datetime) -> int:
    """Delete readings taken before ``time``; return how many (retention)."""
    result = session.execute(delete(TemperatureReadingRow)
                             .where(TemperatureReadingRow.time < time))
    return int(getattr(result, "rowcount", 0) or 0)
