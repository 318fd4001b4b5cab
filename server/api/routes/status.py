"""``/api/status`` and ``/api/machines/{name}/status``: live links and map versions."""

from __future__ import annotations

from fastapi import APIRouter
from sqlalchemy.orm import Session

from ednc import __version__
from server.api.deps import CenterDep, MachineDep
from server.api.errors import NOT_FOUND
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db.tables import MachineRow
from server.schemas.status import MachineStatus, ServiceStatus
from server.state import Registry

router = APIRouter(tags=["status"])

MapVersions = tuple[int | None, int | None, int | None, str | None]


def _map_versions(session: Session, machine_id: int) -> MapVersions:
    latest = map_repo.get_map_version(session, machine_id, with_payload=False)
    sent = map_repo.latest_sent(session, machine_id)
    applied = map_repo.latest_acked(session, machine_id)
    return (
        latest.version if latest else None,
        sent.map_version if sent else None,
        applied.map_version if applied else None,
        sent.reject_reason if sent else None,
    )


def _all_map_versions(session: Session) -> list[tuple[MachineRow, MapVersions]]:
    return [(m, _map_versions(session, m.id)) for m in machine_repo.list_machines(session)]


def _status(registry: Registry, name: str, versions: MapVersions) -> MachineStatus:
    link = registry.get(name)
    latest, sent, applied, reject = versions
    return MachineStatus(
        name=name, connected=link.connected, address=link.address,
        connected_since=link.connected_since, last_seen=link.last_seen,
        telemetry=dict(link.telemetry), map_version_latest=latest, map_version_sent=sent,
        map_version_applied=applied, last_reject_reason=reject,
    )


@router.get("/status")
async def service_status(center: CenterDep) -> ServiceStatus:
    """The service and every machine's status."""
    rows = await center.db.run(_all_map_versions)
    machine_status = [_status(center.registry, m.name, v) for m, v in rows]
    return ServiceStatus(
        version=__version__, node_id=center.settings.node_id, started_at=center.started_at,
        writes_enabled=center.settings.writes_enabled,
        mqtt_enabled=center.settings.mqtt_enabled, machines=len(machine_status),
        connected=sum(1 for s in machine_status if s.connected),
        machine_status=machine_status,
    )


@router.get("/machines/{name}/status", responses=NOT_FOUND)
async def machine_status(center: CenterDep, machine: MachineDep) -> MachineStatus:
    """One machine's link and map versions."""
    versions = await center.db.run(_map_versions, machine.id)
    return _status(center.registry, machine.name, versions)
