"""``/api/machines/{name}/models``: a machine's error models, versioned.

A model is uploaded (checked by the numeric core against the machine) or fitted here to
stored measurement sets.
"""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, Version, WriteAccess
from server.api.errors import NOT_FOUND, WRITE, unprocessable
from server.db import Database, DuplicateError
from server.db import error_models as model_repo
from server.db import measurements as measurement_repo
from server.db.tables import MachineRow, ModelRow
from server.numeric import MeasurementError, ModelError, check_model, fit_model
from server.schemas.model import FitRequest, ModelCreate, ModelPublic, ModelSource, ModelSummary

router = APIRouter(
    prefix="/machines/{name}/models", tags=["models"], responses=NOT_FOUND
)

_RETRY: dict[int | str, dict[str, str]] = {
    409: {"description": "Another writer took the version number; retry."}
}


def model_public(row: ModelRow, machine: str) -> ModelPublic:
    return ModelPublic.model_validate(
        {"machine": machine, "version": row.version, "source": row.source,
         "body": row.body, "created_at": row.created_at}
    )


async def _store(
    db: Database, machine: MachineRow, source: ModelSource, body: dict[str, object]
) -> ModelPublic:
    try:
        row = await db.run(model_repo.add_model, machine.id, source=source, body=body)
    except DuplicateError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, f"{exc}; retry") from None
    return model_public(row, machine.name)


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
             responses={**WRITE, **_RETRY})
async def add_model(db: DatabaseDep, machine: MachineDep, model: ModelCreate) -> ModelPublic:
    """Store a model (``MachineModel.to_json`` of the numeric core) as the next version.

    422 when the core cannot read it, it names errors of axes the machine lacks, or it
    was written for another machine (its ``machine``): its maps would carry that name and
    the machine would reject every one (WRONG_MACHINE).
    """
    written_for = model.body.get("machine")
    if written_for is not None and written_for != machine.name:
        raise unprocessable(["body", "body", "machine"],
                            f"the model is for machine {written_for!r}, not {machine.name!r}",
                            "wrong_machine")
    try:
        await asyncio.to_thread(check_model, model.body, machine.description)
    except ModelError as exc:
        raise unprocessable(["body", "body"], str(exc), "model_format") from None
    return await _store(db, machine, model.source, model.body)


@router.post("/fit", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
             responses={**WRITE, **_RETRY})
async def fit(db: DatabaseDep, machine: MachineDep, request: FitRequest) -> ModelPublic:
    """Fit the rigid model to stored measurement sets and store it as the next version.

    The fit statistics (degrees chosen, uncertainties, unidentifiable parameters, RMS) are
    in the model's ``info``. 422 when a set is unknown or the readings cannot be fitted.
    """
    sets: list[tuple[str, str]] = []
    for i, set_name in enumerate(request.measurement_sets):
        row = await db.run(measurement_repo.get_measurement_set, machine.id, set_name)
        if row is None:
            raise unprocessable(["body", "measurement_sets", i],
                                f"machine {machine.name!r} has no measurement set {set_name!r}",
                                "unknown_set")
        sets.append((row.name, row.csv_text))
    try:
        body = await asyncio.to_thread(fit_model, machine.description, sets,
                                       select=request.select)
    except (MeasurementError, ModelError) as exc:
        raise unprocessable(["body", "measurement_sets"], str(exc), "fit_failed") from None
    return await _store(db, machine, "fit", body)


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
