"""``ednc export``: a machine's compensation in a controller's native format."""

from __future__ import annotations

import dataclasses
import datetime
import json
from pathlib import Path
from typing import Annotated

import typer

from ednc.cli import UserError
from ednc.commands.compensate import parse_temperatures
from ednc.inputs import read_machine, read_model
from volumetric.compensate.cec import CONTROLS, LeftOut, cec_export
from volumetric.compensate.cec_check import tool_tip
from volumetric.compensate.cec_text import CecFile, cec_text, program_name
from volumetric.compensate.iso230_1 import iso230_1_export
from volumetric.compensate.native import model_geometry
from volumetric.errors import ComponentErrorSpecError
from volumetric.model.machine import Machine
from volumetric.plausible.lengths import TOOL_LENGTH
from volumetric.plausible.limit import Implausible
from volumetric.plausible.sizes import check_output_size

HELP_FORMAT = (
    "cec: Siemens CEC tables ($AN_CEC, K3 sag compensation) as an MPF part program (or "
    "INI with --program ini): per input/output pair one 1-D table (positioning, "
    "straightness, squareness and the angular errors' share that depends on one axis), "
    "the angular errors' Abbe terms as products of a factor table and a linear arm table "
    "($AN_CEC_MULT_BY_TABLE), backlash as direction-dependent tables ($AN_CEC_DIRECTION), "
    "a full-turn rotary axis's angular positioning as a modulo table; within the "
    "control's table count, the rest named with its tool-tip effect (rotary axes' other "
    "errors: the 5-axis transformation data; thermal terms: the temperature path). "
    "iso230-1: every component error of every axis as CSV with units, metadata (machine, "
    "model, sign convention, tool length, reference temperature), rows at a regular "
    "step, columns the model did not identify present and empty, for controls that "
    "evaluate the chain (ISG/Beckhoff kind); backlash and thermal terms named, not "
    "tabulated.")


def parse_axis_names(text: str | None, machine: Machine) -> dict[str, str]:
    """``X=X1,Y=Y1`` → {"X": "X1", ...}; refused when an axis is unknown or a name is not
    a SINUMERIK identifier."""
    if not text:
        return {}
    out: dict[str, str] = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        key, value = key.strip().upper(), value.strip()
        if not sep or key not in machine.axis_names:
            raise UserError(f"--axis-names {text!r}: expected AXIS=NAME pairs such as "
                            f"X=X1 for axes {', '.join(machine.axis_names)}")
        if not value or not value.replace("_", "").isalnum() or not value[0].isalpha():
            raise UserError(f"--axis-names: {value!r} is not an axis name (letters, digits, "
                            "_; e.g. X1 or AX1)")
        out[key] = value
    return out


def register(app: typer.Typer) -> None:
    @app.command("export")
    def export_cmd(
        machine_path: Annotated[Path, typer.Option(
            "--machine", help="Machine description JSON (formats.md §1).")],
        model_path: Annotated[Path, typer.Option(
            "--model", help="Model JSON as written by 'ednc fit' or 'ednc diagnose'.")],
        fmt: Annotated[str, typer.Option("--format", help=HELP_FORMAT)],
        out: Annotated[Path, typer.Option(
            "--out", help="cec: the file (or a directory: EDNC_CEC.MPF in it). "
                          "iso230-1: a directory for X.csv, ..., "
                          "locations.csv, or a file ending in .csv for all tables in one "
                          "(blocks separated by a blank line).")],
        tolerance_um: Annotated[float, typer.Option(
            "--tolerance-um", help="cec: interpolation budget at the tool tip per output "
                                   "axis, µm (sets the points per table).")] = 0.5,
        control: Annotated[str, typer.Option(
            "--control", help="cec: 828d (8 tables of 200 points, fixed) or 840d (as many "
                              "as MD18342 reserves; assumed here up to 62 tables of 2000 "
                              "points: give the machine's with --max-tables, "
                              "--max-points).")] = "840d",
        max_tables: Annotated[int | None, typer.Option(
            "--max-tables", help="cec: tables available (default: the control's).")] = None,
        max_points: Annotated[int | None, typer.Option(
            "--max-points", help="cec: points per table (default: the control's).")] = None,
        lec: Annotated[bool, typer.Option(
            "--lec", help="cec: leave the positioning errors (EXX, EYY, EZZ, ECC, ...) "
                          "to the leadscrew (LEC) tables instead of writing them.")] = False,
        first_table: Annotated[int, typer.Option(
            "--first-table", help="cec: number of the first table (tables below stay "
                                  "the OEM's).")] = 0,
        axis_names: Annotated[str | None, typer.Option(
            "--axis-names", help="cec: control axis names, e.g. X=X1,Y=Y1,Z=Z1 "
                                 "(default: the model's name followed by 1).")] = None,
        program: Annotated[str, typer.Option(
            "--program", help="cec: mpf (a part program, %_N_<NAME>_MPF, ends M30) or ini "
                              "(%_N_NC_CEC_INI with CHANDATA(1), ends M17).")] = "mpf",
        tool_length: Annotated[float | None, typer.Option(
            "--tool-length", help="Tool length the Abbe arms are taken with, mm (default: "
                                  "the machine description's).")] = None,
        work_z: Annotated[float | None, typer.Option(
            "--work-z", help="cec: the z (mm) at which an Abbe term with arm z that does "
                             "not fit as a product is folded into a 1-D table (exact "
                             "there; default: the middle of the z travel).")] = None,
        step: Annotated[float | None, typer.Option(
            "--step", help="iso230-1: row step of the linear axes, mm (default: a round "
                           "step giving 20-50 rows).")] = None,
        temperature: Annotated[list[str] | None, typer.Option(
            "--temperature", help="SENSOR=°C: fold the thermal terms in at these "
                                  "temperatures (static); may repeat. Without it they are "
                                  "named as left to the temperature path.")] = None,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    ) -> None:
        """Write the compensation for a controller without our endpoint (see --format for
        what each format carries) and say what it leaves at the tool tip."""
        if fmt not in ("cec", "iso230-1"):
            raise UserError(f"--format {fmt!r}: expected cec or iso230-1")
        if control not in CONTROLS:
            raise UserError(f"--control {control!r}: expected 828d or 840d")
        if program not in ("mpf", "ini"):
            raise UserError(f"--program {program!r}: expected mpf or ini")
        tables_cap, points_cap = CONTROLS[control]
        if max_points is not None and not 2 <= max_points <= points_cap:
            raise UserError(f"--max-points must be 2..{points_cap} on the {control}, "
                            f"got {max_points}")
        if max_tables is not None and not 1 <= max_tables <= tables_cap:
            raise UserError(f"--max-tables must be 1..{tables_cap} on the {control}, "
                            f"got {max_tables}")
        if not 0 <= first_table < tables_cap:
            raise UserError(f"--first-table {first_table}: the {control} numbers its "
                            f"tables 0..{tables_cap - 1}")
        room = tables_cap - first_table  # the tables below the first stay the OEM's
        if max_tables is not None and max_tables > room:
            raise UserError(f"--max-tables {max_tables} from table {first_table}: the "
                            f"{control} has {room} tables left (0..{tables_cap - 1})")
        max_tables = room if max_tables is None else max_tables
        if not (tolerance_um > 0 and tolerance_um < 1e3):
            raise UserError(f"--tolerance-um must be > 0 and < 1000, got {tolerance_um}")
        if step is not None and not 0 < step <= 1e4:
            raise UserError(f"--step must be > 0 mm, got {step}")
        if tool_length is not None and not TOOL_LENGTH.holds(tool_length):
            raise UserError(f"--tool-length: {TOOL_LENGTH.refusal(tool_length)}")
        machine = read_machine(machine_path)
        if fmt == "cec" and machine.controller == "fanuc":
            # a controller's native format for another controller: nothing loads it
            raise UserError(f"machine {machine.name!r} has a fanuc controller; CEC tables "
                            "($AN_CEC) are SINUMERIK's own and a Fanuc control cannot load "
                            "them: use --format iso230-1 for a table, or 'ednc map' for its "
                            "ladder (or correct 'controller' if the machine is a SINUMERIK)")
        if fmt == "iso230-1" and step is not None:
            rows = sum((a.travel[1] - a.travel[0]) / step + 2 for a in machine.axes
                       if a.kind == "linear")
            try:  # before any work: a step in µm given as mm is 1000 times the rows
                check_output_size(rows * 7 * 16.0, f"--out {out}", "give a larger --step "
                                  "(mm)")
            except Implausible as exc:
                raise UserError(str(exc)) from None
        if len(machine.branches) > 1:
            raise UserError(f"machine {machine.name!r} has {len(machine.branches)} "
                            "spindles; native exports cover one tool tip")
        names = parse_axis_names(axis_names, machine)
        if work_z is not None:
            if "Z" not in machine.axis_names:
                raise UserError(f"--work-z: machine {machine.name!r} has no Z axis")
            lo, hi = machine.axis("Z").travel
            if not lo <= work_z <= hi:
                raise UserError(f"--work-z {work_z:g}: outside the z travel {lo:g}..{hi:g} mm")
        model = read_model(model_path, machine)
        temps = parse_temperatures(temperature or [])
        tool = machine.branches[0].tool_length_mm if tool_length is None else tool_length
        try:
            geo, backlash, thermal = model_geometry(model, temps or None, machine)
        except (ValueError, ComponentErrorSpecError) as exc:
            raise UserError(str(exc)) from None
        if fmt == "cec":
            e = cec_export(machine, geo, tool_mm=tool, control=control,
                           max_tables=max_tables, max_points=max_points,
                           tolerance_um=tolerance_um, positioning=not lec,
                           backlash_um=backlash,
                           fold_at=None if work_z is None else {"Z": work_z})
            left = list(e.left_out) + [LeftOut(n, None, f"thermal ({w}): left to the "
                                              "temperature path, not a static table")
                                       for n, w in thermal]
            e = dataclasses.replace(e, left_out=tuple(left))
            figures = tool_tip(machine, geo, e)
            note = f"model {_source(model_path)}" + (
                f" at {', '.join(f'{k}={v:g} C' for k, v in temps.items())}" if temps else "")
            if out.is_dir():  # a directory: the file goes in it, named as the control does
                out = out / ("NC_CEC.INI" if program == "ini" else "EDNC_CEC.MPF")
            spec = CecFile(program, program_name(out.stem), names, first_table)
            offsets = {str(k): float(v) for k, v in
                       dict(model.info.get("offsets_um", {}) or {}).items()}
            text = cec_text(e, figures, machine_name=machine.name, model_note=note, f=spec,
                            offsets_um=offsets)
            _write(out, text)
            result = {"format": fmt, "files": [str(out)], "tables": len(e.tables),
                      "control": control, "first_table": first_table,
                      "tool_tip": figures.to_json(),
                      "decomposition_um": round(e.affine_um, 6),
                      "products": sum(1 for t in e.tables if t.role == "factor"),
                      "offsets_um_not_in_tables": offsets,
                      "left_out": [x.to_json() for x in e.left_out]}
        else:
            iso = iso230_1_export(machine, model, geo, step_mm=step, tool_mm=tool,
                                  thermal=thermal, backlash_um=backlash,
                                  source=_source(model_path))
            if out.suffix.lower() == ".csv":
                _write(out, iso.single())
                written = [str(out)]
            else:
                try:
                    out.mkdir(parents=True, exist_ok=True)
                except OSError as exc:
                    raise UserError(f"{out}: cannot create ({exc.strerror or exc})") from None
                written = []
                for key, text in iso.files.items():
                    _write(out / f"{key}.csv", text)
                    written.append(str(out / f"{key}.csv"))
            left_iso = ([{"error": f"backlash {k}", "effect_um": round(v / 2, 4),
                          "reason": "direction-dependent: not in a direction-free table"}
                         for k, v in sorted(backlash.items())]
                        + [{"error": n, "effect_um": None,
                            "reason": f"thermal ({w}): left to the temperature path"}
                           for n, w in thermal]
                        + [{"error": n, "effect_um": None,
                            "reason": "not identified: written as an empty column"}
                           for n in iso.unidentified]
                        + ([{"error": "between the rows", "effect_um": round(iso.tool_tip_um, 4),
                             "reason": "linear interpolation between the rows (a finer "
                                       "--step lowers it)"}] if iso.tool_tip_um > 0.1 else []))
            result = {"format": fmt, "files": written, "tables": len(iso.files),
                      "tool_tip": {"rows_vs_model_worst_um": round(iso.tool_tip_um, 4),
                                   "tool_mm": tool},
                      "interpolation_max": {k: round(v, 6) for k, v in iso.interp.items()},
                      "left_out": left_iso}
        if as_json:
            typer.echo(json.dumps(result))
            return
        files = result["files"]
        assert isinstance(files, list)
        typer.echo(f"{fmt}: {result['tables']} tables -> {', '.join(files)}")
        if fmt != "cec":
            typer.echo(f"  the rows reproduce the model within {iso.tool_tip_um:.3f} µm at "
                       f"the tool tip ({tool:g} mm tool)")
        if fmt == "cec":
            f = figures
            typer.echo(f"  tool tip ({tool:g} mm tool), worst / RMS: model "
                       f"{f.worst_before_um:.2f} / {f.rms_before_um:.2f} µm, with the tables "
                       f"{f.worst_after_um:.2f} / {f.rms_after_um:.2f} µm")
        for x in result["left_out"]:  # type: ignore[attr-defined]
            eff = "" if x["effect_um"] is None else f", {x['effect_um']:.2f} µm at the tool tip"
            typer.echo(f"  not carried: {x['error']}{eff} ({x['reason']})")


def _source(path: Path) -> str:
    """``model.json of 2026-11-27 12:40 UTC``: the model file and when it was written."""
    when = datetime.datetime.fromtimestamp(path.stat().st_mtime, datetime.UTC)
    return f"{path.name} of {when:%Y-%m-%d %H:%M} UTC"


def _write(path: Path, text: str) -> None:
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise UserError(f"{path}: cannot write ({exc.strerror or exc})") from None
