"""Machines from a file (``EDNC_MACHINES_FILE``): the plant's fleet, registered at start-up.

The file has the format of the simulator's fleet file (:mod:`machine_sim.fleet`): JSON, or
YAML for ``.yaml``/``.yml``, with a ``machines`` list of ``{"machine": {description},
"secret": "..."}`` (``machine`` may also be a path relative to the file). Each named machine
is created, or updated to the file's description and secret, so the file is the truth
for the machines it names; machines registered through the API and not in the file are
left alone. Every entry is checked like an API request (``MachineCreate``); a bad file
stops start-up with a message naming the entry.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError
from sqlalchemy.orm import Session

from server.db import machines as machine_repo
from server.db.secretbox import SecretBox
from server.schemas.machine import MachineCreate


class MachinesFileError(ValueError):
    """A machines file that cannot be used; the message names the file and entry."""


def read_machines_file(path: Path) -> list[MachineCreate]:
    """The machines of a file, each validated as an API request would be."""
    try:
        text = path.read_text()
    except OSError as exc:
        raise MachinesFileError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        data = yaml.safe_load(text) if path.suffix in (".yaml", ".yml") else json.loads(text)
    except (json.JSONDecodeError, yaml.YAMLError) as exc:
        raise MachinesFileError(f"{path}: not valid JSON/YAML: {exc}") from None
    if not isinstance(data, Mapping) or not isinstance(data.get("machines"), list):
        raise MachinesFileError(f"{path}: expected an object with a 'machines' list")
    out: list[MachineCreate] = []
    for i, raw in enumerate(data["machines"]):
        where = f"{path}: machines[{i}]"
        if not isinstance(raw, Mapping) or "machine" not in raw:
            raise MachinesFileError(f"{where}: expected an object with 'machine' and 'secret'")
        spec: Any = raw["machine"]
        if isinstance(spec, str):
            try:
                spec = json.loads((path.parent / spec).read_text())
            except (OSError, json.JSONDecodeError) as exc:
                raise MachinesFileError(f"{where}.machine: cannot read {spec!r}: {exc}") from None
        if not isinstance(spec, Mapping):
            raise MachinesFileError(f"{where}.machine: expected a description or a path")
        try:
            out.append(MachineCreate.model_validate({**spec, "secret": raw.get("secret")}))
        except ValidationError as exc:
            first = exc.errors()[0]
            loc = ".".join(str(p) for p in first["loc"])
            raise MachinesFileError(f"{where}.{loc}: {first['msg']}") from None
    return out


def register_machines(session: Session, machines: list[MachineCreate],
                      box: SecretBox | None = None) -> dict[str, int]:
    """Create or update each machine (secrets sealed by ``box``); counts of each.

    A machine whose secret is already the file's keeps its row untouched, so a restart
    does not close sessions as a changed secret would.
    """
    created = updated = 0
    for m in machines:
        description = m.as_json()
        secret = m.secret.get_secret_value()
        if machine_repo.get_machine(session, m.name) is None:
            machine_repo.create_machine(session, name=m.name, ip=description["ip"],
                                        controller=m.controller, description=description,
                                        secret=secret, box=box)
            created += 1
        else:
            row = machine_repo.get_machine(session, m.name)
            box = box or SecretBox(None)
            same = row is not None and box.open(row.secret, row.id) == secret
            machine_repo.update_machine(session, m.name, description=description,
                                        secret=None if same else secret, box=box)
            updated += 1
    return {"created": created, "updated": updated}
