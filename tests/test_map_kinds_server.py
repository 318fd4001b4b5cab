"""The center's side of the map kinds: content to payload and back, the kind picked per
machine, and the dashboard's view of a tables map."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from protocol.codes import MapEncoding
from protocol.mapfactored import FactoredPayload
from protocol.maptables import decode_payload, payload_kind
from server.dashboard.mapgrid import MapSliceError, decode_stored, slice_tables
from server.mapcodec import (
    build_for,
    carries_thermal,
    declared_kinds,
    encode,
    kind_of,
    tables_from_payload,
    tables_to_payload,
)
from tests.support.kinematics import machine, random_errors, random_q
from volumetric.compensate.factoredmap import FactoredMap
from volumetric.compensate.maps import MapBuildError
from volumetric.compensate.tablesmap import TablesMap, build_tables_map
from volumetric.model.machine import Machine
from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm


def five_axis() -> Machine:
    """The demo's 5ax-04 chain and pivots."""
    return machine("w C A X b Y Z t",
                   travel_mm={"x": [0, 500], "y": [0, 300], "z": [-300, 0], "a": [-110, 110],
                              "c": [-180, 180]},
                   pivots_mm={"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]})


def thermal_model(mach_name: str, geo_seed: int = 3) -> MachineModel:
    mach = five_axis()
    return MachineModel(mach_name, random_errors(mach, np.random.default_rng(geo_seed), 5.0), (
        ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 21.0),
        ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0, 0.0),
        BacklashTerm("y", 4.0)))


def test_a_tables_map_survives_the_wire_unchanged() -> None:
    mach = five_axis()
    t = build_tables_map(mach, thermal_model(mach.name), tolerance_um=0.2, controller="siemens")
    data = encode(t)
    decoded = decode_payload(data)
    assert payload_kind(decoded) == "tables" and carries_thermal(data)
    back = tables_from_payload(decoded, mach)  # type: ignore[arg-type]
    assert isinstance(back, TablesMap)
    q = random_q(mach, np.random.default_rng(1), 300)
    for temps in ({}, {"T_spindle_C": 29.0, "T_x_C": 24.0}):
        assert np.allclose(back.corrections(q, temps), t.corrections(q, temps), atol=1e-9)
    assert back.reversal == t.reversal
    assert tables_to_payload(back) == decoded


def test_auto_picks_the_smallest_kind_the_machine_evaluates() -> None:
    five = five_axis()
    model = MachineModel(five.name, random_errors(five, np.random.default_rng(4), 5.0))
    siemens = build_for(five, model, tolerance_um=1.0, controller="siemens")
    assert kind_of(siemens) == "tables" and len(encode(siemens)) < 16_000
    # a Fanuc ladder takes factored maps: smaller than its grid and closer as sent (the
    # grid's rotary corrections are rounded to 0.001° over a lever of hundreds of mm)
    fanuc = build_for(five, model, tolerance_um=2.0, controller="fanuc")
    old_ladder = build_for(five, model, tolerance_um=2.0, controller="fanuc",
                           formats=MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL)
    assert kind_of(fanuc) == "factored" and kind_of(old_ladder) == "grid"
    assert fanuc.report is not None and old_ladder.report is not None
    assert len(encode(fanuc)) < len(encode(old_ladder))
    assert fanuc.report.worst_error_um <= 2.0 < old_ladder.report.worst_error_um
    with pytest.raises(MapBuildError, match="does not evaluate tables maps"):
        build_for(five, model, kind="tables", controller="fanuc")
    # a machine that declared grids only gets a grid whatever its controller family
    grid_only = build_for(five, model, tolerance_um=2.0, controller="siemens",
                          formats=MapEncoding.FLOAT32_MM)
    assert kind_of(grid_only) == "grid"
    assert declared_kinds(MapEncoding.FLOAT32_MM | MapEncoding.TABLES) == ("tables", "grid")
    # a 3-axis machine: whichever is smaller, never larger than the grid
    three = machine("w X Y b Z t")
    model3 = MachineModel(three.name, random_errors(three, np.random.default_rng(5), 5.0))
    auto3 = build_for(three, model3, tolerance_um=0.5, controller="siemens")
    grid3 = build_for(three, model3, tolerance_um=0.5, controller="siemens", kind="grid")
    assert len(encode(auto3)) <= len(encode(grid3))


def test_the_dashboard_shows_a_tables_map_as_the_machine_computes_it() -> None:
    mach = five_axis()
    t = build_tables_map(mach, thermal_model(mach.name), tolerance_um=0.5, controller="siemens")
    payload = decode_payload(encode(t))
    view = slice_tables(payload, mach, "X", "C")  # type: ignore[arg-type]
    assert view.kind == "tables" and view.u == "X" and view.v == "C"
    gx = next(g for g in view.grid if g.name == "X")
    gc = next(g for g in view.grid if g.name == "C")
    q = np.array([[view.fixed.get(a.name, 0.0) for a in mach.axes]])
    j, i = 3, 5
    q[0, mach.axis_names.index("X")] = gx.start + i * gx.step
    q[0, mach.axis_names.index("C")] = gc.start + j * gc.step
    want = t.corrections(q)[0]
    z = next(s for s in view.outputs if s.output == "Z")
    assert z.values[j][i] == pytest.approx(want[mach.axis_names.index("Z")] * 1e3, abs=1e-3)
    with pytest.raises(MapSliceError, match="not an axis"):
        slice_tables(payload, mach, "Q", None)  # type: ignore[arg-type]


def test_the_dashboard_shows_a_factored_map_as_the_ladder_computes_it() -> None:
    mach = machine("w C X Y b Z t", controller="fanuc",
                   travel_mm={"x": [0, 400], "y": [0, 300], "z": [-300, 0], "c": [-180, 180]},
                   pivots_mm={"C": [200.0, 150.0, -100.0]})
    model = MachineModel(mach.name, random_errors(mach, np.random.default_rng(8), 4.0))
    fm = build_for(mach, model, tolerance_um=1.0, kind="factored")
    assert isinstance(fm, FactoredMap)
    payload = decode_stored(encode(fm))
    assert isinstance(payload, FactoredPayload)
    view = slice_tables(payload, mach, "X", "C")
    assert view.kind == "factored" and view.encoding == "int32"
    gx = next(g for g in view.grid if g.name == "X")
    gc = next(g for g in view.grid if g.name == "C")
    q = np.array([[view.fixed.get(a.name, 0.0) for a in mach.axes]])
    q[0, mach.axis_names.index("X")] = gx.start + 4 * gx.step
    q[0, mach.axis_names.index("C")] = gc.start + 7 * gc.step
    want = fm.corrections(q)[0]
    for out in view.outputs:
        k = mach.axis_names.index(out.output)
        scale = 1e6 * np.pi / 180 if out.output == "C" else 1e3
        assert out.values[7][4] == pytest.approx(want[k] * scale, abs=1e-3)
    other = machine("w X Y b Z t", controller="fanuc")
    with pytest.raises(MapSliceError, match="not those of"):
        slice_tables(payload, other, "X", "Y")


def test_a_thermal_model_without_temperatures_still_gets_its_tables() -> None:
    mach = five_axis()
    model = thermal_model(mach.name)
    got = build_for(mach, model, {}, tolerance_um=1.0, controller="siemens")
    assert kind_of(got) == "tables"
    # a ladder gets them in its factored map, or (one that takes grids only) in its grid,
    # built at reference
    fanuc = build_for(mach, model, {}, tolerance_um=4.0, controller="fanuc")
    assert kind_of(fanuc) == "factored" and fanuc.thermal and carries_thermal(fanuc)
    grid = build_for(mach, model, {}, tolerance_um=4.0, controller="fanuc",
                     formats=MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL)
    assert kind_of(grid) == "grid" and grid.thermal and carries_thermal(grid)
    assert carries_thermal(encode(grid)) and not carries_thermal(encode(
        dataclasses.replace(grid, thermal=())))
    # one that takes version-1 grids only still needs today's temperatures
    with pytest.raises(MapBuildError, match="temperatures"):
        build_for(mach, model, {}, tolerance_um=4.0, controller="fanuc",
                  formats=MapEncoding.INT32_INCREMENTS)
