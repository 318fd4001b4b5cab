"""Error-map versions and their deliveries as the API shows them."""

from __future__ import annotations

import datetime as dt
from typing import Any, Literal

from pydantic import BaseModel, Field


class MapPublic(BaseModel):
    """An error map's metadata (its bytes: ``.../payload``)."""

    machine: str
    version: int
    model_version: int | None
    sha256: str = Field(description="SHA-256 of the payload, hex.")
    size_bytes: int
    temperatures: dict[str, Any] = Field(
        description="The temperature inputs the map was built for, °C by sensor."
    )
    created_at: dt.datetime


class AppliedPublic(BaseModel):
    """One delivery of a map version to its machine."""

    machine: str
    map_version: int
    sent_at: dt.datetime = Field(description="When the map was sent.")
    applied_at: dt.datetime | None = Field(
        description="When the map the machine applied was sent; null unless applied.")
    answered_at: dt.datetime | None = Field(
        default=None, description="When the delivery got its outcome (null: pending, or "
        "stored before this field existed).")
    state: Literal["pending", "applied", "rejected", "failed", "superseded"] = Field(
        description="applied, rejected (the machine's verdict), failed (no answer: the "
        "transport failed; the map is sent again), superseded (a newer delivery went out "
        "before any answer), pending.")
    reject_reason: str | None = Field(
        description="The machine's verdict and code when rejected; null otherwise.")
    failure: str | None = Field(default=None,
                                description="Why a failed delivery got no answer.")
