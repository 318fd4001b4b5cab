"""The fleet cycle's evaluation (:meth:`ChainBatch.corrections`, rows last, one batch for
many machines, :mod:`machine_sim.chaineval_cycle`) equals the straightforward one
(:meth:`ChainBatch.corrections_reference`, rows first, stacked 3x3 products), for every
chain type, with location errors, thermal records, rank-deficient weights, cold and warm
starts:

- on the same rows within SAME_ROWS = 3e-12 mm (degrees): both are exact, so only
  rounding separates them, a few ulps of the ~600 mm tool-tip coordinates (ulp 1.1e-13)
  through the least squares; 396 random cases: worst 5.6e-13 (the previous fast path,
  rows last with a Cholesky pseudo-inverse: 4.5e-13); the worst case hypothesis found,
  1.07e-12, is the same for both;
- against each machine evaluated alone within TOL = 1e-9 mm: the refinement stops when no
  row of the call changes by more than STEP_TOL, so a machine in a batch may take a step
  more than alone (each step contracts by the errors' slope, ~1e-4 · STEP_TOL)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from machine_sim.chaineval import ChainBatch
from protocol import ComponentTable, TablesPayload, ThermalRecord
from tests.support.sim_tables import (
    CHAINS,
    random_machine,
    random_tables,
    random_weights,
    tables_payload,
)
from volumetric.compensate.solver import Weights
from volumetric.model.components import location_names
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
TOL = 1e-9  # mm or degrees
SAME_ROWS = 3e-12  # mm or degrees


def fleet(chain: str, n: int, rng: np.random.Generator
          ) -> tuple[list[TablesPayload], Machine]:
    """n maps of one chain structure: own pivots, tables, locations, weights, thermal."""
    maps = []
    first = random_machine(chain, rng)
    for _ in range(n):
        m = random_machine(chain, rng)
        _, tables = random_tables(m, rng, float(rng.uniform(1, 25)))
        locs = {k: float(rng.normal(0, 40)) for k in location_names(m) if rng.random() < 0.8}
        lin = [a.name for a in m.axes if a.kind == "linear"]
        thermal = (ThermalRecord("spindle", lin[-1], 1, float(rng.normal(0, 3)), 20.0),
                   ThermalRecord("screw", lin[0], 2, float(rng.normal(0, 12)), 20.0,
                                 float(m.travel_lo[m.axis_names.index(lin[0])])))
        maps.append(tables_payload(m, tables, locs, random_weights(m, rng), thermal=thermal))
    return maps, first


def reference(maps: list[TablesPayload], temps: list[dict[str, float]], idx: NDArray[np.int64],
              q: F64, start: F64 | None, steps: int) -> F64:
    """Each machine alone, the straightforward way."""
    out = np.zeros((q.shape[0], len(maps[0].outputs)))
    for i, p in enumerate(maps):
        alone = ChainBatch([p])
        alone.set_temperatures(0, temps[i])
        rows = idx == i
        if rows.any():
            out[rows] = alone.corrections_reference(
                None, q[rows], None if start is None else start[rows], steps)
    return out


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(CHAINS), st.integers(0, 2**32 - 1))
def test_the_fleet_cycle_equals_each_machine_alone(chain: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    maps, m = fleet(chain, int(rng.integers(1, 6)), rng)
    batch = ChainBatch(maps)
    temps = [{"spindle": float(rng.uniform(15, 35)), "T_screw_C": float(rng.uniform(15, 35))}
             for _ in maps]
    for i, t in enumerate(temps):
        batch.set_temperatures(i, t)
    lo, hi = m.travel_lo, m.travel_hi
    n = 60
    idx = rng.integers(0, len(maps), n)
    q = rng.uniform(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), (n, len(m.axes)))
    cold = batch.corrections(idx, q)
    np.testing.assert_allclose(cold, reference(maps, temps, idx, q, None, 6), rtol=0, atol=TOL)
    # a PLC's next cycle: a little further on, one step from the last corrections
    q2 = q + rng.normal(0, 0.5, q.shape)
    warm = batch.corrections(idx, q2, cold, 1)
    np.testing.assert_allclose(warm, reference(maps, temps, idx, q2, cold, 1), rtol=0, atol=TOL)
    assert np.abs(cold).max() > 1e-4  # the maps do correct something


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(CHAINS), st.integers(0, 2**32 - 1), st.sampled_from([1, 2, 6]))
def test_the_fleet_cycle_equals_the_reference_to_rounding(chain: str, seed: int,
                                                          steps: int) -> None:
    rng = np.random.default_rng(seed)
    maps, m = fleet(chain, int(rng.integers(1, 6)), rng)
    batch = ChainBatch(maps)
    for i in range(len(maps)):
        batch.set_temperatures(i, {"spindle": float(rng.uniform(15, 35)),
                                   "T_screw_C": float(rng.uniform(15, 35))})
    lo, hi = m.travel_lo, m.travel_hi
    idx = rng.integers(0, len(maps), 50)
    q = rng.uniform(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), (50, len(m.axes)))
    cold = batch.corrections(idx, q, None, steps)
    np.testing.assert_allclose(cold, batch.corrections_reference(idx, q, None, steps),
                               rtol=0, atol=SAME_ROWS)
    q2 = q + rng.normal(0, 0.5, q.shape)
    np.testing.assert_allclose(batch.corrections(idx, q2, cold, 1),
                               batch.corrections_reference(idx, q2, cold, 1),
                               rtol=0, atol=SAME_ROWS)


def test_the_comparison_can_fail() -> None:
    # one machine's temperature differs between the two evaluations: they disagree
    rng = np.random.default_rng(3)
    maps, m = fleet("w C A X Y b Z t", 3, rng)
    temps = [{"spindle": 30.0, "screw": 25.0} for _ in maps]
    batch = ChainBatch(maps)
    for i, t in enumerate(temps):
        batch.set_temperatures(i, t)
    idx = np.arange(30) % 3
    q = rng.uniform(m.travel_lo, m.travel_hi, (30, len(m.axes)))
    got = batch.corrections(idx, q)
    np.testing.assert_allclose(got, reference(maps, temps, idx, q, None, 6), rtol=0, atol=TOL)
    temps[1] = {"spindle": 31.0, "screw": 25.0}
    assert np.abs(got - reference(maps, temps, idx, q, None, 6)).max() > 100 * TOL
    # on the same rows, a map whose table values all differ by 1e-6 (1 nm, 1 µrad) is seen
    nudged = ChainBatch(maps)
    for i, t in enumerate(temps):
        nudged.set_temperatures(i, t)
    nudged.t_si[1:] += 1e-6  # entry 0 is the shared zero of missing tables
    gap = np.abs(got - nudged.corrections_reference(idx, q)).max()
    assert gap > 1000 * SAME_ROWS


def test_row_sets_that_change_between_calls_are_gathered_anew() -> None:
    # the per-row constants are cached by row set: a PLC group, then another, then the
    # first again must each see their own machines
    rng = np.random.default_rng(5)
    maps, m = fleet("w b X Y Z B C t", 4, rng)
    batch = ChainBatch(maps)
    q = rng.uniform(m.travel_lo, m.travel_hi, (8, len(m.axes)))
    temps: list[dict[str, float]] = [{} for _ in maps]
    for idx in (np.array([0, 1] * 4), np.array([2, 3] * 4), np.array([0, 1] * 4)):
        np.testing.assert_allclose(batch.corrections(idx, q),
                                   reference(maps, temps, idx, q, None, 6), rtol=0, atol=TOL)


@pytest.mark.parametrize("size", [0.2, 3e4])
def test_tiny_and_huge_errors_agree_too(size: float) -> None:
    # tiny errors: every orientation residual below 1e-4 rad, where the fleet cycle takes
    # the rotation vector's series without the arctangent; huge ones (tens of mrad): the
    # exact Rodrigues coefficients instead of their series
    rng = np.random.default_rng(11)
    m = random_machine("w C A X Y b Z t", rng)
    _, tables = random_tables(m, rng, size)
    weighed = Weights(np.ones((1, 3)), np.ones((1, 3)))  # orientation counts
    batch = ChainBatch([tables_payload(m, tables, {}, weighed)])
    q = rng.uniform(m.travel_lo, m.travel_hi, (40, len(m.axes)))
    ori = np.abs(batch.errors(None, q)[:, 3:6])  # µrad
    if size < 1:
        assert ori.max() < 99.0
    else:
        assert ori.max() > 1e4
    for steps in (1, 6):
        want = batch.corrections_reference(None, q, None, steps)
        # rounding is relative: the huge errors ask for corrections of ~200 mm (no real
        # machine), which the two evaluations round alike to 1e-13 of their size
        atol = SAME_ROWS if size < 1 else 1e-13 * float(np.abs(want).max())
        np.testing.assert_allclose(batch.corrections(None, q, None, steps), want,
                                   rtol=0, atol=atol)


def test_tables_over_the_travel_as_the_center_builds_them() -> None:
    # every table of an axis from the start of its travel to its end, node counts of its
    # own (or one value, or none): the cycle subtracts once per axis and skips the clamp
    # while every axis is inside its travel; outside it clamps
    rng = np.random.default_rng(21)
    m = random_machine("w C A X Y b Z t", rng)
    tables = []
    for a in m.axes:
        start, end = (float(x) for x in a.travel)
        for name in (f"E{c}{a.name}" for c in "XYZABC"):
            n = int(rng.choice([0, 1, 2, 9, 33]))
            if n:
                vals = rng.normal(0, 8, n).astype(np.float32).astype(float)
                tables.append(ComponentTable(name, start, (end - start) / max(n - 1, 1),
                                             tuple(vals)))
    batch = ChainBatch([tables_payload(m, tables, {"EC0Y": 20.0}, Weights.default(m))])
    lo, hi = m.travel_lo, m.travel_hi
    inside = rng.uniform(lo, hi, (40, len(m.axes)))
    outside = rng.uniform(lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo), (40, len(m.axes)))
    idx = np.zeros(40, dtype=np.int64)
    assert batch._cycle.rows(idx).shared_start is not None
    for q in (inside, outside, inside):
        np.testing.assert_allclose(batch.corrections(idx, q), batch.corrections_reference(idx, q),
                                   rtol=0, atol=SAME_ROWS)
