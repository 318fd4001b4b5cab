"""A stored model's terms as the machine page shows them (pure).

Each position-dependent component error is sampled over its axis's travel (from the
machine description; 0-360° for a rotary axis without one) so that the page can draw it
and state its extent; location errors are constants. Units follow ISO 230-1 naming:
errors in a direction X/Y/Z are µm, about A/B/C are µrad.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Mapping
from typing import Any

import numpy as np

from server.dashboard.schemas import ComponentView, ModelView
from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import component_from_json, parse_name

SAMPLES = 41
ROTARY_TRAVEL_DEG = (0.0, 360.0)


class ModelViewError(ValueError):
    """A stored model body that cannot be read (the message names the entry)."""


def _travel(description: Mapping[str, Any], axis: str) -> tuple[float, float]:
    travel = description.get("travel_mm")
    if isinstance(travel, Mapping):
        span = travel.get(axis.lower())
        if isinstance(span, list | tuple) and len(span) == 2:
            lo, hi = (float(s) for s in span)
            if np.isfinite(lo) and np.isfinite(hi) and hi > lo:
                return lo, hi
    if axis[:1] in "ABC":
        return ROTARY_TRAVEL_DEG
    raise ModelViewError(f"the machine description has no travel for axis {axis}")


def _component(name: str, spec: Any, description: Mapping[str, Any]) -> ComponentView:
    parsed = parse_name(name)
    unit = "µrad" if parsed.direction in "ABC" else "µm"
    lo, hi = _travel(description, parsed.axis)
    q = np.linspace(lo, hi, SAMPLES)
    values = np.asarray(component_from_json(spec)(q), dtype=float)
    if not np.all(np.isfinite(values)):
        raise ModelViewError(f"components.{name}: not finite over the travel [{lo:g}, {hi:g}]")
    kind = spec.get("type", "polynomial") if isinstance(spec, Mapping) else "?"
    return ComponentView(
        name=name, axis=parsed.axis, location=False, unit=unit, kind=str(kind),
        min=float(values.min()), max=float(values.max()),
        positions=np.round(q, 6).tolist(), values=np.round(values, 6).tolist(),
    )


def _location(name: str, value: Any) -> ComponentView:
    parsed = parse_name(name)
    number = float(value)
    if not np.isfinite(number):
        raise ValueError(f"{number} is not a finite number")
    return ComponentView(
        name=name, axis=parsed.axis, location=True,
        unit="µrad" if parsed.direction in "ABC" else "µm", kind="constant",
        min=number, max=number, positions=[], values=[],
    )


def model_view(body: Mapping[str, Any], description: Mapping[str, Any], *, version: int,
               source: str, created_at: dt.datetime) -> ModelView:
    """The page's view of a stored model body (``MachineModel.to_json``).

    Raises
    ------
    ModelViewError
        An entry that does not read (named), or an axis without travel.
    """
    components = body.get("components", {})
    locations = body.get("locations", {})
    if not isinstance(components, Mapping) or not isinstance(locations, Mapping):
        raise ModelViewError("'components' and 'locations' must be JSON objects")
    views: list[ComponentView] = []
    for name, spec in components.items():
        try:
            views.append(_component(str(name), spec, description))
        except (ComponentErrorSpecError, TypeError, ValueError, KeyError) as exc:
            if isinstance(exc, ModelViewError):
                raise
            raise ModelViewError(f"components.{name}: {exc}") from None
    for name, value in locations.items():
        try:
            views.append(_location(str(name), value))
        except (ComponentErrorSpecError, TypeError, ValueError) as exc:
            raise ModelViewError(f"locations.{name}: {exc}") from None
    terms = body.get("terms", [])
    info = body.get("info", {})
    return ModelView(
        version=version, source=source, created_at=created_at, components=views,
        terms=[t for t in terms if isinstance(t, dict)] if isinstance(terms, list) else [],
        info=dict(info) if isinstance(info, Mapping) else {},
    )
