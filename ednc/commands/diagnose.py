"""``ednc diagnose``: what the rigid model gets wrong, its cause, and the gain of the fix."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.inputs import (
    ReadingsTravel,
    check_output,
    dump_json,
    float_option,
    int_option,
    read_machine,
)
from ednc.progress import CommandProgress, read_shown, wanted
from volumetric.diagnose.diagnosis import DiagnosisError, diagnose
from volumetric.diagnose.text import effects_text
from volumetric.measure.measurement import subsample

MAX_READINGS = 100_000
"""Readings a diagnosis takes by default. Its held-out tests judge 30 contiguous chunks,
and 100 000 readings give each chunk thousands; more cost time and memory in proportion
(measured: 200 000 readings, 46 s of CPU and 0.9 GB) without changing the verdict."""
PER_TEST = 2000
"""Fewest readings a test keeps in the draw (what resolves a period or a reversal)."""


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
        max_readings: Annotated[int, typer.Option(
            "--max-readings", help="Diagnose at most about this many readings, drawn at "
                                   "random within each test (0: all).")] = MAX_READINGS,
        outside_travel: Annotated[bool, typer.Option(
            "--allow-outside-travel", help="Use readings outside the description's travel "
                                           "(refused by default).")] = False,
    ) -> None:
        """Fit the rigid model, test physical extensions on held-out readings, name the cause.

        The JSON has effect, axis, sensor, estimate, rms_before_um, rms_after_um and the
        ranked candidates (formats.md section 3), plus not_assessed: what the readings
        cannot support.
        """
        int_option(max_readings, "--max-readings", 0, meaning=" (0: all readings)")
        if holdout_after is not None:
            float_option(holdout_after, "--holdout-after", -3.2e9, 3.2e9, unit=" s")
        check_output(out, "--out")
        check_output(report, "--report", directory=True)
        m = read_machine(machine)
        with CommandProgress(wanted(as_json)) as progress:
            readings = read_shown(data, progress)
            travel = ReadingsTravel(m, data)
            travel.check_axes(readings)
            if not outside_travel:
                travel.check(readings)
            if max_readings > 0 and len(readings) > max_readings:
                total = len(readings)
                readings = subsample(readings, max_readings, per_test=PER_TEST)
                # every test keeps at least PER_TEST readings, so the draw can exceed the
                # limit: say what is diagnosed, not what was asked
                typer.echo(f"diagnosing {len(readings)} of the {total} readings, drawn at "
                           f"random within each test (--max-readings {max_readings}; every "
                           f"test keeps its share and at least {PER_TEST})", err=True)
            progress.stage(f"diagnosing {len(readings)} readings")
            try:
                d = diagnose(m, readings, holdout_after=holdout_after)
            except DiagnosisError as exc:
                raise UserError(f"{data}: {exc}") from exc
        if report is not None:
            from volumetric.diagnose.report import write_report

            write_report(m, readings, d, report, data_file=data, machine_file=machine)
        if out is not None:
            try:
                out.write_text(dump_json(d.model.to_json(), indent=1))
            except OSError as exc:
                raise UserError(f"--out {out}: cannot write ({exc.strerror or exc})") from None
        if as_json:
            typer.echo(dump_json(d.to_json()))
            return
        for line in effects_text(d):
            typer.echo(line)
        typer.echo("candidates (held-out RMS alone, z):")
        for c in d.candidates[:8]:
            model = "  (lagged model)" if c.get("model") == "lagged" else ""
            typer.echo(f"  {c['effect']:18s} {c['axis']} {c.get('sensor') or '':14s} "
                       f"{c['rms_after_um']:8.3f} µm  z={c['z']}{model}")
        for k, v in d.not_assessed.items():
            typer.echo(f"not assessed: {k}: {v}")
        if report is not None:
            typer.echo(f"report: {report / 'index.html'}")
