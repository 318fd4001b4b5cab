"""Repository: the ``events`` table (connections, refusals, pushes, rejections)."""

from __future__ import annotations

import datetime as dt

from sqlalchemy import delete, insert, select
from sqlalchemy.orm import Session

from server.db.tables import Base, EventRow, utcnow

MAX_MACHINE_CHARS = 128  # the column's width
MAX_DETAIL_CHARS = 2000


def _storable(text: str, limit: int) -> str:
    # Event text often comes from peers (a refused Hello's name, a reject reason): make it
    # something every backend stores (PostgreSQL refuses NUL; varchar has a width).
    text = text.replace("\x00", "\\0")
    return text if len(text) <= limit else text[: limit - 1] + "…"


def add_event(
    session: Session, *, kind: str, machine: str, detail: str = "",
    time: dt.datetime | None = None,
) -> EventRow:
    """Append an event; ``machine`` is a machine name or, for unknown peers, an address.

    NUL characters are escaped and over-long texts shortened (with ``…``), never refused:
    an event must not fail because of what a peer sent.
    """
    row = EventRow(kind=kind, machine=_storable(machine, MAX_MACHINE_CHARS),
                   detail=_storable(detail, MAX_DETAIL_CHARS), time=time or utcnow())
    session.add(row)
    session.flush()
    return row


_INSERT = insert(Base.metadata.tables[EventRow.__tablename__])


def note_event(session: Session, *, kind: str, machine: str, detail: str = "") -> None:
    """:func:`add_event` without its row object: one Core INSERT in this transaction, for
    the push's steps (a thousand machines a round; the ORM's flush costs several times
    the statement)."""
    session.connection().execute(_INSERT, {
        "kind": kind, "machine": _storable(machine, MAX_MACHINE_CHARS),
        "detail": _storable(detail, MAX_DETAIL_CHARS), "time": utcnow()})


def add_events(session: Session, kind: str, rows: list[tuple[str, str]]) -> int:
    """Append events of one ``kind``, ``(machine, detail)`` each, in this transaction."""
    now = utcnow()
    session.add_all(EventRow(kind=kind, machine=_storable(machine, MAX_MACHINE_CHARS),
                             detail=_storable(detail, MAX_DETAIL_CHARS), time=now)
                    for machine, detail in rows)
    session.flush()
    return len(rows)


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


def delete_events_before(session: Session, time: dt.datetime) -> int:
    """Delete events older than ``time``; return how many (retention)."""
    result = session.execute(delete(EventRow).where(EventRow.time < time))
    return int(getattr(result, "rowcount", 0) or 0)
