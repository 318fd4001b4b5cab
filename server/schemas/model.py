"""Error models (versioned per machine): Create / Summary / Public."""

from __future__ import annotations

import datetime as dt
from typing import Any, Literal

from pydantic import BaseModel, Field

from server.schemas.common import JsonObject, SetNames

ModelSource = Literal["fit", "upload", "diagnose"]


class ModelCreate(BaseModel):
    """A model to store as the machine's next version."""

    source: ModelSource = "upload"
    body: JsonObject = Field(description="The model as the numeric core writes it (JSON).")


class ModelSummary(BaseModel):
    """A model version without its body (for listings)."""

    machine: str
    version: int
    source: ModelSource
    created_at: dt.datetime


class ModelPublic(ModelSummary):
    """A model version with its body."""

    body: dict[str, Any]


class FitRequest(BaseModel):
    """Fit the machine's rigid model to stored measurement sets."""

    measurement_sets: SetNames
    select: bool = Field(
        default=True, description="Choose polynomial degrees from the data (BIC)."
    )
