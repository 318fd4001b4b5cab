"""A link's telemetry (``LinkState.telemetry``, "as received") in one shape for the pages.

The registry keeps what the machine TCP server stores, which is the protocol's Telemetry
message (protocol README §3, 0x20) as a mapping. Both natural spellings are read:

* ``dataclasses.asdict`` of the message: ``axes`` a list of ``{"name", "position",
  "compensation"}``, ``temperatures`` a list of ``{"name", "celsius"}``;
* keyed by name: ``axes`` ``{"X": {"position": .., "compensation": ..}}`` and
  ``temperatures`` ``{"spindle": 24.1}``.

Positions and compensation arrive in mm (degrees for rotary axes); the pages get
compensation in µm (µrad), the size a metrology engineer reads. Entries that are not
numbers are left out rather than shown wrong.
"""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from server.dashboard.schemas import AxisLive, TemperatureLive

UM_PER_MM = 1000.0
URAD_PER_DEG = math.pi / 180.0 * 1e6
ROTARY = frozenset("ABC")


@dataclass(frozen=True, slots=True)
class LiveValues:
    """Telemetry made uniform.

    Attributes
    ----------
    state : str or None
        The machine's state label.
    map_version : int or None
        Map version the machine reports applied (0: none).
    measured_at : datetime or None
        The machine's timestamp of the reading (UTC), when it sent one.
    axes, temperatures
        Readings in the units of :class:`~server.dashboard.schemas.AxisLive` and
        :class:`~server.dashboard.schemas.TemperatureLive` (``stale`` still False).
    """

    state: str | None
    map_version: int | None
    measured_at: dt.datetime | None
    axes: tuple[AxisLive, ...]
    temperatures: tuple[TemperatureLive, ...]


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def _entries(raw: Any) -> Iterable[tuple[str, Any]]:
    """``(name, entry)`` pairs of a list of ``{"name": ..}`` or a mapping keyed by name."""
    if isinstance(raw, Mapping):
        yield from ((str(k), v) for k, v in raw.items())
    elif isinstance(raw, list | tuple):
        for item in raw:
            if isinstance(item, Mapping) and isinstance(item.get("name"), str):
                yield item["name"], item


def _axis(name: str, entry: Any) -> AxisLive | None:
    if isinstance(entry, Mapping):
        position = _number(entry.get("position", entry.get("position_mm")))
        compensation = _number(entry.get("compensation", entry.get("compensation_mm", 0.0)))
    else:
        position, compensation = _number(entry), 0.0
    if position is None or compensation is None:
        return None
    rotary = name[:1].upper() in ROTARY
    scale = URAD_PER_DEG if rotary else UM_PER_MM
    return AxisLive(name=name, rotary=rotary, position=position,
                    compensation=compensation * scale)


def _temperature(name: str, entry: Any) -> TemperatureLive | None:
    value = _number(entry.get("celsius")) if isinstance(entry, Mapping) else _number(entry)
    return None if value is None else TemperatureLive(name=name, celsius=value, stale=False)


def live_values(telemetry: Mapping[str, Any]) -> LiveValues:
    """Read a link's telemetry mapping (see the module docstring); never raises."""
    axes = [_axis(n, e) for n, e in _entries(telemetry.get("axes"))]
    temps = [_temperature(n, e) for n, e in _entries(telemetry.get("temperatures"))]
    state = telemetry.get("state")
    version = telemetry.get("map_version")
    stamp = _number(telemetry.get("timestamp_ms"))
    measured_at = None
    if stamp is not None and 0 <= stamp < 1e14:  # beyond that is not a clock (year 5138)
        measured_at = dt.datetime.fromtimestamp(stamp / 1000.0, dt.UTC)
    return LiveValues(
        state=state if isinstance(state, str) else None,
        map_version=version if isinstance(version, int) and not isinstance(version, bool)
        else None,
        measured_at=measured_at,
        axes=tuple(a for a in axes if a is not None),
        temperatures=tuple(t for t in temps if t is not None),
    )
