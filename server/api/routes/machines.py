"""``/api/machines``: the machines the center knows (formats.md §1 descriptions)."""

from __future__ import annotations

import logging
from typing import Any

from fastapi import APIRouter, HTTPException, Response, status
from fastapi.exceptions import RequestValidationError
from pydantic import ValidationError

from server.api.deps import CenterDep, DatabaseDep, MachineDep, WriteAccess
from server.api.errors import NOT_FOUND, WRITE
from server.center import Center
from server.db import DuplicateError
from server.db import live_links as live_repo
from server.db import machines as machine_repo
from server.db.tables import MachineRow
from server.schemas.machine import MachineCreate, MachineDescription, MachinePublic, MachineUpdate
from volumetric.model.machine import description_warnings, parse_machine

log = logging.getLogger(__name__)

router = APIRouter(prefix="/machines", tags=["machines"])

_CONFLICT: dict[int | str, dict[str, Any]] = {
    409: {"description": "The name or ip is already taken."}
}


def machine_public(row: MachineRow) -> MachinePublic:
    return MachinePublic.model_validate(row, from_attributes=True)


@router.get("", response_model=list[MachinePublic])
async def list_machines(db: DatabaseDep) -> list[MachinePublic]:
    """Every machine, by name."""
    return [machine_public(r) for r in await db.run(machine_repo.list_machines)]


@router.post(
    "", status_code=status.HTTP_201_CREATED, dependencies=[WriteAccess],
    responses={**WRITE, **_CONFLICT},
)
async def create_machine(db: DatabaseDep, machine: MachineCreate) -> MachinePublic:
    """Add a machine. Its ``secret`` is stored for the challenge-response and never shown."""
    description = machine.as_json()
    try:
        row = await db.run(
            machine_repo.create_machine,
            name=machine.name, ip=description["ip"], controller=machine.controller,
            description=description, secret=machine.secret.get_secret_value(),
            box=db.secrets,
        )
    except DuplicateError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, str(exc)) from None
    return _warned(machine_public(row))


def _warned(public: MachinePublic) -> MachinePublic:
    """``public`` with the description's warnings, logged as the CLI prints them: an
    accepted description whose travels look like metres is said so on every way in."""
    warnings = description_warnings(parse_machine(public.description))
    for w in warnings:
        log.warning("%s", w)
    return public.model_copy(update={"warnings": warnings})


@router.get("/{name}", responses=NOT_FOUND)
async def get_machine(machine: MachineDep) -> MachinePublic:
    """One machine."""
    return machine_public(machine)


@router.patch("/{name}", dependencies=[WriteAccess],
              responses={**NOT_FOUND, **WRITE, **_CONFLICT})
async def update_machine(
    center: CenterDep, machine: MachineDep, update: MachineUpdate
) -> MachinePublic:
    """Change some keys of a machine's description (``null`` removes a key) or its secret.

    The result is validated as a whole description, as on creation.
    """
    merged: dict[str, Any] = {**machine.description, **update.changes()}
    merged = {k: v for k, v in merged.items() if v is not None}
    try:
        description = MachineDescription.model_validate(merged).as_json()
    except ValidationError as exc:
        errors = [{**e, "loc": ("body", *e["loc"])} for e in exc.errors(include_url=False)]
        raise RequestValidationError(errors) from None
    secret = update.secret.get_secret_value() if update.secret is not None else None
    try:
        row = await center.db.run(
            machine_repo.update_machine, machine.name, description=description, secret=secret,
            box=center.db.secrets,
        )
    except DuplicateError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, str(exc)) from None
    if row is None:  # deleted meanwhile
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no machine named {machine.name!r}")
    if row.name != machine.name:
        center.registry.forget(machine.name)
        _forget_temperatures(center, machine.name)
        await center.db.run(live_repo.forget, machine.name)
    return _warned(machine_public(row))


def _forget_temperatures(center: Center, name: str) -> None:
    """A deleted or renamed machine's temperatures go with it: a new machine of that name
    would otherwise show the old sensors (as stale) and have them forwarded."""
    if center.intake is not None:
        center.intake.forget(name)
    elif center.temperatures is not None:
        center.temperatures.forget(name)


@router.delete("/{name}", status_code=status.HTTP_204_NO_CONTENT, dependencies=[WriteAccess],
               responses={**NOT_FOUND, **WRITE})
async def delete_machine(center: CenterDep, machine: MachineDep) -> Response:
    """Remove a machine with its models, measurements, maps and reports (events stay)."""
    await center.db.run(machine_repo.delete_machine, machine.name)
    center.registry.forget(machine.name)
    _forget_temperatures(center, machine.name)
    await center.db.run(live_repo.forget, machine.name)  # its plant-wide live link too
    return Response(status_code=status.HTTP_204_NO_CONTENT)
