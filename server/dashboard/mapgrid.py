"""A 2-D slice of an encoded error map, for a heat map per output axis (pure, numpy).

A grid payload (protocol README §6) holds values of shape ``(count_1, ..., count_D, K)``;
the slice spans two grid axes ``u`` and ``v`` and holds every other grid axis at its node
nearest the middle of its range. A tables or factored payload holds no grid: its
corrections are evaluated (as the center evaluates them,
:func:`server.mapcodec.tables_from_payload`, :func:`server.mapcodec.factored_from_payload`;
a factored map before the ladder's rounding) on a display grid of ``DISPLAY_NODES`` per
axis over two machine axes, the others at mid-travel. Values come out in µm for linear
output axes and µrad for rotary ones.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from protocol.codes import MapEncoding
from protocol.mapfactored import FactoredPayload
from protocol.mapformat import ErrorMapPayload, MapFormatError
from protocol.maptables import TablesPayload, decode_payload
from server.dashboard.schemas import GridAxisView, MapGrid, MapSlice
from server.dashboard.telemetry import ROTARY, UM_PER_MM, URAD_PER_DEG
from server.mapcodec import factored_from_payload, tables_from_payload
from volumetric.compensate.maps import MapBuildError
from volumetric.compensate.solver import CompensationError
from volumetric.model.machine import Machine

DISPLAY_NODES = 21


class MapSliceError(ValueError):
    """A stored map that cannot be decoded, or a slice request that does not fit the map."""


def _is_rotary(name: str) -> bool:
    return name[:1].upper() in ROTARY


def _scale(name: str) -> float:
    """Map unit (mm or degrees) to display unit (µm or µrad) of an output axis."""
    return URAD_PER_DEG if _is_rotary(name) else UM_PER_MM


def decode_stored(payload: bytes) -> ErrorMapPayload | TablesPayload | FactoredPayload:
    """Decode a stored payload of any kind; :class:`MapSliceError` names what is wrong."""
    try:
        return decode_payload(payload)
    except MapFormatError as exc:
        raise MapSliceError(f"the stored map does not decode: {exc}") from None


def map_values_mm(payload: ErrorMapPayload) -> NDArray[np.float64]:
    """The values in mm (degrees for rotary outputs), shape ``(count_1, ..., count_D, K)``."""
    raw = np.frombuffer(payload.values, payload.dtype).reshape(payload.shape)
    values = raw.astype(np.float64)
    if payload.encoding == MapEncoding.INT32_INCREMENTS:
        values *= payload.increment_mm
    return values


def slice_map(payload: ErrorMapPayload, u: str | None = None, v: str | None = None
              ) -> MapGrid:
    """The map over grid axes ``u`` (horizontal) and ``v`` (vertical).

    Parameters
    ----------
    payload
        A decoded map.
    u, v
        Grid axis names; by default the first two grid axes (``v`` None on a 1-D map).

    Returns
    -------
    MapGrid
        ``outputs[k].values[j][i]`` is output k at v-node j, u-node i, in µm (µrad).

    Raises
    ------
    MapSliceError
        ``u`` or ``v`` is not a grid axis of the map, or both name the same axis.
    """
    names = [g.name for g in payload.grid]
    u = u if u is not None else names[0]
    if v is None and len(names) > 1:
        v = next(n for n in names if n != u)
    for which, name in (("u", u), ("v", v)):
        if name is not None and name not in names:
            raise MapSliceError(f"{which}={name!r} is not a grid axis of the map "
                                f"(it has {', '.join(names)})")
    if u == v:
        raise MapSliceError(f"u and v are both {u!r}; choose two different grid axes")
    values = map_values_mm(payload)
    index: list[int | slice] = []
    fixed: dict[str, float] = {}
    for g in payload.grid:
        if g.name in (u, v):
            index.append(slice(None))
        else:
            mid = (g.count - 1) // 2
            index.append(mid)
            fixed[g.name] = g.start + mid * g.step
    plane = values[tuple(index)]  # the kept axes in grid order, then K
    kept = [g.name for g in payload.grid if g.name in (u, v)]
    if v is None:
        plane = plane[np.newaxis, :, :]  # one row
    elif kept[0] == u:
        plane = np.swapaxes(plane, 0, 1)  # rows follow v, columns u
    slices = []
    for k, out in enumerate(payload.outputs):
        scale = _scale(out.name)
        grid_values = plane[:, :, k] * scale
        reversal = None
        if out.reversal is not None:
            step = (payload.increment_mm
                    if payload.encoding == MapEncoding.INT32_INCREMENTS else 1.0)
            reversal = float(out.reversal) * step * scale
        slices.append(MapSlice(
            output=out.name, unit="µrad" if _is_rotary(out.name) else "µm",
            reversal=reversal, values=np.round(grid_values, 4).tolist(),
            min=float(grid_values.min()), max=float(grid_values.max()),
        ))
    return MapGrid(
        machine=payload.machine, version=payload.version,
        encoding="int32" if payload.encoding == MapEncoding.INT32_INCREMENTS else "float32",
        increment_mm=payload.increment_mm,
        grid=[GridAxisView(name=g.name, unit="deg" if _is_rotary(g.name) else "mm",
                           start=g.start, step=g.step, count=g.count) for g in payload.grid],
        u=u, v=v, fixed=fixed, outputs=slices,
    )



def slice_tables(payload: TablesPayload | FactoredPayload, machine: Machine,
                 u: str | None = None, v: str | None = None) -> MapGrid:
    """The corrections of a tables or factored map over machine axes ``u`` and ``v`` (by
    default the first two linear axes), on a display grid, the other axes at mid-travel.

    Raises
    ------
    MapSliceError
        An axis the machine does not have, ``u == v``, or a map that does not fit the
        machine's registered description.
    """
    names = list(machine.axis_names)
    linear = [a.name for a in machine.axes if a.kind == "linear"] or names
    u = u if u is not None else linear[0]
    if v is None and len(names) > 1:
        v = next(n for n in (linear + names) if n != u)
    for which, name in (("u", u), ("v", v)):
        if name is not None and name not in names:
            raise MapSliceError(f"{which}={name!r} is not an axis of {machine.name!r} "
                                f"(it has {', '.join(names)})")
    if u == v:
        raise MapSliceError(f"u and v are both {u!r}; choose two different axes")
    try:
        content = (factored_from_payload(payload) if isinstance(payload, FactoredPayload)
                   else tables_from_payload(payload, machine))
    except MapBuildError as exc:
        raise MapSliceError(str(exc)) from None
    if content.outputs != machine.axis_names:
        raise MapSliceError(f"the map's axes {' '.join(content.outputs)} are not those of "
                            f"{machine.name!r} ({' '.join(machine.axis_names)})")
    axes = {a.name: a for a in machine.axes}
    views, fixed, nodes = [], {}, {}
    for a in machine.axes:  # every axis is offered for the plot: list them all
        lo, hi = float(a.travel[0]), float(a.travel[1])
        step = (hi - lo) / (DISPLAY_NODES - 1) if hi > lo else 1.0
        views.append(GridAxisView(name=a.name, unit="deg" if a.kind == "rotary" else "mm",
                                  start=lo, step=step, count=DISPLAY_NODES))
        if a.name in (u, v):
            nodes[a.name] = lo + step * np.arange(DISPLAY_NODES)
        else:
            fixed[a.name] = 0.5 * (lo + hi)
    uu = nodes[u]
    vv = nodes[v] if v is not None else np.array([0.0])
    gv, gu = np.meshgrid(vv, uu, indexing="ij")  # rows follow v, columns u
    q = np.empty((gu.size, len(names)))
    for j, name in enumerate(names):
        if name == u:
            q[:, j] = gu.ravel()
        elif name == v:
            q[:, j] = gv.ravel()
        else:
            q[:, j] = fixed[name]
    try:
        dq = content.corrections(q)
    except CompensationError as exc:
        raise MapSliceError(f"the map's corrections cannot be evaluated: {exc}") from None
    slices = []
    for k, (name, rev) in enumerate(zip(content.outputs, content.reversal, strict=True)):
        rotary = axes[name].kind == "rotary"
        scale = URAD_PER_DEG if rotary else UM_PER_MM
        grid_values = dq[:, k].reshape(gu.shape) * scale
        slices.append(MapSlice(
            output=name, unit="µrad" if rotary else "µm",
            reversal=None if rev is None else float(rev) * scale,
            values=np.round(grid_values, 4).tolist(),
            min=float(grid_values.min()), max=float(grid_values.max()),
        ))
    if isinstance(payload, FactoredPayload):  # a ladder's: whole increments
        return MapGrid(machine=payload.machine, version=payload.version, kind="factored",
                       encoding="int32", increment_mm=payload.increment_mm, grid=views, u=u,
                       v=v, fixed=fixed, outputs=slices)
    return MapGrid(
        machine=payload.machine, version=payload.version, kind="tables",
        encoding="int32" if payload.encoding == MapEncoding.INT32_INCREMENTS else "float32",
        increment_mm=payload.increment_mm, grid=views, u=u, v=v, fixed=fixed,
        outputs=slices,
    )
