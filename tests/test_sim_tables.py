"""The machine endpoint's tables evaluation pinned to the center: the same errors given to
volumetric (``GeometricErrors`` with ``Table`` components) and, as a tables map, to
:mod:`machine_sim.chaineval` give the same corrections; the map store, the Siemens NC and
a Siemens-style machine over a real socket apply tables maps, the Fanuc-style ones refuse
them, bad payloads are refused and the last good map kept."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from machine_sim.chaineval import ChainBatch
from machine_sim.fanuc import FanucPMC
from machine_sim.link import SimulatedCNC
from machine_sim.lookup import TablesMap
from machine_sim.runtime import MachineRuntime
from machine_sim.siemens import SiemensConfig, SiemensNC
from protocol import (
    ComponentTable,
    MapAck,
    MapEncoding,
    MapReject,
    MapRejectReason,
    Message,
    TablesPayload,
    ThermalRecord,
    encode_payload,
    split_into_chunks,
)
from tests.support.kinematics import machine
from tests.support.sim_link import SECRET, MiniCenter, Session
from tests.support.sim_tables import (
    CHAINS,
    random_machine,
    random_tables,
    random_weights,
    sample,
    siemens_5ax,
    tables_payload,
)
from volumetric.compensate.solver import Weights, corrections
from volumetric.model.components import GeometricErrors, location_names
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import MachineModel, ThermalTerm

F64 = NDArray[np.float64]
def tip_gap_um(m: Machine, q: F64, dq_a: F64, dq_b: F64) -> float:
    """Largest tool-tip position difference the two corrections make, µm (first order)."""
    worst = 0.0
    for br in m.branches:
        j = jacobian(m, q, spindle=br.name)[:, :3]
        worst = max(worst, float(np.abs(np.einsum("nij,nj->ni", j, dq_a - dq_b)).max()))
    return worst


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(CHAINS), st.integers(0, 2**32 - 1))
def test_endpoint_corrections_equal_the_centers_solver(chain: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    m = random_machine(chain, rng)
    comps, tables = random_tables(m, rng, float(rng.uniform(1, 25)))
    locs = {n: float(rng.normal(0, 40)) for n in location_names(m) if rng.random() < 0.8}
    w = random_weights(m, rng)
    batch = ChainBatch([tables_payload(m, tables, locs, w)])
    lo, hi = m.travel_lo, m.travel_hi
    q = rng.uniform(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), (40, len(m.axes)))
    want = corrections(m, GeometricErrors(comps, locs), q, weights=w)
    got = batch.corrections(None, q)
    assert tip_gap_um(m, q, got, want) < 1e-3
    lin = np.array([a.kind == "linear" for a in m.axes])
    np.testing.assert_allclose(got[:, lin], want[:, lin], rtol=0, atol=1e-6)
    np.testing.assert_allclose(got[:, ~lin], want[:, ~lin], rtol=0, atol=1e-7)


def test_the_comparison_can_fail() -> None:
    # one sign flipped in the map (EC0Y) and the endpoint no longer agrees: the property
    # above is not vacuous
    rng = np.random.default_rng(4)
    m = random_machine("w C A X Y b Z t", rng)
    comps, tables = random_tables(m, rng, 10.0)
    locs = {"EC0Y": 30.0}
    w = Weights.default(m)
    q = rng.uniform(m.travel_lo, m.travel_hi, (20, len(m.axes)))
    want = corrections(m, GeometricErrors(comps, locs), q, weights=w)
    got = ChainBatch([tables_payload(m, tables, {"EC0Y": -30.0}, w)]).corrections(None, q)
    assert tip_gap_um(m, q, got, want) > 1.0


def test_thermal_records_equal_the_models_thermal_terms() -> None:
    rng = np.random.default_rng(8)
    m = random_machine("w C A X Y b Z t", rng)
    comps, tables = random_tables(m, rng, 5.0)
    terms = (ThermalTerm("thermal_expansion", "x", "T_x_screw_C", 11.5, 20.0, 0.0),
             ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.0, 21.0))
    model = MachineModel(m.name, GeometricErrors(comps, {"EC0Y": 12.0}), terms)
    temps = {"T_x_screw_C": 27.5, "T_spindle_C": 31.0}
    records = (ThermalRecord("T_x_screw_C", "X", 2, 11.5, 20.0, 0.0),
               ThermalRecord("spindle", "Z", 1, -2.0, 21.0))
    w = Weights.default(m)
    batch = ChainBatch([tables_payload(m, tables, {"EC0Y": 12.0}, w, thermal=records)])
    # the machine's sensors are named without the column decoration
    batch.set_temperatures(0, {"x_screw": 27.5, "T_spindle_C": 31.0})
    q = rng.uniform(m.travel_lo, m.travel_hi, (30, len(m.axes)))
    want = corrections(m, model.geometry_at(temps), q, weights=w)
    got = batch.corrections(None, q)
    assert tip_gap_um(m, q, got, want) < 1e-3
    cold = corrections(m, model.geometry_at({k: 20.0 for k in temps}), q, weights=w)
    assert tip_gap_um(m, q, got, cold) > 5.0  # the temperatures did change the answer


def test_a_batch_of_machines_equals_each_machine_alone() -> None:
    rng = np.random.default_rng(12)
    maps, machines = [], []
    for i in range(6):
        m = random_machine("w C A X Y b Z t", rng)
        _, tables = random_tables(m, rng, 8.0)
        maps.append(tables_payload(m, tables, {"EX0C": float(i)}, Weights.default(m)))
        machines.append(m)
    batch = ChainBatch(maps)
    idx = rng.integers(0, 6, 50)
    q = rng.uniform(machines[0].travel_lo, machines[0].travel_hi, (50, 5))
    together = batch.corrections(idx, q)
    for i, p in enumerate(maps):
        alone = ChainBatch([p]).corrections(None, q[idx == i])
        np.testing.assert_allclose(together[idx == i], alone, rtol=0, atol=1e-12)


def test_applied_is_clamped_rounded_and_carries_the_reversal() -> None:
    m = machine("w C A X Y b Z t", pivots_mm={"C": [0, 0, 0], "A": [0, 0, 0]})
    w = Weights.default(m)
    big = [ComponentTable("EXX", 0.0, 1.0, (300.0,)), ComponentTable("EYY", 0.0, 1.0, (4.0,))]
    q = np.array([[10.0, 5.0, 100.0, 100.0, -100.0]])
    f32 = ChainBatch([tables_payload(m, big, {}, w, limit=0.2, reversal={"Y": 0.004})])
    dq = f32.corrections(None, q)
    x, y = m.axis_names.index("X"), m.axis_names.index("Y")
    out = f32.applied(None, q, np.array([[1, 1, 1, -1, 1]]))
    assert out[0, x] == pytest.approx(-0.2) and dq[0, x] < -0.29  # clamped to the limit
    # §6.3 step 6: the reversal added, then the clamp, the nearest float32 last
    assert out[0, y] == float(np.float32(dq[0, y] + float(np.float32(0.004))))
    i32 = ChainBatch([tables_payload(m, big, {}, w, limit=0.2, reversal={"Y": 4},
                                     encoding=MapEncoding.INT32_INCREMENTS)])
    out = i32.applied(None, q, np.array([[1, 1, 1, -1, 1]]))
    assert out[0, y] == pytest.approx((round(dq[0, y] / 0.001) + 4) * 0.001, abs=1e-15)


# --- the machine side: store, NC, link ---------------------------------------------------


def push_to(ctl: SiemensNC | FanucPMC, data: bytes, version: int) -> MapAck | MapReject:
    reply = None
    for msg in split_into_chunks(data, version, 512):
        reply = ctl.feed_map(msg, 0.0)
    assert reply is not None
    return reply


def test_siemens_nc_applies_a_tables_map_and_keeps_it_over_bad_ones() -> None:
    m = siemens_5ax()
    e, tables = sample(m)
    w = Weights.default(m)
    nc = SiemensNC(m.name, m.axis_names, SiemensConfig(limit_mm=0.5))
    good = tables_payload(m, tables, dict(e.locations), w, version=2)
    assert isinstance(push_to(nc, encode_payload(good), 2), MapAck)
    assert isinstance(nc.store.active, TablesMap) and nc.store.version == 2
    q = np.array([20.0, -30.0, 250.0, 120.0, -150.0])
    want = corrections(m, e, q[None, :], weights=w)[0]
    got = nc.wanted_mm(0.0, q)
    np.testing.assert_allclose(got, want.astype(np.float32), rtol=0, atol=1e-9)
    # a corrupted payload, a stale version, an axis this NC lacks: refused, map kept
    data = bytearray(encode_payload(tables_payload(m, tables, {}, w, version=3)))
    data[7] = 9  # the kind byte
    bad = push_to(nc, bytes(data), 3)
    assert isinstance(bad, MapReject) and bad.reason is MapRejectReason.DECODE_ERROR
    assert "map kind 9 at offset 7" in bad.text
    stale = push_to(nc, encode_payload(tables_payload(m, tables, {}, w, version=1)), 1)
    assert isinstance(stale, MapReject) and stale.reason is MapRejectReason.STALE_VERSION
    other = parse_machine({"name": m.name, "chain": "w C B X Y b Z t",
                           "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}})
    wrong = push_to(nc, encode_payload(tables_payload(other, [], {}, Weights.default(other),
                                                      version=4)), 4)
    assert isinstance(wrong, MapReject) and wrong.reason is MapRejectReason.APPLY_FAILED
    assert "chain axis 'B' is not an axis of sim-5ax" in wrong.text
    assert nc.store.version == 2
    np.testing.assert_array_equal(nc.wanted_mm(1.0, q), got)


def test_fanuc_pmc_refuses_tables_maps() -> None:
    m = siemens_5ax("fanuc-5ax")
    _, tables = sample(m)
    pmc = FanucPMC(m.name, m.axis_names)
    p = tables_payload(m, tables, {}, Weights.default(m),
                       encoding=MapEncoding.INT32_INCREMENTS)
    reply = push_to(pmc, encode_payload(p), 1)
    assert isinstance(reply, MapReject)
    assert reply.reason is MapRejectReason.UNSUPPORTED_ENCODING
    assert pmc.store.active is None


@pytest.fixture
async def center() -> AsyncIterator[MiniCenter]:
    c = MiniCenter(SECRET)
    server = await asyncio.start_server(c.handle, "127.0.0.1", 0)
    c.port = server.sockets[0].getsockname()[1]
    async with server:
        yield c


async def push(s: Session, p: TablesPayload) -> Message:
    for msg in split_into_chunks(encode_payload(p), p.version, 1024):
        await s.send(msg)
    return await s.expect((MapAck, MapReject))  # type: ignore[arg-type]


async def test_siemens_machine_applies_a_tables_map_over_the_link(center: MiniCenter) -> None:
    m = siemens_5ax()
    e, tables = sample(m, 3)
    w = Weights.default(m)
    runtime = MachineRuntime(m, seed=2)
    async with asyncio.timeout(20.0), SimulatedCNC(m, ("127.0.0.1", center.port), SECRET,
                                                   runtime=runtime, cycle_s=0.004) as sim:
        s = await center.sessions.get()
        assert s.hello is not None
        assert s.hello.map_formats == MapEncoding.FLOAT32_MM | MapEncoding.TABLES
        ack = await push(s, tables_payload(m, tables, dict(e.locations), w, version=5))
        assert isinstance(ack, MapAck) and ack.version == 5
        active = sim.runtime.controller.store.active
        assert isinstance(active, TablesMap) and active.version == 5
        q = np.array(sim.runtime.positions, dtype=float)
        want = corrections(m, e, q[None, :], weights=w)[0]
        got = active.lookup(q[None, :])[0]
        np.testing.assert_allclose(got, want.astype(np.float32), rtol=0, atol=1e-9)
        assert np.abs(want).max() > 1e-3  # the map does correct something


def test_one_step_per_cycle_from_the_previous_cycle_tracks_the_solution() -> None:
    # a PLC refines once per cycle, starting from its last corrections: along a path at
    # 10 m/min sampled every 4 ms it stays on the fully refined solution
    m = siemens_5ax()
    e, tables = sample(m, 9)
    batch = ChainBatch([tables_payload(m, tables, dict(e.locations), Weights.default(m))])
    t = np.arange(200)[:, None] * 0.004
    q = np.array([0.0, -20.0, 100.0, 100.0, -150.0]) + t * [20.0, 5.0, 166.0, 50.0, -20.0]
    last = batch.corrections(None, q[:1])
    worst = 0.0
    for k in range(1, q.shape[0]):
        last = batch.corrections(None, q[k:k + 1], last, 1)
        full = batch.corrections(None, q[k:k + 1])
        worst = max(worst, float(np.abs(last - full).max()))
    assert worst < 1e-6


def test_the_nc_folds_its_latest_temperatures_into_a_thermal_tables_map() -> None:
    m = siemens_5ax()
    e, tables = sample(m, 6)
    w = Weights.default(m)
    records = (ThermalRecord("T_spindle_C", "Z", 1, -2.0, 20.0),)
    nc = SiemensNC(m.name, m.axis_names)
    assert isinstance(push_to(nc, encode_payload(
        tables_payload(m, tables, dict(e.locations), w, thermal=records)), 1), MapAck)
    q = np.array([10.0, -20.0, 250.0, 120.0, -150.0])
    cold = nc.wanted_mm(0.0, q)  # no reading yet: the term is 0
    np.testing.assert_allclose(cold, corrections(m, e, q[None, :], weights=w)[0]
                               .astype(np.float32), rtol=0, atol=1e-9)
    nc.temperatures.update("spindle", 30.0, 1.0, "sensor")  # +10 K: EZZ drifts by -20 µm
    warm = nc.wanted_mm(1.0, q)
    z = m.axis_names.index("Z")
    assert warm[z] - cold[z] == pytest.approx(0.020, abs=2e-5)
