"""``ednc diagnose``: what the rigid model gets wrong, its cause, and the gain of the fix."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.inputs import read_data, read_machine
from volumetric.diagnose.diagnosis import DiagnosisError, diagnose


def register(app: typer.Typer) -> None:
    @app.command("diagnose")
    def diagnose_cmd(
        machine: Annotated[Path, typer.Option("--machine", help="Machine description JSON.")],
        data: Annotated[Path, typer.Option("--data", help="Measurement CSV (formats.md §2).")],
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
        report: Annotated[Path | None, typer.Option(
            "--report", help="Write PNG plots and index.html into this directory.")] = None,
        holdout_after: Annotated[float | None, typer.Option(
            "--holdout-after", help="Judge on readings at or after this time (s), fitted "
                                    "on the earlier ones (default: folds of runs).")] = None,
        out: Annotated[Path | None, typer.Option(
            "--out", help="Write the extended machine model (JSON) here.")] = None,
    ) -> None:
        """Fit the rigid model, test physical extensions on held-out readings, name the cause.

        The JSON has effect, axis, sensor, estimate, rms_before_um, rms_after_um and the
        ranked candidates (formats.md section 3), plus not_assessed: what the readings
        cannot support.
        """
        m = read_machine(machine)
        readings = read_data(data)
        try:
            d = diagnose(m, readings, holdout_after=holdout_after)
        except DiagnosisError as exc:
            raise UserError(f"{data}: {exc}") from exc
        if report is not None:
            from volumetric.diagnose.report import write_report

            write_report(m, readings, d, report, data_file=data, machine_file=machine)
        if out is not None:
            out.write_text(json.dumps(d.model.to_json(), indent=1))
        if as_json:
            typer.echo(json.dumps(d.to_json()))
            return
        typer.echo(f"effect: {d.effect} {d.axis or ''} {d.sensor or ''}".rstrip())
        for k, v in d.estimate.items():
            if not isinstance(v, dict):
                typer.echo(f"  {k}: {v:.4g}" if isinstance(v, float) else f"  {k}: {v}")
        typer.echo(f"held-out RMS: {d.rms_before_um:.3f} µm rigid, {d.rms_after_um:.3f} µm "
                   "extended")
        for c in d.candidates[:8]:
            typer.echo(f"  {c['effect']:18s} {c['axis']} {c.get('sensor') or '':14s} "
                       f"{c['rms_after_um']:8.3f} µm  z={c['z']}")
        for k, v in d.not_assessed.items():
            typer.echo(f"not assessed: {k}: {v}")
        if report is not None:
            typer.echo(f"report: {report / 'index.html'}")
