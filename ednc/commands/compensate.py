"""``ednc compensate``: actuator corrections and residual tool-tip errors at given points.

Also holds the input readers ``ednc map`` shares (model file, temperatures, weights).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from numpy.typing import NDArray

from ednc.cli import UserError
from ednc.inputs import dump_json, parse_number, read_machine, read_model, warn
from volumetric.compensate.solver import Compensation, CompensationError, Weights, compensate
from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import GeometricErrors
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel
from volumetric.plausible.temperatures import temperature_problem, temperature_warning

F64 = NDArray[np.float64]


def parse_temperatures(items: Sequence[str]) -> dict[str, float]:
    """``["T_x_C=21.3", ...]`` → ``{"T_x_C": 21.3}``, each within the temperature limits
    every entry point shares (:mod:`volumetric.plausible.temperatures`: 293 is refused as
    kelvin, 72 warned about as °F)."""
    out: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UserError(f"--temperature {item!r}: expected SENSOR=°C such as T_x_C=21.3")
        try:
            t = float(value)
        except ValueError:
            raise UserError(f"--temperature {item!r}: {value!r} is not a number") from None
        if not math.isfinite(t):
            raise UserError(f"--temperature {item!r}: the temperature must be finite")
        problem = temperature_problem(t, f"--temperature {name}")
        if problem is not None:  # the limits every entry point shares
            raise UserError(problem)
        hot = temperature_warning([t], f"--temperature {name}")
        if hot is not None:
            warn(hot)
        if name in out:
            raise UserError(f"--temperature: {name} given twice")
        out[name] = t
    return out


def parse_weights(text: str | None, machine: Machine) -> Weights | None:
    if text is None:
        return None
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise UserError(f"--weights {text!r}: expected comma-separated numbers") from None
    try:
        return Weights.parse(machine, values)
    except CompensationError as exc:
        raise UserError(f"--weights: {exc}") from None


def geometry(model: MachineModel, temperatures: dict[str, float],
             model_path: Path) -> GeometricErrors:
    unknown = sorted(set(temperatures) - set(model.sensors))
    if unknown:  # a typo would otherwise leave the term at its reference silently
        uses = ", ".join(model.sensors) or "no temperatures"
        raise UserError(f"--temperature {', '.join(unknown)}: the model does not use "
                        f"{'this sensor' if len(unknown) == 1 else 'these sensors'} "
                        f"(it uses {uses})")
    try:
        return model.geometry_at(temperatures)
    except ComponentErrorSpecError as exc:
        raise UserError(f"{model_path}: {exc}") from None
    except ValueError as exc:
        raise UserError(f"{model_path}: {exc}; give them with --temperature NAME=°C") from None


def check_travel(q: F64, machine: Machine) -> None:
    """Refuse points outside the travel: the model's polynomials are fitted over it, and
    outside they extrapolate (hundreds of µm a few metres out) as if that were valid."""
    lo, hi = machine.travel_lo, machine.travel_hi
    span = np.maximum(hi - lo, 1.0)
    outside = (q < lo - 1e-9 * span) | (q > hi + 1e-9 * span)
    if not outside.any():
        return
    i, k = (int(v) for v in np.argwhere(outside)[0])
    axis = machine.axes[k]
    raise UserError(
        f"point {i + 1}: {axis.name} = {q[i, k]:g} {_unit(machine, k)} is outside its travel "
        f"[{lo[k]:g}, {hi[k]:g}] ({int(outside.any(axis=1).sum())} of {len(q)} points are); "
        "the model is not valid there (--extrapolate to compute anyway)")


def _unit(machine: Machine, i: int) -> str:
    return "deg" if machine.axes[i].kind == "rotary" else "mm"


def parse_point(text: str, machine: Machine) -> F64:
    """``"100,50,-20"`` (machine axis order) or ``"x=100,y=50,z=-20"``, one row."""
    keys = [a.key for a in machine.axes]
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if any("=" in p for p in parts):
        row = {}
        for p in parts:
            k, sep, v = p.partition("=")
            k = k.strip().lower()
            if not sep or k not in keys:
                raise UserError(f"--point {text!r}: unknown axis {k!r}; machine "
                                f"{machine.name!r} has axes {' '.join(keys)}")
            if k in row:
                raise UserError(f"--point {text!r}: axis {k} given twice")
            row[k] = parse_number(v, f"--point {text!r}: axis {k}")
        missing = [k for k in keys if k not in row]
        if missing:
            raise UserError(f"--point {text!r}: no value for axes {' '.join(missing)}")
        return np.array([row[k] for k in keys])
    if len(parts) != len(keys):
        raise UserError(f"--point {text!r}: expected {len(keys)} values for axes "
                        f"{' '.join(keys)}, got {len(parts)}")
    return np.array([parse_number(v, f"--point {text!r}: value {i + 1}")
                     for i, v in enumerate(parts)])


def read_points(path: Path, machine: Machine) -> F64:
    """A CSV with a header naming the axes (``x`` or ``x_mm``, ``c`` or ``c_deg``, ``z1``
    or ``z1_mm``); other columns are ignored."""
    try:
        with path.open(newline="") as fh:
            rows = list(csv.reader(fh))
    except OSError as exc:
        raise UserError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise UserError(f"{path}: not a text file") from None
    if not rows:
        raise UserError(f"{path}: empty; expected a header naming the axes")
    header = [h.strip().lower() for h in rows[0]]
    cols = []
    for i, a in enumerate(machine.axes):
        names = (a.key, f"{a.key}_{_unit(machine, i)}")
        found = [j for j, h in enumerate(header) if h in names]
        if not found:
            raise UserError(f"{path}: no column for axis {a.key} (expected {names[0]!r} or "
                            f"{names[1]!r}); the header is {','.join(header)}")
        cols.append(found[0])
    out = []
    for line, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        if len(row) < len(header):
            raise UserError(f"{path}: line {line} has {len(row)} cells, the header "
                            f"{len(header)}")
        out.append([parse_number(row[j], f"{path}: line {line}, column {header[j]}") for j in cols])
    if not out:
        raise UserError(f"{path}: no points after the header")
    return np.array(out)


def approach_shift(machine: Machine, model: MachineModel, approach: str) -> F64:
    """What each axis's correction adds for the approach direction, mm (or degrees), (A,).

    A backlash B lets the axis lag B/2 behind its motion, around the position the rigid
    model describes (its mean over both approaches): the correction after a positive
    approach is B/2 more, after a negative one B/2 less (how every map kind builds it, and
    what ``ednc lookup`` applies on the positive approach)."""
    sign = 1.0 if approach == "+" else -1.0
    rev = {k.lower(): v for k, v in model.reversal_um().items()}
    return np.array([sign * 0.5 * rev.get(a.key, 0.0) * 1e-3 for a in machine.axes])


def _result_json(machine: Machine, c: Compensation, shift: F64,
                 approach: str, backlash: dict[str, float]) -> dict[str, Any]:
    keys = [a.key for a in machine.axes]
    points = []
    for n in range(c.q.shape[0]):
        item: dict[str, Any] = {
            "q": dict(zip(keys, c.q[n].tolist(), strict=True)),
            "correction": dict(zip(keys, (c.dq[n] + shift).tolist(), strict=True)),
            "error_um": {b: c.error_um[k, n].tolist() for k, b in enumerate(c.branches)},
            "residual_um": {b: c.residual_um[k, n].tolist()
                            for k, b in enumerate(c.branches)},
        }
        if c.residual_urad is not None and c.error_urad is not None:
            item["error_urad"] = {b: c.error_urad[k, n].tolist()
                                  for k, b in enumerate(c.branches)}
            item["residual_urad"] = {b: c.residual_urad[k, n].tolist()
                                     for k, b in enumerate(c.branches)}
        points.append(item)
    return {
        "machine": machine.name,
        "axes": keys,
        "units": {k: _unit(machine, i) for i, k in enumerate(keys)},
        "approach": approach,
        "backlash_um": backlash,
        "spindles": list(c.branches),
        "points": points,
        "max_error_um": {b: v.tolist() for b, v in zip(c.branches, c.max_error_um(),
                                                         strict=True)},
        "max_residual_um": {b: v.tolist() for b, v in zip(c.branches, c.max_residual_um(),
                                                            strict=True)},
        "converged": c.converged,
        "iterations": c.iterations,
    }


def _result_text(machine: Machine, c: Compensation, shift: F64,
                 approach: str, backlash: dict[str, float]) -> str:
    keys = [a.key for a in machine.axes]
    side = "positive" if approach == "+" else "negative"
    lash = ""
    if backlash:
        lash = "; backlash " + ", ".join(
            f"{k} {v:g} µm ({'+' if approach == '+' else '-'}{v / 2:g} µm in d{k})"
            for k, v in backlash.items()) + ", not in the tool-tip errors"
    lines = [f"{machine.name}: corrections (mm, degrees on rotary axes) for the {side} "
             f"approach (--approach){lash}, and tool-tip errors (µm, x y z) before -> after"]
    for n in range(c.q.shape[0]):
        where = " ".join(f"{k}={v:g}" for k, v in zip(keys, c.q[n], strict=True))
        corr = "  ".join(f"d{k} {v:+.6f}" for k, v in zip(keys, c.dq[n] + shift,
                                                           strict=True))
        lines.append(f"point {n + 1}: {where}")
        lines.append(f"  {corr}")
        for k, b in enumerate(c.branches):
            before = " ".join(f"{v:+8.3f}" for v in c.error_um[k, n])
            after = " ".join(f"{v:+8.3f}" for v in c.residual_um[k, n])
            lines.append(f"  {b:<6} {before}  ->  {after}")
    lines.append("max |error| per spindle (µm, x y z) before -> after:")
    for b, before, after in zip(c.branches, c.max_error_um(), c.max_residual_um(), strict=True):
        lines.append(f"  {b:<6} {' '.join(f'{v:8.3f}' for v in before)}  ->  "
                     f"{' '.join(f'{v:8.3f}' for v in after)}")
    if not c.converged:
        lines.append(f"warning: {c.message}")
    return "\n".join(lines)


def register(app: typer.Typer) -> None:
    @app.command("compensate")
    def compensate_cmd(
        machine_path: Annotated[Path, typer.Option(
            "--machine", help="Machine description JSON (formats.md §1).")],
        model_path: Annotated[Path, typer.Option(
            "--model", help="Model JSON as written by 'ednc fit'.")],
        points: Annotated[Path | None, typer.Option(
            "--points", help="CSV of points, a header naming the axes (x or x_mm, ...).")
        ] = None,
        point: Annotated[list[str] | None, typer.Option(
            "--point", help="One point: 'x,y,z' in axis order or 'x=..,y=..,z=..'; "
                            "may repeat.")] = None,
        weights: Annotated[str | None, typer.Option(
            "--weights", help="x,y,z weights per tool tip (3 per spindle), or x,y,z,a,b,c "
                              "(6 per spindle).")] = None,
        temperature: Annotated[list[str] | None, typer.Option(
            "--temperature", help="SENSOR=°C for the model's thermal terms; may "
                                  "repeat.")] = None,
        extrapolate: Annotated[bool, typer.Option(
            "--extrapolate", help="Allow points outside the travel (the model extrapolates "
                                  "there; refused by default).")] = False,
        approach: Annotated[str, typer.Option(
            "--approach", help="+ or -: the direction each axis last moved; a model's "
                               "backlash B adds +B/2 (or -B/2) to that axis's correction, "
                               "as the maps do.")] = "+",
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    ) -> None:
        """Corrections per axis that minimise the weighted tool-tip errors, and what is left
        of them per spindle."""
        if approach not in ("+", "-"):
            raise UserError(f"--approach {approach!r}: expected + (positive) or - (negative)")
        machine = read_machine(machine_path)
        model = read_model(model_path, machine)
        if (points is None) == (not point):
            raise UserError("give either --points P.csv or --point (one or more)")
        q = read_points(points, machine) if points is not None else np.vstack(
            [parse_point(p, machine) for p in point or []])
        w = parse_weights(weights, machine)
        geo = geometry(model, parse_temperatures(temperature or []), model_path)
        if not extrapolate:  # after the options: their mistakes are named first
            check_travel(q, machine)
        try:
            result = compensate(machine, geo, q, weights=w)
        except (CompensationError, ComponentErrorSpecError) as exc:
            raise UserError(str(exc)) from None
        shift = approach_shift(machine, model, approach)
        backlash = {k.lower(): float(v) for k, v in model.reversal_um().items()}
        if as_json:
            typer.echo(dump_json(_result_json(machine, result, shift, approach, backlash)))
        else:
            typer.echo(_result_text(machine, result, shift, approach, backlash))
