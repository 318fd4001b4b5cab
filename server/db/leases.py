"""Repository: the ``leases`` table, which node serves which machine.

Every change is one statement whose ``WHERE`` says when it may happen, so two nodes racing
for the same machine cannot both win, whatever the interleaving:

* :func:`acquire`: ``UPDATE ... WHERE machine = m AND (owner = me OR expires_at < now)``;
  when no row was updated, ``INSERT ... ON CONFLICT DO NOTHING`` (the primary key guards
  a row two nodes insert at once); when neither wrote, another node holds the lease and
  the row says which. On PostgreSQL a concurrent UPDATE waits for the other's row lock and
  re-checks its ``WHERE`` against the committed row, so only one node steals an expired
  lease.
* :func:`renew`: ``UPDATE ... WHERE owner = me AND machine IN (...)``, one statement for
  all of a node's machines; the machines it did not update are lost to another node.
* :func:`release`: ``DELETE ... WHERE owner = me``: a node never deletes another's lease.

Time: every comparison uses one clock, :func:`clock` (PostgreSQL's ``clock_timestamp()``
when the database is PostgreSQL, so nodes on several hosts agree whatever their own
clocks say; the process clock on SQLite, which only one host can share). Tests pass
``now`` to step through expiry without sleeping.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any, Final

from sqlalchemy import case, delete, func, literal, or_, select, update
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session

from server.db.tables import LeaseRow, UTCDateTime

_CHUNK: Final = 500
"""Machine ids per renewal statement: well under every backend's parameter limit."""


@dataclass(frozen=True, slots=True)
class Lease:
    """A lease as stored: ``owner`` serves ``machine_id`` until ``expires_at`` (UTC)."""

    machine_id: int
    owner: str
    acquired_at: dt.datetime
    expires_at: dt.datetime


def _lease(row: LeaseRow) -> Lease:
    return Lease(row.machine_id, row.owner, row.acquired_at, row.expires_at)


def clock(session: Session) -> dt.datetime:
    """Now (UTC) on the clock every lease comparison uses (module docstring)."""
    if session.get_bind().dialect.name == "postgresql":
        now = session.scalar(select(func.clock_timestamp()))
        if isinstance(now, dt.datetime):
            return now.astimezone(dt.UTC)
    return dt.datetime.now(dt.UTC)


def _ttl(ttl_s: float) -> dt.timedelta:
    if not ttl_s > 0:
        raise ValueError(f"lease time to live must be > 0 s, got {ttl_s}")
    return dt.timedelta(seconds=ttl_s)


def acquire(session: Session, machine_id: int, node: str, ttl_s: float,
            now: dt.datetime | None = None) -> Lease:
    """Take or keep the lease of ``machine_id`` for ``node`` for ``ttl_s`` seconds.

    Returns
    -------
    Lease
        The lease as it stands after the call: ``owner == node`` when ``node`` holds it
        (newly, or renewed), else the other node's unexpired lease.
    """
    ttl = _ttl(ttl_s)
    now = now or clock(session)
    when = literal(now, UTCDateTime())
    for _ in range(3):  # a row deleted between the two statements: look again
        taken = session.execute(
            update(LeaseRow)
            .where(LeaseRow.machine_id == machine_id,
                   or_(LeaseRow.owner == node, LeaseRow.expires_at < when))
            .values(owner=node, expires_at=now + ttl,
                    acquired_at=case((LeaseRow.owner == node, LeaseRow.acquired_at),
                                     else_=when))
            .returning(LeaseRow.machine_id, LeaseRow.acquired_at)
            .execution_options(synchronize_session=False)
        ).first()
        if taken is not None:
            return Lease(machine_id, node, taken.acquired_at, now + ttl)
        values = {"machine_id": machine_id, "owner": node, "acquired_at": now,
                  "expires_at": now + ttl}
        inserted = session.execute(_insert_new(session, values)).first()
        if inserted is not None:
            return Lease(machine_id, node, now, now + ttl)
        row = session.scalar(select(LeaseRow).where(LeaseRow.machine_id == machine_id)
                             .execution_options(populate_existing=True))
        if row is not None:
            return _lease(row)
    raise RuntimeError(f"lease of machine {machine_id}: row kept changing under the query")


def _insert_new(session: Session, values: dict[str, Any]) -> Any:
    """``INSERT ... ON CONFLICT DO NOTHING RETURNING machine_id`` in the session's dialect."""
    if session.get_bind().dialect.name == "postgresql":
        return (postgresql.insert(LeaseRow).values(**values)
                .on_conflict_do_nothing(index_elements=[LeaseRow.machine_id])
                .returning(LeaseRow.machine_id))
    return (sqlite.insert(LeaseRow).values(**values)
            .on_conflict_do_nothing(index_elements=[LeaseRow.machine_id])
            .returning(LeaseRow.machine_id))


def renew(session: Session, machine_ids: Iterable[int], node: str, ttl_s: float,
          now: dt.datetime | None = None) -> set[int]:
    """Extend ``node``'s leases of ``machine_ids`` to ``now + ttl_s``.

    Returns
    -------
    set of int
        The machines whose lease ``node`` still holds; the others were taken by another
        node after they expired (or released): their sessions must end.
    """
    ttl = _ttl(ttl_s)
    ids = sorted(set(machine_ids))
    if not ids:
        return set()
    now = now or clock(session)
    kept: set[int] = set()
    for start in range(0, len(ids), _CHUNK):
        chunk = ids[start:start + _CHUNK]
        kept.update(session.scalars(
            update(LeaseRow).where(LeaseRow.owner == node, LeaseRow.machine_id.in_(chunk))
            .values(expires_at=now + ttl).returning(LeaseRow.machine_id)
            .execution_options(synchronize_session=False)))
    return kept


def release(session: Session, machine_ids: Iterable[int], node: str) -> int:
    """Delete ``node``'s leases of ``machine_ids`` (another node's are left alone);
    returns how many were deleted."""
    ids = sorted(set(machine_ids))
    gone = 0
    for start in range(0, len(ids), _CHUNK):
        gone += len(list(session.scalars(
            delete(LeaseRow).where(LeaseRow.owner == node,
                                   LeaseRow.machine_id.in_(ids[start:start + _CHUNK]))
            .returning(LeaseRow.machine_id).execution_options(synchronize_session=False))))
    return gone


def release_all(session: Session, node: str) -> int:
    """Delete every lease of ``node`` (its clean shutdown); returns how many."""
    return len(list(session.scalars(
        delete(LeaseRow).where(LeaseRow.owner == node).returning(LeaseRow.machine_id)
        .execution_options(synchronize_session=False))))


def list_leases(session: Session, *, live_only: bool = False,
                now: dt.datetime | None = None) -> list[Lease]:
    """Every lease by machine id; ``live_only`` leaves out the expired ones."""
    query = select(LeaseRow).order_by(LeaseRow.machine_id)
    if live_only:
        query = query.where(LeaseRow.expires_at >= literal(now or clock(session),
                                                           UTCDateTime()))
    return [_lease(r) for r in session.scalars(query)]


__all__ = ["Lease", "acquire", "clock", "list_leases", "release", "release_all", "renew"]
