"""The diagnosis report's HTML names every effect the diagnosis found, not only the first
(issue 25: a five-axis run's ``rotary_periodic c`` and ``unexplained a`` were missing)."""

from __future__ import annotations

from typing import Any

from volumetric.diagnose.report import _effects_table

FIVE_AXIS_EFFECTS: list[dict[str, Any]] = [
    {"effect": "backlash", "axis": "x", "sensor": None, "estimate": {"reversal_um": 8.0},
     "rms_after_um": 1.0},
    {"effect": "rotary_periodic", "axis": "c", "sensor": None,
     "estimate": {"order": 2, "radial_um": 4.1, "angular_urad": 12.0}, "rms_after_um": 0.61},
    {"effect": "unexplained", "axis": "a", "sensor": None,
     "estimate": {"correlates_with": "position a", "structure_um": 0.4, "correlates": []},
     "rms_after_um": 0.61},
]


def test_every_named_effect_has_its_row() -> None:
    html = _effects_table(FIVE_AXIS_EFFECTS)
    assert html.count("<tr>") == 1 + len(FIVE_AXIS_EFFECTS)
    for effect, axis in (("backlash", "x"), ("rotary_periodic", "c"), ("unexplained", "a")):
        assert f"<td>{effect}</td><td>{axis}</td>" in html
    assert "position a" in html and "0.610" in html
