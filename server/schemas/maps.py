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
    applied_at: dt.datetime = Field(description="When the map was sent.")
    state: Literal["pending", "applied", "rejected"]
    reject_reason: str | None
