"""Thermal terms travel with grid maps (format version 3): the center builds a Fanuc grid
at the terms' references and carries them; applied at other temperatures as the ladder
does (interpolated values plus the terms' corrections, rounded together to increments) it
meets the exact model within its tolerance plus one increment, without a rebuild; the
simulated machine's GridMap applies exactly the model's terms, also on an axis that is
not a grid dimension."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from machine_sim.campaign import map_compensation
from machine_sim.lookup import GridMap
from protocol import MapEncoding, decode_map, encode_map
from protocol.mapformat import ErrorMapPayload, GridAxis, OutputAxis, ThermalRecord, pack_values
from server.mapcodec import build_for, carries_thermal, encode, grid_from_payload
from tests.support.kinematics import machine, random_errors, random_q
from volumetric.compensate.gridmap import ErrorMap, build_map
from volumetric.compensate.solver import compensate
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
INC = 0.001  # mm, Fanuc IS-B


def vmc() -> Machine:
    return machine("w X Y b Z t")


def thermal_model(mach: Machine) -> MachineModel:
    """Random geometry plus a spindle drift along z and a ballscrew expansion of x."""
    base = MachineModel("m", random_errors(mach, np.random.default_rng(5), 5.0))
    return base.with_terms(
        ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 20.0),
        ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0,
                    float(mach.travel_lo[0])))


GRID_LADDER = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL
"""A Fanuc ladder that takes grids with thermal records (not factored maps)."""


def tip_um(mach: Machine, q: F64, ddq: F64) -> F64:
    d = np.einsum("nij,nj->ni", jacobian(mach, q)[:, :3], ddq)
    out: F64 = np.linalg.norm(d, axis=1)
    return out


def applied_by_ladder(m: ErrorMap, q: F64, temps: dict[str, float]) -> F64:
    """What a ladder applies: lookup plus the thermal corrections, rounded together."""
    raw = m.lookup(m.select(q, ("X", "Y", "Z"))) + m.thermal_correction(q, temps)
    out: F64 = np.rint(raw / INC) * INC
    return out


def test_fanuc_grid_carries_the_terms_and_holds_at_other_temperatures() -> None:
    mach = vmc()
    model = thermal_model(mach)
    tol = 0.5
    m = build_for(mach, model, {"T_spindle_C": 20.0, "T_x_C": 20.0}, tolerance_um=tol,
                  controller="fanuc", formats=GRID_LADDER)
    assert isinstance(m, ErrorMap) and carries_thermal(m)
    assert {t.sensor for t in m.thermal} == {"T_spindle_C", "T_x_C"}
    assert m.report is not None and m.report.worst_error_um <= tol + INC * 1e3
    data = encode(m)
    assert data[4:6] == b"\x03\x00" and m.report.bytes == len(data) == m.nbytes
    back = grid_from_payload(decode_map(data))
    assert back.thermal == m.thermal and np.array_equal(back.values, m.values)
    q = random_q(mach, np.random.default_rng(11), 3000)
    worst = []
    for temps in ({"T_spindle_C": 26.0, "T_x_C": 23.0}, {"T_spindle_C": 34.5, "T_x_C": 18.0}):
        exact = compensate(mach, model.geometry_at(temps), q).dq
        stale = np.rint(m.lookup(m.select(q, mach.axis_names)) / INC) * INC
        err = tip_um(mach, q, applied_by_ladder(m, q, temps) - exact)
        without = tip_um(mach, q, stale - exact)
        worst.append(float(err.max()))
        assert without.max() > 10.0  # the temperatures matter: a v1 grid would be off
        assert err.max() <= tol + INC * 1e3  # the same map, no rebuild
    print(f"\ngrid + thermal records, Fanuc, {tol} µm: worst tool tip at two other "
          f"temperatures {worst[0]:.3f} / {worst[1]:.3f} µm, {len(data)} bytes")


def test_the_report_judges_the_terms_at_the_given_temperatures() -> None:
    mach = vmc()
    model = thermal_model(mach)
    hot = {"T_spindle_C": 31.0, "T_x_C": 27.0}
    m = build_map(mach, model, hot, tolerance_um=0.5, controller="fanuc",
                  thermal_in_map=True)
    assert m.temperatures == hot and m.report is not None
    q = random_q(mach, np.random.default_rng(12), 4000)
    exact = compensate(mach, model.geometry_at(hot), q).dq
    measured = float(tip_um(mach, q, applied_by_ladder(m, q, hot) - exact).max())
    # the report's figure is the same kind of number: close to what we measure here
    assert abs(m.report.worst_error_um - measured) < 0.25
    # a grid built at the references is the same grid: the terms are not in the values
    ref = build_map(mach, model, None, tolerance_um=0.5, controller="fanuc",
                    thermal_in_map=True)
    assert np.array_equal(ref.values, m.values)
    with pytest.raises(ValueError, match="temperatures"):
        build_map(mach, model, None, tolerance_um=0.5, controller="fanuc")


def test_a_grid_only_machine_still_gets_a_version_1_grid() -> None:
    mach = vmc()
    model = thermal_model(mach)
    temps = {"T_spindle_C": 22.0, "T_x_C": 21.0}
    m = build_for(mach, model, temps, tolerance_um=0.5, controller="fanuc",
                  formats=MapEncoding.INT32_INCREMENTS)
    assert isinstance(m, ErrorMap) and not m.thermal and not carries_thermal(m)
    assert encode(m)[4:6] == b"\x01\x00" and not carries_thermal(encode(m))


def test_machine_gridmap_applies_the_models_terms() -> None:
    mach = vmc()
    model = thermal_model(mach)
    m = build_for(mach, model, {}, tolerance_um=1.0, controller="fanuc", formats=GRID_LADDER)
    assert isinstance(m, ErrorMap)
    p = decode_map(encode(m))
    cold = GridMap.from_payload(p)
    temps = {"T_spindle_C": 27.0, "x": 24.0}  # a column name, or the sensor's own name
    hot = GridMap.from_payload(p, temps)
    assert hot.inputs == cold.inputs
    q = random_q(mach, np.random.default_rng(13), 500)
    cols = [mach.axis_names.index(a) for a in hot.inputs]
    delta = hot.lookup(q[:, cols]) - cold.lookup(q[:, cols])
    want = np.zeros(q.shape)
    for t in model.terms:
        if isinstance(t, ThermalTerm):
            j = mach.axis_names.index(t.axis.upper())
            celsius = temps["T_spindle_C"] if t.sensor == "T_spindle_C" else temps["x"]
            want[:, j] -= 1e-3 * np.asarray(t.component(celsius)(q[:, j]))
    np.testing.assert_allclose(delta, want, rtol=0, atol=1e-12)
    assert np.abs(want).max() > 0.01  # 10 µm and more: a move the test sees
    cold.set_temperatures(temps)  # the scan's constants follow new temperatures in place
    np.testing.assert_array_equal(cold.lookup(q[:, cols]), hot.lookup(q[:, cols]))


def test_an_expansion_axis_outside_the_grid_is_looked_up_by_its_position() -> None:
    mach = vmc()
    # the grid depends on Y alone; X expands with T_x_C (q_min = 0)
    p = ErrorMapPayload("m", 1, MapEncoding.INT32_INCREMENTS, (GridAxis("Y", 0.0, 100.0, 2),),
                        (OutputAxis("X"), OutputAxis("Y"), OutputAxis("Z")),
                        pack_values(MapEncoding.INT32_INCREMENTS, [1, 2, 3, 4, 5, 6]), INC,
                        thermal=(ThermalRecord("x", "X", 2, 10.0, 20.0, 0.0),
                                 ThermalRecord("spindle", "Z", 1, -2.0, 20.0)))
    assert decode_map(encode_map(p)) == p
    g = GridMap.from_payload(decode_map(encode_map(p)), {"x": 25.0, "T_spindle_C": 23.0})
    assert g.grid == ("Y",) and g.inputs == ("Y", "X")
    got = g.lookup(np.array([[50.0, 400.0]]))[0]
    # x: 2.5 counts at mid-grid, then -10·5·400·1e-6 mm; z: 4.5 counts + 2·3·1e-3 mm
    np.testing.assert_allclose(got, [0.0025 - 0.02, 0.0035, 0.0045 + 0.006], atol=1e-12)
    with pytest.raises(ValueError, match="positions of axes Y X"):
        g.lookup(np.array([[50.0]]))
    # the campaign's shift takes the positions in the machine's order, rounded to counts
    q = np.zeros((1, 3))
    q[0, mach.axis_names.index("X")] = 400.0
    q[0, mach.axis_names.index("Y")] = 50.0
    shift = map_compensation(mach, g, increment_mm=INC)(q, np.zeros((1, 3), dtype=np.int8))
    np.testing.assert_allclose(shift[0], np.rint(got / INC) * INC, atol=1e-12)
