"""``/api/machines/{name}/verifications``: ISO 230-6 verification reports of a machine.

They are stored by the numeric core's verification run (``server.db.reports.add_report``
with ``kind="verification"``); the API only reads them.
"""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, ReportId
from server.api.routes.diagnoses import report_public
from server.db import reports as report_repo
from server.schemas.report import ReportPublic

router = APIRouter(prefix="/machines/{name}/verifications", tags=["verifications"])


@router.get("")
async def list_verifications(db: DatabaseDep, machine: MachineDep) -> list[ReportPublic]:
    """The machine's verification reports, newest first."""
    rows = await db.run(report_repo.list_reports, machine.id, "verification")
    return [report_public(r, machine.name) for r in rows]


@router.get("/{report_id}")
async def get_verification(
    db: DatabaseDep, machine: MachineDep, report_id: ReportId
) -> ReportPublic:
    """One verification report."""
    row = await db.run(report_repo.get_report, machine.id, "verification", report_id)
    if row is None:
        raise HTTPException(status.HTTP_404_NOT_FOUND,
                            f"machine {machine.name!r} has no verification report {report_id}")
    return report_public(row, machine.name)
