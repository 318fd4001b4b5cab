"""The diagnosis chooses its held-out split from the data alone and never judges a reading
by a model that saw it or anything after it, when the data are a time series; in every
split, a lagged thermal model's sensors and time constants are chosen without the readings
it is judged on."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from tests.support.data import FL_MACHINE
from tests.support.thermal_sim import lagged_spindle
from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.diagnosis import (
    FIRST_JUDGED,
    FORWARD_BLOCKS,
    BaseGrams,
    diagnose,
    fold_fits,
    fold_labels,
    forward_blocks,
    forward_residuals,
    heldout_per_fold,
    time_ordered,
)
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import parse_machine


def readings(tests: list[str], times: np.ndarray) -> Measurements:
    n = times.size
    return Measurements(test=np.array(tests), run=np.zeros(n, np.int64), time_s=times,
                        q=np.zeros((n, 6)), direction=np.zeros((n, 3), np.int8),
                        tool_mm=np.zeros(n), is_angle=np.zeros(n, bool),
                        u=np.tile([0.0, 0.0, 1.0], (n, 1)), value=np.zeros(n))


def test_a_repeated_test_over_the_campaign_is_time_ordered_a_sequence_of_tests_is_not() -> None:
    t = np.arange(600, dtype=float)
    assert time_ordered(readings(["thermal"] * 600, t))
    assert time_ordered(readings(["a", "b"] * 300, t))  # two tests interleaved all along
    assert not time_ordered(readings(["a"] * 300 + ["b"] * 300, t))  # one after the other


def test_forward_residuals_use_only_the_past() -> None:
    n = 600
    t = np.arange(n, dtype=float)
    m = readings(["thermal"] * n, t[::-1].copy())  # rows out of time order on purpose
    blocks = forward_blocks(m)
    assert blocks.max() == FORWARD_BLOCKS - 1
    # block k holds later readings than every block before it
    for k in range(1, FORWARD_BLOCKS):
        assert m.time_s[blocks == k].min() > m.time_s[blocks < k].max()
    # a step that only the last block shows: a model of the past cannot know it
    y = np.where(blocks == FORWARD_BLOCKS - 1, 10.0, 0.0)
    a = np.ones((n, 1))
    r = forward_residuals(a, y, np.ones(n), blocks)
    assert np.all(np.isnan(r[blocks < FIRST_JUDGED]))
    np.testing.assert_allclose(r[blocks == FORWARD_BLOCKS - 1], 10.0)
    np.testing.assert_allclose(r[(blocks >= FIRST_JUDGED) & (blocks < FORWARD_BLOCKS - 1)], 0.0)


def test_a_held_out_run_does_not_shape_the_lagged_model_that_judges_it() -> None:
    # the simulated spindle as two tests one after the other: not a time series, so the
    # runs split (contiguous stretches of each test), and a lagged drift is what it finds
    machine = parse_machine(FL_MACHINE)
    m = lagged_spindle(0)
    m = replace(m, test=np.where(m.time_s >= np.median(m.time_s), "second", "first"))
    d = diagnose(machine, m)
    assert d.details["split"] == "runs"
    assert d.effect == "thermal_drift" and "dynamic" in d.estimate
    # change what one fold reads: its prediction comes from the other folds alone, so its
    # held-out residuals move by exactly that change (with the sensors and time constants
    # chosen on every reading, the fold's own readings would reshape the model)
    folds = fold_labels(m)
    held = folds == 2
    bump = np.where(held, 1.5 * np.sin(m.time_s / 4000.0), 0.0)
    d2 = diagnose(machine, replace(m, value=m.value + bump))
    assert [e["effect"] for e in d2.details["effects"]] == [
        e["effect"] for e in d.details["effects"]]
    np.testing.assert_allclose(d2.residual_after[held] - bump[held], d.residual_after[held],
                               rtol=0, atol=1e-8)
    assert not np.allclose(d2.residual_after[~held], d.residual_after[~held], atol=1e-3)


def test_judging_from_summed_normal_equations_equals_fitting_each_fold() -> None:
    # the diagnosis sums the base's normal equations once per cell of the split; what it
    # judges must equal the plain weighted fit of every fold, a replacing candidate and
    # per-fold columns included
    rng = np.random.default_rng(7)
    n = 300
    a0 = rng.normal(size=(n, 6))
    y = a0 @ rng.normal(size=6) + rng.normal(size=n)
    w = rng.uniform(0.5, 2.0, n)
    cells = (np.arange(n) * 6) // n
    fits = fold_fits("forward", cells, np.ones(n, bool))
    assert len(fits) == FORWARD_BLOCKS - FIRST_JUDGED
    replacing = Candidate("rotary_periodic", "c", None, rng.normal(size=(n, 3)), drop=(4, 5))
    per_fold = Candidate("thermal_drift", "z", "T_a_C", np.zeros((n, 2)),
                         per_fold=tuple(rng.normal(size=(n, 1 + f % 2)) for f in range(3)))
    plain = Candidate("backlash", "x", None, rng.normal(size=(n, 1)))
    # a prediction that enters as it comes (the averaged lagged drift): per fold, and one
    # serving every fold
    fixed = Candidate("thermal_drift", "z", "T_a_C", np.zeros((n, 1)), fixed=True,
                      per_fold=tuple(rng.normal(size=(n, 1)) for _ in range(3)))
    fixed_all = Candidate("thermal_drift", "y", "T_b_C", rng.normal(size=(n, 1)), fixed=True)
    for cands in ([plain], [plain, per_fold], [replacing, per_fold], [plain, fixed],
                  [fixed], [replacing, fixed], [replacing, fixed_all, per_fold]):
        expect = np.full(n, np.nan)
        for f, (tr, te) in enumerate(fits):
            kept = [c.in_fold(f) for c in cands]
            base = np.delete(a0, list(replacing.drop), axis=1) if replacing in cands else a0
            a = np.column_stack([base, *(c.columns for c in kept if not c.fixed)])
            yk = y - sum((c.columns[:, 0] for c in kept if c.fixed), np.zeros(n))
            x = np.linalg.lstsq(a[tr] * np.sqrt(w[tr, None]), yk[tr] * np.sqrt(w[tr]),
                                rcond=None)[0]
            expect[te] = yk[te] - a[te] @ x
        if any(c.drop for c in cands):
            got = heldout_per_fold(a0, cands, y, w, fits, cells)
        else:
            got = BaseGrams(a0, y, w, fits, cells).heldout(cands)
        np.testing.assert_allclose(got, expect, rtol=0, atol=1e-9)
