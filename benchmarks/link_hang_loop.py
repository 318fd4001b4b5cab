"""The link server's bad-frame tests, run again and again: a rare hang shows as a timeout.

    .venv/bin/python benchmarks/link_hang_loop.py [--runs 200] [--timeout 120] [-k bad_frame]

Each run is a fresh pytest process over ``tests/test_server_link.py`` (by default only the
bad-frame tests, where the hang was seen: a machine's bad frame early in its session, or
after Welcome), stopped after ``--timeout`` seconds. Prints a line per failure or hang and
the totals: runs, passed, failed, hung (timed out), and the slowest run.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per run")
    ap.add_argument("-k", default="bad_frame", help="pytest -k expression ('' for all)")
    args = ap.parse_args()
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p",
           "no:randomly", "tests/test_server_link.py"]
    if args.k:
        cmd += ["-k", args.k]
    passed = failed = hung = 0
    slowest = 0.0
    for run in range(1, args.runs + 1):
        t0 = time.perf_counter()
        try:
            out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True,
                                 timeout=args.timeout, check=False)
        except subprocess.TimeoutExpired:
            hung += 1
            print(f"run {run}: no result within {args.timeout:g} s (hang)", flush=True)
            continue
        took = time.perf_counter() - t0
        slowest = max(slowest, took)
        if out.returncode == 0:
            passed += 1
        else:
            failed += 1
            tail = out.stdout.strip().splitlines()[-1:] or ["(no output)"]
            print(f"run {run}: exit {out.returncode}: {tail[0]}", flush=True)
        if run % 25 == 0:
            print(f"... {run} runs: {passed} passed, {failed} failed, {hung} hung",
                  flush=True)
    print(f"{args.runs} runs of {' '.join(cmd[3:])}: {passed} passed, {failed} failed, "
          f"{hung} hung; slowest run {slowest:.1f} s")


if __name__ == "__main__":
    main()
