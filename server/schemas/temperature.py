"""Temperatures at the API edge: readings posted, the latest per sensor, the time series."""

from __future__ import annotations

import datetime as dt
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, StringConstraints

SensorName = Annotated[
    str, StringConstraints(pattern=r"^[A-Za-z0-9_]{1,64}$"),
    Field(description="A sensor name (`spindle`) or model column (`T_spindle_C`).",
          examples=["spindle"]),
]


class TemperatureIn(BaseModel):
    """One reading to take."""

    model_config = ConfigDict(allow_inf_nan=False, extra="forbid")

    sensor: SensorName
    celsius: float = Field(description="°C.", examples=[21.43])
    time: dt.datetime | None = Field(
        default=None, description="When it was read (with a time zone); arrival if absent.")


class TemperaturesIn(BaseModel):
    """Readings of one machine's sensors."""

    model_config = ConfigDict(extra="forbid")

    readings: list[TemperatureIn] = Field(min_length=1, max_length=256)


class TemperatureVerdict(BaseModel):
    """What became of one posted reading."""

    sensor: str
    accepted: bool
    reason: str | None = Field(default=None, description="Why it was refused: "
                               "`not_finite`, `out_of_range`, `unknown_sensor`, "
                               "`too_fast`, ...")
    detail: str | None = None


class TemperaturesTaken(BaseModel):
    """The verdict on each posted reading, in order."""

    machine: str
    accepted: int
    refused: int
    verdicts: list[TemperatureVerdict]


class TemperatureLatest(BaseModel):
    """A sensor's latest accepted reading, as the center uses it now."""

    sensor: str = Field(description="Model column, e.g. `T_spindle_C`.")
    celsius: float
    time: dt.datetime
    age_s: float = Field(description="Seconds since it arrived.")
    source: str
    stale: bool


class TemperaturePoint(BaseModel):
    """One stored reading of the time series."""

    sensor: str
    celsius: float
    time: dt.datetime
    source: str


class TemperatureRefusal(BaseModel):
    """A recent refused reading."""

    sensor: str
    celsius: float | None
    source: str
    reason: str
    detail: str
    time: dt.datetime


class TemperaturesPublic(BaseModel):
    """A machine's temperatures: latest per sensor, the series newest first, recent
    refusals, and the sensors the center accepts for it (null while the intake is off)."""

    machine: str
    known_sensors: list[str] | None
    latest: list[TemperatureLatest]
    history: list[TemperaturePoint]
    refusals: list[TemperatureRefusal]
