"""The diagnosis chooses its held-out split from the data alone and never judges a reading
by a model that saw it or anything after it, when the data are a time series."""

from __future__ import annotations

import numpy as np

from volumetric.diagnose.diagnosis import (
    FIRST_JUDGED,
    FORWARD_BLOCKS,
    forward_blocks,
    forward_residuals,
    time_ordered,
)
from volumetric.measure.measurement import Measurements


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
