"""``/api/machines/{name}/models``: a machine's error models, versioned."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, Version, WriteAccess
from server.db import DuplicateError
from server.db import error_models as model_repo
from server.db.tables import ModelRow
from server.schemas.model import ModelCreate, ModelPublic, ModelSummary

router = APIRouter(prefix="/machines/{name}/models", tags=["models"])


def model_public(row: ModelRow, machine: str) -> ModelPublic:
    return ModelPublic.model_validate(
        {"machine": machine, "version": row.version, "source": row.source,
         "body": row.body, "created_at": row.created_at}
    )


@router.get("")
async def list_models(db: DatabaseDep, machine: MachineDep) -> list[ModelSummary]:
    """The machine's model versions, newest first (without bodies)."""
    rows = await db.run(model_repo.list_models, machine.id)
    return [
        ModelSummary(machine=machine.name, version=r.version, source=r.source,
                     created_at=r.created_at)
        for r in rows
    ]


@router.post("", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
             responses={409: {"description": "Another writer took the version; retry."}})
async def add_model(db: DatabaseDep, machine: MachineDep, model: ModelCreate) -> ModelPublic:
    """Store a model as the machine's next version."""
    try:
        row = await db.run(model_repo.add_model, machine.id, source=model.source, body=model.body)
    except DuplicateError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, f"{exc}; retry") from None
    return model_public(row, machine.name)


@router.get("/latest")
async def latest_model(db: DatabaseDep, machine: MachineDep) -> ModelPublic:
    """The machine's newest model."""
    row = await db.run(model_repo.get_model, machine.id)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"machine {machine.name!r} has no model")
    return model_public(row, machine.name)


@router.get("/{version}")
async def get_model(db: DatabaseDep, machine: MachineDep, version: Version) -> ModelPublic:
    """One model version."""
    row = await db.run(model_repo.get_model, machine.id, version)
    if row is None:
        raise HTTPException(
            status.HTTP_404_NOT_FOUND, f"machine {machine.name!r} has no model version {version}"
        )
    return model_public(row, machine.name)
