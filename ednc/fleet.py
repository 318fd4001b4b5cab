"""The demo fleet: a mixed set of machine descriptions and the physics hidden in each.

Fanuc-style and Siemens-style controllers, three-axis and five-axis chains, and the
two-spindle arch machine of the first seed (x on the workpiece, y shared, z1 and z2
tilted in the y-z plane). One machine hides a spindle growth along z that the diagnosis
has to find.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from machine_sim.effects import Backlash, Effects, Noise, ThermalDrift


@dataclass(frozen=True)
class FleetMachine:
    """One demo machine: its description (formats.md §1) and its hidden physics."""

    description: dict[str, Any]
    effects: Effects
    seed: int
    scale: float = 2.0

    @property
    def name(self) -> str:
        return str(self.description["name"])


def _tilted(theta_deg: float) -> list[float]:
    t = math.radians(theta_deg)
    return [0.0, -math.sin(t), math.cos(t)]


NOISE = Noise(0.2, 0.3)
TRAVEL = {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}


def demo_fleet() -> list[FleetMachine]:
    return [
        FleetMachine({"name": "vmc-01", "controller": "siemens", "ip": "127.0.0.1",
                      "chain": "w X Y b Z t", "travel_mm": TRAVEL, "tool_length_mm": 100.0},
                     Effects(drift=(ThermalDrift("z", "spindle", -2.5),), noise=NOISE), 11),
        FleetMachine({"name": "gantry-02", "controller": "fanuc", "ip": "127.0.0.1",
                      "chain": "w b Y X Z t", "travel_mm": TRAVEL, "tool_length_mm": 150.0},
                     Effects(noise=NOISE), 12),
        FleetMachine({"name": "hmc-03", "controller": "fanuc", "ip": "127.0.0.1",
                      "translational_type": 3, "rotary_type": 0, "travel_mm": TRAVEL,
                      "tool_length_mm": 120.0},
                     Effects(backlash=(Backlash("y", 6.0),), noise=NOISE), 13),
        FleetMachine({"name": "5ax-04", "controller": "siemens", "ip": "127.0.0.1",
                      "chain": "w C A X b Y Z t",
                      "travel_mm": {**TRAVEL, "a": [-110, 110], "c": [-180, 180]},
                      "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
                      "tool_length_mm": 100.0},
                     Effects(noise=NOISE), 14),
        FleetMachine({"name": "arch-05", "controller": "fanuc", "ip": "127.0.0.1",
                      "chain": "w X b Y t",
                      "travel_mm": {"x": [10, 500], "y": [10, 290], "z1": [-300, -10],
                                    "z2": [-300, -10]},
                      "spindles": [
                          {"name": "S1", "axis": "Z1", "direction": _tilted(0.0),
                           "tool_length_mm": 50.0},
                          {"name": "S2", "axis": "Z2", "direction": _tilted(30.0),
                           "tool_length_mm": 50.0}]},
                     Effects(noise=NOISE), 15),
    ]
