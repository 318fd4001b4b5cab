"""Repository: the ``measurement_sets`` table (raw measurement CSV per machine)."""

from __future__ import annotations

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

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
                            row_count=row_count)
    session.add(row)
    try:
        session.flush()
    except IntegrityError:
        raise DuplicateError("measurement set", "name", name) from None
    return row


def list_measurement_sets(session: Session, machine_id: int) -> list[MeasurementSetRow]:
    """A machine's measurement sets, newest first."""
    query = select(MeasurementSetRow).where(MeasurementSetRow.machine_id == machine_id)
    return list(session.scalars(query.order_by(MeasurementSetRow.id.desc())))


def get_measurement_set(session: Session, machine_id: int, name: str) -> MeasurementSetRow | None:
    """The set called ``name``, or None."""
    return session.scalar(
        select(MeasurementSetRow).where(
            MeasurementSetRow.machine_id == machine_id, MeasurementSetRow.name == name
        )
    )


def count_measurement_sets(session: Session, machine_id: int) -> int:
    """How many sets the machine has (used to name unnamed uploads)."""
    rows = select(MeasurementSetRow.id).where(MeasurementSetRow.machine_id == machine_id)
    return len(session.scalars(rows).all())
