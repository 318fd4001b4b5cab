"""``/api/events``: what happened on the machine links, newest first."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query

from server.api.deps import INT32_MAX, DatabaseDep
from server.db import events as event_repo
from server.events import EventKind
from server.schemas.event import EventPublic

router = APIRouter(prefix="/events", tags=["events"])


@router.get("")
async def list_events(
    db: DatabaseDep,
    kind: Annotated[EventKind | None, Query(description="Only this kind.")] = None,
    machine: Annotated[str | None, Query(pattern=r"^[^\x00]{1,128}$",
                                         description="Only this machine name or address.")] = None,
    before_id: Annotated[int | None, Query(ge=1, le=INT32_MAX,
                                           description="Only events older than this id "
                                           "(paging).")] = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> list[EventPublic]:
    """Events, newest first; ``kind=refused`` is the dashboard's refusal list."""
    rows = await db.run(
        event_repo.list_events, kind=kind.value if kind else None, machine=machine,
        before_id=before_id, limit=limit,
    )
    return [EventPublic.model_validate(r, from_attributes=True) for r in rows]
