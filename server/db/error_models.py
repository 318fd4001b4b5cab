"""Repository: the ``models`` table (versioned error models per machine).

Named ``error_models`` so that "model" never has to mean an ORM class here.
"""

from __future__ import annotations

from typing import Any

from sqlalchemy import func, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server.db.errors import DuplicateError
from server.db.tables import ModelRow


def add_model(session: Session, machine_id: int, *, source: str, body: dict[str, Any]) -> ModelRow:
    """Store a new model version (one more than the machine's latest, starting at 1)."""
    latest = session.scalar(
        select(func.max(ModelRow.version)).where(ModelRow.machine_id == machine_id)
    )
    row = ModelRow(machine_id=machine_id, version=(latest or 0) + 1, source=source, body=body)
    session.add(row)
    try:
        session.flush()
    except IntegrityError:  # another writer took the same version number
        raise DuplicateError("model", "version", str(row.version)) from None
    return row


def list_models(session: Session, machine_id: int) -> list[ModelRow]:
    """A machine's models, newest first."""
    query = select(ModelRow).where(ModelRow.machine_id == machine_id)
    return list(session.scalars(query.order_by(ModelRow.version.desc())))


def get_model(session: Session, machine_id: int, version: int | None = None) -> ModelRow | None:
    """One model version, or the latest when ``version`` is None; None when absent."""
    query = select(ModelRow).where(ModelRow.machine_id == machine_id)
    if version is not None:
        return session.scalar(query.where(ModelRow.version == version))
    return session.scalar(query.order_by(ModelRow.version.desc()).limit(1))
