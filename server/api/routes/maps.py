"""``/api/machines/{name}/maps`` and ``/deliveries``: error maps built for a machine and
their delivery. Maps are written by the push scheduler, not through the API."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, Response, status

from server.api.deps import DatabaseDep, MachineDep, Version
from server.api.errors import NOT_FOUND
from server.db import Database
from server.db import maps as map_repo
from server.db.tables import AppliedRow, MachineRow, MapVersionRow
from server.schemas.maps import AppliedPublic, MapPublic

router = APIRouter(
    prefix="/machines/{name}", tags=["maps"], responses=NOT_FOUND
)


def map_public(row: MapVersionRow, machine: str) -> MapPublic:
    return MapPublic(
        machine=machine, version=row.version, model_version=row.model_version,
        sha256=row.sha256, size_bytes=row.size_bytes, temperatures=row.temperatures,
        created_at=row.created_at,
    )


def applied_public(row: AppliedRow, machine: str) -> AppliedPublic:
    state = map_repo.delivery_state(row)
    return AppliedPublic(machine=machine, map_version=row.map_version,
                         sent_at=row.applied_at,
                         applied_at=row.applied_at if state == "applied" else None,
                         answered_at=row.answered_at, state=state,
                         reject_reason=row.reject_reason if state == "rejected" else None,
                         # a row stored before ``failure`` existed kept it as a reason
                         failure=(row.failure or row.reject_reason)
                         if state in ("failed", "superseded") else None)


async def _get_map(
    db: Database, machine: MachineRow, version: int | None, *, with_payload: bool = False
) -> MapVersionRow:
    row = await db.run(map_repo.get_map_version, machine.id, version, with_payload=with_payload)
    if row is None:
        which = "no map" if version is None else f"no map version {version}"
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"machine {machine.name!r} has {which}")
    return row


@router.get("/maps")
async def list_maps(db: DatabaseDep, machine: MachineDep) -> list[MapPublic]:
    """The machine's map versions, newest first."""
    return [map_public(r, machine.name)
            for r in await db.run(map_repo.list_map_versions, machine.id)]


@router.get("/maps/latest")
async def latest_map(db: DatabaseDep, machine: MachineDep) -> MapPublic:
    """The machine's newest map."""
    return map_public(await _get_map(db, machine, None), machine.name)


@router.get("/maps/{version}")
async def get_map(db: DatabaseDep, machine: MachineDep, version: Version) -> MapPublic:
    """One map version's metadata."""
    return map_public(await _get_map(db, machine, version), machine.name)


@router.get(
    "/maps/{version}/payload", response_class=Response,
    responses={200: {"content": {"application/octet-stream": {
        "schema": {"type": "string", "format": "binary"}}}}},
)
async def download_map(db: DatabaseDep, machine: MachineDep, version: Version) -> Response:
    """The encoded map, byte for byte as sent to the machine (ETag: its SHA-256)."""
    row = await _get_map(db, machine, version, with_payload=True)
    return Response(
        row.payload, media_type="application/octet-stream",
        headers={
            "ETag": f'"{row.sha256}"',
            "Content-Disposition": f'attachment; filename="{machine.name}-map-v{row.version}.bin"',
        },
    )


@router.get("/deliveries")
async def list_deliveries(db: DatabaseDep, machine: MachineDep) -> list[AppliedPublic]:
    """The machine's map deliveries, newest first: pending, applied, rejected (the
    machine's verdict), failed (no answer: the transport failed; sent again) or
    superseded (a newer one went out before any answer)."""
    return [applied_public(r, machine.name)
            for r in await db.run(map_repo.list_applied, machine.id)]
