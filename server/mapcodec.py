"""Maps between the numeric core's content and the wire: one place that knows both.

:mod:`volumetric.compensate` builds map *content* (numbers in mm, degrees, µm) without
knowing the wire; :mod:`protocol` knows the bytes without knowing the numbers' meaning.
This module converts one into the other, and picks the map kind for a machine
(:func:`build_for`): the smallest payload that meets the tolerance among the kinds the
machine evaluates, preferring a kind that carries the model's thermal terms (so a
temperature change never needs a new map). Tables maps always carry them; grid maps do for
machines that declared ``MapEncoding.THERMAL`` (format version 3: the ladder applies them
by multiply-add), and :func:`carries_thermal` tells either from a map or its payload.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from protocol.codes import MapEncoding
from protocol.mapfactored import (
    FACTORED_FORMAT_VERSION,
    BasisTable,
    FactoredAxis,
    FactoredPayload,
    FactoredThermal,
    TermTable,
    decode_factored,
    encode_factored,
    thermal_fixed,
)
from protocol.mapformat import (
    GRID_THERMAL_FORMAT_VERSION,
    ErrorMapPayload,
    GridAxis,
    OutputAxis,
    encode_map,
)
from protocol.maptables import (
    TABLES_FORMAT_VERSION,
    ChainAxis,
    ComponentTable,
    Spindle,
    TablesPayload,
    ThermalRecord,
    encode_payload,
)
from volumetric.compensate.factoredmap import (
    AxisGrid,
    FactoredMap,
    Table1D,
    Term,
    build_factored_map,
)
from volumetric.compensate.gridmap import ErrorMap, GridDim, build_map
from volumetric.compensate.maps import (
    DEFAULT_INCREMENT,
    MAX_MAP_BYTES,
    MapBuildError,
    MapKind,
    MapTooLargeError,
)
from volumetric.compensate.solver import Weights
from volumetric.compensate.tablesmap import ComponentSamples, TablesMap, build_tables_map
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

MapContent = ErrorMap | TablesMap | FactoredMap


def grid_to_payload(m: ErrorMap) -> ErrorMapPayload:
    """The wire payload of a grid map (format version 1, or 3 when it carries thermal
    terms).

    Raises
    ------
    MapBuildError
        When a value does not fit the encoding (int32 overflow) or a field is invalid.
    """
    if m.increment is not None:
        counts = np.rint(m.values / m.increment)
        if np.abs(counts).max(initial=0) >= 2**31:
            raise MapBuildError("map values overflow int32 counts")
        raw = counts.astype("<i4").tobytes()
        rev: list[float | None] = [None if r is None else float(round(r / m.increment))
                                   for r in m.reversal]
        encoding = MapEncoding.INT32_INCREMENTS
    else:
        raw = m.values.astype("<f4").tobytes()
        rev = [None if r is None else float(r) for r in m.reversal]
        encoding = MapEncoding.FLOAT32_MM
    try:
        return ErrorMapPayload(
            machine=m.machine, version=m.version, encoding=encoding,
            grid=tuple(GridAxis(g.name, float(g.start), float(g.step), g.count)
                       for g in m.grid),
            outputs=tuple(OutputAxis(n, r) for n, r in zip(m.outputs, rev, strict=True)),
            values=raw,
            increment_mm=float(m.increment) if m.increment is not None else 0.0,
            valid_s=m.valid_s,
            thermal=_records(m.thermal),
        )
    except ValueError as exc:
        raise MapBuildError(f"map of {m.machine!r} cannot be encoded: {exc}") from None


def grid_from_payload(payload: ErrorMapPayload) -> ErrorMap:
    """The grid map a payload carries (limits and temperatures are not on the wire: the
    limits come back as the largest |value| per output, the temperatures empty)."""
    raw = np.frombuffer(payload.values, dtype=payload.dtype).reshape(payload.shape)
    fanuc = payload.encoding is MapEncoding.INT32_INCREMENTS
    inc = payload.increment_mm if fanuc else None
    values = raw.astype(float) * inc if inc is not None else raw.astype(float)
    reversal = tuple(
        None if o.reversal is None else (o.reversal * inc if inc is not None
                                         else float(o.reversal))
        for o in payload.outputs)
    k = len(payload.outputs)
    limits = tuple(float(np.abs(values[..., j]).max(initial=0.0)) for j in range(k))
    return ErrorMap(
        machine=payload.machine, version=payload.version,
        controller="fanuc" if fanuc else "siemens",
        grid=tuple(GridDim(g.name, g.start, g.step, g.count) for g in payload.grid),
        outputs=tuple(o.name for o in payload.outputs),
        values=values, increment=inc, limits=limits, reversal=reversal,
        valid_s=payload.valid_s, thermal=_terms(payload.thermal),
    )


_THERMAL_KINDS = {"thermal_drift": 1, "thermal_expansion": 2}
_THERMAL_NAMES = {v: k for k, v in _THERMAL_KINDS.items()}


def wire_sensor(column: str) -> str:
    """The sensor name a thermal record carries: exactly the name the Temperatures message
    carries (``T_spindle_C`` → ``spindle``), so that a machine matching names exactly
    applies it; MapBuildError when it does not fit the record's 16 bytes."""
    name = column[2:-2] if column.startswith("T_") and column.endswith("_C") and \
        len(column) > 4 else column
    if not 1 <= len(name.encode("utf-8")) <= 16 or not name.isascii() or \
            not all("!" <= ch <= "~" for ch in name):
        raise MapBuildError(f"thermal sensor {column!r}: the map's record carries "
                            f"{name!r}, which must be 1 to 16 printable ASCII characters "
                            f"without spaces")
    return name


def _records(terms: tuple[ThermalTerm, ...]) -> tuple[ThermalRecord, ...]:
    """The wire records of the model's thermal terms (all map kinds)."""
    return tuple(ThermalRecord(wire_sensor(th.sensor), th.axis.upper(),
                               _THERMAL_KINDS[th.kind], float(th.coefficient),
                               float(th.t_ref_C),
                               float(th.q_min) if th.kind != "thermal_drift" else 0.0)
                 for th in terms)


def _terms(records: tuple[ThermalRecord, ...]) -> tuple[ThermalTerm, ...]:
    # the model names a sensor by its column (T_<sensor>_C)
    return tuple(ThermalTerm(_THERMAL_NAMES[r.kind],  # type: ignore[arg-type]
                             r.axis.lower(), f"T_{r.sensor}_C", r.coefficient, r.t_ref_C,
                             r.q_min)
                 for r in records)


def tables_to_payload(t: TablesMap) -> TablesPayload:
    """The wire payload of a tables map (format version 2, protocol/README.md §6).

    Raises
    ------
    MapBuildError
        When a field does not fit the wire format.
    """
    m = t.machine
    weights = np.hstack([t.weights.position, t.weights.orientation])
    inc = t.increment_mm
    # an endpoint writing counts gets its reversals in whole counts (§6.2)
    reversal = t.reversal if inc is None else tuple(
        None if r is None else round(r / inc) for r in t.reversal)
    try:
        return TablesPayload(
            machine=m.name, version=t.version,
            encoding=MapEncoding.FLOAT32_MM if inc is None else MapEncoding.INT32_INCREMENTS,
            valid_s=t.valid_s, increment_mm=0.0 if inc is None else float(inc),
            axes=tuple(ChainAxis(a.name, a.kind == "rotary", a.side == "tool",
                                 _vec3(a.direction),
                                 _vec3(a.pivot_mm),
                                 (float(a.travel[0]), float(a.travel[1])))
                       for a in m.axes),
            spindles=tuple(Spindle(b.name, tuple(x.name for x in b.links),
                                   float(t.tool_mm.get(b.name, b.tool_length_mm)),
                                   _vec3(b.tool_direction),
                                   _six(weights[i]))
                           for i, b in enumerate(m.branches)),
            outputs=tuple(OutputAxis(n, r) for n, r in zip(t.outputs, reversal, strict=True)),
            tables=tuple(ComponentTable(s.name, float(s.start), float(s.step),
                                        tuple(float(v) for v in s.values))
                         for s in t.tables),
            locations=tuple((k, float(v)) for k, v in sorted(t.locations.items())),
            thermal=_records(t.thermal),
            limit_mm=float(_limit(t, "linear")),
            limit_deg=float(_limit(t, "rotary")),
        )
    except ValueError as exc:
        raise MapBuildError(f"map of {m.name!r} cannot be encoded: {exc}") from None


def tables_from_payload(p: TablesPayload, machine: Machine) -> TablesMap:
    """The tables map a payload carries, on the machine it was built for (the registered
    description gives the chain; the payload's chain must match it).

    Raises
    ------
    MapBuildError
        The payload's axes are not the machine's.
    """
    names = tuple(a.name for a in p.axes)
    if names != machine.axis_names:
        raise MapBuildError(f"the map's axes {' '.join(names)} are not those of "
                            f"{machine.name!r} ({' '.join(machine.axis_names)})")
    w = np.array([s.weights for s in p.spindles], dtype=float)
    limits = tuple(p.limit_deg if a.rotary else p.limit_mm for a in p.axes)
    inc = p.increment_mm if p.encoding is MapEncoding.INT32_INCREMENTS else None
    return TablesMap(
        machine=machine, version=p.version,
        controller="fanuc" if p.encoding is MapEncoding.INT32_INCREMENTS else "siemens",
        tables=tuple(ComponentSamples(t.name, t.start, t.step,
                                      np.asarray(t.values, dtype=float)) for t in p.tables),
        locations=dict(p.locations),
        thermal=_terms(p.thermal),
        reversal=tuple(None if o.reversal is None else float(o.reversal) * (inc or 1.0)
                       for o in p.outputs),
        weights=Weights(w[:, :3].copy(), w[:, 3:].copy()),
        tool_mm={s.name: s.tool_length_mm for s in p.spindles},
        limits=limits, valid_s=p.valid_s, increment_mm=inc,
    )


def _vec3(v: Any) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _six(v: Any) -> tuple[float, float, float, float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]), float(v[3]), float(v[4]), float(v[5]))


def _limit(t: TablesMap, kind: str) -> float:
    vals = [lim for a, lim in zip(t.machine.axes, t.limits, strict=True) if a.kind == kind]
    return max(vals, default=1.0)


def _ints(values: Any) -> tuple[int, ...]:
    return tuple(int(v) for v in np.asarray(values, dtype=np.int64))


def factored_to_payload(f: FactoredMap) -> FactoredPayload:
    """The wire payload of a factored map (format version 5, protocol/README.md §6.5).

    Raises
    ------
    MapBuildError
        When a field does not fit the wire format.
    """
    inc, per_unit = f.increment, f.counts_per_unit
    try:
        return FactoredPayload(
            machine=f.machine, version=f.version, valid_s=f.valid_s,
            counts_per_unit=per_unit,
            axes=tuple(FactoredAxis(n, r, None if rev is None else round(rev / inc),
                                    max(1, round(lim / inc)), g.count, g.start, g.shift)
                       for n, r, rev, lim, g in zip(f.axes, f.rotary, f.reversal, f.limits,
                                                    f.grids, strict=True)),
            bases=tuple(BasisTable(b.axis, b.start, b.shift, _ints(b.values))
                        for b in f.bases),
            terms=tuple(TermTable(t.field, t.table.axis, t.table.exponent, t.factors,
                                  _ints(t.table.values)) for t in f.terms),
            thermal=tuple(thermal_fixed(r, f.axes.index(r.axis.upper()), per_unit)
                          for r in _records(f.thermal)),
        )
    except ValueError as exc:
        raise MapBuildError(f"map of {f.machine!r} cannot be encoded: {exc}") from None


def factored_from_payload(p: FactoredPayload) -> FactoredMap:
    """The factored map a payload carries (temperatures are not on the wire; thermal
    records come back from their fixed point, to 2^-32 counts per m°C)."""
    inc = 1.0 / p.counts_per_unit
    grids = tuple(AxisGrid(a.count, a.start, a.shift) for a in p.axes)
    return FactoredMap(
        machine=p.machine, version=p.version, controller="fanuc",
        axes=tuple(a.name for a in p.axes), rotary=tuple(a.rotary for a in p.axes),
        increment=inc, limits=tuple(a.limit * inc for a in p.axes),
        reversal=tuple(None if a.reversal is None else a.reversal * inc for a in p.axes),
        grids=grids,
        bases=tuple(Table1D(b.axis, b.start, b.shift, np.array(b.values, dtype=np.int64),
                            -14) for b in p.bases),
        terms=tuple(Term(t.field, Table1D(t.axis, grids[t.axis].start, grids[t.axis].shift,
                                          np.array(t.values, dtype=np.int64), t.exponent),
                         t.factors)
                    for t in p.terms),
        valid_s=p.valid_s, thermal=tuple(_term_of(r, p) for r in p.thermal),
    )


def _term_of(r: FactoredThermal, p: FactoredPayload) -> ThermalTerm:
    """A fixed-point record back as a model term (its coefficient to the record's
    resolution)."""
    if r.kind == 1:
        coef = r.coefficient / 2.0**32 * 1e6 / p.counts_per_unit
    else:
        coef = r.coefficient / 2.0**48 * 1e9
    return ThermalTerm(_THERMAL_NAMES[r.kind],  # type: ignore[arg-type]
                       p.axes[r.axis].name.lower(), f"T_{r.sensor}_C", coef,
                       r.t_ref_mC / 1000, r.q_min / p.counts_per_unit)


def encode(content: MapContent) -> bytes:
    """The payload bytes a machine receives for ``content``."""
    if isinstance(content, TablesMap):
        return encode_payload(tables_to_payload(content))
    if isinstance(content, FactoredMap):
        return encode_factored(factored_to_payload(content))
    return encode_map(grid_to_payload(content))


def with_size(content: MapContent) -> MapContent:
    """``content`` with its report's ``bytes`` set to the encoded length."""
    if content.report is None:
        return content
    report = dataclasses.replace(content.report, bytes=len(encode(content)))
    return dataclasses.replace(content, report=report)


def with_version(content: MapContent, version: int) -> MapContent:
    """The same map stamped with another version number."""
    return dataclasses.replace(content, version=version)


def kind_of(content: MapContent) -> MapKind:
    if isinstance(content, FactoredMap):
        return "factored"
    return "tables" if isinstance(content, TablesMap) else "grid"


def carries_thermal(map_or_payload: MapContent | bytes) -> bool:
    """Whether a map (or its encoded payload) carries the thermal terms, so that the
    machine applies its latest temperatures itself: a tables map, or a grid map with
    thermal terms (format version 3). A grid of a model without thermal terms carries
    nothing, and needs nothing either."""
    if isinstance(map_or_payload, bytes):
        version = int.from_bytes(map_or_payload[4:6], "little")
        if version == FACTORED_FORMAT_VERSION:  # carries them when it has records
            return bool(decode_factored(map_or_payload).thermal)
        return version in (TABLES_FORMAT_VERSION, GRID_THERMAL_FORMAT_VERSION)
    return isinstance(map_or_payload, TablesMap) or bool(map_or_payload.thermal)


def declared_kinds(formats: MapEncoding) -> tuple[MapKind, ...]:
    """The map kinds a machine that declared ``formats`` evaluates."""
    kinds: list[MapKind] = []
    if formats & MapEncoding.TABLES:
        kinds.append("tables")
    if formats & MapEncoding.FACTORED and formats & MapEncoding.INT32_INCREMENTS:
        kinds.append("factored")
    if formats & (MapEncoding.INT32_INCREMENTS | MapEncoding.FLOAT32_MM):
        kinds.append("grid")
    return tuple(kinds)


def default_formats(controller: str) -> MapEncoding:
    """What a machine of a controller family evaluates when it has not said (the
    simulated Siemens-style endpoint evaluates tables, the Fanuc-style one grids with
    their thermal records and factored maps)."""
    if controller.lower() == "fanuc":
        return MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    return MapEncoding.FLOAT32_MM | MapEncoding.TABLES


def _size(content: MapContent) -> int:
    return content.report.bytes if content.report is not None else len(encode(content))


def build_for(machine: Machine, model: MachineModel,
              temperatures: Mapping[str, float] | None = None, *,
              formats: MapEncoding | None = None, kind: str = "auto",
              tolerance_um: float = 0.5, max_tolerance_um: float | None = None,
              **options: Any) -> MapContent:
    """The map a machine receives.

    Parameters
    ----------
    machine, model, temperatures
        As for :func:`volumetric.compensate.gridmap.build_map`.
    formats : MapEncoding, optional
        What the machine declared in its Hello (or its registration); by default what its
        controller family evaluates. With ``MapEncoding.THERMAL`` a grid carries the
        model's thermal terms (built at their references, checked at ``temperatures``).
    kind : {"auto", "grid", "tables", "factored"}
        ``auto`` picks the smallest payload meeting the tolerance among the declared kinds
        (a factored map's tolerance is its error as sent: it fails rather than miss it).
    tolerance_um : float
        Largest tool-tip error allowed, µm.

    Raises
    ------
    MapBuildError
        An unknown or undeclared kind, or no kind meets the tolerance.
    """
    t0 = time.perf_counter()
    ctrl = str(options.get("controller") or machine.controller)
    declared = default_formats(ctrl) if formats is None else formats
    have = declared_kinds(declared)
    thermal_grid = bool(declared & MapEncoding.THERMAL)
    if kind not in ("auto", "grid", "tables", "factored"):
        raise MapBuildError(f"map kind {kind!r}: expected auto, grid, tables or factored")
    if kind != "auto" and kind not in have:
        raise MapBuildError(f"machine {machine.name!r} does not evaluate {kind} maps (it "
                            f"takes {', '.join(have) or 'none'})")
    wanted = have if kind == "auto" else (kind,)
    # a factored map asked for by name may miss its tolerance if the caller says so
    over_ok = bool(options.pop("allow_over_tolerance", False)) and kind == "factored"
    table_opts = {k: v for k, v in options.items() if k not in ("increment", "max_bytes",
                                                                  "check_points")}
    best: MapContent | None = None
    if "tables" in wanted:
        try:
            tables = build_tables_map(machine, model, temperatures,
                                      tolerance_um=tolerance_um, **table_opts)
            if (declared & MapEncoding.INT32_INCREMENTS
                    and not declared & MapEncoding.FLOAT32_MM):
                # an endpoint that writes counts only (a PLC program): int32 tables
                inc = float(options.get("increment") or DEFAULT_INCREMENT)
                tables = dataclasses.replace(tables, increment_mm=inc)
            best = with_size(tables)
        except MapBuildError:
            if kind == "tables":
                raise
    if "factored" in wanted:
        fopts = {k: v for k, v in options.items() if k not in ("check_points",)}
        try:
            fac = with_size(build_factored_map(machine, model, temperatures,
                                               tolerance_um=tolerance_um,
                                               thermal_in_map=thermal_grid,
                                               over_tolerance_ok=over_ok, **fopts))
            if best is None or _size(fac) < _size(best):
                best = fac
        except MapBuildError:
            if kind == "factored":
                raise
    if "grid" in wanted:
        # a grid only wins when smaller: it may not grow beyond the tables' size (a
        # five-axis grid at a tight tolerance would take seconds and megabytes), and the
        # tables carry the thermal terms, so they win a tie when the model has any
        # (unless the grid carries them too)
        limit = MAX_MAP_BYTES
        if best is not None and best.report is not None:
            limit = best.report.bytes - (1 if model.sensors and not thermal_grid else 0)
        tol = tolerance_um
        while True:
            try:
                grid = build_map(machine, model, temperatures, tolerance_um=tol,
                                 max_bytes=max(limit, 1), thermal_in_map=thermal_grid,
                                 **options)
                best = grid
                break
            except MapTooLargeError:
                if best is not None:
                    break
                if max_tolerance_um is None or tol * 2 > max_tolerance_um:
                    raise
                tol *= 2
            except MapBuildError:
                # e.g. a thermal model without today's temperatures: a grid needs them,
                # the tables (which carry the terms) do not
                if best is None:
                    raise
                break
    if best is None:
        raise MapBuildError(f"machine {machine.name!r}: no map kind it takes "
                            f"({', '.join(have)}) meets {tolerance_um} µm")
    report = best.report
    if report is not None:
        report = dataclasses.replace(report, build_s=time.perf_counter() - t0)
        best = dataclasses.replace(best, report=report)
    return best


__all__ = [
    "MapContent",
    "build_for",
    "carries_thermal",
    "declared_kinds",
    "default_formats",
    "encode",
    "factored_from_payload",
    "factored_to_payload",
    "grid_from_payload",
    "grid_to_payload",
    "kind_of",
    "tables_from_payload",
    "tables_to_payload",
    "with_size",
    "with_version",
]
