"""Repository: the ``map_versions`` and ``applied`` tables (error maps and their delivery)."""

from __future__ import annotations

import datetime as dt
import hashlib
from dataclasses import dataclass
from typing import Any, Literal

from sqlalchemy import and_, func, or_, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session, defer

from server.db.errors import DuplicateError
from server.db.tables import AppliedRow, MachineRow, MapVersionMarkRow, MapVersionRow, utcnow


def _name(session: Session, machine_id: int) -> str | None:
    return session.scalar(select(MachineRow.name).where(MachineRow.id == machine_id))


def next_map_version(session: Session, machine_id: int) -> int:
    """The version the machine's next map gets: above its own maps and above every version
    stored for its name before (a machine deleted and registered again, see
    :class:`~server.db.tables.MapVersionMarkRow`)."""
    latest = session.scalar(
        select(func.max(MapVersionRow.version)).where(MapVersionRow.machine_id == machine_id)
    ) or 0
    name = _name(session, machine_id)
    mark = session.get(MapVersionMarkRow, name) if name is not None else None
    return max(latest, mark.version if mark is not None else 0) + 1


def add_map_version(
    session: Session, machine_id: int, *, payload: bytes, model_version: int | None,
    temperatures: dict[str, Any] | None = None,
) -> MapVersionRow:
    """Store an encoded map as the machine's next version (:func:`next_map_version`;
    sha256 and size computed here) and raise its name's mark to it."""
    version = next_map_version(session, machine_id)
    row = MapVersionRow(
        machine_id=machine_id,
        version=version,
        model_version=model_version,
        payload=payload,
        sha256=hashlib.sha256(payload).hexdigest(),
        size_bytes=len(payload),
        temperatures=dict(temperatures or {}),
    )
    session.add(row)
    name = _name(session, machine_id)
    if name is not None:
        mark = session.get(MapVersionMarkRow, name)
        if mark is None:
            session.add(MapVersionMarkRow(machine=name, version=version))
        elif mark.version < version:
            mark.version = version
    try:
        session.flush()
    except IntegrityError:  # another writer took the version (or the mark) meanwhile
        raise DuplicateError("map", "version", str(row.version)) from None
    return row


# Listings and metadata leave the payload in the database (see measurements.py).
_WITHOUT_PAYLOAD = defer(MapVersionRow.payload, raiseload=True)


def list_map_versions(session: Session, machine_id: int) -> list[MapVersionRow]:
    """A machine's maps, newest first, without their payloads."""
    query = select(MapVersionRow).where(MapVersionRow.machine_id == machine_id)
    query = query.options(_WITHOUT_PAYLOAD).order_by(MapVersionRow.version.desc())
    return list(session.scalars(query))


def get_map_version(
    session: Session, machine_id: int, version: int | None = None, *, with_payload: bool = True
) -> MapVersionRow | None:
    """One map version (its payload only ``with_payload``), or the latest when ``version``
    is None; None when absent."""
    query = select(MapVersionRow).where(MapVersionRow.machine_id == machine_id)
    if not with_payload:
        query = query.options(_WITHOUT_PAYLOAD)
    if version is not None:
        return session.scalar(query.where(MapVersionRow.version == version))
    return session.scalar(query.order_by(MapVersionRow.version.desc()).limit(1))


def record_sent(
    session: Session, machine_id: int, version: int, at: dt.datetime | None = None
) -> AppliedRow | None:
    """Note that map ``version`` was sent to the machine (pending its answer).

    None when the machine has no such map version.
    """
    map_row = get_map_version(session, machine_id, version, with_payload=False)
    if map_row is None:
        return None
    # a delivery still without an answer when the next goes out never gets one here
    session.execute(update(AppliedRow).where(
        AppliedRow.machine_id == machine_id,
        or_(AppliedRow.state == "pending",
            and_(AppliedRow.state.is_(None), AppliedRow.reject_reason.is_(None),
                 AppliedRow.acked.is_(False))))
        .values(state="superseded", answered_at=at or utcnow()))
    row = AppliedRow(machine_id=machine_id, map_id=map_row.id, map_version=version,
                     applied_at=at or utcnow(), state="pending")
    session.add(row)
    session.flush()
    return row


def record_answer(
    session: Session, applied_id: int, *, acked: bool, reject_reason: str | None = None
) -> AppliedRow | None:
    """Record the machine's answer to a delivery: applied (``acked``) or rejected (its
    verdict in ``reject_reason``)."""
    row = session.get(AppliedRow, applied_id)
    if row is None:
        return None
    row.acked = acked
    row.reject_reason = None if acked else (reject_reason or "rejected")
    row.state = "applied" if acked else "rejected"
    row.failure = None
    row.answered_at = utcnow()
    session.flush()
    return row


def record_failure(session: Session, applied_id: int, failure: str) -> AppliedRow | None:
    """A delivery that got no answer: the transport failed (a write refused, the link
    lost, no verdict in time). Not the machine's verdict: the map is sent again."""
    row = session.get(AppliedRow, applied_id)
    if row is None:
        return None
    row.acked = False
    row.reject_reason = None
    row.state = "failed"
    row.failure = failure
    row.answered_at = utcnow()
    session.flush()
    return row


DeliveryState = Literal["pending", "applied", "rejected", "failed", "superseded"]

UNANSWERED = ("session ended before the answer", "no answer to map version")
"""How deliveries without an answer were marked as rejections before ``state`` existed."""


def delivery_state(row: AppliedRow) -> DeliveryState:
    """What happened to a delivery (rows from before the ``state`` column read as they
    were meant: a missing answer was stored as a rejection then)."""
    if row.state in ("pending", "applied", "rejected", "failed", "superseded"):
        return row.state  # type: ignore[return-value]
    if row.acked:
        return "applied"
    if row.reject_reason is None:
        return "pending"
    return "failed" if row.reject_reason.startswith(UNANSWERED) else "rejected"


def list_applied(session: Session, machine_id: int, limit: int = 100) -> list[AppliedRow]:
    """A machine's deliveries, newest first."""
    query = select(AppliedRow).where(AppliedRow.machine_id == machine_id)
    return list(session.scalars(query.order_by(AppliedRow.id.desc()).limit(limit)))


def latest_sent(session: Session, machine_id: int) -> AppliedRow | None:
    """The machine's most recent delivery, whatever its answer."""
    query = select(AppliedRow).where(AppliedRow.machine_id == machine_id)
    return session.scalar(query.order_by(AppliedRow.id.desc()).limit(1))


def latest_acked(session: Session, machine_id: int) -> AppliedRow | None:
    """The machine's most recent delivery that it acknowledged as applied."""
    query = select(AppliedRow).where(AppliedRow.machine_id == machine_id, AppliedRow.acked)
    return session.scalar(query.order_by(AppliedRow.id.desc()).limit(1))


def latest_versions(session: Session, names: list[str], *, chunk: int = 500
                    ) -> dict[str, tuple[int | None, int | None]]:
    """Per registered machine of ``names``: the map version of its most recent delivery
    and of its most recent acknowledged one (:func:`latest_sent`, :func:`latest_acked`),
    in a few queries for all of them: a thousand machines one by one kept the database
    thread, and with it the GIL, busy for seconds."""
    out: dict[str, tuple[int | None, int | None]] = {}
    for i in range(0, len(names), chunk):
        ids = dict(session.execute(select(MachineRow.id, MachineRow.name).where(
            MachineRow.name.in_(names[i:i + chunk]))).all())
        if not ids:
            continue
        found: list[dict[int, int]] = []
        for acked_only in (False, True):
            newest = select(func.max(AppliedRow.id)).where(
                AppliedRow.machine_id.in_(ids)).group_by(AppliedRow.machine_id)
            if acked_only:
                newest = newest.where(AppliedRow.acked)
            rows = session.execute(select(AppliedRow.machine_id, AppliedRow.map_version)
                                   .where(AppliedRow.id.in_(newest))).all()
            found.append(dict(rows))
        for machine_id, name in ids.items():
            out[name] = (found[0].get(machine_id), found[1].get(machine_id))
    return out


@dataclass(frozen=True)
class MapState:
    """Where a machine's maps stand: newest built, newest sent, newest applied."""

    latest: int | None = None
    sent: int | None = None
    applied: int | None = None
    reject_reason: str | None = None
    """Why the machine rejected the newest map sent, if it did."""


def map_states(session: Session, machine_id: int | None = None) -> dict[int, MapState]:
    """:class:`MapState` by machine id (machines without maps are absent), in three
    grouped queries whatever the number of machines; one machine only if given."""

    def only(query: Any, column: Any) -> Any:
        return query if machine_id is None else query.where(column == machine_id)

    latest: dict[int, int] = {
        mid: version for mid, version in session.execute(only(
            select(MapVersionRow.machine_id, func.max(MapVersionRow.version)),
            MapVersionRow.machine_id).group_by(MapVersionRow.machine_id))
    }
    newest = only(select(func.max(AppliedRow.id)), AppliedRow.machine_id)
    sent = {r.machine_id: r for r in session.scalars(select(AppliedRow).where(
        AppliedRow.id.in_(newest.group_by(AppliedRow.machine_id))))}
    newest_acked = newest.where(AppliedRow.acked).group_by(AppliedRow.machine_id)
    acked = {r.machine_id: r for r in session.scalars(select(AppliedRow).where(
        AppliedRow.id.in_(newest_acked)))}
    return {
        mid: MapState(
            latest=latest.get(mid),
            sent=sent[mid].map_version if mid in sent else None,
            applied=acked[mid].map_version if mid in acked else None,
            reject_reason=sent[mid].reject_reason if mid in sent else None,
        )
        for mid in set(latest) | set(sent)
    }
