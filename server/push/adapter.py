"""The numeric adapter: from the database's JSON to the core's map build.

The scheduler holds rows; the core takes :class:`~volumetric.model.machine.Machine` and
:class:`~volumetric.model.model.MachineModel`. This module is the one place that turns the
first into the second, and the only one of the push package that imports the core.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from protocol import MapEncoding
from server import mapcodec
from server.mapcodec import MapContent
from volumetric.model.live import live_model, live_needs, plain_thermal_sensors
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel


def thermal_sensors(body: Mapping[str, Any]) -> frozenset[str]:
    """The temperature columns of the thermal records of a model's map (read from its JSON
    without building the model): its thermal terms' sensors and, for a lagged thermal
    model, the lag states the center sends as ``T_lag1_C`` ... (:mod:`volumetric.model.live`)."""
    terms = body.get("terms") or []
    try:
        return live_needs(terms).records
    except (ValueError, KeyError, TypeError):  # ComponentErrorSpecError is a ValueError
        # a dynamic term that cannot be read: the build says why; the plain ones still count
        return plain_thermal_sensors(terms)


def build_for(description: Mapping[str, Any], controller: str, model_body: Mapping[str, Any],
              temperatures: Mapping[str, float], tolerance_um: float,
              formats: MapEncoding | None = None) -> MapContent:
    """Build a machine's map (synchronous, seconds at most: run it off the loop).

    Raises
    ------
    ValueError
        The description, the model or the build is refused (MapBuildError is one); the
        text is the core's.
    """
    machine = parse_machine(description)
    try:
        # lagged thermal terms as the machine applies them: records on the lag states the
        # center follows and sends (server/intake.py), not frozen at today's temperatures
        model = live_model(MachineModel.from_json(model_body))
    except (TypeError, KeyError) as exc:
        raise ValueError(f"stored model cannot be read: {exc}") from None
    # the smallest kind the machine takes; a grid alone is built at the tightest tolerance
    # that fits the map memory (five-axis grids can need a coarser one)
    return mapcodec.build_for(machine, model, dict(temperatures), formats=formats,
                              tolerance_um=tolerance_um, max_tolerance_um=4.0,
                              controller="fanuc" if controller == "fanuc" else "siemens")


__all__ = ["build_for", "thermal_sensors"]
