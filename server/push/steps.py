"""The push's database steps: each runs in one transaction through ``Database.run``.

Storing a map, noting its delivery and recording the machine's answer write the map
tables and the event log together, so a crash never leaves a delivery without its event.
"""

from __future__ import annotations

from dataclasses import dataclass

from sqlalchemy.orm import Session

from server import mapcodec
from server.db import error_models as model_repo
from server.db import events as event_repo
from server.db import maps as map_repo
from server.db.tables import MachineRow, MapVersionRow, ModelRow
from server.events import EventKind
from server.mapcodec import MapContent


@dataclass(frozen=True, slots=True)
class Inputs:
    """What a refresh starts from: the machine, its current model and map (no payload)."""

    machine: MachineRow | None
    model: ModelRow | None
    map: MapVersionRow | None


def load_inputs(session: Session, machine_id: int) -> Inputs:
    """The machine's row, current model and current map version (without its bytes)."""
    machine = session.get(MachineRow, machine_id)
    if machine is None:
        return Inputs(None, None, None)
    return Inputs(machine, model_repo.get_model(session, machine_id),
                  map_repo.get_map_version(session, machine_id, with_payload=False))


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
