"""``ednc lookup`` checks the rules of protocol/README.md §6 a from-spec implementation
needs (issue 30): a negative-approach mode (``--negative``, or a ``dir_<axis>`` column
per point) that gives the vectors' counts in both directions, the reversal added before
the final clamp, and the no-reading rule (a sensor without ``--temperature`` adds 0)."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

VECTORS = Path(__file__).parent / "vectors"


def _ednc(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", "from ednc.cli import main; main()", *args],
                          capture_output=True, text=True, timeout=600)


def _points(path: Path, axes: list[str], q: list[list[float]],
            negative: list[list[bool]]) -> None:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([a.lower() for a in axes] + [f"dir_{a.lower()}" for a in axes])
        for row, neg in zip(q, negative, strict=True):
            w.writerow([repr(float(v)) for v in row] + [-1 if f else 1 for f in neg])


def _counts(run: subprocess.CompletedProcess[str], axes: list[str], per_unit: int
            ) -> tuple[np.ndarray, dict[str, Any]]:
    assert run.returncode == 0, run.stderr
    body: dict[str, Any] = json.loads(run.stdout)
    keys = [a.lower() for a in axes]
    mm = np.array([[p["correction"][k] for k in keys] for p in body["points"]])
    return np.asarray(np.rint(mm * per_unit), dtype=np.int64), body


@pytest.mark.parametrize("name", ["factored_5axis", "grid_3axis", "grid_ties"])
def test_lookup_gives_the_vectors_in_both_directions(name: str, tmp_path: Path) -> None:
    vec = json.loads((VECTORS / f"{name}.json").read_text())
    axes = vec["axes"]
    pts = vec["points"]
    _points(tmp_path / "p.csv", axes, [[p["q"][a] for a in axes] for p in pts],
            [p["negative"] for p in pts])
    args = ["lookup", "--map", str(VECTORS / vec["map"]), "--points",
            str(tmp_path / "p.csv"), "--json", "--extrapolate"]
    for k, v in vec["temperatures_C"].items():
        args += ["--temperature", f"{k}={v!r}"]
    got, body = _counts(_ednc(*args), axes, vec["counts_per_unit"])
    if vec["kind"] == "grid":  # a grid's outputs: those the vector lists
        outputs = len(pts[0]["counts"])
        got = got[:, :outputs]
    assert got.tolist() == [p["counts"] for p in pts]
    assert any(p.get("negative") for p in body["points"])


def test_lookup_runs_the_rules_scenario_with_unread_sensors(tmp_path: Path) -> None:
    """Steps of ``rules.json`` on map A: step 2, spindle alone (x_screw and coolant never
    read: their records add 0, and stderr says so); then step 3's readings and positions with X
    negative too (step 6's move): X 8 + 5 clamped to 10, Z and C as in step 3, through
    ``--negative`` for every point."""
    vec = json.loads((VECTORS / "rules.json").read_text())
    steps = vec["steps"]
    axes = vec["axes"]
    mapfile = str(VECTORS / vec["maps"]["A"])
    _points(tmp_path / "p.csv", axes, [[v / 1000 for v in steps[1]["q_counts"]]],
            [[d < 0 for d in steps[1]["direction"]]])
    run = _ednc("lookup", "--map", mapfile, "--points", str(tmp_path / "p.csv"), "--json",
                "--extrapolate", "--temperature", "spindle=26")
    got, body = _counts(run, axes, 1000)
    assert got.tolist() == [steps[1]["counts"]]
    assert body["unread_sensors"] == ["coolant", "x_screw"] and "never read" in run.stderr
    step = steps[2]
    with (tmp_path / "q.csv").open("w") as fh:
        fh.write("x,z,c\n" + ",".join(str(v / 1000) for v in step["q_counts"]) + "\n")
    run = _ednc("lookup", "--map", mapfile, "--points", str(tmp_path / "q.csv"), "--json",
                "--extrapolate", "--temperature", "spindle=26", "--temperature",
                "x_screw=25", "--negative", "x,z", "--negative", "c")
    got, body = _counts(run, axes, 1000)
    assert got.tolist() == [[10, *step["counts"][1:]]]
    assert body["unread_sensors"] == ["coolant"]  # step 3 has no coolant reading yet
    assert body["points"][0]["negative"] == ["x", "z", "c"]
    bad = _ednc("lookup", "--map", mapfile, "--points", str(tmp_path / "q.csv"),
                "--extrapolate", "--negative", "y")
    assert bad.returncode == 2 and "--negative y: not an axis" in bad.stderr
