"""Machine descriptions (formats.md §1) at the API edge: Create / Update / Public."""

from __future__ import annotations

import datetime as dt
from typing import Annotated, Any, Literal

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

from server.numeric import check_machine_description
from server.schemas.common import Name, check_json_object

Controller = Literal["fanuc", "siemens"]
AxisKey = Annotated[str, StringConstraints(pattern=r"^[xyzabc][0-9]*$")]
Chain = Annotated[str, StringConstraints(min_length=1, max_length=64,
                                         pattern=r"^[wbtXYZABC ]+$")]
TypeNumber = Annotated[int, Field(ge=0, le=99)]
FiniteFloat = Annotated[float, Field(allow_inf_nan=False)]
Secret = Annotated[
    SecretStr,
    Field(min_length=8, max_length=256,
          description="Shared secret for the machine's challenge-response; write-only."),
]


class SpindleSpec(BaseModel):
    """One tool branch of a multi-spindle machine."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)

    name: Annotated[str, StringConstraints(min_length=1, max_length=32,
                                           pattern=r"^[A-Za-z0-9._\-]+$")]
    axis: Annotated[str, StringConstraints(pattern=r"^[XYZ][0-9]+$")]
    direction: tuple[FiniteFloat, FiniteFloat, FiniteFloat]
    tool_length_mm: FiniteFloat | None = None


class _DescriptionFields(BaseModel):
    """The fields of formats.md §1; unknown keys are kept (the format may be extended)."""

    model_config = ConfigDict(extra="allow", allow_inf_nan=False)

    chain: Chain | None = Field(default=None, examples=["w X Y b Z t"])
    translational_type: TypeNumber | None = None
    rotary_type: TypeNumber | None = None
    travel_mm: dict[AxisKey, tuple[FiniteFloat, FiniteFloat]] = Field(
        default_factory=dict, examples=[{"x": [0, 500], "y": [0, 300], "z": [-300, 0]}]
    )
    tool_length_mm: FiniteFloat = 0.0
    spindles: Annotated[list[SpindleSpec], Field(max_length=16)] | None = None

    @model_validator(mode="after")
    def _extras_are_json(self) -> _DescriptionFields:
        check_json_object(dict(self.model_extra or {}))
        return self


class MachineDescription(_DescriptionFields):
    """A complete machine description, checked by the numeric core when it is present."""

    name: Name
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
    def _printable(cls, value: SecretStr) -> SecretStr:
        if not value.get_secret_value().isprintable():
            raise ValueError("must be printable text (no control characters)")
        return value


class MachineUpdate(_DescriptionFields):
    """Changes to a machine: any subset of the description's keys (``null`` removes an
    optional key, e.g. ``"chain": null`` to switch to type numbers) and a new secret."""

    name: Name | None = None
    controller: Controller | None = None
    ip: IPvAnyAddress | None = None
    secret: Secret | None = None

    @field_validator("secret")
    @classmethod
    def _printable(cls, value: SecretStr | None) -> SecretStr | None:
        if value is not None and not value.get_secret_value().isprintable():
            raise ValueError("must be printable text (no control characters)")
        return value

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
