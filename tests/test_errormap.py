"""Error maps: lookup, grid choice against the exact compensation, quantisation, limits, the
payload round trip and the ``ednc map`` / ``ednc compensate`` commands."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from protocol.mapformat import decode_map, encode_map
from server.mapcodec import grid_from_payload, grid_to_payload
from tests.support.compensate import realistic_arch_errors
from tests.support.kinematics import arch, machine, random_errors, random_q
from volumetric.compensate.gridmap import ErrorMap, GridDim, MapBuildError, build_map
from volumetric.compensate.solver import Weights, compensate
from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import GeometricErrors, Polynomial, Sinusoid
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine
from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm

F64 = NDArray[np.float64]
EDNC = Path(sys.executable).parent / "ednc"


def vmc() -> Machine:
    return machine("w X Y b Z t")


def vmc_model(seed: int = 1, size: float = 5.0) -> MachineModel:
    return MachineModel("m", random_errors(vmc(), np.random.default_rng(seed), size))


# --- lookup ---

def naive_lookup(m: ErrorMap, p: F64) -> F64:
    """Per point: find the cell, weigh its 2^D corners; independent of the vectorised code."""
    out = np.zeros(len(m.outputs))
    base, frac = [], []
    for g, x in zip(m.grid, p, strict=True):
        x = min(max(x, g.start), g.stop)
        i = min(int((x - g.start) // g.step), g.count - 2)
        base.append(i)
        frac.append((x - g.start) / g.step - i)
    for corner in np.ndindex(*([2] * len(m.grid))):
        w = math.prod(f if c else 1 - f for c, f in zip(corner, frac, strict=True))
        out += w * m.values[tuple(b + c for b, c in zip(base, corner, strict=True))]
    return out


def handmade_map(values: F64, grid: tuple[GridDim, ...]) -> ErrorMap:
    k = values.shape[-1]
    return ErrorMap("m", 1, "siemens", grid, tuple(f"O{i}" for i in range(k)), values, None,
                    (1.0,) * k, (None,) * k)


def test_lookup_reproduces_multilinear_functions_and_clamps_at_the_edges() -> None:
    grid = (GridDim("X", 0.0, 50.0, 11), GridDim("Y", -10.0, 20.0, 4), GridDim("C", 0, 90, 5))
    nodes = np.meshgrid(*[g.nodes() for g in grid], indexing="ij")
    x, y, c = nodes

    def f(x: F64, y: F64, c: F64) -> F64:  # multilinear: interpolation is exact
        return np.stack([1 + 2e-3 * x - 3e-3 * y + 1e-5 * x * y * c, 0.5 * c - x * y], -1)

    m = handmade_map(f(x, y, c), grid)
    rng = np.random.default_rng(0)
    p = np.column_stack([rng.uniform(0, 500, 200), rng.uniform(-10, 50, 200),
                         rng.uniform(0, 360, 200)])
    np.testing.assert_allclose(m.lookup(p), f(p[:, 0], p[:, 1], p[:, 2]), rtol=1e-12,
                               atol=1e-9)
    outside = np.array([[-100.0, 80.0, 400.0], [600.0, -50.0, -5.0]])
    clamped = np.array([[0.0, 50.0, 360.0], [500.0, -10.0, 0.0]])
    np.testing.assert_allclose(m.lookup(outside), m.lookup(clamped))
    for row in np.vstack([p[:20], outside]):
        np.testing.assert_allclose(m.lookup(row)[0], naive_lookup(m, row), atol=1e-12)


def test_lookup_refuses_wrong_shape_and_nan() -> None:
    m = handmade_map(np.zeros((2, 2, 1)), (GridDim("X", 0, 1, 2), GridDim("Y", 0, 1, 2)))
    with pytest.raises(ValueError, match=r"shape \(N, 2\) for axes X Y"):
        m.lookup(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="NaN"):
        m.lookup([[0.0, float("nan")]])
    with pytest.raises(MapBuildError, match="count must be an int >= 2"):
        GridDim("X", 0, 1, 1)


# --- the map against the exact compensation ---

def tip_error_um(mach: Machine, q: F64, ddq: F64) -> F64:
    """Largest tool-tip displacement over the spindles caused by correction errors ddq."""
    worst = np.zeros(q.shape[0])
    for br in mach.branches:
        d = np.einsum("nij,nj->ni", jacobian(mach, q, spindle=br.name)[:, :3], ddq)
        worst = np.maximum(worst, np.linalg.norm(d, axis=1))
    return worst


@pytest.mark.parametrize("tolerance", [0.5, 0.2])
def test_three_axis_map_meets_the_tolerance_at_random_points(tolerance: float) -> None:
    mach, model = vmc(), vmc_model()
    m = build_map(mach, model, tolerance_um=tolerance, controller="siemens")
    assert m.report is not None
    q = random_q(mach, np.random.default_rng(99), 3000)
    exact = compensate(mach, model.geometry, q).dq
    err_um = np.linalg.norm(m.lookup(m.select(q, mach.axis_names)) - exact, axis=1) * 1e3
    assert np.abs(exact).max() * 1e3 > 10 * tolerance  # the map has work to do
    assert err_um.max() <= tolerance
    assert m.report.worst_interpolation_um <= tolerance
    assert m.report.nodes == m.nodes == m.values.shape[0] * m.values.shape[1] * m.values.shape[2]
    assert m.report.bytes == len(encode_map(grid_to_payload(m)))


def test_a_tighter_tolerance_costs_more_nodes() -> None:
    mach, model = vmc(), vmc_model()
    coarse = build_map(mach, model, tolerance_um=1.0, controller="siemens")
    fine = build_map(mach, model, tolerance_um=0.1, controller="siemens")
    assert fine.nodes > 2 * coarse.nodes


def test_arch_map_meets_the_tolerance_for_both_spindles() -> None:
    mach = arch(0.0, 30.0)
    geo = realistic_arch_errors(mach, np.random.default_rng(7))
    w = Weights.parse(mach, [1, 1, 1, 10, 10, 10])
    m = build_map(mach, MachineModel("arch", geo), tolerance_um=0.5, weights=w,
                  controller="siemens")
    assert m.outputs == ("X", "Y", "Z1", "Z2")
    q = random_q(mach, np.random.default_rng(5), 2000)
    exact = compensate(mach, geo, q, weights=w).dq
    assert tip_error_um(mach, q, m.lookup(m.select(q, mach.axis_names)) - exact).max() <= 0.5


def test_an_axis_the_correction_does_not_depend_on_is_no_grid_dimension() -> None:
    mach = vmc()
    # errors of X only, and a Z straightness that depends on z alone: Y plays no part
    geo = GeometricErrors({"EXX": Polynomial((2.0, 0.03, -4e-5)),
                           "EYX": Polynomial((0.0, 0.0, 6e-5)),
                           "EXZ": Polynomial((0.0, 0.02))})
    m = build_map(mach, MachineModel("m", geo), controller="siemens")
    assert m.dims == ("X", "Z")
    assert m.grid[1].count == 2  # EXZ is linear in z: two nodes interpolate it exactly
    # the arch machine weighing spindle 1 alone: the correction ignores z2
    a = arch(0.0, 30.0)
    geo_a = realistic_arch_errors(a, np.random.default_rng(3))
    ma = build_map(a, MachineModel("arch", geo_a),
                   weights=Weights.parse(a, [1, 1, 1, 0, 0, 0]), controller="siemens")
    assert "Z2" not in ma.dims
    assert np.all(ma.values[..., 3] == 0.0)


def test_periodic_error_needs_nodes_on_its_axis_only() -> None:
    mach = vmc()
    geo = GeometricErrors({"EYY": Sinusoid(3.0, 100.0)})  # 3 µm ballscrew pitch error on y
    m = build_map(mach, MachineModel("m", geo), tolerance_um=0.5, controller="siemens")
    assert m.dims == ("Y",)
    # a sinusoid of amplitude a sampled at h errs by up to a (πh/p)²/2: h <= 18 mm
    assert m.grid[0].step <= 100.0 / math.pi * math.sqrt(2 * 0.5 / 3.0)


# --- thermal terms and backlash ---

def test_map_follows_the_temperature_through_the_model() -> None:
    mach = vmc()
    alpha = 11.5  # µm/(m·K): steel
    model = MachineModel("m", GeometricErrors(), (
        ThermalTerm("thermal_expansion", "x", "T_x_C", alpha, 20.0, 0.0),))
    cold = build_map(mach, model, {"T_x_C": 20.0}, controller="siemens")
    warm = build_map(mach, model, {"T_x_C": 28.0}, controller="siemens")
    q = random_q(mach, np.random.default_rng(2), 500)
    dx = (warm.lookup(warm.select(q, mach.axis_names))
          - cold.lookup(cold.select(q, mach.axis_names)))[:, 0]
    # the scale grows by α ΔT: the correction pulls x back by that much
    np.testing.assert_allclose(dx * 1e3, -alpha * 8.0 * q[:, 0] * 1e-3, atol=0.01)
    assert warm.temperatures == {"T_x_C": 28.0}
    with pytest.raises(MapBuildError, match="T_x_C"):
        build_map(mach, model, {}, controller="siemens")


def test_backlash_travels_as_the_reversal_of_its_axis() -> None:
    mach, model = vmc(), vmc_model().with_terms(BacklashTerm("x", 9.8))
    fanuc = build_map(mach, model, controller="fanuc")
    siemens = build_map(mach, model, controller="siemens")
    rigid = build_map(mach, vmc_model(), controller="siemens")
    # a lagging axis: the negative approach needs 9.8 µm less correction than the positive
    assert fanuc.reversal == (-0.01, None, None)  # -9.8 µm in 0.001 mm counts
    assert siemens.reversal[0] == pytest.approx(-0.0098, rel=1e-7)
    assert grid_to_payload(fanuc).outputs[0].reversal == -10
    # and the values are the positive-approach corrections: the mean plus half of it
    shift = siemens.values[..., 0] - rigid.values[..., 0]
    np.testing.assert_allclose(shift, 0.0049, atol=1e-6)


# --- quantisation and limits ---

def test_fanuc_values_are_whole_increments_and_siemens_float32() -> None:
    mach, model = vmc(), vmc_model()
    for inc in (0.001, 0.0001):
        m = build_map(mach, model, controller="fanuc", increment=inc)
        assert m.report is not None
        counts = m.values / inc
        np.testing.assert_allclose(counts, np.rint(counts), atol=1e-6)
        # quantisation adds at most half an increment per axis to the interpolation error
        bound = m.report.worst_interpolation_um + 0.5 * inc * 1e3 * math.sqrt(3)
        assert m.report.worst_error_um <= bound
    s = build_map(mach, model, controller="siemens")
    np.testing.assert_array_equal(s.values, s.values.astype(np.float32))


def test_corrections_beyond_the_limit_are_clamped_and_counted() -> None:
    mach = vmc()
    geo = GeometricErrors({"EXX": Polynomial((400.0, 1.0))})  # 0.4 mm + 1 µm/mm: up to 0.9
    m = build_map(mach, MachineModel("m", geo), controller="fanuc", limit_mm=0.5)
    assert m.report is not None
    x = m.grid[0].nodes()
    over = 0.4 + 1e-3 * x > 0.5
    assert over.any() and not over.all()
    np.testing.assert_allclose(m.values[over, 0], -0.5)
    assert m.report.clamped_nodes == int(over.sum()) * m.nodes // m.grid[0].count
    assert np.abs(m.values).max() <= 0.5
    roomy = build_map(mach, MachineModel("m", geo), controller="fanuc", limit_mm=1.0)
    assert roomy.report is not None and roomy.report.clamped_nodes == 0


# --- payload round trip ---

@pytest.mark.parametrize("controller", ["fanuc", "siemens"])
def test_payload_round_trip(controller: str) -> None:
    mach = arch(0.0, 30.0)
    geo = realistic_arch_errors(mach, np.random.default_rng(4))
    model = MachineModel("arch", geo, (BacklashTerm("y", 6.3),))
    m = build_map(mach, model, tolerance_um=1.0, controller=controller,  # type: ignore[arg-type]
                  version=7, valid_s=3600)
    wire = encode_map(grid_to_payload(m))
    back = grid_from_payload(decode_map(wire))
    assert back == m
    assert back.report is None
    assert back.controller == controller and back.version == 7 and back.valid_s == 3600
    q = random_q(mach, np.random.default_rng(1), 100)
    np.testing.assert_array_equal(back.lookup(back.select(q, mach.axis_names)),
                                  m.lookup(m.select(q, mach.axis_names)))


# --- bad input ---

def test_bad_models_and_parameters_are_refused_by_name() -> None:
    mach = vmc()
    data = vmc_model().to_json()
    data["locations"]["EC0Y"] = float("nan")
    with pytest.raises(ComponentErrorSpecError, match=r"EC0Y = nan is not finite"):
        build_map(mach, MachineModel.from_json(data))
    nan_term = MachineModel("m", GeometricErrors(), (
        ThermalTerm("thermal_drift", "z", "T_s_C", float("nan"), 20.0),))
    with pytest.raises(MapBuildError, match=r"term 0 \(thermal_drift, axis z\): coefficient"):
        build_map(mach, nan_term, {"T_s_C": 25.0})
    with pytest.raises(MapBuildError, match="tolerance"):
        build_map(mach, vmc_model(), tolerance_um=0.0)
    with pytest.raises(MapBuildError, match="model is for machine 'other'"):
        build_map(mach, MachineModel("other", GeometricErrors()))
    with pytest.raises(MapBuildError, match="over the 4000-byte map limit"):
        build_map(mach, vmc_model(), tolerance_um=0.01, max_bytes=4000)
    with pytest.raises(MapBuildError, match=r"backlash for axes \['q'\]"):
        build_map(mach, vmc_model().with_terms(BacklashTerm("q", 3.0)))


# --- the commands ---

@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    mach = {"name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.21",
            "chain": "w X Y b Z t", "travel_mm": {"x": [0, 500], "y": [0, 300],
                                                  "z": [-300, 0]},
            "tool_length_mm": 100.0}
    model = vmc_model().with_terms(
        ThermalTerm("thermal_expansion", "x", "T_x_C", 11.0, 20.0, 0.0),
        BacklashTerm("x", 9.8))
    data = model.to_json()
    data["machine"] = "vmc-01"
    (tmp_path / "m.json").write_text(json.dumps(mach))
    (tmp_path / "model.json").write_text(json.dumps(data))
    return tmp_path / "m.json", tmp_path / "model.json"


def ednc(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(EDNC), *map(str, args)], capture_output=True, text=True)


def test_map_command_writes_a_payload_and_reports_it(files: tuple[Path, Path],
                                                     tmp_path: Path) -> None:
    mach, model = files
    out = tmp_path / "vmc.map"
    args = ["map", "--machine", mach, "--model", model, "--out", out,
            "--temperature", "T_x_C=23.5", "--tolerance-um", "0.4", "--kind", "grid"]
    # Fanuc's 1 µm increments leave more than 0.4 µm as sent: at the terminal that stops
    # with the reason and no map written...
    refused = ednc(*args)
    assert refused.returncode == 2 and "--allow-over-tolerance" in refused.stderr
    assert not out.exists()
    assert ednc(*args, "--allow-over-tolerance").returncode == 0 and out.exists()
    out.unlink()
    # ...while --json, the stable interface other tools call (formats.md §3), writes the map
    # and says so in the JSON and loudly on stderr
    r = ednc(*args, "--json")
    assert r.returncode == 0, r.stderr
    assert "warning" in r.stderr
    info = json.loads(r.stdout)
    assert info["over_tolerance"] is True and info["kind"] == "grid"
    assert info["worst_error_um"] > 0.4
    payload = decode_map(out.read_bytes())
    assert info["bytes"] == len(out.read_bytes())
    assert info["nodes"] == math.prod(g.count for g in payload.grid)
    assert info["worst_interpolation_um"] <= 0.4
    assert info["controller"] == "fanuc" and payload.increment_mm == 0.001
    assert info["temperatures"] == {"T_x_C": 23.5}
    assert payload.outputs[0].reversal == -10


def test_compensate_command_prints_corrections_and_residuals(files: tuple[Path, Path],
                                                             tmp_path: Path) -> None:
    mach, model = files
    pts = tmp_path / "p.csv"
    pts.write_text("x_mm,y_mm,z_mm,note\n100,50,-20,a\n400,250,-280,b\n")
    r = ednc("compensate", "--machine", mach, "--model", model, "--points", pts,
             "--temperature", "T_x_C=20", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert [p["q"] for p in out["points"]] == [{"x": 100.0, "y": 50.0, "z": -20.0},
                                               {"x": 400.0, "y": 250.0, "z": -280.0}]
    one = ednc("compensate", "--machine", mach, "--model", model, "--point",
               "z=-20,x=100,y=50", "--temperature", "T_x_C=20", "--json")
    assert json.loads(one.stdout)["points"][0] == out["points"][0]
    c = out["points"][0]
    # the correction of the positive approach (the default): the errors' negative plus half
    # the model's backlash of x (9.8 µm), as the maps and ednc lookup apply it
    assert out["approach"] == "+" and out["backlash_um"] == {"x": 9.8}
    half = np.array([out["backlash_um"].get(k, 0.0) / 2 for k in "xyz"])
    assert np.allclose([c["correction"][k] * 1e3 for k in "xyz"],
                       -np.array(c["error_um"]["main"]) + half, atol=0.01)
    assert max(out["max_residual_um"]["main"]) < 1e-3


@pytest.mark.parametrize(("args", "message"), [
    (["compensate", "--point", "x=1,q=2,z=3"], "unknown axis 'q'; machine 'vmc-01' has axes x y z"),
    (["compensate", "--point", "1,2"], "expected 3 values for axes x y z"),
    (["compensate", "--point", "1,2,3", "--weights", "1,1,1,10"],
     "--weights: weights: machine 'vmc-01' has 1 tool tip"),
    (["compensate", "--point", "1,2,3", "--temperature", "T_x_C=hot"], "'hot' is not a number"),
    (["compensate"], "give either --points P.csv or --point"),
    (["map"], "needs the temperatures of T_x_C"),
    (["map", "--temperature", "T_x_C=20", "--temperature", "T_q_C=3"],
     "--temperature T_q_C: not a sensor of the model (it uses T_x_C)"),
    (["map", "--temperature", "T_x_C=20", "--controller", "heidenhain"], "expected fanuc or"),
])
def test_commands_refuse_bad_input_in_one_line(files: tuple[Path, Path], tmp_path: Path,
                                               args: list[str], message: str) -> None:
    mach, model = files
    extra = ["--out", str(tmp_path / "x.bin")] if args[0] == "map" else []
    r = ednc(args[0], "--machine", mach, "--model", model, *args[1:], *extra)
    assert r.returncode == 2
    assert message in r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr


def test_commands_refuse_a_model_with_nan_naming_the_entry(files: tuple[Path, Path]) -> None:
    mach, model = files
    data = json.loads(model.read_text())
    data["components"]["EXX"]["coefficients"][1] = float("nan")
    model.write_text(json.dumps(data))  # json writes NaN, which Python's reader accepts
    r = ednc("map", "--machine", mach, "--model", model, "--temperature", "T_x_C=20")
    assert r.returncode == 2
    assert "components.EXX" in r.stderr and "finite" in r.stderr


def test_build_map_within_relaxes_the_tolerance_until_the_map_fits() -> None:
    from volumetric.compensate.gridmap import MapTooLargeError, build_map_within

    mach, model = vmc(), vmc_model()
    tight = build_map(mach, model, tolerance_um=0.5, controller="siemens")
    assert tight.report is not None
    limit = tight.report.bytes - 1  # the 0.5 µm map no longer fits
    with pytest.raises(MapTooLargeError):
        build_map(mach, model, tolerance_um=0.5, controller="siemens", max_bytes=limit)
    relaxed = build_map_within(mach, model, tolerance_um=0.5, controller="siemens",
                               max_bytes=limit)
    assert relaxed.report is not None
    assert relaxed.report.tolerance_um == 1.0 and relaxed.report.bytes <= limit
    assert relaxed.report.worst_interpolation_um <= 1.0
