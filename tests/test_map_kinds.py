"""The ``tables`` map kind against the exact compensation: tolerance met at points the build
never saw (rotary axes over their whole travel), thermal terms applied without a rebuild,
backlash folded in, sizes far below the grid's, and inputs it cannot express refused."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from tests.support.compensate import realistic_arch_errors
from tests.support.kinematics import arch, machine, random_errors, random_q
from volumetric.compensate.gridmap import build_map
from volumetric.compensate.maps import MapBuildError, MapProblem
from volumetric.compensate.solver import Weights, corrections
from volumetric.compensate.tablesmap import TablesMap, build_tables_map
from volumetric.model.components import GeometricErrors, Polynomial, Sinusoid
from volumetric.model.machine import Machine
from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm

F64 = NDArray[np.float64]


def five_axis() -> Machine:
    """The demo's 5ax-04 chain and pivots."""
    return machine("w C A X b Y Z t",
                   travel_mm={"x": [0, 500], "y": [0, 300], "z": [-300, 0], "a": [-110, 110],
                              "c": [-180, 180]},
                   pivots_mm={"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]})


def worst_tip_um(t: TablesMap, model: MachineModel, q: F64,
                 temps: dict[str, float] | None = None) -> float:
    """Worst tool-tip error of the map's corrections against the exact model's, µm."""
    geo = model.geometry_at(temps)
    prob = MapProblem(t.machine, geo, t.weights, t.tool_mm, t.machine.travel_lo,
                      t.machine.travel_hi)
    exact = corrections(t.machine, geo, q, weights=t.weights, tool_mm=t.tool_mm)
    return float(prob.tip_um(q, t.corrections(q, temps) - exact).max())


@pytest.mark.parametrize("chain", ["w X Y b Z t", "five"])
@pytest.mark.parametrize("tolerance", [1.0, 0.1])
def test_tables_meet_the_tolerance_at_points_the_build_never_saw(chain: str,
                                                                  tolerance: float) -> None:
    mach = five_axis() if chain == "five" else machine(chain)
    model = MachineModel(mach.name, random_errors(mach, np.random.default_rng(4), 5.0))
    t = build_tables_map(mach, model, tolerance_um=tolerance, controller="siemens")
    assert t.report is not None and t.report.kind == "tables"
    assert t.report.worst_error_um <= tolerance
    q = random_q(mach, np.random.default_rng(99), 3000)
    assert worst_tip_um(t, model, q) <= tolerance
    # the reference without tables is tens of µm: the check can fail
    prob = MapProblem(mach, model.geometry, t.weights, t.tool_mm, mach.travel_lo,
                      mach.travel_hi)
    assert prob.tip_um(q, corrections(mach, model.geometry, q)).max() > 20 * tolerance


def test_tables_are_a_fraction_of_the_grid_for_five_axes_and_never_larger_for_three() -> None:
    five = five_axis()
    model5 = MachineModel(five.name, random_errors(five, np.random.default_rng(4), 5.0))
    t5 = build_tables_map(five, model5, tolerance_um=1.0, controller="siemens")
    g5 = build_map(five, model5, tolerance_um=1.0, controller="siemens")
    assert g5.report is not None
    # 4 bytes per table value against 4 bytes per node and output
    assert 4 * t5.entries * 20 < g5.report.bytes
    three = machine("w X Y b Z t")
    model3 = MachineModel(three.name, random_errors(three, np.random.default_rng(5), 5.0))
    t3 = build_tables_map(three, model3, tolerance_um=0.5, controller="siemens")
    g3 = build_map(three, model3, tolerance_um=0.5, controller="siemens")
    assert g3.report is not None
    assert 4 * t3.entries < g3.report.bytes


def test_constant_and_absent_components_cost_one_value_or_nothing() -> None:
    mach = machine("w X Y b Z t")
    geo = GeometricErrors({"EXX": Polynomial((3.0,)), "EYY": Sinusoid(3.0, 10.0)},
                          {"EC0Y": 20.0})
    t = build_tables_map(mach, MachineModel(mach.name, geo), tolerance_um=0.1,
                         controller="siemens")
    names = {s.name: s for s in t.tables}
    assert set(names) == {"EXX", "EYY"}
    assert names["EXX"].values.size == 1
    # a 10 mm pitch over 300 mm of travel needs about 8 or more nodes per period
    assert names["EYY"].values.size >= 8 * 30
    assert t.locations == {"EC0Y": 20.0}


def test_thermal_terms_travel_with_the_map_and_follow_the_temperature() -> None:
    mach = machine("w X Y b Z t")
    rigid = random_errors(mach, np.random.default_rng(6), 5.0)
    model = MachineModel(mach.name, rigid, (
        ThermalTerm("thermal_drift", "z", "T_s_C", -2.5, 20.0),
        ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0, 0.0)))
    t = build_tables_map(mach, model, {"T_s_C": 20.0, "T_x_C": 20.0}, tolerance_um=0.2,
                         controller="siemens")
    assert {term.sensor for term in t.thermal} == {"T_s_C", "T_x_C"}
    q = random_q(mach, np.random.default_rng(7), 2000)
    warm = {"T_s_C": 28.0, "T_x_C": 25.0}
    # the same map, evaluated at other temperatures, meets the tolerance there
    assert worst_tip_um(t, model, q, warm) <= 0.2
    cold = t.corrections(q, {"T_s_C": 20.0, "T_x_C": 20.0})
    moved = t.corrections(q, warm)
    # z follows the spindle drift: -(-2.5 µm/K · 8 K) = +20 µm of correction
    assert np.allclose(moved[:, 2] - cold[:, 2], 0.020, atol=2e-4)


def test_backlash_is_folded_into_the_positive_approach_and_sent_as_the_reversal() -> None:
    mach = machine("w X Y b Z t")
    geo = random_errors(mach, np.random.default_rng(8), 3.0)
    plain = build_tables_map(mach, MachineModel(mach.name, geo), tolerance_um=0.1,
                             controller="siemens")
    lagging = build_tables_map(mach, MachineModel(mach.name, geo, (BacklashTerm("y", 6.0),)),
                               tolerance_um=0.1, controller="siemens")
    q = random_q(mach, np.random.default_rng(9), 500)
    diff = lagging.corrections(q) - plain.corrections(q)
    assert np.allclose(diff[:, 1], 0.003, atol=2e-4)  # +B/2 on y
    assert np.allclose(diff[:, [0, 2]], 0.0, atol=2e-4)
    assert lagging.reversal[1] == pytest.approx(-0.006)
    assert plain.reversal[1] is None


def test_the_arch_machine_gets_tables_for_both_spindles() -> None:
    mach = arch(0.0, 30.0)
    geo = realistic_arch_errors(mach, np.random.default_rng(7))
    w = Weights.parse(mach, [1, 1, 1, 10, 10, 10])
    model = MachineModel(mach.name, geo)
    t = build_tables_map(mach, model, tolerance_um=0.2, weights=w, controller="siemens")
    assert worst_tip_um(t, model, random_q(mach, np.random.default_rng(2), 2000)) <= 0.2


def test_what_the_tables_cannot_express_is_refused_by_name() -> None:
    mach = five_axis()
    model = MachineModel(mach.name, GeometricErrors(), (BacklashTerm("c", 10.0),))
    with pytest.raises(MapBuildError, match="backlash of a rotary axis"):
        build_tables_map(mach, model, controller="siemens")
    with pytest.raises(MapBuildError, match="tolerance"):
        build_tables_map(mach, MachineModel(mach.name, GeometricErrors()), tolerance_um=-1.0)
