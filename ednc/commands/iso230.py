"""``ednc iso230-2``: ISO 230-2 bidirectional positioning evaluation of a measurement CSV."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ednc.cli import UserError
from ednc.inputs import dump_json
from volumetric.measure.measurement import MeasurementFormatError, read_measurements
from volumetric.verify.iso230_2 import PositioningResult, PositioningTestError, evaluate_positioning


def register(app: typer.Typer) -> None:
    @app.command("iso230-2")
    def iso230_2(
        data: Annotated[Path, typer.Option("--data", help="Measurement CSV (formats.md §2).")],
        as_json: Annotated[bool, typer.Option(
            "--json", help='Print {"A_um", "B_um", "E_um", "M_um", "R_um"} as one JSON '
                           "object.")] = False,
        test: Annotated[str | None, typer.Option(
            "--test", help="Evaluate only the rows with this test label.")] = None,
    ) -> None:
        """Evaluate one axis's bidirectional positioning test after ISO 230-2:2014.

        Rows: run = cycle, the moving axis's dir_* = approach direction, value = deviation
        (µm) along the axis.
        """
        result = evaluate_file(data, test)
        if as_json:
            typer.echo(dump_json(result.summary()))
        else:
            typer.echo(format_table(result))


def evaluate_file(path: Path, test: str | None) -> PositioningResult:
    """Read and evaluate, turning every input problem into a :class:`UserError`."""
    try:
        m = read_measurements(path)
    except (MeasurementFormatError, UnicodeDecodeError) as exc:
        raise UserError(str(exc)) from exc
    except OSError as exc:
        raise UserError(f"cannot read {path}: {exc.strerror or exc}") from exc
    if test is not None:
        keep = m.test == test
        if not keep.any():
            labels = ", ".join(map(repr, np.unique(m.test).tolist()))
            raise UserError(f"{path}: no rows with test {test!r} (the file has {labels})")
        m = m.select(keep)
    try:
        return evaluate_positioning(m)
    except PositioningTestError as exc:
        raise UserError(f"{path}: {exc}") from exc


def format_table(r: PositioningResult) -> str:
    """A plain-text report: per-target statistics, then the axis values (µm).

    The sign of each target's reversal is said on the page, since the diagnosis reports a
    backlash as a size B >= 0 and the error map as a correction: B_i = x̄↑ - x̄↓ is -B for
    an axis that lags behind the motion.
    """
    ax = r.axis
    lines = [f"ISO 230-2 bidirectional positioning, axis {ax} (deviations in µm)",
             "B = x̄↑ - x̄↓ per target (negative: the axis lags behind the motion, "
             "as a backlash does)",
             f"{'target ' + ax + ' mm':>14} {'x̄↑':>9} {'s↑':>8} {'x̄↓':>9} {'s↓':>8} "
             f"{'x̄':>9} {'B':>9} {'R':>8}"]
    for k, target in enumerate(r.targets_mm):
        lines.append(
            f"{target:14.4f} {r.mean_up_um[k]:9.3f} {r.s_up_um[k]:8.3f} "
            f"{r.mean_down_um[k]:9.3f} {r.s_down_um[k]:8.3f} {r.mean_um[k]:9.3f} "
            f"{r.reversal_um[k]:9.3f} {r.repeatability_um[k]:8.3f}")
    lines.append("")
    for key, value, what in (
        ("A", r.A_um, "bidirectional accuracy"),
        ("B", r.B_um, "reversal value (max |Bi|, so >= 0)"),
        ("E", r.E_um, "bidirectional systematic positioning error"),
        ("M", r.M_um, "mean bidirectional positional deviation"),
        ("R", r.R_um, "bidirectional repeatability"),
    ):
        lines.append(f"{key} = {value:10.3f} µm  {what}")
    return "\n".join(lines)
