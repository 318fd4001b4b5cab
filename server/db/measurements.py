"""Repository: the ``measurement_sets`` table (raw measurement CSV per machine)."""

from __future__ import annotations

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session, defer

from server.db.errors import DuplicateError
from server.db.tables import MeasurementSetRow


def add_measurement_set(
    session: Session, machine_id: int, *, name: str, csv_text: str, row_count: int
) -> MeasurementSetRow:
    """Store a CSV under ``name``; :class:`DuplicateError` when the machine has that name."""
    taken = select(MeasurementSetRow.id).where(
        MeasurementSetRow.machine_id == machine_id, MeasurementSetRow.name == name
    )
    if session.scalar(taken) is not None:
        raise DuplicateError("measurement set", "name", name)
    row = MeasurementSetRow(machine_id=machine_id, name=name, csv_text=csv_text,
                            row_count=row_count, size_bytes=len(csv_text.encode()))
    session.add(row)
    try:
        session.flush()
    except IntegrityError:
        raise DuplicateError("measurement set", "name", name) from None
    return row


# Listings and metadata leave the CSV (megabytes) in the database; touching it on such a
# row raises instead of lazily loading on a row whose session is gone.
_WITHOUT_TEXT = defer(MeasurementSetRow.csv_text, raiseload=True)


def list_measurement_sets(session: Session, machine_id: int) -> list[MeasurementSetRow]:
    """A machine's measurement sets, newest first, without their CSV text."""
    query = select(MeasurementSetRow).where(MeasurementSetRow.machine_id == machine_id)
    query = query.options(_WITHOUT_TEXT).order_by(MeasurementSetRow.id.desc())
    return list(session.scalars(query))


def get_measurement_set(
    session: Session, machine_id: int, name: str, *, with_text: bool = True
) -> MeasurementSetRow | None:
    """The set called ``name`` (its CSV text only ``with_text``), or None."""
    query = select(MeasurementSetRow).where(
        MeasurementSetRow.machine_id == machine_id, MeasurementSetRow.name == name
    )
    if not with_text:
        query = query.options(_WITHOUT_TEXT)
    return session.scalar(query)


def count_measurement_sets(session: Session, machine_id: int) -> int:
    """How many sets the machine has (used to name unnamed uploads)."""
    rows = select(MeasurementSetRow.id).where(MeasurementSetRow.machine_id == machine_id)
    return len(session.scalars(rows).all())
