"""Repository: the ``machines`` table."""

from __future__ import annotations

from typing import Any

from sqlalchemy import delete, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server.db.errors import DuplicateError
from server.db.secretbox import SecretBox
from server.db.tables import MachineRow


def _check_unique(session: Session, name: str, ip: str, exclude_id: int | None = None) -> None:
    for field, value in (("name", name), ("ip", ip)):
        column = MachineRow.name if field == "name" else MachineRow.ip
        query = select(MachineRow.id).where(column == value)
        if exclude_id is not None:
            query = query.where(MachineRow.id != exclude_id)
        if session.scalar(query) is not None:
            raise DuplicateError("machine", field, value)


def _flush(session: Session, name: str) -> None:
    # The checks above race with another process writing the same name; the unique
    # constraints are the real guard.
    try:
        session.flush()
    except IntegrityError:
        raise DuplicateError("machine", "name or ip", name) from None


def create_machine(
    session: Session, *, name: str, ip: str, controller: str,
    description: dict[str, Any], secret: str, box: SecretBox | None = None,
) -> MachineRow:
    """Add a machine; raise :class:`DuplicateError` when its name or ip is taken.

    ``box`` seals the secret (bound to the new row's id, hence after the first flush);
    without it the secret is stored as given.
    """
    _check_unique(session, name, ip)
    row = MachineRow(
        name=name, ip=ip, controller=controller, description=description, secret=secret
    )
    session.add(row)
    _flush(session, name)
    if box is not None and box.seals:
        row.secret = box.seal(secret, row.id)
        session.flush()
    return row


def get_machine(session: Session, name: str) -> MachineRow | None:
    """The machine called ``name``, or None."""
    return session.scalar(select(MachineRow).where(MachineRow.name == name))


def get_machine_by_ip(session: Session, ip: str) -> MachineRow | None:
    """The machine known by address ``ip`` (how the TCP server identifies a peer), or None."""
    return session.scalar(select(MachineRow).where(MachineRow.ip == ip))


def list_machines(session: Session) -> list[MachineRow]:
    """All machines, by name."""
    return list(session.scalars(select(MachineRow).order_by(MachineRow.name)))


def update_machine(
    session: Session, name: str, *, description: dict[str, Any], secret: str | None = None,
    box: SecretBox | None = None,
) -> MachineRow | None:
    """Replace a machine's description (its name, ip and controller follow it) and,
    when given, its secret. None when there is no such machine."""
    row = get_machine(session, name)
    if row is None:
        return None
    new_name, new_ip = str(description["name"]), str(description["ip"])
    _check_unique(session, new_name, new_ip, exclude_id=row.id)
    row.name = new_name
    row.ip = new_ip
    row.controller = str(description["controller"])
    row.description = description
    if secret is not None:
        row.secret = box.seal(secret, row.id) if box is not None else secret
    _flush(session, new_name)
    return row


def delete_machine(session: Session, name: str) -> bool:
    """Delete a machine and (by cascade) its models, data, maps and reports."""
    result = session.execute(delete(MachineRow).where(MachineRow.name == name))
    return bool(getattr(result, "rowcount", 0))
