"""Measurement sets (raw CSV of formats.md §2) as the API shows them."""

from __future__ import annotations

import datetime as dt

from pydantic import BaseModel


class MeasurementSetPublic(BaseModel):
    """A stored measurement CSV's metadata (the CSV itself: ``.../csv``)."""

    machine: str
    name: str
    row_count: int
    size_bytes: int
    created_at: dt.datetime
