"""``ednc map``: build a machine's error map and write its binary payload."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer

from ednc.cli import UserError
from ednc.commands.compensate import (
    parse_temperatures,
    parse_weights,
)
from ednc.inputs import read_machine, read_model
from protocol.mapformat import encode_map
from server.mapcodec import grid_to_payload
from volumetric.compensate.gridmap import (
    DEFAULT_INCREMENT,
    DEFAULT_LIMIT_DEG,
    DEFAULT_LIMIT_MM,
    ErrorMap,
    MapBuildError,
    build_map,
)
from volumetric.compensate.solver import CompensationError
from volumetric.errors import ComponentErrorSpecError


def summary(m: ErrorMap, out: Path | None) -> dict[str, Any]:
    """The map's size and quality as one JSON-able object."""
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
        "temperatures": dict(m.temperatures),
        **(r.to_json() if r is not None else {"nodes": m.nodes, "bytes": m.nbytes}),
    }


def _text(m: ErrorMap, out: Path | None) -> str:
    r = m.report
    assert r is not None
    unit = (f"int32 counts of {m.increment:g} mm (deg)" if m.increment is not None
            else "float32 mm (deg)")
    grid = " x ".join(f"{g.name} {g.count}" for g in m.grid)
    lines = [
        f"error map of {m.machine} v{m.version} for {m.controller} ({unit})",
        f"grid {grid} = {r.nodes} nodes; outputs {' '.join(m.outputs)}; {r.bytes} bytes"
        + (f" -> {out}" if out is not None else ""),
        f"worst interpolation error {r.worst_interpolation_um:.3f} µm (tolerance "
        f"{r.tolerance_um:g} µm, {r.check_points} independent check points); as sent "
        f"(quantised, clamped) {r.worst_error_um:.3f} µm",
        f"clamped nodes: {r.clamped_nodes}; built in {r.build_s:.2f} s",
    ]
    return "\n".join(lines)


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
    ) -> None:
        """Build the error map (corrections on a grid chosen to meet the tolerance) and
        write it in the binary map format the machines receive."""
        machine = read_machine(machine_path)
        model = read_model(model_path, machine)
        if controller is not None and controller.lower() not in ("fanuc", "siemens"):
            raise UserError(f"--controller {controller!r}: expected fanuc or siemens")
        ctrl = (controller or machine.controller).lower()
        temps = parse_temperatures(temperature or [])
        missing = [s for s in model.sensors if s not in temps]
        if missing:
            raise UserError(f"{model_path}: the model needs the temperatures of "
                            f"{', '.join(missing)}; give them with --temperature NAME=°C")
        try:
            m = build_map(
                machine, model, temps,
                tolerance_um=tolerance_um,
                controller="fanuc" if ctrl == "fanuc" else "siemens",
                increment=increment, limit_mm=limit_mm, limit_deg=limit_deg,
                weights=parse_weights(weights, machine), version=version,
            )
            payload = encode_map(grid_to_payload(m))
        except (MapBuildError, CompensationError, ComponentErrorSpecError) as exc:
            raise UserError(str(exc)) from None
        try:
            out.write_bytes(payload)
        except OSError as exc:
            raise UserError(f"{out}: cannot write ({exc.strerror or exc})") from None
        if as_json:
            typer.echo(json.dumps(summary(m, out)))
        else:
            typer.echo(_text(m, out))
