"""``/api/machines/{name}/diagnoses``: diagnoses (formats.md §3) of a machine.

A diagnosis is uploaded (the JSON of ``ednc diagnose --json``) or run here on stored
measurement sets; a run that names an effect also stores the extended model.
"""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, ReportId, WriteAccess
from server.api.errors import NOT_FOUND, WRITE, unprocessable
from server.db import DuplicateError
from server.db import error_models as model_repo
from server.db import measurements as measurement_repo
from server.db import reports as report_repo
from server.db.tables import DiagnosisRow
from server.numeric import MeasurementError, ModelError, diagnose_sets
from server.schemas.report import DiagnoseRequest, DiagnosisCreate, ReportPublic

router = APIRouter(
    prefix="/machines/{name}/diagnoses", tags=["diagnoses"], responses=NOT_FOUND
)


def report_public(row: DiagnosisRow, machine: str) -> ReportPublic:
    return ReportPublic.model_validate(
        {"id": row.id, "machine": machine, "kind": row.kind, "result": row.result,
         "created_at": row.created_at}
    )


@router.get("")
async def list_diagnoses(db: DatabaseDep, machine: MachineDep) -> list[ReportPublic]:
    """The machine's diagnoses, newest first."""
    rows = await db.run(report_repo.list_reports, machine.id, "diagnosis")
    return [report_public(r, machine.name) for r in rows]


@router.post("", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
             responses=WRITE)
async def add_diagnosis(
    db: DatabaseDep, machine: MachineDep, diagnosis: DiagnosisCreate
) -> ReportPublic:
    """Store a diagnosis made elsewhere (the output of ``ednc diagnose --json``)."""
    row = await db.run(report_repo.add_report, machine.id, kind="diagnosis",
                       result=diagnosis.model_dump(mode="json"))
    return report_public(row, machine.name)


@router.post("/run", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
             responses=WRITE)
async def run_diagnosis(
    db: DatabaseDep, machine: MachineDep, request: DiagnoseRequest
) -> ReportPublic:
    """Diagnose stored measurement sets: what the rigid model misses and why.

    The report is stored; when it names an effect, the model extended by it is stored as
    the machine's next model version (source ``diagnose``) and the report says which
    (``model_version``). 422 when a set is unknown or the readings cannot support a
    diagnosis.
    """
    sets: list[tuple[str, str]] = []
    for i, set_name in enumerate(request.measurement_sets):
        stored = await db.run(measurement_repo.get_measurement_set, machine.id, set_name)
        if stored is None:
            raise unprocessable(["body", "measurement_sets", i],
                                f"machine {machine.name!r} has no measurement set {set_name!r}",
                                "unknown_set")
        sets.append((stored.name, stored.csv_text))
    try:
        result, model = await asyncio.to_thread(diagnose_sets, machine.description, sets,
                                                holdout_after=request.holdout_after)
    except (MeasurementError, ModelError) as exc:
        raise unprocessable(["body", "measurement_sets"], str(exc), "diagnosis_failed") \
            from None
    result["measurement_sets"] = list(request.measurement_sets)
    if model is not None:
        try:
            stored_model = await db.run(model_repo.add_model, machine.id, source="diagnose",
                                        body=model)
        except DuplicateError as exc:
            raise HTTPException(status.HTTP_409_CONFLICT, f"{exc}; retry") from None
        result["model_version"] = stored_model.version
    report = await db.run(report_repo.add_report, machine.id, kind="diagnosis", result=result)
    return report_public(report, machine.name)


@router.get("/{report_id}")
async def get_diagnosis(db: DatabaseDep, machine: MachineDep, report_id: ReportId) -> ReportPublic:
    """One diagnosis."""
    row = await db.run(report_repo.get_report, machine.id, "diagnosis", report_id)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND,
                            f"machine {machine.name!r} has no diagnosis {report_id}")
    return report_public(row, machine.name)
