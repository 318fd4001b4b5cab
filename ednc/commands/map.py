"""``ednc map``: build a machine's error map and write its binary payload."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from ednc.cli import UserError
from ednc.commands.compensate import (
    parse_temperatures,
    parse_weights,
)
from ednc.inputs import (
    check_output,
    dump_json,
    float_option,
    int_option,
    read_machine,
    read_model,
)
from server.mapcodec import MapContent, build_for, encode, kind_of
from volumetric.compensate.factoredmap import FactoredMap, as_sent_floor_um
from volumetric.compensate.gridmap import (
    DEFAULT_INCREMENT,
    DEFAULT_LIMIT_DEG,
    DEFAULT_LIMIT_MM,
    MapBuildError,
)
from volumetric.compensate.solver import CompensationError
from volumetric.compensate.tablesmap import TablesMap
from volumetric.errors import ComponentErrorSpecError


def held_tolerance_um(m: MapContent, asked_um: float, controller: str,
                      increment: float) -> float:
    """The one tolerance a map is held to, µm: the one asked, raised to what the controller
    can carry at all. A Fanuc-style endpoint applies whole increments, so any map it
    receives leaves up to half an increment per linear axis (plus 0.1 µm of tables,
    :func:`~volumetric.compensate.factoredmap.as_sent_floor_um`, 0.97 µm on three axes at
    0.001 mm); asking for less cannot be met and is raised to that floor, by the factored
    builder and here for every kind alike. ``tolerance_um`` in the output is this figure,
    and ``over_tolerance`` compares the error as sent with it."""
    reported = m.report.tolerance_um if m.report is not None else asked_um
    held = max(asked_um, reported)
    if controller == "fanuc":
        outputs = m.outputs
        n_lin = sum(1 for o in outputs if o.upper()[0] in "XYZUVW")
        held = max(held, as_sent_floor_um(n_lin, increment))
    return held


def summary(m: MapContent, out: Path | None) -> dict[str, Any]:
    """The map's kind, size and quality as one JSON-able object (formats.md §3: at least
    ``kind``, ``bytes``, ``worst_error_um`` and ``build_s``)."""
    if isinstance(m, TablesMap):
        return _tables_summary(m, out)
    if isinstance(m, FactoredMap):
        return _factored_summary(m, out)
    r = m.report
    return {
        "machine": m.machine,
        "controller": m.controller,
        "version": m.version,
        "out": str(out) if out is not None else None,
        "grid": [{"axis": g.name, "start": g.start, "step": g.step, "count": g.count}
                 for g in m.grid],
        "outputs": list(m.outputs),
        "increment": m.increment,
        "limits": dict(zip(m.outputs, m.limits, strict=True)),
        "reversal": {o: r_ for o, r_ in zip(m.outputs, m.reversal, strict=True)
                     if r_ is not None},
        # a grid carrying the model's thermal terms is format version 3 (protocol/README.md
        # §6.4): the records the machine applies with its own temperatures
        "format_version": 3 if m.thermal else 1,
        "thermal": _thermal(m.thermal),
        "temperatures": dict(m.temperatures),
        **(r.to_json() if r is not None else {"nodes": m.nodes, "bytes": m.nbytes}),
    }


def _thermal(terms: Any) -> list[dict[str, Any]]:
    """The thermal records a map carries, as ``ednc map --json`` lists them."""
    return [{"effect": t.kind, "axis": t.axis, "sensor": t.sensor} for t in terms]


def _tables_summary(m: TablesMap, out: Path | None) -> dict[str, Any]:
    r = m.report
    return {
        "machine": m.machine.name, "controller": m.controller, "version": m.version,
        "out": str(out) if out is not None else None,
        "tables": [{"name": t.name, "start": t.start, "step": t.step,
                    "entries": int(t.values.size)} for t in m.tables],
        "locations": dict(m.locations),
        "format_version": 2,
        "thermal": _thermal(m.thermal),
        "outputs": list(m.outputs),
        "limits": dict(zip(m.outputs, m.limits, strict=True)),
        "reversal": {o: r_ for o, r_ in zip(m.outputs, m.reversal, strict=True)
                     if r_ is not None},
        "temperatures": dict(m.temperatures),
        **(r.to_json() if r is not None else {}),
    }


def _factored_summary(m: FactoredMap, out: Path | None) -> dict[str, Any]:
    r = m.report
    return {
        "machine": m.machine, "controller": m.controller, "version": m.version,
        "out": str(out) if out is not None else None,
        "terms": len(m.terms), "basis_tables": len(m.bases),
        "term_nodes": {a: g.count for a, g in zip(m.axes, m.grids, strict=True)},
        "format_version": 5,
        "thermal": _thermal(m.thermal),
        "outputs": list(m.outputs), "increment": m.increment,
        "limits": dict(zip(m.outputs, m.limits, strict=True)),
        "reversal": {o: r_ for o, r_ in zip(m.outputs, m.reversal, strict=True)
                     if r_ is not None},
        "temperatures": dict(m.temperatures),
        **(r.to_json() if r is not None else {"nodes": m.entries, "bytes": m.nbytes}),
    }


def _factored_text(m: FactoredMap, out: Path | None, held: float) -> str:
    r = m.report
    assert r is not None
    return "\n".join([
        f"factored map of {m.machine} v{m.version} for {m.controller} (int32 counts of "
        f"{m.increment:g} mm (deg), rotary rounded first): {len(m.terms)} terms over "
        f"{len(m.bases)} basis tables, {r.nodes} values; {r.bytes} bytes"
        + (f" -> {out}" if out is not None else ""),
        f"worst tool-tip error as sent {r.worst_error_um:.3f} µm (unrounded "
        f"{r.worst_interpolation_um:.3f} µm; tolerance {held:g} µm, "
        f"{r.check_points} random check points)",
        f"built in {r.build_s:.2f} s",
    ])


def _text(m: MapContent, out: Path | None, held: float) -> str:
    if isinstance(m, TablesMap):
        return _tables_text(m, out, held)
    if isinstance(m, FactoredMap):
        return _factored_text(m, out, held)
    r = m.report
    assert r is not None
    unit = (f"int32 counts of {m.increment:g} mm (deg)" if m.increment is not None
            else "float32 mm (deg)")
    grid = " x ".join(f"{g.name} {g.count}" for g in m.grid)
    thermal = (f"; thermal records of {', '.join(sorted({t.sensor for t in m.thermal}))} "
               "applied by the machine (format version 3)" if m.thermal else "")
    lines = [
        f"error map of {m.machine} v{m.version} for {m.controller} ({unit}){thermal}",
        f"grid {grid} = {r.nodes} nodes; outputs {' '.join(m.outputs)}; {r.bytes} bytes"
        + (f" -> {out}" if out is not None else ""),
        f"worst interpolation error {r.worst_interpolation_um:.3f} µm (tolerance "
        f"{held:g} µm, {r.check_points} independent check points); as sent "
        f"(quantised, clamped) {r.worst_error_um:.3f} µm",
        f"clamped nodes: {r.clamped_nodes}; built in {r.build_s:.2f} s",
    ]
    return "\n".join(lines)


def _tables_text(m: TablesMap, out: Path | None, held: float) -> str:
    r = m.report
    assert r is not None
    thermal = (f"; thermal terms of {', '.join(m.sensors)} applied by the machine"
               if m.thermal else "")
    return "\n".join([
        f"tables map of {m.machine.name} v{m.version} for {m.controller}: {len(m.tables)} "
        f"component tables, {r.nodes} values, {len(m.locations)} location constants"
        f"{thermal}; {r.bytes} bytes" + (f" -> {out}" if out is not None else ""),
        f"worst tool-tip error as the machine computes it {r.worst_error_um:.3f} µm "
        f"(tolerance {held:g} µm, {r.check_points} random check points)",
        f"built in {r.build_s:.2f} s (of which the check {r.check_s:.2f} s)",
    ])


def register(app: typer.Typer) -> None:
    @app.command("map")
    def map_cmd(
        machine_path: Annotated[Path, typer.Option(
            "--machine", help="Machine description JSON (formats.md §1).")],
        model_path: Annotated[Path, typer.Option(
            "--model", help="Model JSON as written by 'ednc fit'.")],
        out: Annotated[Path, typer.Option(
            "--out", help="Where to write the binary map payload.")] = Path("map.bin"),
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
        tolerance_um: Annotated[float, typer.Option(
            "--tolerance-um", help="Largest tool-tip interpolation error, µm.")] = 0.5,
        controller: Annotated[str | None, typer.Option(
            "--controller", help="fanuc (int32 increments) or siemens (float32 mm); the "
                                 "machine's own by default.")] = None,
        temperature: Annotated[list[str] | None, typer.Option(
            "--temperature", help="SENSOR=°C for the model's thermal terms; may "
                                  "repeat.")] = None,
        weights: Annotated[str | None, typer.Option(
            "--weights", help="Solver weights, as for 'ednc compensate'.")] = None,
        increment: Annotated[float, typer.Option(
            "--increment", help="Fanuc least input increment, mm per count.")
        ] = DEFAULT_INCREMENT,
        limit_mm: Annotated[float, typer.Option(
            "--limit-mm", help="Clamp linear corrections to ±this, mm.")] = DEFAULT_LIMIT_MM,
        limit_deg: Annotated[float, typer.Option(
            "--limit-deg", help="Clamp rotary corrections to ±this, degrees.")
        ] = DEFAULT_LIMIT_DEG,
        version: Annotated[int, typer.Option("--version", help="Map version, >= 1.")] = 1,
        kind: Annotated[str, typer.Option(
            "--kind", help="auto (the smallest the controller evaluates that meets the "
                           "tolerance), tables (component tables the machine evaluates: "
                           "Siemens-style endpoints), factored (sums of products of 1-D "
                           "tables, rotary rounded first: Fanuc-style ladders) or grid "
                           "(corrections on a grid).")
        ] = "auto",
        allow_over_tolerance: Annotated[bool, typer.Option(
            "--allow-over-tolerance",
            help="Write the map even when its error as sent (quantisation included) "
                 "exceeds the tolerance; otherwise that is an error (exit 2). With --json "
                 "the map is written and the JSON says over_tolerance (a warning on "
                 "stderr).")] = False,
    ) -> None:
        """Build the error map the machine's controller evaluates (by default the smallest
        kind that meets the tolerance: --kind) and write it in the binary map format the
        machines receive."""
        float_option(tolerance_um, "--tolerance-um", 0.0, 1000.0, lo_open=True, unit=" µm")
        float_option(increment, "--increment", 0.0, 1.0, lo_open=True, unit=" mm per count")
        float_option(limit_mm, "--limit-mm", 0.0, 100.0, lo_open=True, unit=" mm")
        float_option(limit_deg, "--limit-deg", 0.0, 360.0, lo_open=True, unit="°")
        int_option(version, "--version", 1, 2**31 - 1)
        check_output(out, "--out")
        machine = read_machine(machine_path)
        model = read_model(model_path, machine)
        if controller is not None and controller.lower() not in ("fanuc", "siemens"):
            raise UserError(f"--controller {controller!r}: expected fanuc or siemens")
        ctrl = (controller or machine.controller).lower()
        temps = parse_temperatures(temperature or [])
        unknown = sorted(set(temps) - set(model.sensors))
        if unknown:
            raise UserError(f"--temperature {', '.join(unknown)}: not a sensor of the model "
                            f"(it uses {', '.join(model.sensors) or 'none'})")
        missing = [s for s in model.sensors if s not in temps]
        if missing:
            raise UserError(f"{model_path}: the model needs the temperatures of "
                            f"{', '.join(missing)}; give them with --temperature NAME=°C")
        if kind not in ("auto", "tables", "factored", "grid"):
            raise UserError(f"--kind {kind!r}: expected auto, tables, factored or grid")
        options: dict[str, Any] = {"increment": increment} if ctrl == "fanuc" else {}
        try:
            m = build_for(
                machine, model, temps, kind=kind,
                tolerance_um=tolerance_um,
                controller="fanuc" if ctrl == "fanuc" else "siemens",
                limit_mm=limit_mm, limit_deg=limit_deg,
                weights=parse_weights(weights, machine), version=version,
                # a factored map missing the tolerance is built and judged below, as
                # every kind's is (the builder would otherwise refuse it: exit 2)
                allow_over_tolerance=True, **options,
            )
            payload = encode(m)
        except (MapBuildError, CompensationError, ComponentErrorSpecError) as exc:
            raise UserError(str(exc)) from None
        r = m.report
        held = held_tolerance_um(m, tolerance_um, ctrl, increment)
        over = r is not None and r.worst_error_um > held
        # --json is the interface other tools call (formats.md §3, stable): there the map is
        # written and the JSON says over_tolerance; a person at the terminal is stopped
        if over and not allow_over_tolerance and not as_json:
            assert r is not None
            raise UserError(f"the {kind_of(m)} map leaves {r.worst_error_um:.3f} µm as sent, "
                            f"over its tolerance of {held:g} µm; ask for a larger "
                            f"tolerance, or write it anyway with --allow-over-tolerance")
        if over and r is not None:
            typer.echo(f"warning: the {kind_of(m)} map leaves {r.worst_error_um:.3f} µm as "
                       f"sent, over its tolerance of {held:g} µm", err=True)
        if held > tolerance_um and not as_json:
            typer.echo(f"note: the tolerance is {held:g} µm, not the {tolerance_um:g} µm asked "
                       f"for: whole increments of {increment:g} mm cannot carry less "
                       "(the achievable floor)", err=True)
        try:
            out.write_bytes(payload)
        except OSError as exc:
            raise UserError(f"{out}: cannot write ({exc.strerror or exc})") from None
        if as_json:
            typer.echo(dump_json({**summary(m, out), "tolerance_um": held,
                                  "tolerance_asked_um": tolerance_um,
                                  "over_tolerance": over}))
        else:
            typer.echo(_text(m, out, held))
