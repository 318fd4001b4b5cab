"""``/api/machines/{name}/diagnoses``: diagnoses (formats.md §3) of a machine."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, ReportId, WriteAccess
from server.db import reports as report_repo
from server.db.tables import DiagnosisRow
from server.schemas.report import DiagnosisCreate, ReportPublic

router = APIRouter(prefix="/machines/{name}/diagnoses", tags=["diagnoses"])


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


@router.post("", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess])
async def add_diagnosis(
    db: DatabaseDep, machine: MachineDep, diagnosis: DiagnosisCreate
) -> ReportPublic:
    """Store a diagnosis made elsewhere (the output of ``ednc diagnose --json``)."""
    row = await db.run(report_repo.add_report, machine.id, kind="diagnosis",
                       result=diagnosis.model_dump(mode="json"))
    return report_public(row, machine.name)


@router.get("/{report_id}")
async def get_diagnosis(db: DatabaseDep, machine: MachineDep, report_id: ReportId) -> ReportPublic:
    """One diagnosis."""
    row = await db.run(report_repo.get_report, machine.id, "diagnosis", report_id)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND,
                            f"machine {machine.name!r} has no diagnosis {report_id}")
    return report_public(row, machine.name)
