"""``ednc model upload``: store a fitted model at a running center, which then builds the
machine's map and sends it (REST ``POST /api/machines/NAME/models``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ednc.api import ApiOption, KeyOption, call, detail
from ednc.cli import UserError
from ednc.inputs import read_model

model_app = typer.Typer(name="model", no_args_is_help=True,
                        help="Upload a machine's model to a running center.")


@model_app.command("upload")
def upload_cmd(
    machine: Annotated[str, typer.Option(
        "--machine", help="The registered machine's name.")],
    model: Annotated[Path, typer.Option(
        "--model", help="Model JSON (ednc fit --out or ednc diagnose --out).")],
    api: ApiOption = "http://127.0.0.1:8080",
    api_key: KeyOption = None,
) -> None:
    """Store the model as the machine's next version; the center builds its map and sends
    it to the machine when connected (see 'ednc machine status NAME')."""
    m = read_model(model)  # the offline checks first: one line, before the network
    if m.machine and m.machine != machine:
        raise UserError(f"{model}: the model is of machine {m.machine!r}, not {machine!r}")
    body = json.loads(model.read_text())
    r = call("POST", api, f"/machines/{machine}/models", api_key,
             body={"source": "upload", "body": body})
    if r.status_code == 404:
        raise UserError(f"the center at {api} has no machine {machine!r}; register it first "
                        "with 'ednc machine register'")
    if r.status_code != 201:
        raise UserError(f"the center refused {model} ({r.status_code}): {detail(r)}")
    version = r.json().get("version")
    typer.echo(f"model v{version} of {machine} stored at {api}; the center builds its map "
               f"and sends it when the machine is connected ('ednc machine status {machine}')")


def register(app: typer.Typer) -> None:
    app.add_typer(model_app, name="model")
