"""Repository: the ``correction_samples`` table (a machine's applied compensation per axis
and sampling period; see :class:`~server.db.tables.CorrectionSampleRow`)."""

from __future__ import annotations

import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass

from sqlalchemy import delete, insert
from sqlalchemy.orm import Session

from server.db.tables import CorrectionSampleRow


@dataclass(frozen=True, slots=True)
class NewSample:
    """One period of one axis: machine id, axis, end of the period (UTC), mean, smallest
    and largest compensation (µm, µrad for a rotary axis), readings summarised."""

    machine_id: int
    axis: str
    time: dt.datetime
    mean: float
    low: float
    high: float
    samples: int


def add_samples(session: Session, samples: Sequence[NewSample]) -> int:
    """Insert ``samples`` in one statement; returns how many."""
    if not samples:
        return 0
    session.execute(insert(CorrectionSampleRow), [
        {"machine_id": s.machine_id, "axis": s.axis, "time": s.time, "mean": s.mean,
         "low": s.low, "high": s.high, "samples": s.samples} for s in samples])
    return len(samples)


def delete_samples_before(session: Session, time: dt.datetime) -> int:
    """Delete the samples of periods that ended before ``time``; returns how many."""
    result = session.execute(delete(CorrectionSampleRow).where(CorrectionSampleRow.time < time))
    return int(getattr(result, "rowcount", 0) or 0)
