"""Machine descriptions (formats.md §1) at the API edge: Create / Update / Public.

A registration that could never log in or never get a map is refused here (422 with the
reason) rather than accepted and failing later: the name fits the protocol's name field
(:data:`protocol.limits.MAX_NAME_BYTES`), the secret is long enough for the challenge
(:data:`protocol.auth.MIN_SECRET_BYTES`), travels and tool lengths are finite and within
:data:`MAX_LENGTH_MM`, and the kinematics are what the numeric core accepts.
"""

from __future__ import annotations

import datetime as dt
from typing import Annotated, Any, Final, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    IPvAnyAddress,
    SecretStr,
    StringConstraints,
    field_serializer,
    field_validator,
    model_validator,
)

from protocol.auth import MIN_SECRET_BYTES
from protocol.limits import MAX_NAME_BYTES
from server.numeric import check_machine_description
from server.schemas.common import check_json_object
from server.schemas.link import LinkSpec
from volumetric.plausible.lengths import LINEAR_POSITION, TOOL_LENGTH

MAX_LENGTH_MM: Final = LINEAR_POSITION.hi
"""Largest travel end, mm (degrees for rotary travels; the core refuses beyond ±36 000°):
100 m is beyond any machine tool, and keeps every grid coordinate of a map far inside what
a Fanuc map's int32 increments hold (±2.1e6 mm at 0.001 mm). A travel of [0, 1e308]
passes as a float but no map can be built over it. The limits every entry point shares
(:mod:`volumetric.plausible`)."""

MAX_SECRET_BYTES: Final = 256
"""A secret's longest UTF-8 form: sealed (server/db/secretbox.py) it fits its column."""

MachineName = Annotated[
    str,
    StringConstraints(pattern=rf"^[A-Za-z0-9][A-Za-z0-9._\-]{{0,{MAX_NAME_BYTES - 1}}}$"),
    Field(description=f"1-{MAX_NAME_BYTES} letters, digits, '.', '_' or '-', starting with "
                      "a letter or digit (the protocol's name field)", examples=["vmc-01"]),
]

Controller = Literal["fanuc", "siemens"]
AxisKey = Annotated[str, StringConstraints(pattern=r"^[xyzabc][0-9]*$")]
Chain = Annotated[str, StringConstraints(min_length=1, max_length=64,
                                         pattern=r"^[wbtXYZABC ]+$")]
TypeNumber = Annotated[int, Field(ge=0, le=99)]
FiniteFloat = Annotated[float, Field(allow_inf_nan=False)]
Length = Annotated[float, Field(allow_inf_nan=False, ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM)]
ToolLength = Annotated[float, Field(allow_inf_nan=False, ge=TOOL_LENGTH.lo, le=TOOL_LENGTH.hi,
                                    description="gauge line to tool tip, mm (>= 0)")]
Secret = Annotated[
    SecretStr,
    Field(min_length=1, max_length=MAX_SECRET_BYTES,
          description=f"Shared secret for the machine's challenge-response, "
                      f"{MIN_SECRET_BYTES}-{MAX_SECRET_BYTES} bytes of printable UTF-8; "
                      "write-only."),
]


def _check_secret(value: SecretStr) -> SecretStr:
    text = value.get_secret_value()
    if not text.isprintable():
        raise ValueError("must be printable text (no control characters)")
    size = len(text.encode("utf-8"))
    if size < MIN_SECRET_BYTES:
        # the protocol's HMAC wants this much; a shorter one could never log in
        raise ValueError(f"must be at least {MIN_SECRET_BYTES} bytes (the protocol's "
                         f"minimum for the challenge-response), got {size}")
    if size > MAX_SECRET_BYTES:
        raise ValueError(f"must be at most {MAX_SECRET_BYTES} bytes of UTF-8, got {size}")
    return value


class SpindleSpec(BaseModel):
    """One tool branch of a multi-spindle machine."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)

    name: Annotated[str, StringConstraints(min_length=1, max_length=32,
                                           pattern=r"^[A-Za-z0-9._\-]+$")]
    axis: Annotated[str, StringConstraints(pattern=r"^[XYZ][0-9]+$")]
    direction: tuple[FiniteFloat, FiniteFloat, FiniteFloat]
    tool_length_mm: ToolLength | None = None


class _DescriptionFields(BaseModel):
    """The fields of formats.md §1; unknown keys are kept (the format may be extended)."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)

    chain: Chain | None = Field(default=None, examples=["w X Y b Z t"])
    translational_type: TypeNumber | None = None
    rotary_type: TypeNumber | None = None
    travel_mm: dict[AxisKey, tuple[Length, Length]] = Field(
        default_factory=dict, examples=[{"x": [0, 500], "y": [0, 300], "z": [-300, 0]}]
    )
    tool_length_mm: ToolLength = 0.0
    spindles: Annotated[list[SpindleSpec], Field(max_length=16)] | None = None
    link: LinkSpec | None = Field(
        default=None, description="how the center reaches the machine: ednc (the machine "
        "connects, the default), modbus (a Fanuc PMC's Modbus/TCP server) or opcua (a "
        "SINUMERIK's OPC UA server); server/schemas/link.py")

    @model_validator(mode="after")
    def _extras_are_json(self) -> _DescriptionFields:
        check_json_object(dict(self.model_extra or {}))
        return self


class MachineDescription(_DescriptionFields):
    """A complete machine description, checked by the numeric core when it is present."""

    name: MachineName
    controller: Controller
    ip: IPvAnyAddress = Field(examples=["10.0.0.21"])

    @field_serializer("ip")
    def _ip_text(self, ip: IPvAnyAddress) -> str:
        return str(ip)

    @model_validator(mode="after")
    def _kinematics(self) -> MachineDescription:
        if self.chain is None and self.translational_type is None:
            raise ValueError("needs 'chain' or 'translational_type' (and 'rotary_type')")
        check_machine_description(self.as_json())
        return self

    def as_json(self) -> dict[str, Any]:
        """The description as stored and returned: JSON types, unset optionals left out."""
        body = self.model_dump(mode="json", exclude_none=True, exclude={"secret"})
        identity = {k: body.pop(k) for k in ("name", "controller", "ip")}
        return {**identity, **body}


class MachineCreate(MachineDescription):
    """A new machine: its description plus the secret it authenticates with."""

    secret: Secret

    @field_validator("secret")
    @classmethod
    def _secret(cls, value: SecretStr) -> SecretStr:
        return _check_secret(value)


class MachineUpdate(_DescriptionFields):
    """Changes to a machine: any subset of the description's keys (``null`` removes an
    optional key, e.g. ``"chain": null`` to switch to type numbers) and a new secret."""

    name: MachineName | None = None
    controller: Controller | None = None
    ip: IPvAnyAddress | None = None
    secret: Secret | None = None

    @field_validator("secret")
    @classmethod
    def _secret(cls, value: SecretStr | None) -> SecretStr | None:
        return None if value is None else _check_secret(value)

    def changes(self) -> dict[str, Any]:
        """The keys the request set, as JSON (``None`` for keys to remove)."""
        return self.model_dump(mode="json", exclude_unset=True, exclude={"secret"})


class MachinePublic(BaseModel):
    """A machine as the API shows it; never with its secret."""

    name: str
    controller: Controller
    ip: str
    description: dict[str, Any] = Field(description="The machine description (formats.md §1).")
    created_at: dt.datetime
    updated_at: dt.datetime
    warnings: list[str] = Field(
        default_factory=list, description="On creation or update: what in the accepted "
        "description looks like a unit slip all the same (travels that look like metres, "
        "rotary travels within ±2π); empty otherwise.")
