"""Simulated controllers: map lookup, EMZPS quantisation and rate limits, MD32750 gating,
map swap atomicity, last good map kept on a bad push, release and expiry."""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Sequence

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy.interpolate import RegularGridInterpolator

from machine_sim.controller import Compensator
from machine_sim.fanuc import ALARM_JUMP, FanucConfig, FanucPMC
from machine_sim.lookup import FleetLadder, FleetLookup, GridMap
from machine_sim.siemens import SiemensAlarm, SiemensConfig, SiemensNC
from protocol.codes import MapEncoding, MapRejectReason
from protocol.mapformat import (
    ErrorMapPayload,
    GridAxis,
    OutputAxis,
    ThermalRecord,
    encode_map,
)
from protocol.maptransfer import split_into_chunks
from protocol.messages import MapAck, MapBegin, MapChunk, MapEnd, MapReject

F64 = NDArray[np.float64]
AXES = ("X", "Y", "Z")


def payload(values: F64, *, grid: Sequence[GridAxis] | None = None, machine: str = "m1",
            version: int = 1, encoding: MapEncoding = MapEncoding.INT32_INCREMENTS,
            outputs: Sequence[OutputAxis] | None = None, valid_s: int = 0) -> ErrorMapPayload:
    g = tuple(grid) if grid is not None else (GridAxis("X", 0.0, 100.0, 6),
                                              GridAxis("Y", 0.0, 100.0, 4))
    outs = tuple(outputs) if outputs is not None else tuple(OutputAxis(a) for a in AXES)
    int32 = encoding is MapEncoding.INT32_INCREMENTS
    raw = values.astype("<i4" if int32 else "<f4").tobytes()
    return ErrorMapPayload(machine, version, encoding, g, outs, raw,
                           0.001 if int32 else 0.0, valid_s)


def push(ctl: Compensator, p: ErrorMapPayload | bytes, now: float = 0.0, *, version: int = 1,
         chunk: int = 8192) -> MapAck | MapReject | None:
    data = p if isinstance(p, bytes) else encode_map(p)
    reply = None
    for msg in split_into_chunks(data, version, chunk):
        reply = ctl.feed_map(msg, now)
    return reply


def linear_field(grid: Sequence[GridAxis], coef: F64) -> F64:
    """Node values of f_k(q) = c_k0 + Σ_d c_kd q_d, shape (N_nodes, K)."""
    axes = [g.start + g.step * np.arange(g.count) for g in grid]
    mesh = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(grid))
    return coef[:, 0] + mesh @ coef[:, 1:].T


def test_lookup_matches_scipy_and_clamps_at_the_edges() -> None:
    rng = np.random.default_rng(0)
    grid = (GridAxis("X", -10.0, 25.0, 7), GridAxis("Y", 5.0, 40.0, 5),
            GridAxis("Z", -300.0, 50.0, 4))
    values = rng.normal(0, 0.01, (7 * 5 * 4, 2))
    g = GridMap.from_payload(payload(values, grid=grid, encoding=MapEncoding.FLOAT32_MM,
                                     outputs=(OutputAxis("X"), OutputAxis("Z"))))
    axes = [gr.start + gr.step * np.arange(gr.count) for gr in grid]
    ref = RegularGridInterpolator(axes, g.node_values(), method="linear")
    inside = np.column_stack([rng.uniform(a[0], a[-1], 500) for a in axes])
    np.testing.assert_allclose(g.lookup(inside), ref(inside), rtol=0, atol=1e-15)
    outside = inside + rng.choice([-1, 1], inside.shape) * 1000.0
    clamped = np.column_stack([np.clip(outside[:, d], axes[d][0], axes[d][-1])
                               for d in range(3)])
    np.testing.assert_allclose(g.lookup(outside), ref(clamped), rtol=0, atol=1e-15)
    # on a node the map returns the node value exactly (float32 as stored)
    node = np.array([[axes[0][3], axes[1][2], axes[2][1]]])
    np.testing.assert_array_equal(g.lookup(node)[0], g.node_values()[3, 2, 1])


def test_fleet_lookup_equals_each_machines_lookup() -> None:
    rng = np.random.default_rng(1)
    maps = []
    for i in range(20):
        grid = (GridAxis("X", rng.uniform(-5, 5), rng.uniform(10, 50), int(rng.integers(2, 9))),
                GridAxis("Y", 0.0, rng.uniform(10, 50), int(rng.integers(2, 6))))
        n = grid[0].count * grid[1].count
        maps.append(GridMap.from_payload(payload(rng.integers(-300, 300, (n, 3)), grid=grid,
                                                 machine=f"m{i}")))
    fleet = FleetLookup(maps)
    q = rng.uniform(-20, 300, (20, 2))
    want = np.vstack([m.lookup(q[i:i + 1]) for i, m in enumerate(maps)])
    np.testing.assert_allclose(fleet.lookup(q), want, rtol=0, atol=1e-15)


def fanuc(**kw: object) -> FanucPMC:
    return FanucPMC("m1", AXES, FanucConfig(**kw))  # type: ignore[arg-type]


def settle(ctl: FanucPMC, pos: dict[str, float], scans: int = 200, t0: float = 0.0
           ) -> NDArray[np.int64]:
    out = ctl.shifts()
    for i in range(scans):
        out = ctl.scan(t0 + i * ctl.config.scan_s, pos)
    return out


def test_fanuc_scan_interpolates_between_nodes_and_quantises() -> None:
    grid = (GridAxis("X", 0.0, 100.0, 6), GridAxis("Y", 0.0, 100.0, 4))
    coef = np.array([[3.0, 0.2, -0.1], [-7.0, 0.05, 0.3], [11.0, -0.15, 0.0]])
    values = np.rint(linear_field(grid, coef)).astype(np.int64)
    ctl = fanuc(max_step_counts=1000)
    assert isinstance(push(ctl, payload(values)), MapAck)
    # a bilinear interpolation of node values at (x, y) inside one cell, rounded to counts
    x, y = 237.0, 161.0
    cell = values.reshape(6, 4, 3)
    fx, fy = 0.37, 0.61
    want = ((1 - fx) * (1 - fy) * cell[2, 1] + fx * (1 - fy) * cell[3, 1]
            + (1 - fx) * fy * cell[2, 2] + fx * fy * cell[3, 2])
    shifts = ctl.scan(0.0, {"x": x, "y": y, "z": -50.0})
    np.testing.assert_array_equal(shifts, np.rint(want))
    # the R addresses hold the same numbers, little-endian int32 from R7000
    raw = bytes(ctl.r[7000:7012])
    assert struct.unpack("<3i", raw) == tuple(int(v) for v in np.rint(want))
    assert struct.unpack_from("<I", ctl.r, 7036)[0] == 1  # map version
    assert struct.unpack_from("<i", ctl.r, 7044)[0] == 237000  # X read by the scan
    assert ctl.state == "compensating"


def test_fanuc_scan_adds_the_thermal_records_and_rounds_once() -> None:
    grid = (GridAxis("X", 0.0, 100.0, 6), GridAxis("Y", 0.0, 100.0, 4))
    coef = np.array([[3.0, 0.2, -0.1], [-7.0, 0.05, 0.3], [11.0, -0.15, 0.0]])
    values = np.rint(linear_field(grid, coef)).astype(np.int64)
    records = (ThermalRecord("spindle", "Z", 1, -2.5, 20.0),  # drift of Z
               ThermalRecord("x", "X", 2, 11.5, 20.0, 0.0))  # expansion of X (exact name)
    p = dataclasses.replace(payload(values), thermal=records)
    plain = fanuc(max_step_counts=1000, thermal_records=False)  # version-1 grids only
    refused = push(plain, p)
    assert isinstance(refused, MapReject)
    assert refused.reason is MapRejectReason.UNSUPPORTED_ENCODING
    ctl = fanuc(max_step_counts=1000)
    assert ctl.store.assembler.accepted == \
        MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    assert isinstance(push(ctl, p), MapAck)
    pos = {"x": 237.0, "y": 161.0, "z": -50.0}
    cold = ctl.scan(0.0, pos).copy()  # no temperature yet: the records add nothing
    # the center's Temperatures arrive; the next scan folds them in
    ctl.temperatures.update("spindle", 25.4, 0.01, "center")
    ctl.temperatures.update("x", 31.0, 0.01, "center")
    hot = ctl.scan(0.02, pos)
    cell = values.reshape(6, 4, 3)
    fx, fy = 0.37, 0.61
    interp = ((1 - fx) * (1 - fy) * cell[2, 1] + fx * (1 - fy) * cell[3, 1]
              + (1 - fx) * fy * cell[2, 2] + fx * fy * cell[3, 2])
    # counts (µm): -ΔE of each record, added before the one rounding
    thermal = np.array([-11.5 * 11.0 * 237.0 * 1e-3, 0.0, 2.5 * 5.4])
    np.testing.assert_array_equal(cold, np.rint(interp))
    np.testing.assert_array_equal(hot, np.rint(interp + thermal))
    assert np.abs(hot - cold).max() >= 13  # a move the test sees


def test_fanuc_clamps_beyond_the_grid_and_the_emzps_range() -> None:
    values = np.zeros((24, 3), dtype=np.int64)
    values[:, 0] = np.arange(24) * 20  # grows with the node index, up to 460 counts
    outs = (OutputAxis("X", 40), OutputAxis("Y"), OutputAxis("Z"))
    ctl = fanuc(max_step_counts=1000, limit_counts=500)
    assert isinstance(push(ctl, payload(values, outputs=outs)), MapAck)
    far = ctl.scan(0.0, {"x": 900.0, "y": 900.0}, {"x": -1})  # beyond the last node
    assert far[0] == 500 and not ctl.status & 16  # 460 + 40 = 500, at the range
    ctl2 = fanuc(max_step_counts=1000, limit_counts=470)
    vals2 = values.copy()
    vals2[:, 0] = np.minimum(vals2[:, 0], 440)
    assert isinstance(push(ctl2, payload(vals2, outputs=outs)), MapAck)
    s = ctl2.scan(0.0, {"x": 900.0, "y": 900.0}, {"x": -1})
    assert s[0] == 470 and ctl2.status & 16  # 440 + 40 clamped to 470, flagged
    s = ctl2.scan(0.008, {"x": 900.0, "y": 900.0}, {"x": 1})
    assert s[0] == 440  # positive approach: the map value alone


def test_fanuc_splits_a_large_change_over_scans() -> None:
    values = np.full((24, 3), 23, dtype=np.int64)
    ctl = fanuc(max_step_counts=5)
    push(ctl, payload(values))
    seen = [int(ctl.scan(i * 0.008, {"x": 50.0, "y": 50.0})[0]) for i in range(7)]
    assert seen == [5, 10, 15, 20, 23, 23, 23]
    assert ctl.state == "compensating"


def test_fanuc_alarm_mode_holds_the_shift_on_a_jump() -> None:
    values = np.full((24, 3), 23, dtype=np.int64)
    ctl = fanuc(max_step_counts=5, on_jump="alarm")
    push(ctl, payload(values))
    for i in range(3):
        assert ctl.scan(i * 0.008, {"x": 50.0})[0] == 0
    assert ctl.alarm == ALARM_JUMP and ctl.state == "alarm"
    ctl.reset_alarm()
    small = np.full((24, 3), 4, dtype=np.int64)
    push(ctl, payload(small, version=2), version=2)
    assert ctl.scan(1.0, {"x": 50.0})[0] == 4 and ctl.alarm == 0


def test_map_swap_is_atomic_and_only_after_the_whole_map() -> None:
    ctl = fanuc(max_step_counts=1000)
    push(ctl, payload(np.full((24, 3), 10, dtype=np.int64)))
    pos = {"x": 120.0, "y": 80.0}
    assert ctl.scan(0.0, pos).tolist() == [10, 10, 10]
    data = encode_map(payload(np.full((24, 3), 20, dtype=np.int64), version=2))
    msgs = split_into_chunks(data, 2, 50)
    assert len(msgs) > 5
    for i, msg in enumerate(msgs[:-1]):
        assert ctl.feed_map(msg, 0.1 + i) is None
        assert ctl.scan(0.1 + i, pos).tolist() == [10, 10, 10]  # never half new
        assert ctl.store.version == 1
    assert isinstance(ctl.feed_map(msgs[-1], 99.0), MapAck)
    assert ctl.scan(99.0, pos).tolist() == [20, 20, 20]


def good_then(bad: ErrorMapPayload | bytes, **kw: object) -> tuple[FanucPMC, object]:
    ctl = fanuc(max_step_counts=1000)
    push(ctl, payload(np.full((24, 3), 10, dtype=np.int64)))
    reply = push(ctl, bad, 1.0, **kw)  # type: ignore[arg-type]
    return ctl, reply


@pytest.mark.parametrize(("bad", "reason", "text"), [
    (payload(np.full((24, 3), 30), machine="other", version=2),
     MapRejectReason.WRONG_MACHINE, "'other'"),
    (payload(np.full((24, 3), 30), version=2, grid=(GridAxis("X", 0, 100, 6),
                                                    GridAxis("W", 0, 100, 4))),
     MapRejectReason.APPLY_FAILED, "grid axis 'W'"),
    (payload(np.full((24, 2), 30), version=2, outputs=(OutputAxis("X"), OutputAxis("B"))),
     MapRejectReason.APPLY_FAILED, "output axis 'B'"),
    (payload(np.where(np.arange(72).reshape(24, 3) == 40, 900, 30), version=2),
     MapRejectReason.APPLY_FAILED, "0.9 mm for axis Y at node (3, 1)"),
    (payload(np.full((24, 3), 0.03), version=2, encoding=MapEncoding.FLOAT32_MM),
     MapRejectReason.UNSUPPORTED_ENCODING, "FLOAT32_MM"),
])
def test_bad_push_is_rejected_and_the_last_good_map_stays(
        bad: ErrorMapPayload, reason: MapRejectReason, text: str) -> None:
    ctl, reply = good_then(bad, version=2)
    assert isinstance(reply, MapReject)
    assert reply.reason == reason and text in reply.text
    assert ctl.store.version == 1
    assert ctl.scan(2.0, {"x": 50.0, "y": 50.0}).tolist() == [10, 10, 10]
    assert ctl.store.events[-1].kind == "rejected"


def test_truncated_push_is_rejected_and_the_last_good_map_stays() -> None:
    ctl = fanuc(max_step_counts=1000)
    push(ctl, payload(np.full((24, 3), 10, dtype=np.int64)))
    msgs = split_into_chunks(encode_map(payload(np.full((24, 3), 30), version=2)), 2, 64)
    reply = None
    for msg in [m for m in msgs if not (isinstance(m, MapChunk) and m.index == 2)]:
        reply = ctl.feed_map(msg, 1.0)
    assert isinstance(reply, MapReject) and reply.reason == MapRejectReason.MISSING_CHUNK
    assert ctl.scan(2.0, {"x": 50.0}).tolist() == [10, 10, 10]
    assert isinstance(msgs[0], MapBegin) and isinstance(msgs[-1], MapEnd)


def test_release_ramps_linearly_to_zero_and_owes_one_released() -> None:
    ctl = fanuc(max_step_counts=1000)
    push(ctl, payload(np.full((24, 3), 40, dtype=np.int64)))
    pos = {"x": 50.0}
    assert ctl.scan(0.0, pos)[0] == 40
    ctl.release(1.0, ramp_s=0.8)
    seen = [int(ctl.scan(1.0 + 0.2 * i, pos)[0]) for i in range(6)]
    assert seen == [40, 30, 20, 10, 0, 0]
    assert ctl.take_released() == 1 and ctl.take_released() == 0
    assert ctl.store.version == 0 and ctl.state == "idle"


def test_expired_map_ramps_to_zero_without_a_released() -> None:
    ctl = fanuc(max_step_counts=1000, expiry_ramp_s=1.0)
    push(ctl, payload(np.full((24, 3), 40, dtype=np.int64), valid_s=10), 0.0)
    assert ctl.scan(5.0, {"x": 50.0})[0] == 40
    assert ctl.scan(10.0, {"x": 50.0})[0] == 40  # the ramp starts here
    assert ctl.scan(10.5, {"x": 50.0})[0] == 20
    assert ctl.scan(11.0, {"x": 50.0})[0] == 0
    assert ctl.store.version == 0 and ctl.status & 32
    assert ctl.take_released() == 0
    assert ctl.store.events[-1].kind == "expired"


def siemens(**kw: object) -> SiemensNC:
    return SiemensNC("m1", AXES, SiemensConfig(**kw))  # type: ignore[arg-type]


def test_siemens_sd43900_needs_md32750_bit_0() -> None:
    nc = siemens(temp_comp_type=0)
    with pytest.raises(SiemensAlarm, match="SD43900 write refused, MD32750 = 0"):
        nc.write_sd(43900, "x", 0.01)
    assert nc.read_sd(43900, "x") == 0.0
    push(nc, payload(np.full((24, 3), 0.02), encoding=MapEncoding.FLOAT32_MM))
    for i in range(10):
        applied = nc.ipo_cycle(i * 0.004, {"x": 50.0})
    assert np.all(applied == 0.0) and nc.state == "alarm"
    assert "SD43900_DISABLED" in nc.alarms[0]
    nc.write_md(32750, "x", 1)
    nc.reset_alarms()
    nc.write_sd(43900, "x", 0.01)
    assert nc.read_sd(43900, "x") == 0.01


def test_siemens_applies_the_map_rate_limited_per_ipo_cycle() -> None:
    nc = siemens(velo_factor=0.003, max_ax_velo_mm_min=10000.0)  # 2 µm per 4 ms cycle
    step = 0.003 * 10000.0 / 60.0 * 0.004
    values = np.tile([0.0105, -0.004, 0.0], (24, 1))
    assert isinstance(push(nc, payload(values, encoding=MapEncoding.FLOAT32_MM)), MapAck)
    seen = [nc.ipo_cycle(i * 0.004, {"x": 50.0, "y": 20.0})[0] for i in range(8)]
    target = float(np.float32(0.0105))
    want = [min((i + 1) * step, target) for i in range(8)]
    np.testing.assert_allclose(seen, want, rtol=0, atol=1e-15)
    # the weights of a multilinear interpolation sum to 1 within a rounding
    assert nc.read_sd(43900, "x") == pytest.approx(target, rel=1e-15)
    assert nc.state == "compensating"


def test_siemens_position_dependent_part_needs_bit_1() -> None:
    nc = siemens(temp_comp_type=3, velo_factor=1.0)
    nc.write_sd(43910, "z", 1e-5)
    nc.write_sd(43920, "z", -100.0)
    applied = nc.ipo_cycle(0.0, {"z": -300.0})
    assert applied[2] == pytest.approx(1e-5 * (-200.0))
    nc.write_md(32750, "z", 1)
    with pytest.raises(SiemensAlarm, match="bit 1 off"):
        nc.write_sd(43910, "z", 2e-5)


def test_fleet_ladder_scans_like_each_fanuc_pmc() -> None:
    rng = np.random.default_rng(4)
    pmcs, maps = [], []
    for i in range(5):
        values = rng.integers(-60, 60, (24, 3))
        p = payload(values, machine=f"m{i}")
        maps.append(GridMap.from_payload(p))
        pmc = FanucPMC(f"m{i}", AXES, FanucConfig(max_step_counts=7))
        assert isinstance(push(pmc, p), MapAck)
        pmcs.append(pmc)
    ladder = FleetLadder(maps, max_step_counts=7)
    for k in range(30):
        q = rng.uniform(-50, 600, (5, 2))
        fleet = ladder.scan(q)
        for i, pmc in enumerate(pmcs):
            one = pmc.scan(k * 0.008, {"x": q[i, 0], "y": q[i, 1]})
            np.testing.assert_array_equal(fleet[i], one)


def test_siemens_reports_ramping_until_the_slope_part_is_reached() -> None:
    nc = siemens(temp_comp_type=3, velo_factor=0.003)  # 2 µm per cycle
    nc.write_sd(43910, "x", 1e-4)  # 0.1 µm per mm from the reference 0
    assert nc.ipo_cycle(0.0, {"x": 100.0})[0] == pytest.approx(0.002)  # wants 0.01 mm
    assert nc.state == "ramping"
    for i in range(1, 6):
        nc.ipo_cycle(i * 0.004, {"x": 100.0})
    assert nc.applied[0] == pytest.approx(0.01) and nc.state == "idle"  # no map: idle
