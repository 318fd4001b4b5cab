"""Diagnoses (formats.md §3) and verification reports."""

from __future__ import annotations

import datetime as dt
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, StringConstraints, model_validator

from server.schemas.common import JsonObject, Name, SetNames, check_json_object

EffectName = Annotated[str, StringConstraints(pattern=r"^[a-z][a-z0-9_]{0,63}$")]
Rms = Annotated[float, Field(ge=0.0, allow_inf_nan=False)]


class _Open(BaseModel):
    # The format may gain keys; keep them, as long as they are JSON.
    model_config = ConfigDict(extra="allow", allow_inf_nan=False)

    @model_validator(mode="after")
    def _extras_are_json(self) -> _Open:
        check_json_object(dict(self.model_extra or {}))
        return self


AxisName = Annotated[str, StringConstraints(pattern=r"^[a-z][a-z0-9]{0,7}$")]


class Candidate(_Open):
    """One effect the diagnosis tried."""

    effect: EffectName
    axis: AxisName | None = None
    rms_after_um: Rms | None = None


class DiagnosisCreate(_Open):
    """The JSON that ``ednc diagnose --json`` prints (formats.md §3)."""

    effect: EffectName = Field(examples=["backlash"])
    axis: AxisName | None = Field(default=None, examples=["x"])
    sensor: Annotated[str, StringConstraints(pattern=r"^[^\x00]{1,128}$")] | None = None
    estimate: JsonObject = Field(default_factory=dict, examples=[{"reversal_um": 9.8}])
    rms_before_um: Rms
    rms_after_um: Rms
    candidates: Annotated[list[Candidate], Field(max_length=1000)] = Field(default_factory=list)


class ReportPublic(BaseModel):
    """A stored diagnosis or verification report."""

    id: int
    machine: str
    kind: Literal["diagnosis", "verification"]
    result: dict[str, Any]
    created_at: dt.datetime


class VerificationRequest(BaseModel):
    """Evaluate stored body-diagonal tests (ISO 230-6), optionally before and after."""

    before: Name = Field(description="Measurement set with the diag-* tests, uncompensated.")
    after: Name | None = Field(default=None,
                               description="The same tests with compensation applied.")
    target_tol_mm: float = Field(default=1e-3, gt=0.0, le=10.0, allow_inf_nan=False,
                                 description="Points closer than this are one target (mm).")


class DiagnoseRequest(BaseModel):
    """Diagnose stored measurement sets (what ``ednc diagnose`` does with a CSV)."""

    measurement_sets: SetNames
    holdout_after: float | None = Field(
        default=None, ge=0.0, allow_inf_nan=False,
        description="Judge on readings at or after this time (s), fitted on the earlier ones.",
    )
