"""Measurement sets (raw CSV of formats.md §2) as the API shows them."""

from __future__ import annotations

import datetime as dt

from pydantic import BaseModel, Field


class MeasurementSetPublic(BaseModel):
    """A stored measurement CSV's metadata (the CSV itself: ``.../csv``)."""

    machine: str
    name: str
    row_count: int
    size_bytes: int
    created_at: dt.datetime
    warnings: list[str] = Field(
        default_factory=list, description="On upload: what in the accepted readings looks "
        "like a unit slip all the same (readings of 0.01 µm that are mm, temperatures hot "
        "enough to be °F); empty otherwise.")
