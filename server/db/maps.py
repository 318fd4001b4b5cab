"""Repository: the ``map_versions`` and ``applied`` tables (error maps and their delivery)."""

from __future__ import annotations

import datetime as dt
import hashlib
from dataclasses import dataclass
from typing import Any, Literal

from sqlalchemy import and_, bindparam, func, insert, literal, or_, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session, defer

from server.db.errors import DuplicateError
from server.db.tables import (
    AppliedRow,
    Base,
    MachineRow,
    MapVersionMarkRow,
    MapVersionRow,
    UTCDateTime,
    utcnow,
)


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


_APPLIED = Base.metadata.tables[AppliedRow.__tablename__]
"""The deliveries' table for the push's own statements: Core, not the ORM's unit of work
(a flush costs about a millisecond of CPU per statement at a thousand pushes a round;
nothing listens to these rows' ORM events, :mod:`server.push.watcher` follows models and
machines)."""

_SUPERSEDE = (update(_APPLIED).where(
    _APPLIED.c.machine_id == bindparam("m_id"),
    _APPLIED.c.id != bindparam("new_id"),
    or_(_APPLIED.c.state == "pending",
        and_(_APPLIED.c.state.is_(None), _APPLIED.c.reject_reason.is_(None),
             _APPLIED.c.acked.is_(False))))
    .values(state="superseded", answered_at=bindparam("at")))
"""A delivery still without an answer when the next goes out never gets one here."""

_MAPS = Base.metadata.tables[MapVersionRow.__tablename__]

_NOTE_SENT = insert(_APPLIED).from_select(
    ["machine_id", "map_id", "map_version", "applied_at", "acked", "state"],
    select(_MAPS.c.machine_id, _MAPS.c.id, _MAPS.c.version, bindparam("at", type_=UTCDateTime),
           literal(False), literal("pending"))
    .where(_MAPS.c.id == bindparam("map_id"), _MAPS.c.machine_id == bindparam("m_id"),
           _MAPS.c.version == bindparam("version"))).returning(_APPLIED.c.id)
"""The delivery row of a map row, only if that row is the machine's ``version``."""

_ANSWER = (update(_APPLIED).where(_APPLIED.c.id == bindparam("a_id"))
           .values(acked=bindparam("acked"), reject_reason=bindparam("reason"),
                   state=bindparam("state"), failure=bindparam("failure"),
                   answered_at=bindparam("at")))


def note_sent(session: Session, machine_id: int, map_id: int, version: int,
              at: dt.datetime | None = None) -> int | None:
    """Note that map ``version`` (the machine's ``map_versions`` row ``map_id``, read by
    the caller) was sent to the machine, superseding its deliveries still pending; the
    delivery row's id, None (and nothing written) when ``map_id`` is not that machine's
    ``version`` (gone meanwhile)."""
    when = at or utcnow()
    conn = session.connection()
    applied_id = conn.execute(_NOTE_SENT, {"m_id": machine_id, "map_id": map_id,
                                           "version": version, "at": when}).scalar()
    if applied_id is None:
        return None
    conn.execute(_SUPERSEDE, {"m_id": machine_id, "at": when, "new_id": applied_id})
    return int(applied_id)


def note_answer(session: Session, applied_id: int, *, acked: bool,
                reject_reason: str | None = None) -> bool:
    """Store the machine's answer to a delivery (applied, or rejected with its verdict in
    ``reject_reason``); False when there is no such delivery."""
    return _set_outcome(session, applied_id, acked=acked,
                        reason=None if acked else (reject_reason or "rejected"),
                        state="applied" if acked else "rejected", failure=None)


def note_failure(session: Session, applied_id: int, failure: str) -> bool:
    """A delivery that got no answer (:func:`record_failure`); False when there is no
    such delivery."""
    return _set_outcome(session, applied_id, acked=False, reason=None, state="failed",
                        failure=failure)


def _set_outcome(session: Session, applied_id: int, *, acked: bool, reason: str | None,
                 state: str, failure: str | None) -> bool:
    result = session.connection().execute(_ANSWER, {
        "a_id": applied_id, "acked": acked, "reason": reason, "state": state,
        "failure": failure, "at": utcnow()})
    return bool(getattr(result, "rowcount", 0))


def _reloaded(session: Session, applied_id: int) -> AppliedRow | None:
    # the row as the Core statement left it, also when this session holds it already
    return session.get(AppliedRow, applied_id, populate_existing=True)


def record_sent(
    session: Session, machine_id: int, version: int, at: dt.datetime | None = None
) -> AppliedRow | None:
    """Note that map ``version`` was sent to the machine (pending its answer).

    None when the machine has no such map version.
    """
    map_row = get_map_version(session, machine_id, version, with_payload=False)
    if map_row is None:
        return None
    applied_id = note_sent(session, machine_id, map_row.id, version, at)
    return None if applied_id is None else _reloaded(session, applied_id)


def record_answer(
    session: Session, applied_id: int, *, acked: bool, reject_reason: str | None = None
) -> AppliedRow | None:
    """Record the machine's answer to a delivery: applied (``acked``) or rejected (its
    verdict in ``reject_reason``)."""
    if not note_answer(session, applied_id, acked=acked, reject_reason=reject_reason):
        return None
    return _reloaded(session, applied_id)


def record_failure(session: Session, applied_id: int, failure: str) -> AppliedRow | None:
    """A delivery that got no answer: the transport failed (a write refused, the link
    lost, no verdict in time). Not the machine's verdict: the map is sent again."""
    if not note_failure(session, applied_id, failure):
        return None
    return _reloaded(session, applied_id)


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
