"""The push's database steps: each runs in one transaction through ``Database.run``.

Storing a map, noting its delivery and recording the machine's answer write the map
tables and the event log together, so a crash never leaves a delivery without its event.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sqlalchemy import bindparam, select
from sqlalchemy.orm import Session

from server import mapcodec
from server.db import events as event_repo
from server.db import maps as map_repo
from server.db.tables import Base, MachineRow, MapVersionRow, ModelRow
from server.events import EventKind
from server.mapcodec import MapContent


@dataclass(frozen=True, slots=True)
class Inputs:
    """What a refresh starts from: the machine, its current model and map (no payload).

    Rows made from plain SELECTs (:func:`load_inputs`), not attached to any session: read
    them, never add them."""

    machine: MachineRow | None
    model: ModelRow | None
    map: MapVersionRow | None


_MACHINES = Base.metadata.tables[MachineRow.__tablename__]
_MODELS = Base.metadata.tables[ModelRow.__tablename__]
_MAPS = Base.metadata.tables[MapVersionRow.__tablename__]

_MACHINE = select(_MACHINES.c.name, _MACHINES.c.controller, _MACHINES.c.description,
                  _MACHINES.c.updated_at).where(_MACHINES.c.id == bindparam("m_id"))
_MODEL = (select(_MODELS.c.id, _MODELS.c.version, _MODELS.c.source, _MODELS.c.created_at)
          .where(_MODELS.c.machine_id == bindparam("m_id"))
          .order_by(_MODELS.c.version.desc()).limit(1))
_MODEL_BODY = select(_MODELS.c.body).where(_MODELS.c.id == bindparam("model_id"))
_MAP = (select(_MAPS.c.id, _MAPS.c.version, _MAPS.c.model_version, _MAPS.c.sha256,
               _MAPS.c.size_bytes, _MAPS.c.temperatures, _MAPS.c.created_at)
        .where(_MAPS.c.machine_id == bindparam("m_id"))
        .order_by(_MAPS.c.version.desc()).limit(1))


def load_inputs(session: Session, machine_id: int,
                known_model: tuple[int, dict[str, Any]] | None = None) -> Inputs:
    """The machine's row, current model and current map version (without its bytes).

    ``known_model``: a model row's id and body the caller holds; when that row is still
    the current model its body is not read again (a model row is never changed, a new
    version is a new row). Three plain SELECTs: the ORM's loading took about 3 ms of CPU
    per call for these three rows, once per push."""
    conn = session.connection()
    found = conn.execute(_MACHINE, {"m_id": machine_id}).first()
    if found is None:
        return Inputs(None, None, None)
    machine = MachineRow(id=machine_id, name=found.name, controller=found.controller,
                         description=found.description, updated_at=found.updated_at)
    model = None
    latest = conn.execute(_MODEL, {"m_id": machine_id}).first()
    if latest is not None:
        if known_model is not None and known_model[0] == latest.id:
            body = known_model[1]
        else:
            body = conn.execute(_MODEL_BODY, {"model_id": latest.id}).scalar_one()
        model = ModelRow(id=latest.id, machine_id=machine_id, version=latest.version,
                         source=latest.source, body=body, created_at=latest.created_at)
    current = conn.execute(_MAP, {"m_id": machine_id}).first()
    map_row = None if current is None else MapVersionRow(
        id=current.id, machine_id=machine_id, version=current.version,
        model_version=current.model_version, sha256=current.sha256,
        size_bytes=current.size_bytes, temperatures=current.temperatures,
        created_at=current.created_at)
    return Inputs(machine, model, map_row)


def store_map(session: Session, machine_id: int, built: MapContent, model_version: int,
              temperatures: dict[str, float]) -> MapVersionRow:
    # above every version a machine of this name ever received: registered again, it still
    # holds its last map and would reject a lower version (STALE_VERSION)
    version = map_repo.next_map_version(session, machine_id)
    payload = mapcodec.encode(mapcodec.with_version(built, version))
    row = map_repo.add_map_version(session, machine_id, payload=payload,
                                   model_version=model_version, temperatures=temperatures)
    if row.version != version:  # cannot happen in one transaction; the payload says `version`
        raise RuntimeError(f"map version {row.version} stored for a payload of {version}")
    return row


def stored_payload(session: Session, machine_id: int, version: int) -> bytes | None:
    """The bytes of a stored map version, None if there is none."""
    row = map_repo.get_map_version(session, machine_id, version)
    return None if row is None else row.payload


def detail_of(version: int, size: int, why: str) -> str:
    """The event text of a delivery."""
    return f"map version {version} ({size} bytes): {why}"


def store_and_send(session: Session, machine_id: int, name: str, built: MapContent,
                   model_version: int, temperatures: dict[str, float],
                   why: str) -> tuple[MapVersionRow, int]:
    """Store a new map and note its delivery in one transaction (one commit saved on the
    way from a temperature change to the machine)."""
    row = store_map(session, machine_id, built, model_version, temperatures)
    detail = detail_of(row.version, row.size_bytes, why)
    return row, record_sent(session, machine_id, name, row.version, row.id, detail)


def record_sent(session: Session, machine_id: int, name: str, version: int, map_id: int,
                detail: str) -> int:
    """Note that ``version`` (the machine's map row ``map_id``, read by the caller) is on
    its way to the machine; the delivery row's id."""
    applied_id = map_repo.note_sent(session, machine_id, map_id, version)
    if applied_id is None:
        raise RuntimeError(f"{name} has no map version {version}")
    event_repo.note_event(session, kind=EventKind.PUSHED.value, machine=name, detail=detail)
    return applied_id


def record_answer(session: Session, applied_id: int, name: str, kind: EventKind, *,
                  acked: bool, reason: str | None, detail: str) -> None:
    """Store the machine's answer to a delivery and its event."""
    map_repo.note_answer(session, applied_id, acked=acked, reject_reason=reason)
    event_repo.note_event(session, kind=kind.value, machine=name, detail=detail)


def record_failure(session: Session, applied_id: int, name: str, *, failure: str) -> None:
    """Store that a delivery got no answer (the transport failed) and its event."""
    map_repo.note_failure(session, applied_id, failure)
    event_repo.note_event(session, kind=EventKind.ERROR.value, machine=name, detail=failure)


__all__ = ["Inputs", "detail_of", "load_inputs", "record_answer", "record_failure",
           "record_sent",
           "store_and_send", "store_map", "stored_payload"]
