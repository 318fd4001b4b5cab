"""Repository: the ``machines`` table."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from typing import Any

from sqlalchemy import delete, func, select, text
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session

from server.db.errors import DuplicateError
from server.db.secretbox import SecretBox
from server.db.tables import MachineRow

LINK_KINDS = ("ednc", "modbus", "opcua", "sinumerik_sd")
"""The ``link.kind`` values a description may carry (server/schemas/link.py)."""


def link_kind(description: Mapping[str, Any]) -> str:
    """``ednc``, ``modbus``, ``opcua`` or ``sinumerik_sd``: the description's link kind
    (no link, or one this center does not know, is ``ednc``)."""
    link = description.get("link")
    kind = link.get("kind") if isinstance(link, Mapping) else None
    return kind if kind in LINK_KINDS else "ednc"


def _lock_ip(session: Session, ip: str) -> None:
    """Serialise registrations at ``ip`` until this transaction ends.

    The partial unique index holds one EDNC machine per ip, but no index can hold "no
    link machine at an EDNC machine's ip" (link machines must stay free to share one), so
    two transactions could each check, see nothing, and insert. Holding a lock from the
    check to the commit makes them one step:

    * PostgreSQL: a transaction-scoped advisory lock keyed by the ip (other ips go on);
    * SQLite: the database's write lock, taken by a write that changes nothing (the
      driver begins the transaction at the first write, so the check's reads would
      otherwise run before it and see a state another writer is about to change).
    """
    dialect = session.get_bind().dialect.name
    if dialect == "postgresql":
        # a 64-bit key from the ip (advisory locks share one key space per database; the
        # prefix keeps this use apart from any other)
        key = int.from_bytes(hashlib.blake2b(b"machines.ip:" + ip.encode(), digest_size=8)
                             .digest(), "big", signed=True)
        session.execute(select(func.pg_advisory_xact_lock(key)))
    elif dialect == "sqlite":
        session.execute(text("UPDATE machines SET id = id WHERE 1 = 0"))


def _check_unique(session: Session, name: str, ip: str, kind: str,
                  exclude_id: int | None = None) -> None:
    """Raise :class:`DuplicateError` when ``name`` is taken, or ``ip`` cannot be shared.

    The ip keys EDNC logins only: an EDNC machine (``kind`` ``ednc``) needs an ip no other
    machine has; link machines may share one with each other (the gateway's or the
    controller's address) but not with an EDNC machine, whose address the EDNC server
    admits and checks logins against: it would then be the address of two machines.
    """
    _lock_ip(session, ip)
    others = select(MachineRow.id)
    if exclude_id is not None:
        others = others.where(MachineRow.id != exclude_id)
    if session.scalar(others.where(MachineRow.name == name)) is not None:
        raise DuplicateError("machine", "name", name)
    at_ip = others.where(MachineRow.ip == ip)
    if kind != "ednc":
        at_ip = at_ip.where(MachineRow.link == "ednc")
    if session.scalar(at_ip) is not None:
        raise DuplicateError("machine", "ip", ip, why=(
            "an EDNC machine needs an ip of its own (its logins are admitted and checked "
            "by address); only machines reached through a link share one" if kind == "ednc"
            else "an EDNC machine logs in from it: a machine reached through a link may "
            "share an ip with other link machines only"))


def _flush(session: Session, name: str) -> None:
    # The checks above race with another process writing the same name; the unique
    # constraints (name; ip among EDNC machines) are the real guard.
    try:
        session.flush()
    except IntegrityError:
        raise DuplicateError("machine", "name or ip", name) from None


def create_machine(
    session: Session, *, name: str, ip: str, controller: str,
    description: dict[str, Any], secret: str, box: SecretBox | None = None,
) -> MachineRow:
    """Add a machine; raise :class:`DuplicateError` when its name is taken or its ip
    cannot be shared (:func:`_check_unique`).

    ``box`` seals the secret (bound to the new row's id, hence after the first flush);
    without it the secret is stored as given.
    """
    kind = link_kind(description)
    _check_unique(session, name, ip, kind)
    row = MachineRow(name=name, ip=ip, link=kind, controller=controller,
                     description=description, secret=secret)
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
    """The EDNC machine registered at address ``ip`` (the one that logs in from there), or
    None. Link machines are not looked up by ip: several may share one."""
    return session.scalar(select(MachineRow).where(MachineRow.ip == ip,
                                                   MachineRow.link == "ednc"))


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
    kind = link_kind(description)
    _check_unique(session, new_name, new_ip, kind, exclude_id=row.id)
    row.name = new_name
    row.ip = new_ip
    row.link = kind
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
