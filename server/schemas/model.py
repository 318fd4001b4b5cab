"""Error models (versioned per machine): Create / Summary / Public."""

from __future__ import annotations

import datetime as dt
from typing import Any, Literal

from pydantic import BaseModel, Field, field_validator

from server.schemas.common import JsonObject, Name

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

    measurement_sets: list[Name] = Field(
        min_length=1, max_length=50, description="Names of the sets, used together."
    )
    select: bool = Field(
        default=True, description="Choose polynomial degrees from the data (BIC)."
    )

    @field_validator("measurement_sets")
    @classmethod
    def _distinct(cls, names: list[str]) -> list[str]:
        if len(set(names)) != len(names):
            raise ValueError("a set is named twice")
        return names
