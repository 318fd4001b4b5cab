"""Repository: the ``diagnoses`` table (diagnoses and verification reports, by ``kind``)."""

from __future__ import annotations

from typing import Any, Literal

from sqlalchemy import select
from sqlalchemy.orm import Session

from server.db.tables import DiagnosisRow

ReportKind = Literal["diagnosis", "verification"]


def add_report(
    session: Session, machine_id: int, *, kind: ReportKind, result: dict[str, Any]
) -> DiagnosisRow:
    """Store a diagnosis or verification result."""
    row = DiagnosisRow(machine_id=machine_id, kind=kind, result=result)
    session.add(row)
    session.flush()
    return row


def list_reports(
    session: Session, machine_id: int, kind: ReportKind, limit: int = 100
) -> list[DiagnosisRow]:
    """A machine's reports of one kind, newest first."""
    query = select(DiagnosisRow).where(
        DiagnosisRow.machine_id == machine_id, DiagnosisRow.kind == kind
    )
    return list(session.scalars(query.order_by(DiagnosisRow.id.desc()).limit(limit)))


def get_report(
    session: Session, machine_id: int, kind: ReportKind, report_id: int
) -> DiagnosisRow | None:
    """One report of the machine, or None (also when the id belongs to another machine)."""
    return session.scalar(
        select(DiagnosisRow).where(
            DiagnosisRow.id == report_id,
            DiagnosisRow.machine_id == machine_id,
            DiagnosisRow.kind == kind,
        )
    )
