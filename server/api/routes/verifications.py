"""``/api/machines/{name}/verifications``: ISO 230-6 body-diagonal verification reports.

A report is made here from stored measurement sets (``POST``): the diagonal ranges before
and, given the compensated run, after, with the gain and the 70 % acceptance.
"""

from __future__ import annotations

import asyncio

from fastapi import APIRouter, HTTPException, status

from server.api.deps import DatabaseDep, MachineDep, ReportId, WriteAccess
from server.api.errors import NOT_FOUND, WRITE, unprocessable
from server.api.routes.diagnoses import report_public
from server.db import measurements as measurement_repo
from server.db import reports as report_repo
from server.numeric import MeasurementError, VerificationError, verify_diagonals
from server.schemas.report import ReportPublic, VerificationRequest

router = APIRouter(
    prefix="/machines/{name}/verifications", tags=["verifications"], responses=NOT_FOUND
)


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


@router.post("", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
             responses=WRITE)
async def verify(
    db: DatabaseDep, machine: MachineDep, request: VerificationRequest
) -> ReportPublic:
    """Evaluate the body-diagonal tests in stored sets and store the report.

    422 when a set is unknown or holds no evaluable ``diag-*`` tests (the core's message).
    """
    sets: dict[str, tuple[str, str]] = {}
    for field, set_name in (("before", request.before), ("after", request.after)):
        if set_name is None:
            continue
        stored = await db.run(measurement_repo.get_measurement_set, machine.id, set_name)
        if stored is None:
            raise unprocessable(["body", field],
                                f"machine {machine.name!r} has no measurement set {set_name!r}",
                                "unknown_set")
        sets[field] = (stored.name, stored.csv_text)
    try:
        result = await asyncio.to_thread(verify_diagonals, sets["before"], sets.get("after"),
                                         target_tol_mm=request.target_tol_mm)
    except (MeasurementError, VerificationError) as exc:
        raise unprocessable(["body"], str(exc), "verification_failed") from None
    report = await db.run(report_repo.add_report, machine.id, kind="verification",
                          result=result)
    return report_public(report, machine.name)
