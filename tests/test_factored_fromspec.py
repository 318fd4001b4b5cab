"""Issue 24's target: an integer implementation written from protocol/README.md section 6
alone (``tests/support/factored_fromspec.py``) matches ``ednc lookup`` exactly, on the
test vectors of ``tests/vectors/`` and on 5,000 random points of the factored vector's
map; the vectors' expected counts (both approach directions) are the machine ladder's."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.support import factored_fromspec as spec

VECTORS = Path(__file__).parent / "vectors"
NAMES = ("factored_5axis", "grid_3axis", "grid_ties")


def _vector(name: str) -> dict[str, Any]:
    body: dict[str, Any] = json.loads((VECTORS / f"{name}.json").read_text())
    return body


def _lookup(map_path: Path, axes: list[str], q: np.ndarray, temps: dict[str, float],
            tmp: Path) -> np.ndarray:
    """``ednc lookup --json`` at points q (N, len(axes)) mm/degrees → counts (N, axes)."""
    pts = tmp / "points.csv"
    with pts.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([a.lower() for a in axes])
        w.writerows([[repr(float(v)) for v in row] for row in q])
    # the vectors hold points just outside the travel too (the ladder holds the ends)
    args = ["lookup", "--map", str(map_path), "--points", str(pts), "--json", "--extrapolate"]
    for k, v in temps.items():
        args += ["--temperature", f"{k}={v!r}"]
    run = subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()", *args],
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    body = json.loads(run.stdout)
    keys = [a.lower() for a in axes]
    mm = np.array([[p["correction"][k] for k in keys] for p in body["points"]])
    return np.asarray(np.rint(mm * 1000), dtype=np.int64)


def _fromspec(name: str, body: dict[str, Any], q_counts: list[list[int]],
              negative: list[list[bool]]) -> list[list[int]]:
    data = (VECTORS / body["map"]).read_bytes()
    readings = {k: spec.millicelsius(v) for k, v in body["temperatures_C"].items()}
    assert readings == body["temperatures_mC"]
    if body["kind"] == "factored":
        m = spec.parse_factored(data)
        return [spec.factored_counts(m, q, readings, neg)
                for q, neg in zip(q_counts, negative, strict=True)]
    g = spec.parse_grid(data)
    axes = body["axes"]
    return [spec.grid_counts(g, dict(zip(axes, q, strict=True)), readings,
                             dict(zip(axes, neg, strict=True)))
            for q, neg in zip(q_counts, negative, strict=True)]


@pytest.mark.parametrize("name", NAMES)
def test_the_fromspec_implementation_gives_the_vectors(name: str) -> None:
    body = _vector(name)
    pts = body["points"]
    for p in pts:  # the README's position rule gives the vector's counts
        assert [spec.position_counts(p["q"][a], body["counts_per_unit"])
                for a in body["axes"]] == p["q_counts"]
    got = _fromspec(name, body, [p["q_counts"] for p in pts], [p["negative"] for p in pts])
    assert got == [p["counts"] for p in pts]
    assert any(any(p["negative"]) for p in pts)


@pytest.mark.parametrize("name", NAMES)
def test_ednc_lookup_gives_the_vectors(name: str, tmp_path: Path) -> None:
    """Positive approach (``ednc lookup`` has no direction): the vectors' counts."""
    body = _vector(name)
    pts = [p for p in body["points"] if not any(p["negative"])]
    axes = body["axes"]
    q = np.array([[p["q"][a] for a in axes] for p in pts])
    got = _lookup(VECTORS / body["map"], axes, q, body["temperatures_C"], tmp_path)
    want = np.array([p["counts"] for p in pts])
    assert np.array_equal(got, want)


def test_fromspec_matches_ednc_lookup_on_5000_random_points(tmp_path: Path) -> None:
    """The factored vector's map, 5,000 random points over its axes' travel (positions
    in whole and fractional µm, temperatures of both records), positive approach."""
    body = _vector("factored_5axis")
    axes = body["axes"]
    m = spec.parse_factored((VECTORS / body["map"]).read_bytes())
    lo = np.array([body["travel"][a][0] for a in axes])
    hi = np.array([body["travel"][a][1] for a in axes])
    rng = np.random.default_rng(24)
    q = lo + (hi - lo) * rng.random((5000, len(axes)))
    q[:2500] = np.round(q[:2500], 3)  # half on whole counts, half between them
    temps = {"spindle": 24.1234, "x_screw": 19.0}
    got = _lookup(VECTORS / body["map"], axes, q, temps, tmp_path)
    readings = {k: spec.millicelsius(v) for k, v in temps.items()}
    want = [spec.factored_counts(m, [spec.position_counts(v, m.per_unit) for v in row],
                                 readings) for row in q.tolist()]
    diff = np.flatnonzero((got != np.array(want)).any(axis=1))
    assert diff.size == 0, f"{diff.size} of 5000 differ, first at {q[diff[0]]}"
