"""``ednc predict``: a saved model applied to readings it was not fitted on."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.inputs import ReadingsTravel, dump_json, read_data, read_machine, read_model
from volumetric.diagnose.predict import PredictionError, predict


def register(app: typer.Typer) -> None:
    @app.command("predict")
    def predict_cmd(
        machine: Annotated[Path, typer.Option("--machine", help="Machine description JSON.")],
        model: Annotated[Path, typer.Option(
            "--model", help="Model JSON (ednc fit --out or ednc diagnose --out).")],
        data: Annotated[Path, typer.Option("--data", help="Measurement CSV (formats.md §2).")],
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    ) -> None:
        """RMS and worst residual of the readings under the model (every term, lagged
        thermal states included) and under its rigid part alone, per test; nothing is
        refitted and no offset removed."""
        m = read_machine(machine)
        mm = read_model(model, m)
        readings = read_data(data)
        ReadingsTravel(m, data).check_axes(readings)
        try:
            p = predict(m, mm, readings)
        except PredictionError as exc:
            raise UserError(f"{data}: {exc}") from exc
        out = p.to_json()
        if as_json:
            typer.echo(dump_json(out))
            return
        typer.echo(f"{out['n_readings']} displacement readings: RMS {out['rms_um']:.3f} µm with "
                   f"the model, {out['rms_rigid_um']:.3f} µm rigid part alone; worst "
                   f"{out['max_abs_um']:.3f} µm")
        for t in out["tests"]:
            typer.echo(f"  {t['test']:24s} {t['rms_um']:8.3f} µm  (rigid {t['rms_rigid_um']:.3f})")
