"""Maps between the numeric core's content and the wire: one place that knows both.

:mod:`volumetric.compensate` builds map *content* (numbers in mm, degrees, µm) without
knowing the wire; :mod:`protocol` knows the bytes without knowing the numbers' meaning.
This module converts one into the other, and picks the map kind for a machine
(:func:`build_for`): the smallest payload that meets the tolerance among the kinds the
machine evaluates, preferring a kind that carries the model's thermal terms (so a
temperature change never needs a new map).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, Final

import numpy as np

from protocol.codes import MapEncoding
from protocol.mapformat import ErrorMapPayload, GridAxis, OutputAxis, encode_map
from volumetric.compensate.gridmap import ErrorMap, GridDim, build_map
from volumetric.compensate.maps import MapBuildError, MapKind, MapTooLargeError
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel

MapContent = ErrorMap


def grid_to_payload(m: ErrorMap) -> ErrorMapPayload:
    """The wire payload of a grid map (format version 1).

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
        valid_s=payload.valid_s,
    )


def encode(content: MapContent) -> bytes:
    """The payload bytes a machine receives for ``content``."""
    return encode_map(grid_to_payload(content))


def with_version(content: MapContent, version: int) -> MapContent:
    """The same map stamped with another version number."""
    return dataclasses.replace(content, version=version)


def kind_of(content: MapContent) -> MapKind:
    return "grid"


CARRIES_THERMAL: Final[frozenset[MapKind]] = frozenset()
"""Kinds whose payload carries the model's thermal terms: the machine applies its latest
temperatures itself, so a temperature change needs no new map."""


def build_for(machine: Machine, model: MachineModel,
              temperatures: Mapping[str, float] | None = None, *,
              kinds: MapEncoding | None = None, kind: str = "auto",
              tolerance_um: float = 0.5, **options: Any) -> MapContent:
    """The map a machine receives.

    Parameters
    ----------
    machine, model, temperatures
        As for :func:`volumetric.compensate.gridmap.build_map`.
    kinds : MapEncoding, optional
        What the machine declared in its Hello (or its registration); by default what its
        controller family evaluates.
    kind : {"auto", "grid", "tables"}
        ``auto`` picks the smallest payload meeting the tolerance among the declared kinds.
    tolerance_um : float
        Largest tool-tip error allowed, µm.

    Raises
    ------
    MapBuildError
        An unknown or undeclared kind, or no kind meets the tolerance.
    """
    if kind not in ("auto", "grid"):
        raise MapBuildError(f"map kind {kind!r}: expected auto or grid")
    try:
        return build_map(machine, model, temperatures, tolerance_um=tolerance_um, **options)
    except MapTooLargeError:
        raise


__all__ = [
    "CARRIES_THERMAL",
    "MapContent",
    "build_for",
    "encode",
    "grid_from_payload",
    "grid_to_payload",
    "kind_of",
    "with_version",
]
