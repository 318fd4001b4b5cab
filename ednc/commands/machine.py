"""``ednc machine register|status``: a machine at a running center, through its REST API."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Annotated

import typer

from ednc.api import ApiOption, KeyOption, Unreachable, call, detail
from ednc.cli import UserError
from ednc.inputs import dump_json, float_option, read_machine

machine_app = typer.Typer(name="machine", no_args_is_help=True,
                          help="Register a machine at a running center, or show its status.")


@machine_app.command("register")
def register_cmd(
    machine: Annotated[Path, typer.Option(
        "--machine", help="Machine description JSON (docs/formats.md).")],
    secret: Annotated[str, typer.Option(
        "--secret", envvar="EDNC_MACHINE_SECRET",
        help="The secret the machine authenticates with (>= 16 characters); the machine "
             "(or 'ednc sim') must use the same.")],
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
    wait: Annotated[float, typer.Option(
        "--wait", help="Wait up to this many seconds for the center to answer (it may be "
                       "starting).")] = 0.0,
) -> None:
    """Register a machine (POST /api/machines): the center then welcomes it on its machine
    port, and sends it a map once it has a model (ednc model upload)."""
    float_option(wait, "--wait", 0.0, 3600.0, unit=" s")
    read_machine(machine)  # the offline checks first: one line, before the network
    description = json.loads(machine.read_text())
    deadline = time.monotonic() + wait
    while True:
        try:
            r = call("POST", api, "/machines", api_key,
                     body={**description, "secret": secret})
            break
        except Unreachable:
            if time.monotonic() >= deadline:
                raise
            time.sleep(0.5)
    name = description.get("name")
    if r.status_code == 201:
        typer.echo(f"registered {name} at {api}; next: upload its model with "
                   f"'ednc model upload --machine {name} --model MODEL.json'")
    elif r.status_code == 409:
        typer.echo(f"{name} is already registered at {api} (left as it is)")
    else:
        raise UserError(f"the center refused {machine} ({r.status_code}): {detail(r)}")


@machine_app.command("status")
def status_cmd(
    name: Annotated[str, typer.Argument(help="The machine's name.")],
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
) -> None:
    """A machine's link and maps (GET /api/machines/NAME/status): connected or not, and the
    newest map built, sent and applied."""
    r = call("GET", api, f"/machines/{name}/status", api_key)
    if r.status_code == 404:
        raise UserError(f"the center at {api} has no machine {name!r}; register it with "
                        "'ednc machine register'")
    if r.status_code != 200:
        raise UserError(f"the center answered {r.status_code}: {detail(r)}")
    s = r.json()
    if as_json:
        typer.echo(dump_json(s))
        return

    def version(key: str) -> str:
        return "none" if s.get(key) is None else f"v{s[key]}"

    typer.echo(f"{name}: {'connected' if s.get('connected') else 'not connected'}"
               + (f" from {s['address']}" if s.get("connected") and s.get("address") else "")
               + f"; map built {version('map_version_latest')}, sent "
               f"{version('map_version_sent')}, applied {version('map_version_applied')}"
               + (f"; last reject: {s['last_reject_reason']}" if s.get("last_reject_reason")
                  else ""))


def register(app: typer.Typer) -> None:
    app.add_typer(machine_app, name="machine")
