"""Repository: the ``events`` table (connections, refusals, pushes, rejections)."""

from __future__ import annotations

import datetime as dt

from sqlalchemy import select
from sqlalchemy.orm import Session

from server.db.tables import EventRow, utcnow


def add_event(
    session: Session, *, kind: str, machine: str, detail: str = "",
    time: dt.datetime | None = None,
) -> EventRow:
    """Append an event; ``machine`` is a machine name or, for unknown peers, an address."""
    row = EventRow(kind=kind, machine=machine, detail=detail, time=time or utcnow())
    session.add(row)
    session.flush()
    return row


def list_events(
    session: Session, *, kind: str | None = None, machine: str | None = None,
    before_id: int | None = None, limit: int = 100,
) -> list[EventRow]:
    """Events newest first, optionally of one kind / one machine, older than ``before_id``
    (for paging)."""
    query = select(EventRow)
    if kind is not None:
        query = query.where(EventRow.kind == kind)
    if machine is not None:
        query = query.where(EventRow.machine == machine)
    if before_id is not None:
        query = query.where(EventRow.id < before_id)
    return list(session.scalars(query.order_by(EventRow.id.desc()).limit(limit)))
