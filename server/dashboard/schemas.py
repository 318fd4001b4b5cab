"""What the dashboard pages read: the snapshot, a machine's detail, map slices, diagonals.

Units are in the field names (``_mm``, ``_um``, ``_C``, ``_s``) so that the pages never
guess; angles of rotary axes are degrees for positions and µrad for errors, as in the
numeric core.
"""

from __future__ import annotations

import datetime as dt
from typing import Any, Literal

from pydantic import BaseModel, Field

from server.health import State
from server.schemas.event import EventPublic

Health = State
"""The machine's accuracy state (:mod:`server.health`), the colour of its row: green ok,
grey unknown or offline, amber warn, red alarm or out of tolerance."""


class AxisLive(BaseModel):
    """One axis as the machine last reported it."""

    name: str
    rotary: bool = Field(description="Rotary axis: position in degrees, compensation in µrad.")
    position: float = Field(description="Machine coordinate, mm (degrees for a rotary axis).")
    compensation: float = Field(
        description="Compensation now applied, µm (µrad for a rotary axis)."
    )


class TemperatureLive(BaseModel):
    """One temperature sensor as the machine last reported it."""

    name: str
    celsius: float = Field(description="°C.")
    stale: bool = Field(description="The reading is older than the stale limit.")
    source: Literal["telemetry", "mqtt", "rest", "lag"] = Field(
        default="telemetry",
        description="Where it came from: the machine link, MQTT or the REST API, or a lag "
                    "state the center follows for a lagged thermal model.")
    age_s: float | None = Field(default=None, description="Age of the reading, s.")
    follows: str | None = Field(
        default=None, description="For a lag state: the sensor it follows and its time "
                                  "constant (a lagged thermal model's, applied live).")


class MapVersions(BaseModel):
    """Where the machine's error maps stand."""

    latest: int | None = Field(description="Newest map built for the machine.")
    sent: int | None = Field(description="Newest map sent to it.")
    sent_at: dt.datetime | None
    sent_state: Literal["pending", "applied", "rejected", "failed", "superseded"] | None = Field(
        description="The machine's answer to the newest delivery."
    )
    applied: int | None = Field(description="Newest map the machine acknowledged.")
    reported: int | None = Field(
        description="Map version the machine reports in its telemetry (0: none applied)."
    )
    reject_reason: str | None
    kind: Literal["grid", "tables", "factored"] | None = Field(
        default=None, description="The newest map's kind: grid (nodes the machine "
        "interpolates), tables (ISO 230-1 component tables it evaluates) or factored "
        "(one-axis basis tables it combines, the Fanuc-style pitch-error layout).")
    bytes: int | None = Field(default=None, description="The newest map's payload, bytes.")
    built_at: dt.datetime | None = Field(default=None, description="When the newest map "
                                         "was built.")
    model_version: int | None = Field(default=None, description="The model version the "
                                      "newest map was built from.")
    built_at_C: dict[str, float] = Field(
        default_factory=dict, description="The temperatures the newest map was built at "
        "(model column to °C); empty for a map without thermal terms.")
    applied_at: dt.datetime | None = Field(
        default=None, description="When the applied map was sent (its acknowledged "
        "delivery).")
    age_s: float | None = Field(default=None, description="Age of the applied map, s.")
    error_um: float | None = Field(
        default=None, description="The newest map's worst tool-tip error as sent "
        "(quantised, against the exact model), µm; null until the center has checked it.")
    tolerance_um: float | None = Field(
        default=None, description="The tolerance the newest map was built for, µm.")


class AccuracyReason(BaseModel):
    """One finding behind a machine's accuracy state (:class:`server.health.Reason`)."""

    state: Health
    code: str = Field(description="Stable name of the rule, e.g. residual, map_old.")
    text: str


class AccuracyView(BaseModel):
    """How far the center vouches for the machine's accuracy, and why."""

    state: Health
    label: str = Field(description="The state for a person: OK, OUT OF TOLERANCE...")
    reasons: list[AccuracyReason] = Field(description="Every finding, worst first.")
    tolerance_um: float = Field(description="The machine's accuracy tolerance: largest "
                                "compensated body-diagonal range allowed, µm.")
    residual_um: float | None = Field(description="The last verification's largest "
                                      "diagonal range, µm (compensated when it has a "
                                      "compensated run).")
    residual_compensated: bool
    verified_at: dt.datetime | None
    model_version: int | None
    model_at: dt.datetime | None
    model_age_s: float | None


class VerificationSummary(BaseModel):
    """The last ISO 230-6 body-diagonal verification of the machine."""

    id: int
    created_at: dt.datetime
    ranges_before_um: dict[str, float] = Field(description="Range per diagonal, µm.")
    ranges_after_um: dict[str, float] | None = Field(description="With compensation, µm.")
    improvement_pct: dict[str, float] | None = Field(
        description="Per diagonal and 'overall': range removed, % (negative: worse)."
    )
    accepted: bool | None = Field(description="Overall improvement at least the acceptance.")
    acceptance_pct: float | None


class DiagnosisSummary(BaseModel):
    """The last diagnosis of the machine (formats.md §3)."""

    id: int
    created_at: dt.datetime
    effect: str
    axis: str | None
    sensor: str | None
    estimate: dict[str, float] = Field(description="The effect's size, units in the keys.")
    rms_before_um: float | None
    rms_after_um: float | None


class MachineCard(BaseModel):
    """One machine's row on the dashboard."""

    name: str
    controller: str
    ip: str
    chain: str = Field(description="Kinematic chain, or the type numbers when none is given.")
    link: str = Field(default="ednc", description="How the center reaches the machine: ednc "
                      "(it connects), modbus or opcua (the center connects to its controller).")
    health: Health = Field(description="The accuracy state (``accuracy.state``).")
    health_reason: str = Field(description="Why the row has its colour, for the operator: "
                               "the first of ``accuracy.reasons``.")
    accuracy: AccuracyView | None = Field(default=None, description="The accuracy state "
                                          "with every reason behind it.")
    connected: bool
    owner: str | None = Field(
        default=None,
        description="The node (EDNC_NODE_ID) serving the machine now; null when offline.")
    address: str | None
    link_state: str = Field(
        default="offline", description="What the link is doing: connected, connecting, "
        "plc_stopped, refused, unreachable, failed or offline (server/links/state.py).")
    link_reason: str = Field(default="", description="Why, as a stable label "
                             "(identity_name, byte_order, magic, no_answer, exception_02...).")
    link_text: str = Field(default="", description="Why, for the operator.")
    connected_since: dt.datetime | None
    last_seen: dt.datetime | None
    telemetry_age_s: float | None = Field(description="Age of the last telemetry, s.")
    telemetry_stale: bool
    state: str | None = Field(description="The machine's state label (idle, compensating...).")
    axes: list[AxisLive]
    temperatures: list[TemperatureLive]
    maps: MapVersions
    verification: VerificationSummary | None
    diagnosis: DiagnosisSummary | None


class DashboardSnapshot(BaseModel):
    """Everything the dashboard shows, at one instant."""

    generated_at: dt.datetime
    version: str
    node_id: str
    stale_after_s: float = Field(description="Telemetry older than this is marked stale, s.")
    machines: list[MachineCard]
    events: list[EventPublic] = Field(description="Recent events, newest first.")


class ComponentView(BaseModel):
    """One component or location error of a model, summarised over the axis travel."""

    name: str = Field(description="ISO 230-1 name, e.g. EXX, EC0Y.")
    axis: str
    location: bool = Field(description="Position-independent (location) error.")
    unit: Literal["µm", "µrad"]
    kind: str = Field(description="polynomial, table, sinusoid, sum, or 'constant'.")
    min: float | None = Field(description="Smallest value over the travel (unit above).")
    max: float | None = Field(description="Largest value over the travel (unit above).")
    positions: list[float] = Field(description="Where the curve is sampled, mm or degrees.")
    values: list[float] = Field(description="The curve at those positions (unit above).")


class ModelView(BaseModel):
    """A stored model's terms, ready to read."""

    version: int
    source: str
    created_at: dt.datetime
    components: list[ComponentView]
    terms: list[dict[str, Any]] = Field(description="Extensions: thermal, backlash, periodic.")
    info: dict[str, Any] = Field(description="Fit statistics as stored.")


class MachineDetail(BaseModel):
    """A machine's page: its description, live row and model."""

    card: MachineCard
    description: dict[str, Any] = Field(description="The machine description (formats.md §1).")
    model: ModelView | None
    model_problem: str | None = Field(description="Why the model cannot be shown, if so.")


class GridAxisView(BaseModel):
    """One grid dimension of a map."""

    name: str
    unit: Literal["mm", "deg"]
    start: float
    step: float
    count: int


class MapSlice(BaseModel):
    """One output axis of the map over the two chosen grid axes."""

    output: str
    unit: Literal["µm", "µrad"]
    reversal: float | None = Field(description="Backlash added on reversal (unit above).")
    values: list[list[float]] = Field(
        description="values[j][i] at v-node j, u-node i (unit above); one row for a 1-D map."
    )
    min: float
    max: float


class MapGrid(BaseModel):
    """A slice of an error map for a heat map: two grid axes, the others held fixed."""

    machine: str
    version: int
    kind: Literal["grid", "tables", "factored"] = Field(
        default="grid", description="grid: the map's own nodes; tables: the corrections "
                                    "the machine computes, on a display grid; factored: "
                                    "the same, before the ladder rounds them.")
    encoding: Literal["int32", "float32"]
    increment_mm: float
    grid: list[GridAxisView]
    u: str = Field(description="Grid axis along the plot's horizontal.")
    v: str | None = Field(description="Grid axis along the vertical (None: 1-D map).")
    fixed: dict[str, float] = Field(
        description="The other grid axes at their node nearest mid-travel, mm or degrees."
    )
    outputs: list[MapSlice]
    thermal_records: int = Field(
        default=0, description="Thermal records the map carries: the machine adds them at "
        "its live temperatures; the values shown leave them out (the thermal terms at "
        "their reference temperatures).")
    built_at_C: dict[str, float] = Field(
        default_factory=dict, description="The temperatures the map was built at (model "
        "column to °C): the thermal terms a map without thermal records carries are "
        "evaluated there.")
    bytes: int | None = Field(default=None, description="The payload's length, bytes.")


class DiagonalProfile(BaseModel):
    """Deviation along one body diagonal: the mean reading at each target."""

    label: str
    along_mm: list[float] = Field(description="Distance from the first target, mm.")
    before_um: list[float] = Field(description="Uncompensated deviation, µm.")
    after_along_mm: list[float] | None
    after_um: list[float] | None = Field(description="Compensated deviation, µm.")
    range_before_um: float
    range_after_um: float | None


class DiagonalPlots(BaseModel):
    """The diagonal profiles of a verification report, from its measurement sets."""

    machine: str
    report_id: int
    before_set: str
    after_set: str | None
    diagonals: list[DiagonalProfile]
