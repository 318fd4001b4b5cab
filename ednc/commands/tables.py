"""``ednc tables``: export and import a model as component-error tables with ISO 230-1
column names (one CSV per axis, ``locations.csv``) and its extension terms
(``terms.json``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.inputs import read_machine, read_model
from volumetric.errors import ComponentErrorSpecError
from volumetric.measure.tables import (
    TERMS_FILE,
    export_model,
    import_model,
    read_table_files,
    write_files,
)
from volumetric.plausible.counts import MAX_TABLE_POINTS, check_count
from volumetric.plausible.limit import Implausible
from volumetric.plausible.sizes import check_output_size


def register(app: typer.Typer) -> None:
    tables = typer.Typer(help="Component-error tables with ISO 230-1 column names, and the "
                              f"model's extension terms in {TERMS_FILE}.",
                         no_args_is_help=True)

    @tables.command("export")
    def export_cmd(
        machine: Annotated[Path, typer.Option("--machine", help="Machine description JSON.")],
        model: Annotated[Path, typer.Option(
            "--model", help="Model JSON (ednc fit, ednc diagnose --out).")],
        out: Annotated[Path, typer.Option("--out", help="Directory for the files.")],
        points: Annotated[int, typer.Option(help="Positions per axis.")] = 21,
    ) -> None:
        """Write one CSV per axis, locations.csv and terms.json (the rest of the model).

        Axis files: x_mm, EXX_um, ..., EAX_urad, ...; terms.json: backlash, periodic and
        thermal terms, each with a one-line description and its units, the model's info
        (the fit's tool-tip offsets, which predict adds) and the exact component functions,
        so that 'ednc tables import' gives the model back whole.
        A term the files cannot carry exactly is refused by name and nothing is written.
        """
        if points < 2:
            raise UserError(f"--points {points}: a table needs at least 2 positions")
        try:  # before any work: an extra zero is a typo, not a table
            check_count(points, "--points", 2, MAX_TABLE_POINTS,
                        " (positions per axis; a 1 µm step over 100 mm)")
        except Implausible as exc:
            raise UserError(str(exc)) from None
        m = read_machine(machine)
        try:
            # one row per position and axis: the position and 6 errors, ~22 bytes a cell
            check_output_size(len(m.axes) * points * 7 * 22.0, f"--out {out}",
                              "ask for fewer --points")
        except Implausible as exc:
            raise UserError(str(exc)) from None
        mm = read_model(model, m)
        try:
            files = export_model(m, mm, points=points)
        except ComponentErrorSpecError as exc:
            raise UserError(f"{model}: {exc}") from exc
        try:
            for p in write_files(files, out):
                typer.echo(str(p))
        except OSError as exc:
            raise UserError(f"{out}: cannot write ({exc.strerror or exc})") from exc

    @tables.command("import")
    def import_cmd(
        machine: Annotated[Path, typer.Option("--machine", help="Machine description JSON.")],
        files: Annotated[list[Path], typer.Argument(
            help=f"Table CSV files and {TERMS_FILE}, or the directory an export wrote.")],
        out: Annotated[Path, typer.Option("--out", help="Model JSON to write.")],
    ) -> None:
        """Build a model from component-error tables and terms.json (rigid without it).

        Reads the files of 'ednc tables export' and 'ednc export --format iso230-1' (a
        directory, or one file of blocks; metadata lines start with #; an empty column is
        unknown) and those of earlier versions (bare ISO names, no metadata). Tables are
        interpolated linearly between rows; with a terms.json of this version whose exact
        functions the tables still match, the model comes back exactly (offsets too)."""
        m = read_machine(machine)
        try:
            model = import_model(m, read_table_files(files))
        except ComponentErrorSpecError as exc:
            raise UserError(str(exc)) from exc
        out.write_text(json.dumps(model.to_json(), indent=1))
        typer.echo(f"model with {len(model.geometry.components)} tables and "
                   f"{len(model.terms)} extension terms written to {out}")

    app.add_typer(tables, name="tables")
