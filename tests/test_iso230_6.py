"""ISO 230-6 body diagonals: target points, ranges from hand-built readings, improvement."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from volumetric.measure.measurement import Measurements, read_measurements, write_measurements
from volumetric.verify.iso230_6 import (
    DIAGONALS,
    DiagonalTestError,
    diagonal_ranges,
    diagonal_targets,
    diagonal_unit_vectors,
    improvement,
)

TRAVEL = {"x": (0.0, 500.0), "y": (0.0, 300.0), "z": (-300.0, 0.0)}


def test_corners_of_the_four_diagonals() -> None:
    pts = diagonal_targets(TRAVEL, n_points=5, margin_mm=10.0)
    assert list(pts) == ["diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN"]
    ends = {label: (p[0].tolist(), p[-1].tolist()) for label, p in pts.items()}
    assert ends["diag-PPP"] == ([10, 10, -290], [490, 290, -10])
    assert ends["diag-NPP"] == ([490, 10, -290], [10, 290, -10])
    assert ends["diag-PNP"] == ([10, 290, -290], [490, 10, -10])
    assert ends["diag-PPN"] == ([10, 10, -10], [490, 290, -290])
    for label, p in pts.items():
        assert p.shape == (5, 3)
        steps = np.diff(p, axis=0)
        np.testing.assert_allclose(steps, np.broadcast_to(steps[0], steps.shape))
        assert (np.sign(steps[0]) == DIAGONALS[label]).all()


def test_unit_vectors_point_from_start_to_end() -> None:
    pts = diagonal_targets(TRAVEL, n_points=3, margin_mm=0.0)
    units = diagonal_unit_vectors(TRAVEL, margin_mm=0.0)
    diag = np.sqrt(500.0**2 + 300.0**2 + 300.0**2)
    np.testing.assert_allclose(units["diag-PPP"], [500 / diag, 300 / diag, 300 / diag])
    np.testing.assert_allclose(units["diag-PPN"], [500 / diag, 300 / diag, -300 / diag])
    for label, u in units.items():
        assert np.linalg.norm(u) == pytest.approx(1.0)
        np.testing.assert_allclose(pts[label][-1] - pts[label][0], diag * u)


@pytest.mark.parametrize(("travel", "kwargs", "what"), [
    ({"x": (0, 100), "y": (0, 100)}, {}, "travel has no z axis"),
    ({**TRAVEL, "y": (300.0, 0.0)}, {}, "travel of y must be"),
    ({**TRAVEL, "y": (0.0, float("nan"))}, {}, "travel of y must be"),
    (TRAVEL, {"margin_mm": 150.0}, "leaves nothing inside a margin of 150"),
    (TRAVEL, {"margin_mm": -1.0}, "must not be negative"),
    (TRAVEL, {"margin_mm": float("nan")}, "must not be negative"),
    (TRAVEL, {"n_points": 1}, "at least 2 points"),
])
def test_bad_travel(travel: dict[str, tuple[float, float]], kwargs: dict[str, float],
                    what: str) -> None:
    with pytest.raises(DiagonalTestError, match=what):
        diagonal_targets(travel, **kwargs)  # type: ignore[arg-type]


def diagonal_readings(error: Callable[[str, int], float], n_points: int = 6, runs: int = 2,
                      reversal_um: float = 3.0, flip_u: str = "") -> Measurements:
    """Bidirectional runs on all four diagonals; reading = error(label, k) +- reversal/2.

    The reversal is +half on the way out and -half on the way back, so it cancels in the
    per-target mean; ``flip_u`` names a diagonal whose laser senses against it.
    """
    pts = diagonal_targets(TRAVEL, n_points=n_points)
    units = diagonal_unit_vectors(TRAVEL)
    test, run, q, u, value, direction = [], [], [], [], [], []
    for label, p in pts.items():
        sign = -1.0 if label == flip_u else 1.0
        for j in range(runs):
            order = [*range(n_points), *reversed(range(n_points))]
            for step, k in enumerate(order):
                out = step < n_points
                test.append(label)
                run.append(j)
                q.append([*p[k], 0.0, 0.0, 0.0])
                u.append(sign * units[label])
                value.append(sign * (error(label, k) + (0.5 if out else -0.5) * reversal_um))
                direction.append([s if out else -s for s in DIAGONALS[label]])
    n = len(test)
    return Measurements(
        test=np.array(test), run=np.array(run, dtype=np.int64), time_s=np.arange(n, dtype=float),
        q=np.array(q), direction=np.array(direction, dtype=np.int8), tool_mm=np.zeros(n),
        is_angle=np.zeros(n, dtype=bool), u=np.array(u), value=np.array(value))


def known_error(label: str, k: int) -> float:
    """A different known profile per diagonal (µm at target k of 6)."""
    return {"diag-PPP": 2.0 * k,                      # range 10
            "diag-NPP": 4.0,                          # range 0
            "diag-PNP": [0, 5, -3, 1, 2, 0][k],       # range 8
            "diag-PPN": -1.5 * k}[label]              # range 7.5


def test_ranges_from_hand_built_readings() -> None:
    ranges = diagonal_ranges(diagonal_readings(known_error, flip_u="diag-PNP"))
    assert list(ranges) == ["diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN"]
    assert ranges["diag-PPP"] == pytest.approx(10.0)
    assert ranges["diag-NPP"] == pytest.approx(0.0, abs=1e-12)
    assert ranges["diag-PNP"] == pytest.approx(8.0)
    assert ranges["diag-PPN"] == pytest.approx(7.5)


def test_ranges_survive_the_csv_and_ignore_other_tests(tmp_path: Path) -> None:
    diag = diagonal_readings(known_error)
    other = diag.select(np.flatnonzero(diag.test == "diag-PPP")[:4])
    other = replace(other, test=np.array(["X-positioning"] * 4), value=other.value + 1000.0)
    path = tmp_path / "diag.csv"
    write_measurements(path, Measurements.concat([other, diag]))
    assert diagonal_ranges(read_measurements(path)) == pytest.approx(diagonal_ranges(diag))


def test_improvement_per_diagonal_and_overall() -> None:
    before = {"diag-PPP": 10.0, "diag-NPP": 20.0}
    after = {"diag-PPP": 3.0, "diag-NPP": 4.0}
    gain = improvement(before, after)
    assert gain == pytest.approx({"diag-PPP": 0.7, "diag-NPP": 0.8, "overall": 1 - 4 / 20})
    worse = improvement(before, {"diag-PPP": 15.0, "diag-NPP": 20.0})
    assert worse["diag-PPP"] == pytest.approx(-0.5) and worse["overall"] == pytest.approx(0.0)


def test_improvement_of_a_compensation_on_readings() -> None:
    before = diagonal_ranges(diagonal_readings(known_error, reversal_um=0.0).select(
        np.arange(4 * 2 * 12) < 2 * 12))  # diag-PPP only, range 10
    after = diagonal_ranges(diagonal_readings(lambda _, k: 0.5 * k, reversal_um=0.0).select(
        np.arange(4 * 2 * 12) < 2 * 12))  # range 2.5
    assert improvement(before, after) == pytest.approx({"diag-PPP": 0.75, "overall": 0.75})


def test_improvement_refuses_what_it_cannot_compare() -> None:
    with pytest.raises(DiagonalTestError, match="before has diagonals"):
        improvement({"diag-PPP": 1.0}, {"diag-NPP": 1.0})
    with pytest.raises(DiagonalTestError, match="range before is 0"):
        improvement({"diag-PPP": 0.0}, {"diag-PPP": 1.0})
    with pytest.raises(DiagonalTestError, match="no diagonals"):
        improvement({}, {})


def test_readings_that_are_not_a_diagonal_test() -> None:
    m = diagonal_readings(known_error)
    with pytest.raises(DiagonalTestError, match="no body-diagonal readings"):
        diagonal_ranges(replace(m, test=np.array(["X-positioning"] * len(m))))
    is_angle = m.is_angle.copy()
    is_angle[0] = True
    with pytest.raises(DiagonalTestError, match="diag-PPP: 1 angle reading"):
        diagonal_ranges(replace(m, is_angle=is_angle))
    q = m.q.copy()
    q[3, 2] += 0.5
    with pytest.raises(DiagonalTestError, match=r"diag-PPP: the commanded points do not lie "
                                                r"on one line .* is 0\.\d+ mm off"):
        diagonal_ranges(replace(m, q=q))
    u = m.u.copy()
    u[30] = [0.0, 0.0, 1.0]
    with pytest.raises(DiagonalTestError, match=r"diag-NPP: .* not along the diagonal"):
        diagonal_ranges(replace(m, u=u))
    single = diagonal_readings(known_error).select(np.array([0, 11]))  # one point, twice
    with pytest.raises(DiagonalTestError, match="diag-PPP: only one target point"):
        diagonal_ranges(single)
