"""``ednc fit``: identify a machine's component errors from a measurement CSV
(``ednc tables`` lives in :mod:`ednc.commands.tables`)."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.inputs import ReadingsTravel, check_output, dump_json, read_machine
from ednc.progress import CommandProgress, wanted
from volumetric.identify.fit import FitError, FitResult, fit_blocks
from volumetric.measure.measurement import (
    MeasurementFormatError,
    Measurements,
    read_measurement_blocks,
)
from volumetric.model.machine import Machine

_ORDER = {0: "constant", 1: "linear", 2: "quadratic", 3: "cubic"}


def term_text(parameter: str) -> str:
    """``EBZ[0]`` -> ``EBZ constant term``: a parameter's name as a reader takes it (the
    index is the order of the component's polynomial term over its travel)."""
    match = re.fullmatch(r"(\w+)\[(\d+)\]", parameter)
    if match is None:
        return parameter
    name, k = match.group(1), int(match.group(2))
    return f"{name} {_ORDER.get(k, f'order-{k}')} term"


def summary(result: FitResult) -> str:
    lines = [f"readings: {result.model.info['n_readings']}",
             "residual RMS: " + ", ".join(f"{k} {v:.3f}" for k, v in result.rms.items()),
             "degrees: " + ", ".join(f"{k} {v}" for k, v in sorted(result.degrees.items()))]
    for u in result.unidentifiable:
        lines.append(f"not identifiable (fixed at 0): {term_text(u['parameter'])} "
                     "(confounded with "
                     f"{', '.join(term_text(p) for p in u['confounded_with'])})")
    if result.not_measured:
        lines.append("not measured: " + ", ".join(result.not_measured))
    return "\n".join(lines)


def _fit_file(machine: Machine, data: Path, as_json: bool,
              outside_travel: bool = False) -> FitResult:
    """Identify from the file block by block (memory follows a block, not the file), with
    a progress bar on a terminal (:mod:`ednc.progress`)."""
    try:
        size = data.stat().st_size
    except OSError as exc:
        raise UserError(f"cannot read {data}: {exc.strerror or exc}") from exc
    with CommandProgress(wanted(as_json)) as progress:
        advance = progress.reading(f"reading {data.name}", size)
        blocks = read_measurement_blocks(data, progress=advance)

        travel = ReadingsTravel(machine, data)

        def staged() -> Iterator[Measurements]:
            for block in blocks:
                yield block if outside_travel else travel.check(block)
            progress.stage("identifying: degrees, null space, uncertainties")

        try:
            return fit_blocks(machine, staged())
        except (MeasurementFormatError, UnicodeDecodeError) as exc:
            raise UserError(str(exc)) from exc
        except FitError as exc:
            raise UserError(f"{data}: {exc}") from exc
        except OSError as exc:
            raise UserError(f"cannot read {data}: {exc.strerror or exc}") from exc


def register(app: typer.Typer) -> None:
    @app.command("fit")
    def fit_cmd(
        machine: Annotated[Path, typer.Option("--machine", help="Machine description JSON.")],
        data: Annotated[Path, typer.Option("--data", help="Measurement CSV (formats.md §2).")],
        out: Annotated[Path | None, typer.Option("--out", help="Write the model here.")] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print the model JSON.")] = False,
        outside_travel: Annotated[bool, typer.Option(
            "--allow-outside-travel", help="Use readings outside the description's travel "
                                           "(refused by default).")] = False,
    ) -> None:
        """Identify the rigid model (ISO 230-1 component and location errors) from readings.

        Degrees are chosen by BIC; parameters the readings cannot separate are named and
        fixed at zero; uncertainties are in the model's info.
        """
        check_output(out, "--out")
        m = read_machine(machine)
        result = _fit_file(m, data, as_json, outside_travel)
        text = dump_json(result.model.to_json(), indent=1)
        if out is not None:
            try:
                out.write_text(text)
            except OSError as exc:
                raise UserError(f"--out {out}: cannot write ({exc.strerror or exc})") from None
        if as_json:
            typer.echo(text)
        else:
            typer.echo(summary(result))
            if out is not None:
                typer.echo(f"model written to {out}")
