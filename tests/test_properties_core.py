"""Properties of the numeric core, over random machines, errors, seeds and noise:

1. the exact volumetric error and its first-order model differ by a second-order amount;
2. identification recovers the parameters within their stated uncertainties;
3. a grid map looked up by the machine at its nodes returns the solver's corrections,
   within the encoding's rounding;
4. the center's and the machine's evaluation of a grid map agree inside the travel
   (thermal records included).

Each property has a plain test beside it showing that its check fails on a deliberately
wrong input, so a green run means the property was checked, not skipped over.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from machine_sim.lookup import GridMap
from protocol.mapformat import decode_map, encode_map
from server.mapcodec import grid_to_payload
from tests.support.kinematics import arch, random_errors, random_q
from tests.support.properties import (
    FIVE_AXIS_CHAINS,
    THREE_AXIS_CHAINS,
    assert_nodes_match,
    assert_recovered,
    assert_second_order,
    make_machine,
    node_points,
    normalised_errors,
    random_layout,
    simulated_readings,
)
from volumetric.compensate.gridmap import ErrorMap, build_map
from volumetric.compensate.maps import STEP_TOL
from volumetric.compensate.solver import corrections
from volumetric.identify.design import design_params
from volumetric.identify.fit import fit, model_from_parameters
from volumetric.model.components import GeometricErrors, component_names
from volumetric.model.exact import VolumetricError
from volumetric.model.linear import linear_volumetric_error
from volumetric.model.machine import Machine
from volumetric.model.model import MachineModel, ThermalTerm

FAST = settings(max_examples=50, deadline=None)
pivots = st.fixed_dictionaries({
    k: st.tuples(*[st.floats(-80.0, 80.0)] * 3) for k in ("A", "B", "C")})


# 1. exact vs first order ---------------------------------------------------------------

@FAST
@given(chain=st.sampled_from(THREE_AXIS_CHAINS + FIVE_AXIS_CHAINS), piv=pivots,
       tool=st.floats(0.0, 250.0), size=st.floats(1.0, 50.0), seed=st.integers(0, 2**32 - 1))
def test_exact_and_first_order_error_agree_to_second_order(
        chain: str, piv: dict[str, tuple[float, float, float]], tool: float, size: float,
        seed: int) -> None:
    m = make_machine(chain, piv, tool)
    rng = np.random.default_rng(seed)
    assert_second_order(m, random_errors(m, rng, size), random_q(m, rng, 200), size)


@settings(max_examples=20, deadline=None)
@given(theta=st.tuples(st.floats(-45.0, 45.0), st.floats(-45.0, 45.0)),
       spindle=st.sampled_from(["S1", "S2"]), size=st.floats(1.0, 50.0),
       seed=st.integers(0, 2**32 - 1))
def test_exact_and_first_order_agree_to_second_order_on_each_spindle(
        theta: tuple[float, float], spindle: str, size: float, seed: int) -> None:
    """The arch-type two-spindle machine, spindle axes tilted in the y-z plane."""
    m = arch(*theta)
    rng = np.random.default_rng(seed)
    assert_second_order(m, random_errors(m, rng, size), random_q(m, rng, 200), size,
                        spindle=spindle)


def test_the_second_order_check_catches_a_first_order_slip() -> None:
    m = make_machine("w C A X b Y Z t", {"A": (0.0, 10.0, -50.0)})
    rng = np.random.default_rng(1)
    e, q = random_errors(m, rng, 10.0), random_q(m, rng, 200)
    assert_second_order(m, e, q, 10.0)  # the real first-order model passes

    def one_percent_off(mach: Machine, err: GeometricErrors, pts: np.ndarray,
                        spindle: str | None) -> VolumetricError:
        v = linear_volumetric_error(mach, err, pts, spindle=spindle)
        assert v.orientation_urad is not None
        return VolumetricError(1.01 * v.position_um, 1.01 * v.orientation_urad)

    with pytest.raises(AssertionError, match="ratio"):
        assert_second_order(m, e, q, 10.0, first_order=one_percent_off)


# 2. identification within its stated uncertainty ------------------------------------

ID_MACHINES = {  # chain, highest degree per component, readings: small, fast problems
    "3-axis": ("w X Y b Z t", 2, 600),
    "5-axis": ("w C A X b Y Z t", 1, 700),
}


def _identification_z(kind: str, seed: int, noise_um: float, noise_urad: float,
                      size: float, shift: float = 0.0) -> np.ndarray:
    """Normalised errors of a fit of simulated readings of a known model; ``shift`` (µm
    or µrad) moves the truth the fit is judged against away from the simulated one."""
    chain, cap, n = ID_MACHINES[kind]
    m = make_machine(chain, {"A": (0.0, 0.0, -50.0)})
    degrees = {c: cap for a in m.axes for c in component_names(a)}
    rng = np.random.default_rng(seed)
    layout = random_layout(m, rng, n)
    # which parameters these readings can separate depends on the layout alone: learn it
    # from a fit of pure noise, and give only those a true value (the others are fixed
    # at zero by the fit, so a true value there would leak into their partners)
    probe = fit(m, simulated_readings(m, layout, GeometricErrors(), np.zeros(3), noise_um,
                                      noise_urad, rng), degrees=degrees, select=False)
    identifiable = {p.name for p in probe.params}
    params = design_params(m, degrees=degrees)
    values = np.array([rng.normal(0.0, size) if p.name in identifiable else 0.0
                       for p in params])
    truth = dict(zip([p.name for p in params], values.tolist(), strict=True))
    geometry = model_from_parameters(m, params, values).geometry
    offset = np.array([truth[f"OFFSET_{c}"] for c in "XYZ"])
    result = fit(m, simulated_readings(m, layout, geometry, offset, noise_um, noise_urad,
                                       rng), degrees=degrees, select=False)
    assert {p.name for p in result.params} == identifiable
    name = result.params[0].name
    truth[name] += shift
    return normalised_errors(result, truth)


@settings(max_examples=25, deadline=None)
@given(kind=st.sampled_from(sorted(ID_MACHINES)), seed=st.integers(0, 2**32 - 1),
       noise_um=st.floats(0.05, 2.0), noise_urad=st.floats(0.1, 3.0),
       size=st.floats(0.5, 20.0))
def test_identification_recovers_parameters_within_their_uncertainty(
        kind: str, seed: int, noise_um: float, noise_urad: float, size: float) -> None:
    assert_recovered(_identification_z(kind, seed, noise_um, noise_urad, size))


def test_the_recovery_check_catches_a_wrong_truth_or_inflated_uncertainty() -> None:
    z = _identification_z("3-axis", 3, 0.5, 1.0, 5.0)
    assert_recovered(z)
    with pytest.raises(AssertionError, match="σ from the truth"):  # truth 1 µm off
        assert_recovered(_identification_z("3-axis", 3, 0.5, 1.0, 5.0, shift=1.0))
    with pytest.raises(AssertionError, match="RMS"):  # uncertainties stated 10 x too large
        assert_recovered(z / 10.0)
    with pytest.raises(AssertionError, match="σ from the truth"):  # 10 x too small
        assert_recovered(z * 10.0)


# 3. a grid map at its nodes returns the solver's corrections ------------------------

MAP_MACHINES = (*THREE_AXIS_CHAINS, "w B X b Y Z t")


def _grid_map(chain: str, seed: int, size: float, controller: str, tolerance_um: float,
              thermal: tuple[ThermalTerm, ...] = ()) -> tuple[Machine, GeometricErrors,
                                                               ErrorMap]:
    m = make_machine(chain, {"B": (0.0, 0.0, -30.0)})
    errors = random_errors(m, np.random.default_rng(seed), size)
    emap = build_map(m, MachineModel(m.name, errors, thermal), tolerance_um=tolerance_um,
                     controller=controller,  # type: ignore[arg-type]
                     seed=seed % 1000, thermal_in_map=bool(thermal))
    return m, errors, emap


@settings(max_examples=25, deadline=None)
@given(chain=st.sampled_from(MAP_MACHINES), seed=st.integers(0, 2**32 - 1),
       size=st.floats(0.5, 8.0), controller=st.sampled_from(["fanuc", "siemens"]),
       tolerance_um=st.sampled_from([0.5, 1.0, 2.0]))
def test_grid_map_at_its_nodes_returns_the_solvers_corrections(
        chain: str, seed: int, size: float, controller: str, tolerance_um: float) -> None:
    m, errors, emap = _grid_map(chain, seed, size, controller, tolerance_um)
    payload = decode_map(encode_map(grid_to_payload(emap)))  # as the machine receives it
    _, q = node_points(m, payload)
    # the solver stopped where the map build stops it (STEP_TOL, 10 nm steps; the tighter
    # default moves the corrections by < 1e-9 mm, measured): what is checked is the node
    # layout, the value order, the encoding and the machine's lookup
    assert_nodes_match(m, payload, corrections(m, errors, q, step_tol=STEP_TOL))


def test_the_node_check_catches_a_map_of_other_errors() -> None:
    m, errors, emap = _grid_map("w X Y b Z t", 4, 5.0, "siemens", 0.5)
    payload = grid_to_payload(emap)
    _, q = node_points(m, payload)
    assert_nodes_match(m, payload, corrections(m, errors, q, step_tol=STEP_TOL))
    other = random_errors(m, np.random.default_rng(5), 5.0)
    with pytest.raises(AssertionError, match="beyond the FLOAT32_MM rounding"):
        assert_nodes_match(m, payload, corrections(m, other, q, step_tol=STEP_TOL))
    # one increment off at the nodes is beyond the int32 rounding too
    fanuc = grid_to_payload(_grid_map("w X Y b Z t", 4, 5.0, "fanuc", 0.5)[2])
    exact = corrections(m, errors, q, step_tol=STEP_TOL)
    assert_nodes_match(m, fanuc, exact)
    with pytest.raises(AssertionError, match="beyond the INT32_INCREMENTS rounding"):
        assert_nodes_match(m, fanuc, exact + fanuc.increment_mm)


# 4. center-side and machine-side evaluation of a grid map agree ---------------------

def _center_and_machine(m: Machine, emap: ErrorMap, q: np.ndarray,
                        temps: dict[str, float], machine_temps: dict[str, float]
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The center's evaluation (interpolation plus thermal terms) and the machine's
    (:class:`GridMap` from the decoded payload), mm, (N, n_outputs) each."""
    center = emap.lookup(emap.select(q, m.axis_names))
    if emap.thermal:
        center = center + emap.thermal_correction(
            q[:, [m.axis_names.index(o) for o in emap.outputs]], temps)
    g = GridMap.from_payload(decode_map(encode_map(grid_to_payload(emap))), machine_temps)
    return center, g.lookup(q[:, [m.axis_names.index(a) for a in g.inputs]])



@pytest.mark.parametrize(("chain", "controller"), [("w C A X b Y Z t", "siemens"),
                                                   ("w X Y b Z A C t", "fanuc")])
def test_five_axis_grid_map_at_its_nodes_and_between_them(chain: str, controller: str) -> None:
    """Properties 3 and 4 on one 5-axis table-table and one head-head machine (a full-turn
    C in the grid): too slow to build for every hypothesis example."""
    m = make_machine(chain, {"A": (0.0, 0.0, -50.0), "C": (1.0, -2.0, 0.0)})
    errors = random_errors(m, np.random.default_rng(2), 1.0)
    emap = build_map(m, MachineModel(m.name, errors), tolerance_um=2.0,
                     controller=controller)  # type: ignore[arg-type]
    payload = decode_map(encode_map(grid_to_payload(emap)))
    assert len(payload.grid) == 5
    _, q = node_points(m, payload)
    assert_nodes_match(m, payload, corrections(m, errors, q, step_tol=STEP_TOL))
    inside = random_q(m, np.random.default_rng(3), 500)
    center, machine = _center_and_machine(m, emap, inside, {}, {})
    np.testing.assert_allclose(machine, center, rtol=0.0, atol=1e-12)

THERMAL = (ThermalTerm("thermal_expansion", "x", "T_x_C", 11.5, 20.0, 0.0),
           ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 22.0))


@settings(max_examples=25, deadline=None)
@given(chain=st.sampled_from(MAP_MACHINES), seed=st.integers(0, 2**32 - 1),
       size=st.floats(0.5, 8.0), controller=st.sampled_from(["fanuc", "siemens"]),
       with_thermal=st.booleans(), t_x=st.floats(15.0, 35.0), t_s=st.floats(15.0, 45.0))
def test_center_and_machine_evaluate_a_grid_map_alike(
        chain: str, seed: int, size: float, controller: str, with_thermal: bool,
        t_x: float, t_s: float) -> None:
    thermal = THERMAL if with_thermal else ()
    m, _, emap = _grid_map(chain, seed, size, controller, 2.0, thermal)
    q = random_q(m, np.random.default_rng(seed), 500)
    temps = {"T_x_C": t_x, "T_spindle_C": t_s}
    center, machine = _center_and_machine(m, emap, q, temps, temps)
    np.testing.assert_allclose(machine, center, rtol=0.0, atol=1e-12)


def test_the_evaluation_check_catches_a_machine_at_other_temperatures() -> None:
    m, _, emap = _grid_map("w X Y b Z t", 6, 5.0, "fanuc", 1.0, THERMAL)
    q = random_q(m, np.random.default_rng(6), 500)
    temps = {"T_x_C": 30.0, "T_spindle_C": 30.0}
    center, machine = _center_and_machine(m, emap, q, temps, temps)
    np.testing.assert_allclose(machine, center, rtol=0.0, atol=1e-12)
    center, machine = _center_and_machine(m, emap, q, temps, {"T_x_C": 30.0})
    with pytest.raises(AssertionError):
        np.testing.assert_allclose(machine, center, rtol=0.0, atol=1e-12)
