"""``ednc lookup``: what the endpoint applies, for a tables map (against the center's
solver) and a grid map (against the map's own nodes), and one clear line for bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from protocol import (
    ErrorMapPayload,
    GridAxis,
    MapEncoding,
    OutputAxis,
    ThermalRecord,
    encode_payload,
    pack_values,
)
from tests.support.sim_tables import sample, siemens_5ax, tables_payload
from volumetric.compensate.solver import Weights, corrections
from volumetric.model.components import GeometricErrors, Polynomial, add_components


def ednc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()", *args],
                          capture_output=True, text=True, timeout=300)


def test_tables_map_corrections_are_the_centers(tmp_path: Path) -> None:
    m = siemens_5ax()
    e, tables = sample(m, 5)
    w = Weights.default(m)
    records = (ThermalRecord("T_spindle_C", "Z", 1, -2.0, 20.0),)
    (tmp_path / "map.bin").write_bytes(encode_payload(
        tables_payload(m, tables, dict(e.locations), w, thermal=records)))
    rng = np.random.default_rng(0)
    q = rng.uniform(m.travel_lo, m.travel_hi, (12, 5))
    header = "c_deg,a,x_mm,y,z,comment"  # units optional, extra columns ignored
    lines = [header] + [",".join(f"{v:.6f}" for v in row) + ",-" for row in q]
    (tmp_path / "p.csv").write_text("\n".join(lines) + "\n")
    q = np.round(q, 6)
    r = ednc("lookup", "--map", str(tmp_path / "map.bin"), "--points",
             str(tmp_path / "p.csv"), "--temperature", "spindle=25", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["axes"] == ["c", "a", "x", "y", "z"] and out["kind"] == "tables"
    got = np.array([[p["correction"][k] for k in out["axes"]] for p in out["points"]])
    assert out["points"][3]["q"]["x"] == pytest.approx(q[3, 2])
    # the drift of -2 µm/K at 5 K over 20 °C on EZZ: the center folds it into EZZ
    comps = dict(e.components)
    comps["EZZ"] = add_components(comps.get("EZZ"), Polynomial((-10.0,)))
    want = corrections(m, GeometricErrors(comps, e.locations), q, weights=w)
    np.testing.assert_allclose(got, want.astype(np.float32), rtol=0, atol=2e-9)
    # without the temperature: a sensor the machine never read, whose records add 0
    # (protocol/README.md §6), which stderr says
    r = ednc("lookup", "--map", str(tmp_path / "map.bin"), "--points",
             str(tmp_path / "p.csv"), "--json")
    assert r.returncode == 0, r.stderr
    assert "no temperature of T_spindle_C" in r.stderr and "add 0" in r.stderr
    out = json.loads(r.stdout)
    assert out["unread_sensors"] == ["T_spindle_C"]
    cold = np.array([[p["correction"][k] for k in out["axes"]] for p in out["points"]])
    want = corrections(m, e, q, weights=w)
    np.testing.assert_allclose(cold, want.astype(np.float32), rtol=0, atol=2e-9)


def test_grid_map_corrections_interpolate_its_nodes(tmp_path: Path) -> None:
    # a map linear in x and y: multilinear interpolation reproduces it exactly
    xs, ys = np.arange(3) * 100.0, np.arange(2) * 300.0
    nodes = [[round(2 * x + 0.5 * y), -round(x)] for x in xs for y in ys]
    p = ErrorMapPayload("vmc-01", 4, MapEncoding.INT32_INCREMENTS,
                        (GridAxis("X", 0.0, 100.0, 3), GridAxis("Y", 0.0, 300.0, 2)),
                        (OutputAxis("X", 7), OutputAxis("Z")),
                        pack_values(MapEncoding.INT32_INCREMENTS,
                                    [v for n in nodes for v in n]), 0.001)
    (tmp_path / "map.bin").write_bytes(encode_payload(p))
    (tmp_path / "p.csv").write_text("x,y\n50,150\n200,0\n")
    r = ednc("lookup", "--map", str(tmp_path / "map.bin"), "--points",
             str(tmp_path / "p.csv"), "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["axes"] == ["x", "y", "z"] and out["kind"] == "grid"
    corr = [[pt["correction"][k] for k in ("x", "y", "z")] for pt in out["points"]]
    np.testing.assert_allclose(corr, [[0.175, 0.0, -0.05], [0.4, 0.0, -0.2]], atol=1e-12)
    # the same grid with thermal records (format version 3): -ΔE added per record
    records = (ThermalRecord("spindle", "Z", 1, -2.0, 20.0),  # the Temperatures name
               ThermalRecord("x", "X", 2, 11.5, 20.0, 0.0))
    (tmp_path / "map3.bin").write_bytes(encode_payload(
        ErrorMapPayload(p.machine, p.version, p.encoding, p.grid, p.outputs, p.values,
                        p.increment_mm, thermal=records)))
    r = ednc("lookup", "--map", str(tmp_path / "map3.bin"), "--points",
             str(tmp_path / "p.csv"), "--temperature", "spindle=25", "--temperature",
             "x=30", "--json")
    assert r.returncode == 0, r.stderr
    hot = [[pt["correction"][k] for k in ("x", "y", "z")] for pt in json.loads(r.stdout)[
        "points"]]
    # x: -11.5 µm/(m·K) · 10 K · x; z: +2 µm/K · 5 K; then, as the ladder writes the
    # EMZPS, whole increments of 0.001 mm (0.16925 mm -> 0.169)
    thermal = [[-1.15e-4 * 50, 0.0, 0.01], [-1.15e-4 * 200, 0.0, 0.01]]
    np.testing.assert_allclose(hot, np.rint(np.add(corr, thermal) / 0.001) * 0.001,
                               atol=1e-12)
    assert hot[0][0] == pytest.approx(0.169, abs=1e-12)


@pytest.mark.parametrize(("map_bytes", "csv", "message"), [
    (None, "x,y\n1,2\n", "cannot read"),
    (b"EDMP\x07\x00" + bytes(80), "x,y\n1,2\n", "not an EDNC map payload: map format "
                                               "version 7 at offset 4"),
    (b"", "x,y\n1,2\n", "not an EDNC map payload: map payload is 0 bytes"),
    ("grid", "x\n1\n", "no column for axis y"),
    ("grid", "x,y\n1,abc\n", "line 2, column y: 'abc' is not a number"),
    ("grid", "x,y\n", "no points after the header"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, map_bytes: bytes | str | None,
                                           csv: str, message: str) -> None:
    path = tmp_path / "map.bin"
    if map_bytes == "grid":
        p = ErrorMapPayload("m", 1, MapEncoding.FLOAT32_MM,
                            (GridAxis("X", 0.0, 1.0, 2), GridAxis("Y", 0.0, 1.0, 2)),
                            (OutputAxis("X"),), pack_values(MapEncoding.FLOAT32_MM, [0.0] * 4),
                            0.0)
        path.write_bytes(encode_payload(p))
    elif isinstance(map_bytes, bytes):
        path.write_bytes(map_bytes)
    (tmp_path / "p.csv").write_text(csv)
    r = ednc("lookup", "--map", str(path), "--points", str(tmp_path / "p.csv"), "--json")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], r.stderr
