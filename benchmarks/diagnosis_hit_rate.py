"""Hit rate of ``ednc diagnose`` on simulated campaigns with one hidden effect (or none).

Run: ``.venv/bin/python benchmarks/diagnosis_hit_rate.py [N]``. Uses the case generator of
``tests/test_diagnose.py`` (kind, axis, sensor, size and chain drawn per seed) on seeds
beyond the ones the test suite uses, and prints the hit rate per effect kind, the misses
and the time per diagnosis.
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.support.diagnose import N_CASES, make_case, run_case


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    hits: Counter[str] = Counter()
    total: Counter[str] = Counter()
    misses = []
    t0 = time.perf_counter()
    for seed in range(N_CASES, N_CASES + n):
        case = make_case(seed)
        ok, said = run_case(case)
        total[case.kind] += 1
        hits[case.kind] += ok
        if not ok:
            misses.append(f"seed {seed} {case.chain}: hid {case.kind} {case.axis} "
                          f"{case.sensor} {case.size}; said {said}")
    dt = (time.perf_counter() - t0) / n
    for kind in sorted(total):
        print(f"{kind:18s} {hits[kind]:3d}/{total[kind]:3d}")
    print(f"{'all':18s} {sum(hits.values()):3d}/{n:3d}   ({dt:.1f} s per campaign incl. "
          "simulation)")
    for line in misses:
        print("miss:", line)


if __name__ == "__main__":
    main()
