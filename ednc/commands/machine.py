"""``ednc machine register|list|status|update|delete``: the machines of a running center,
through its REST API (the same checks as REST, since REST makes them)."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Annotated

import typer

from ednc.api import ApiOption, KeyOption, Unreachable, call, detail
from ednc.cli import UserError
from ednc.inputs import dump_json, float_option, read_machine
from volumetric.plausible.files import decode_text

machine_app = typer.Typer(name="machine", no_args_is_help=True,
                          help="Register, list, show, update or delete the machines of a "
                               "running center.")


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
    description = json.loads(decode_text(machine.read_bytes(), str(machine)))
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
        # the name or the ip is taken: "already registered" only when it is this machine
        same = _registered_as(api, api_key, description)
        if same is None:
            raise UserError(f"{name} is not registered: the center at {api} refused it "
                            f"(409): {detail(r)}; give the machine another name or ip, "
                            f"or change the registered one with 'ednc machine update'")
        typer.echo(f"{name} is already registered at {api} with this description (left as "
                   "it is; 'ednc machine update' changes its secret)")
    else:
        raise UserError(f"the center refused {machine} ({r.status_code}): {detail(r)}")


def _registered_as(api: str, key: str | None, description: dict[str, object]
                   ) -> dict[str, object] | None:
    """The center's description of the machine named in ``description`` when it is the
    same machine (name, ip and controller alike), else None."""
    name = description.get("name")
    if not isinstance(name, str):
        return None
    r = call("GET", api, f"/machines/{name}", key)
    if r.status_code != 200:
        return None
    held = r.json()
    same = (held.get("ip") == str(description.get("ip", "0.0.0.0")) and
            held.get("controller") == description.get("controller", "fanuc"))
    return held if same else None


@machine_app.command("list")
def list_cmd(
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON list.")] = False,
) -> None:
    """Every machine of the center (GET /api/machines): name, controller, address, link."""
    r = call("GET", api, "/machines", api_key)
    if r.status_code != 200:
        raise UserError(f"the center answered {r.status_code}: {detail(r)}")
    rows = r.json()
    if as_json:
        typer.echo(dump_json(rows))
        return
    if not rows:
        typer.echo(f"no machines at {api}; register one with 'ednc machine register'")
    for m in rows:
        link = (m.get("description") or {}).get("link") or {"kind": "ednc"}
        typer.echo(f"{m['name']}\t{m['controller']}\t{m['ip']}\t{link.get('kind', 'ednc')}")


@machine_app.command("update")
def update_cmd(
    name: Annotated[str, typer.Argument(help="The machine's name.")],
    machine: Annotated[Path | None, typer.Option(
        "--machine", help="A new description (formats.md §1); its keys replace the held "
                          "ones, checked as on registration.")] = None,
    secret: Annotated[str | None, typer.Option(
        "--secret", help="A new secret (>= 16 characters); the machine must use it from "
                         "its next login.")] = None,
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
) -> None:
    """Change a machine's description or secret (PATCH /api/machines/NAME)."""
    body: dict[str, object] = {}
    if machine is not None:
        read_machine(machine)  # the offline checks first, one line before the network
        body.update(json.loads(decode_text(machine.read_bytes(), str(machine))))
    if secret is not None:
        body["secret"] = secret
    if not body:
        raise UserError("nothing to change: give --machine M.json and/or --secret S")
    r = call("PATCH", api, f"/machines/{name}", api_key, body=body)
    if r.status_code == 404:
        raise UserError(f"the center at {api} has no machine {name!r} ('ednc machine list')")
    if r.status_code != 200:
        raise UserError(f"the center refused the change of {name} ({r.status_code}): "
                        f"{detail(r)}")
    typer.echo(f"updated {r.json()['name']} at {api}")


@machine_app.command("delete")
def delete_cmd(
    name: Annotated[str, typer.Argument(help="The machine's name.")],
    yes: Annotated[bool, typer.Option(
        "--yes", help="Really delete: the machine goes with its models, measurements, maps "
                      "and reports (its events stay).")] = False,
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
) -> None:
    """Delete a machine with everything the center holds for it (DELETE
    /api/machines/NAME)."""
    if not yes:
        raise UserError(f"deleting {name} deletes its models, measurements, maps and "
                        "reports too; add --yes to do it")
    r = call("DELETE", api, f"/machines/{name}", api_key)
    if r.status_code == 404:
        raise UserError(f"the center at {api} has no machine {name!r} ('ednc machine list')")
    if r.status_code != 204:
        raise UserError(f"the center refused to delete {name} ({r.status_code}): "
                        f"{detail(r)}")
    typer.echo(f"deleted {name} at {api}")


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
