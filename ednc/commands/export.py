"""``ednc export``: a machine's compensation in a controller's native format."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.commands.compensate import parse_temperatures, parse_weights
from ednc.inputs import read_machine, read_model
from volumetric.compensate.maps import MapBuildError
from volumetric.compensate.native import CEC_MAX_POINTS, cec_mpf, cec_tables, iso230_1_tables
from volumetric.compensate.solver import CompensationError
from volumetric.compensate.tablesmap import build_tables_map
from volumetric.errors import ComponentErrorSpecError
from volumetric.measure.tables import write_tables


def register(app: typer.Typer) -> None:
    @app.command("export")
    def export_cmd(
        machine_path: Annotated[Path, typer.Option(
            "--machine", help="Machine description JSON (formats.md §1).")],
        model_path: Annotated[Path, typer.Option(
            "--model", help="Model JSON as written by 'ednc fit' or 'ednc diagnose'.")],
        fmt: Annotated[str, typer.Option(
            "--format", help="cec: Siemens $AN_CEC tables as an MPF file (1-D tables only: "
                             "the file lists what they cannot hold); iso230-1: component "
                             "tables as CSV per axis for controllers that evaluate the "
                             "chain (ISG/Beckhoff kind).")],
        out: Annotated[Path, typer.Option(
            "--out", help="The MPF file (cec) or a directory for the CSV files.")],
        tolerance_um: Annotated[float, typer.Option(
            "--tolerance-um", help="Largest tool-tip error of the tables, µm.")] = 0.5,
        max_points: Annotated[int, typer.Option(
            "--max-points", help="Points per CEC table (828D: 200).")] = CEC_MAX_POINTS,
        temperature: Annotated[list[str] | None, typer.Option(
            "--temperature", help="SENSOR=°C for the model's thermal terms; may repeat."
        )] = None,
        weights: Annotated[str | None, typer.Option(
            "--weights", help="Solver weights, as for 'ednc compensate'.")] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    ) -> None:
        """Write the compensation for a controller without our endpoint: Siemens CEC tables
        or ISO 230-1 component tables, from the tables map at the tolerance."""
        if fmt not in ("cec", "iso230-1"):
            raise UserError(f"--format {fmt!r}: expected cec or iso230-1")
        if max_points < 2:
            raise UserError(f"--max-points must be at least 2, got {max_points}")
        machine = read_machine(machine_path)
        model = read_model(model_path, machine)
        temps = parse_temperatures(temperature or [])
        try:
            t = build_tables_map(machine, model, temps, tolerance_um=tolerance_um,
                                 weights=parse_weights(weights, machine), controller="siemens")
        except (MapBuildError, CompensationError, ComponentErrorSpecError) as exc:
            raise UserError(str(exc)) from None
        try:
            if fmt == "cec":
                out.write_text(cec_mpf(t, max_points=max_points))
                e = cec_tables(t, max_points=max_points)
                written, count, left = [str(out)], len(e.tables), list(e.left_out)
            else:
                written = [str(p) for p in write_tables(iso230_1_tables(t), out)]
                count, left = len(t.tables), []
        except OSError as exc:
            raise UserError(f"{out}: cannot write ({exc.strerror or exc})") from None
        if as_json:
            typer.echo(json.dumps({"format": fmt, "files": written, "tables": count,
                                   "left_out": [{"error": n, "max": v} for n, v in left]}))
            return
        typer.echo(f"{fmt}: {count} tables -> {', '.join(written)}")
        for name, size in left:
            typer.echo(f"  not in 1-D tables, left uncompensated: {name} "
                       f"(up to {size:.3g} µm or µrad)")
