"""``/api/status`` and ``/api/machines/{name}/status``: live links and map versions.

Links are the whole plant's (:mod:`server.plant`): a machine served by another node of
the same database shows as connected, with that node as its ``owner``."""

from __future__ import annotations

from fastapi import APIRouter
from sqlalchemy.orm import Session

from server.api.deps import CenterDep, MachineDep
from server.api.errors import NOT_FOUND
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db.maps import MapState
from server.db.tables import MachineRow
from server.plant import PlantView, plant_view
from server.schemas.status import MachineStatus, ServiceStatus
from server.state import shown_state
from server.version import __version__

router = APIRouter(tags=["status"])


def _all_map_states(session: Session) -> tuple[list[MachineRow], dict[int, MapState]]:
    return machine_repo.list_machines(session), map_repo.map_states(session)


def _status(links: PlantView, name: str, maps: MapState) -> MachineStatus:
    link = links.get(name)
    return MachineStatus(
        name=name, connected=link.connected, address=link.address,
        link_state=shown_state(link),
        link_reason=link.link_reason, link_text=link.link_text,
        connected_since=link.connected_since, last_seen=link.last_seen,
        telemetry=dict(link.telemetry), owner=link.owner, map_version_latest=maps.latest,
        map_version_sent=maps.sent, map_version_applied=maps.applied,
        last_reject_reason=maps.reject_reason,
    )


@router.get("/status")
async def service_status(center: CenterDep) -> ServiceStatus:
    """The service and every machine's status."""
    machines, states = await center.db.run(_all_map_states)
    links = await plant_view(center)
    machine_status = [_status(links, m.name, states.get(m.id, MapState()))
                      for m in machines]
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
    states = await center.db.run(map_repo.map_states, machine.id)
    return _status(await plant_view(center), machine.name, states.get(machine.id, MapState()))
