"""``ednc lookup``: the corrections a machine endpoint applies from a map file.

Computed by the simulated machines' own endpoint code (:mod:`machine_sim.lookup` for grid
and factored maps, :mod:`machine_sim.chaineval` for tables maps), the implementation
written from the protocol README, not by the center's solver: comparing the two is what
this command is for
(``../shared/spec/formats.md`` section 3). Positive approach by default; ``--negative``
(axes, or ``all``) or a ``dir_<axis>`` column of the points (-1: the axis last moved
negative) gives the corrections while those axes' direction is negative: their reversal
values added before the final clamp (protocol/README.md §6). A tables map's corrections
are clamped to its limits and rounded to its encoding, as the machine applies them.

A sensor the map's thermal records name but no ``--temperature`` gives is one the machine
never read: its records add 0 (protocol/README.md §6, "Readings"), and stderr says so.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from numpy.typing import NDArray

from ednc.cli import UserError
from ednc.commands.compensate import parse_temperatures
from ednc.inputs import dump_json, parse_number
from machine_sim.chaineval import StructureError, sensor_key
from machine_sim.lookup import FactoredLadder, GridLadder, GridMap, TablesMap
from protocol.codes import MapEncoding
from protocol.mapfactored import FactoredPayload
from protocol.mapformat import ErrorMapPayload, MapFormatError
from protocol.maptables import TablesPayload, decode_payload

Payload = ErrorMapPayload | TablesPayload | FactoredPayload

F64 = NDArray[np.float64]


def read_map(path: Path) -> Payload:
    """A map payload file (protocol/README.md section 6), any kind."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise UserError(f"{path}: cannot read ({exc.strerror or exc})") from None
    try:
        return decode_payload(data)
    except MapFormatError as exc:
        raise UserError(f"{path}: not an EDNC map payload: {exc}") from None


def map_axes(p: Payload) -> tuple[list[str], list[str]]:
    """The axes of the output (upper case, in order) and the ones whose position the
    evaluation needs. Tables: the chain axes, all needed; factored: its axes, all needed;
    grid: the grid axes (needed) then output axes not in the grid."""
    if isinstance(p, TablesPayload):
        names = list(p.axis_names)
        return names, names
    if isinstance(p, FactoredPayload):
        names = [a.name.upper() for a in p.axes]
        return names, names
    grid = [g.name.upper() for g in p.grid]
    rest = [o.name.upper() for o in p.outputs if o.name.upper() not in grid]
    # a thermal expansion record (format version 3) needs its axis's position too
    needed = GridMap.from_payload(p).inputs
    return grid + rest, list(needed)


def _unit(axis: str) -> str:
    return "deg" if axis[0] in "ABC" else "mm"


def read_points(path: Path, axes: list[str], needed: list[str]
                ) -> tuple[F64, list[str], NDArray[np.bool_]]:
    """Points (N, len(axes)) from a CSV whose header names the axes (``x`` or ``x_mm``,
    ``c`` or ``c_deg``); an axis the evaluation does not need may be missing (0). A
    ``dir_<axis>`` column gives the axis's direction at each point (-1 negative, 0 or 1
    positive). Returns the array, the axes the file gave, and (N, len(axes)) True where
    an axis's direction is negative."""
    try:
        with path.open(newline="") as fh:
            rows = list(csv.reader(fh))
    except OSError as exc:
        raise UserError(f"{path}: cannot read ({exc.strerror or exc})") from None
    except (UnicodeDecodeError, csv.Error) as exc:
        raise UserError(f"{path}: not a CSV text file ({exc})") from None
    if not rows:
        raise UserError(f"{path}: empty; expected a header naming the axes")
    header = [h.strip().lower() for h in rows[0]]
    cols: dict[str, int] = {}
    for a in axes:
        key = a.lower()
        found = [j for j, h in enumerate(header) if h in (key, f"{key}_{_unit(a)}")]
        if found:
            cols[a] = found[0]
        elif a in needed:
            raise UserError(f"{path}: no column for axis {key} (expected {key!r} or "
                            f"{key + '_' + _unit(a)!r}); the header is {','.join(header)}")
    dirs = {a: header.index(f"dir_{a.lower()}") for a in axes if f"dir_{a.lower()}" in header}
    out, neg = [], []
    for line, row in enumerate(rows[1:], start=2):
        if not any(c.strip() for c in row):
            continue
        if len(row) < len(header):
            raise UserError(f"{path}: line {line} has {len(row)} cells, the header "
                            f"{len(header)}")
        out.append([parse_number(row[cols[a]], f"{path}: line {line}, column {header[cols[a]]}")
                    if a in cols else 0.0 for a in axes])
        flags = []
        for a in axes:
            if a not in dirs:
                flags.append(False)
                continue
            d = parse_number(row[dirs[a]], f"{path}: line {line}, column dir_{a.lower()}")
            if d not in (-1.0, 0.0, 1.0):
                raise UserError(f"{path}: line {line}, column dir_{a.lower()}: {d:g}; "
                                "expected -1 (negative), 0 or 1 (positive)")
            flags.append(d < 0)
        neg.append(flags)
    if not out:
        raise UserError(f"{path}: no points after the header")
    return np.array(out), [a for a in axes if a in cols], np.array(neg, dtype=bool)


def parse_negative(values: list[str], axes: list[str]) -> NDArray[np.bool_]:
    """``--negative`` (axis names, comma-separated or repeated, or ``all``) as a (len(axes),)
    mask of the axes whose direction is negative."""
    names = {v.strip().upper() for item in values for v in item.split(",") if v.strip()}
    if "ALL" in names:
        return np.ones(len(axes), dtype=bool)
    unknown = sorted(names - set(axes))
    if unknown:
        raise UserError(f"--negative {', '.join(n.lower() for n in unknown)}: not an axis of "
                        f"the map (it has {', '.join(a.lower() for a in axes)})")
    return np.array([a in names for a in axes], dtype=bool)


def map_travel(p: Payload, axes: list[str]) -> dict[str, tuple[float, float]]:
    """Per axis (upper case) the range the map covers, mm or degrees: a grid's or a
    factored map's nodes, a tables map's chain travel. Outside it the endpoint would
    extrapolate (or clamp), as a model outside its travel: refused as ``ednc compensate``
    refuses points outside the description's travel."""
    if isinstance(p, TablesPayload):
        return {a.name.upper(): (float(a.travel[0]), float(a.travel[1])) for a in p.axes}
    if isinstance(p, FactoredPayload):
        return {a.name.upper(): _factored_range(p, a) for a in p.axes}
    return {g.name.upper(): (float(g.start), float(g.start + g.step * (g.count - 1)))
            for g in p.grid if g.name.upper() in axes}


def _factored_range(p: FactoredPayload, a: Any) -> tuple[float, float]:
    """A factored axis's node range, mm or degrees: nodes at ``start`` by ``step`` (or, in
    the fixed-point layout, ``start`` counts by ``2^shift`` counts of the increment)."""
    if hasattr(a, "shift"):
        inc = float(p.increment_mm)
        lo = float(a.start) * inc
        return lo, lo + float(2 ** int(a.shift)) * inc * (int(a.count) - 1)
    return float(a.start), float(a.start + a.step * (a.count - 1))


def check_travel(q: F64, axes: list[str], given: list[str],
                 travel: dict[str, tuple[float, float]]) -> None:
    """Refuse points outside the map's range, in the words ``ednc compensate`` uses."""
    for k, a in enumerate(axes):
        if a not in travel or a not in given:
            continue
        lo, hi = travel[a]
        span = max(hi - lo, 1.0)
        outside = (q[:, k] < lo - 1e-9 * span) | (q[:, k] > hi + 1e-9 * span)
        if outside.any():
            i = int(np.flatnonzero(outside)[0])
            raise UserError(
                f"point {i + 1}: {a} = {q[i, k]:g} {_unit(a)} is outside its travel "
                f"[{lo:g}, {hi:g}] ({int(outside.sum())} of {len(q)} points are); the map "
                "is not valid there (--extrapolate to compute anyway)")


def check_temperatures(p: Payload, temperatures: dict[str, float]) -> None:
    """Refuse a temperature the map does not use, as ``ednc compensate`` refuses one the
    model does not use: a typo would otherwise leave a term at its reference silently."""
    uses = sorted({r.sensor for r in p.thermal})
    keys = {sensor_key(s) for s in uses}
    unknown = sorted(k for k in temperatures if sensor_key(k) not in keys)
    if unknown:
        said = ", ".join(uses) or "no temperatures: it has no thermal records"
        raise UserError(f"--temperature {', '.join(unknown)}: the map does not use "
                        f"{'this sensor' if len(unknown) == 1 else 'these sensors'} "
                        f"(it uses {said})")


def unread_sensors(p: Payload, temperatures: dict[str, float]) -> list[str]:
    """The sensors the map's thermal records name that no temperature was given for: the
    machine never read them, so their records add 0 (protocol/README.md §6)."""
    have = {sensor_key(k) for k in temperatures}
    return sorted({r.sensor for r in p.thermal if sensor_key(r.sensor) not in have})


def evaluate(p: Payload, q: F64, axes: list[str], temperatures: dict[str, float],
             negative: NDArray[np.bool_] | None = None) -> F64:
    """Corrections (N, len(axes)), mm or degrees, that the endpoint applies at q, with the
    axes ``negative`` (N, len(axes)) approaching negatively (None: a positive approach)."""
    out = np.zeros(q.shape)
    if isinstance(p, FactoredPayload):
        # the ladder's own evaluation: rotary rounded first, whole increments, the
        # reversal before the final clamp
        lad = FactoredLadder(p, temperatures)
        return lad.lookup(q) if negative is None else lad.lookup_directed(q, negative)
    outputs = [o.name.upper() for o in p.outputs]
    out_neg = (None if negative is None
               else negative[:, [axes.index(name) for name in outputs]])
    if isinstance(p, TablesPayload):
        tm = TablesMap.from_payload(p, temperatures)
        try:
            values = (tm.lookup(q) if out_neg is None else
                      tm.batch.applied(None, np.atleast_2d(q), np.where(out_neg, -1, 1)))
        except StructureError as exc:
            raise UserError(str(exc)) from None
    elif p.encoding is MapEncoding.INT32_INCREMENTS:
        # the Fanuc-style ladder's integer evaluation (protocol/README.md §6.1, §6.4):
        # whole increments, halves up, as machine_sim/fanuc.py writes them to the EMZPS
        try:
            ladder = GridLadder.from_payload(p, temperatures)
        except ValueError as exc:
            raise UserError(f"the int32 grid cannot be evaluated in counts: {exc}") from None
        counts = ladder.counts(q[:, [axes.index(a) for a in ladder.inputs]], out_neg)
        values = counts.astype(np.float64) / ladder.per_unit
    else:
        g = GridMap.from_payload(p, temperatures)
        values = g.lookup(q[:, [axes.index(a) for a in g.inputs]])
        if out_neg is not None:
            values = values + np.where(out_neg, g.reversal, 0.0)
    for k, name in enumerate(outputs):
        out[:, axes.index(name)] = values[:, k]
    return out


def register(app: typer.Typer) -> None:
    @app.command("lookup")
    def lookup_cmd(
        map_path: Annotated[Path, typer.Option(
            "--map", help="Map payload file (grid, tables or factored), as 'ednc map --out' "
                          "writes.")],
        points: Annotated[Path, typer.Option(
            "--points", help="CSV of points, a header naming the axes (x or x_mm, ...).")],
        temperature: Annotated[list[str] | None, typer.Option(
            "--temperature", help="SENSOR=°C for the map's thermal records; may repeat. A "
                                  "sensor not given is one the machine never read: its "
                                  "records add 0.")] = None,
        negative: Annotated[list[str] | None, typer.Option(
            "--negative", help="Axes whose direction is negative (their reversal values "
                               "are added), comma-separated or repeated, or 'all'; a "
                               "dir_<axis> column of the points (-1) does it per "
                               "point.")] = None,
        extrapolate: Annotated[bool, typer.Option(
            "--extrapolate", help="Allow points outside the map's travel (refused by "
                                  "default, as by 'ednc compensate').")] = False,
        as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
    ) -> None:
        """Corrections the machine endpoint applies at each point (positive approach unless
        --negative or a dir_<axis> column says otherwise), computed by the endpoint's own
        implementation."""
        p = read_map(map_path)
        axes, needed = map_axes(p)
        q, given, neg = read_points(points, axes, needed)
        neg = neg | parse_negative(negative or [], axes)[None, :]
        directed = bool(neg.any())
        temperatures = parse_temperatures(temperature or [])
        check_temperatures(p, temperatures)
        if not extrapolate:
            check_travel(q, axes, given, map_travel(p, axes))
        unread = unread_sensors(p, temperatures)
        if unread:
            them, their = ("it", "its") if len(unread) == 1 else ("them", "their")
            typer.echo(f"note: no temperature of {', '.join(unread)}: the machine never read "
                       f"{them}, so {their} thermal records add 0 (--temperature "
                       "SENSOR=°C to give one)", err=True)
        corr = evaluate(p, q, axes, temperatures, neg if directed else None)
        keys = [a.lower() for a in axes]
        if as_json:
            body: dict[str, Any] = {
                "machine": p.machine, "version": p.version,
                "kind": ("factored" if isinstance(p, FactoredPayload) else
                         "tables" if isinstance(p, TablesPayload) else "grid"),
                "axes": keys, "units": {k: _unit(a) for k, a in zip(keys, axes, strict=True)},
                "unread_sensors": unread,
                "points": [{"q": {a.lower(): float(q[n, axes.index(a)]) for a in given},
                            "correction": dict(zip(keys, corr[n].tolist(), strict=True)),
                            **({"negative": [k for k, f in zip(keys, neg[n], strict=True)
                                             if f]} if directed else {})}
                           for n in range(q.shape[0])],
            }
            typer.echo(dump_json(body))
            return
        approach = ("direction per point" if directed else "positive approach")
        typer.echo(f"{p.machine} map version {p.version}: corrections (mm, degrees on rotary "
                   f"axes), {approach}")
        for n in range(q.shape[0]):
            where = " ".join(f"{a.lower()}={q[n, axes.index(a)]:g}" for a in given)
            if directed and neg[n].any():
                where += " (negative: " + ",".join(k for k, f in zip(keys, neg[n], strict=True)
                                                    if f) + ")"
            corr_txt = "  ".join(f"d{k} {v:+.6f}" for k, v in zip(keys, corr[n], strict=True))
            typer.echo(f"point {n + 1}: {where}\n  {corr_txt}")
