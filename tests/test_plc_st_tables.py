"""Tables maps (format version 2, protocol/README.md §6.3) in the PLC program of ``plc/``:
``FB_TablesEval`` of ``plc/ednc_tables.st`` (LREAL: the chain, the Jacobian, its weighted
pseudo-inverse by a one-sided Jacobi SVD, the refinement), compiled by MATIEC's iec2c and
gcc, against ``ednc lookup``'s evaluation (``machine_sim/chaineval.py``) on the tables
vector of ``tests/vectors/`` and on 5,000 random points per map (a 5-axis trunnion, a
3-axis machine whose limit clamps, a two-spindle machine with spindle axes in their own
frames, the 5-axis map without orientation rows; thermal records at held readings, reversal
values): equal counts on >= 99.9 % of
the points, never more than 1 count apart."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from numpy.typing import NDArray

from machine_sim.lookup import TablesMap
from machine_sim.stplc import StPlc
from protocol.maptables import TablesPayload, decode_tables
from tests.support.stplc import status, write_map, write_temperatures
from tests.support.sttables import TablesHarness, center_tables, int32_tables

VECTORS = Path(__file__).parent / "vectors"
TRUNNION = {"name": "trunnion-r", "chain": "w C A X Y b Z t", "tool_length_mm": 100.0,
            "travel_mm": {"x": [-250, 250], "y": [-200, 200], "z": [-300, 0],
                          "a": [-120, 30], "c": [-180, 180]},
            "pivots_mm": {"A": [0.0, 0.0, 50.0]}}
VMC = {"name": "vmc-r", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}}
TEMPS_C = {"spindle": 24.123, "x_screw": 19.5}
TABLES_FORMATS = 0x1D
"""int32 values, tables maps, thermal records, factored maps (Hello's map_formats)."""


def _vector() -> dict[str, Any]:
    body: dict[str, Any] = json.loads((VECTORS / "tables_5axis.json").read_text())
    return body


def _sensors(p: TablesPayload) -> list[str]:
    """The temperature slots' sensors: the records' distinct names in order (§13.1)."""
    return list(dict.fromkeys(r.sensor for r in p.thermal))


def _harness(data: bytes, temps_mC: dict[str, int]) -> TablesHarness:
    p = decode_tables(data)
    h = TablesHarness(p.machine, p.axis_names)
    assert h.load(data) == (0, False)
    h.set_readings([temps_mC[s] for s in _sensors(p)])
    return h


def _applied(h: TablesHarness, raw: list[int], negative: list[bool]) -> list[int]:
    """§6.3 step 6 after the evaluation: the reversal while the axis's direction is
    negative, then the clamp to ±floor(limit / increment) counts (as the window program
    does with the FB's counts)."""
    var = h.program.var
    out = []
    for k, c in enumerate(raw):
        v = c + (int(var("reversal")[k]) if negative[k] else 0)
        lim = int(var("outLimit")[k])
        out.append(max(-lim, min(lim, v)))
    return out


def test_the_compiled_fb_gives_the_tables_vector() -> None:
    """Every point of tests/vectors/tables_5axis.json, both approach directions."""
    body = _vector()
    data = (VECTORS / body["map"]).read_bytes()
    h = _harness(data, body["temperatures_mC"])
    assert list(h.axes) == body["axes"]
    got = [_applied(h, h.counts(pt["q_counts"]), pt["negative"]) for pt in body["points"]]
    assert got == [pt["counts"] for pt in body["points"]]
    assert any(any(pt["negative"]) for pt in body["points"])
    assert 1 <= int(h.program.var("steps")[0]) <= 6


def test_ednc_lookup_gives_the_tables_vector(tmp_path: Path) -> None:
    """The vector's positive-approach counts are ``ednc lookup``'s (the command itself)."""
    body = _vector()
    axes = body["axes"]
    pts = [pt for pt in body["points"] if not any(pt["negative"])]
    csv_path = tmp_path / "points.csv"
    with csv_path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([a.lower() for a in axes])
        w.writerows([[repr(float(pt["q"][a])) for a in axes] for pt in pts])
    args = ["lookup", "--map", str(VECTORS / body["map"]), "--points", str(csv_path),
            "--json", "--extrapolate"]
    for k, v in body["temperatures_C"].items():
        args += ["--temperature", f"{k}={v!r}"]
    run = subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()", *args],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    got = [[round(p["correction"][a.lower()] * 1000) for a in axes]
           for p in json.loads(run.stdout)["points"]]
    assert got == [pt["counts"] for pt in pts]


def _map(which: str) -> bytes:
    if which == "5-axis":
        return int32_tables(center_tables(TRUNNION, 2024, backlash={"x": 6.0, "y": 4.0}))
    if which == "3-axis":  # a limit of 15 µm: some corrections clamp
        return int32_tables(center_tables(VMC, 2031, backlash={"y": 5.0}), limit_mm=0.015)
    if which == "5-axis position only":
        return _position_only(_map("5-axis"))
    return _two_spindles()


def _position_only(data: bytes) -> bytes:
    """The same map with its orientation weights 0: 5 outputs, 3 rows, so the
    pseudo-inverse gives the minimum-norm corrections (singular values dropped)."""
    from dataclasses import replace

    from protocol.maptables import encode_tables
    p = decode_tables(data)
    spindles = tuple(replace(s, weights=(*s.weights[:3], 0.0, 0.0, 0.0)) for s in p.spindles)
    return encode_tables(replace(p, spindles=spindles))


def _two_spindles() -> bytes:
    """Two tool branches with spindle axes (own frames), random tables and weights."""
    from protocol import MapEncoding, ThermalRecord
    from protocol.maptables import encode_tables
    from tests.support.sim_tables import (
        random_machine,
        random_tables,
        random_weights,
        tables_payload,
    )
    rng = np.random.default_rng(31)
    m = random_machine("arch", rng)
    _, tables = random_tables(m, rng, 6.0)
    linear = [a.name for a in m.axes if a.kind != "rotary"]
    thermal = (ThermalRecord("spindle", linear[-1], 1, -2.5, 20.0, 0.0),
               ThermalRecord("x_screw", linear[0], 2, 11.5, 20.0, 10.0))
    p = tables_payload(m, tables, {"EC0Y": 12.0}, random_weights(m, rng),
                       encoding=MapEncoding.INT32_INCREMENTS, thermal=thermal, limit=1.0,
                       reversal={linear[0]: 5, linear[1]: -3})
    return encode_tables(p)


def _reference(tm: TablesMap, p: TablesPayload, q: NDArray[np.float64],
               negative: NDArray[np.bool_]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """ednc lookup's counts (positive approach: clamped, rounded) and §6.3 step 6 with the
    reversal (rounded, reversal added, then clamped), from the same evaluation."""
    inc = p.increment_mm
    lookup = np.rint(tm.lookup(q) / inc).astype(np.int64)
    lim = np.array([np.floor((p.limit_deg if a.rotary else p.limit_mm) / inc + 1e-9)
                    for a in (p.axis(o.name) for o in p.outputs)]).astype(np.int64)
    rev = np.array([0 if o.reversal is None else int(o.reversal) for o in p.outputs])
    raw = np.floor(tm.corrections(q) / inc + 0.5).astype(np.int64)
    return lookup, np.clip(raw + np.where(negative, rev, 0), -lim, lim)


@pytest.mark.parametrize("which", ["5-axis", "3-axis", "two-spindle",
                                   "5-axis position only"])
def test_5000_random_points_equal_ednc_lookup(which: str) -> None:
    data = _map(which)
    p = decode_tables(data)
    assert p.thermal and any(o.reversal for o in p.outputs)
    temps_mC = {k: round(v * 1000) for k, v in TEMPS_C.items()}
    h = _harness(data, temps_mC)
    tm = TablesMap.from_payload(p, TEMPS_C)
    rng = np.random.default_rng(2026)
    lo = np.array([a.travel[0] for a in p.axes])
    hi = np.array([a.travel[1] for a in p.axes])
    qc = np.floor((lo - 2.0 + (hi - lo + 4.0) * rng.random((5000, len(lo)))) * 1000 + 0.5)
    q = qc / 1000.0  # the positions the PLC sees: counts / P, a little outside too
    negative = rng.random((5000, len(p.outputs))) < 0.5
    lookup, want = _reference(tm, p, q, negative)
    raw = np.array([h.counts(row) for row in qc.astype(np.int64).tolist()])
    positive = np.array([_applied(h, r, [False] * len(r)) for r in raw.tolist()])
    got = np.array([_applied(h, r, n) for r, n in zip(raw.tolist(), negative.tolist(),
                                                       strict=True)])
    for name, a, b in (("positive", positive, lookup), ("with reversals", got, want)):
        equal = float(np.mean((a == b).all(axis=1)))
        worst = int(np.abs(a - b).max())
        print(f"{which} {name}: {equal:.2%} of 5000 points equal, worst {worst} count")
        assert equal >= 0.999 and worst <= 1, (which, name, equal, worst)
    # the points exercise what they claim: reversals, thermal records, rotary outputs
    assert np.any(want != lookup)
    cold = TablesMap.from_payload(p)
    assert np.any(np.rint(cold.lookup(q[:200]) / p.increment_mm) != lookup[:200])
    if which == "3-axis":
        lim = int(h.program.var("outLimit")[0])
        assert lim == 15 and np.any(np.abs(want) == 15)


def test_a_map_beyond_the_program_is_refused_to_load() -> None:
    """A chain axis the machine does not have: decoded, but not loaded (APPLY_FAILED);
    a byte of a reserved field set: DECODE_ERROR."""
    body = _vector()
    data = (VECTORS / body["map"]).read_bytes()
    p = decode_tables(data)
    h = TablesHarness(p.machine, ["X", "Y", "Z", "A", "B"])
    assert h.load(data) == (0, True)
    bad = bytearray(data)
    bad[80 + 5] = 1   # the first chain axis's reserved byte
    h = TablesHarness(p.machine, p.axis_names)
    assert h.load(bytes(bad))[0] == 6
    assert h.load(data) == (0, False)


def _program(data: bytes, formats: int = TABLES_FORMATS) -> StPlc:
    """The whole program (PRG_Ednc) with ``data`` written to buffer 1 and switched to, no
    channel limit but the map's and no step limit."""
    p = decode_tables(data)
    plc = StPlc(p.machine, list(p.axis_names), channel_limit=(1 << 30) - 1,
                max_step=1 << 30, formats=formats)
    plc.scan([0] * len(plc.axes))
    write_map(plc.window, plc.layout, 1, data, p.version, 1)
    plc.scan([0] * len(plc.axes))
    return plc


def test_the_program_applies_a_tables_map_through_its_window() -> None:
    """PRG_Ednc takes the tables vector through the window protocol (§13.3), its
    temperature slots feed the thermal records, and its targets (reversal, clamp) are
    the vector's counts at every point, both approach directions."""
    body = _vector()
    data = (VECTORS / body["map"]).read_bytes()
    p = decode_tables(data)
    plc = _program(data)
    st = status(plc.window)
    assert (st.ack_seq, st.ack_code, st.active, st.applied_version) == (1, 0, 1, p.version)
    write_temperatures(plc.window, [body["temperatures_mC"][s] for s in _sensors(p)], 1,
                       p.version)
    plc.scan([0] * len(plc.axes))
    assert status(plc.window).temp_ack == 1
    got = [plc.lookup(pt["q_counts"], pt["negative"]).tolist() for pt in body["points"]]
    assert got == [pt["counts"] for pt in body["points"]]


def test_a_tables_map_the_program_does_not_take_is_refused() -> None:
    """Without the tables bit in the program's formats, and for a float32 tables map (the
    program writes counts): UNSUPPORTED_ENCODING (8), nothing applied."""
    data = (VECTORS / _vector()["map"]).read_bytes()
    plc = _program(data, formats=TABLES_FORMATS & ~0x4)
    assert (status(plc.window).ack_code, status(plc.window).active) == (8, 0)
    built = center_tables(VMC, 2031, backlash={"y": 5.0})
    plc = _program(built)
    assert (status(plc.window).ack_code, status(plc.window).active) == (8, 0)


def test_the_center_builds_int32_tables_for_a_program_that_writes_counts() -> None:
    """A machine that declares int32 and tables but not float32 (this program with the
    tables bit on) gets its tables map in int32 counts from the center's own builder:
    the float32 map re-encoded (what the random-point tests hold to ednc lookup), its
    reversals in whole counts; the program takes it."""
    from protocol import MapEncoding
    from server.mapcodec import tables_from_payload
    from volumetric.model.machine import parse_machine

    counts = MapEncoding.INT32_INCREMENTS | MapEncoding.TABLES | MapEncoding.THERMAL
    float32 = center_tables(VMC, 2031, backlash={"y": 5.0})
    int32 = center_tables(VMC, 2031, backlash={"y": 5.0}, formats=counts)
    assert decode_tables(int32).encoding is MapEncoding.INT32_INCREMENTS
    assert int32 == int32_tables(float32)
    back = tables_from_payload(decode_tables(int32),
                               parse_machine({**VMC, "controller": "fanuc"}))
    assert back.increment_mm == 0.001 and back.reversal[1] == pytest.approx(-0.005)  # mm
    plc = _program(int32)
    assert (status(plc.window).ack_code, status(plc.window).active) == (0, 1)


def test_a_restart_keeps_the_tables_map_of_the_retentive_window() -> None:
    """A PLC restart (every variable to its initial value but the window): the start-up
    re-check decodes the active buffer's tables map again and applies it without a new
    switch, the temperature slots (retentive too) are taken again, and the counts are
    those before the restart, thermal records included."""
    body = _vector()
    data = (VECTORS / body["map"]).read_bytes()
    p = decode_tables(data)
    plc = _program(data)
    write_temperatures(plc.window, [body["temperatures_mC"][s] for s in _sensors(p)], 1,
                       p.version)
    plc.scan([0] * len(plc.axes))
    pt = next(pt for pt in body["points"] if not any(pt["negative"]))
    assert plc.lookup(pt["q_counts"], pt["negative"]).tolist() == pt["counts"]
    plc.restart()
    plc.scan(pt["q_counts"])
    st = status(plc.window)
    assert (st.ack_seq, st.ack_code, st.active, st.applied_version) == (1, 0, 1, p.version)
    assert plc.lookup(pt["q_counts"], pt["negative"]).tolist() == pt["counts"]
    h = TablesHarness(p.machine, p.axis_names)
    assert h.load(data) == (0, False)
    h.set_readings([])   # without readings the records add 0: the point shows them
    assert _applied(h, h.counts(pt["q_counts"]), pt["negative"]) != pt["counts"]


def test_one_step_per_scan_tracks_ednc_lookup_on_a_moving_machine() -> None:
    """oneStep (§6.3: one refinement step per scan from the last scan's dq): along a
    path at up to 10 m/min (60 deg/s) in 1 ms scans, 5,000 scans of the 5-axis map, the
    counts equal ``ednc lookup``'s at >= 99.9 % of the scans and never differ by more
    than 1 count (the first scan, from dq = 0, not counted)."""
    data = _map("5-axis")
    p = decode_tables(data)
    temps_mC = {k: round(v * 1000) for k, v in TEMPS_C.items()}
    h = _harness(data, temps_mC)
    h.program.var("oneStep")[0] = 1
    tm = TablesMap.from_payload(p, TEMPS_C)
    lo = np.array([a.travel[0] for a in p.axes])
    hi = np.array([a.travel[1] for a in p.axes])
    rng = np.random.default_rng(7)
    t = np.arange(5001)[:, None] * 1e-3
    amp = 0.45 * (hi - lo)
    omega = np.where([a.rotary for a in p.axes], 60.0, 166.7) / amp
    path = 0.5 * (lo + hi) + amp * np.sin(omega * rng.uniform(0.5, 1.0, len(lo)) * t
                                          + rng.uniform(0, 6.3, len(lo)))
    qc = np.floor(path * 1000 + 0.5)
    want = np.rint(tm.lookup(qc / 1000.0) / p.increment_mm).astype(np.int64)
    got = np.array([h.counts(row) for row in qc.astype(np.int64).tolist()])
    assert int(h.program.var("steps")[0]) == 1
    equal = float(np.mean((got[1:] == want[1:]).all(axis=1)))
    worst = int(np.abs(got[1:] - want[1:]).max())
    print(f"one step per scan: {equal:.2%} of 5000 scans equal, worst {worst} count")
    assert equal >= 0.999 and worst <= 1
    h.program.var("oneStep")[0] = 0   # off again: the full solve from dq = 0
    assert h.counts(qc[-1].astype(np.int64).tolist()) == want[-1].tolist()
    assert int(h.program.var("steps")[0]) > 1
