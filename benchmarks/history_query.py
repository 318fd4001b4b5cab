"""What a trend chart costs the database: one machine's temperature history over a window,
downsampled by the database (server/db/history.py) against the naive way (every reading
in the window fetched and bucketed in Python).

    .venv/bin/python benchmarks/history_query.py [--hours 24] [--rate 10] [--sensors 3]
                                                 [--url postgresql://...]

Fills ``temperature_readings`` of one machine with ``--rate`` readings a second per
sensor over ``--hours`` (one day at 10 Hz and 3 sensors: 2.6 million rows), on a fresh
SQLite file (default) or a PostgreSQL database of its own (loopback, dropped after), then
times, for windows of 1 h and the whole span at 300 points, the downsampled query and the
naive fetch, then summarises every minute (server/db/history.py ``roll_up``, what the
service does once a minute) and times the query again, now reading the per-minute
summaries. Checks that all three give the same bucket means. Prints one JSON object (ms).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import sys
import tempfile
import time
import uuid
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import psycopg  # noqa: E402
from sqlalchemy import insert  # noqa: E402

from server.dashboard.history import window  # noqa: E402
from server.db import Database, make_engine  # noqa: E402
from server.db.history import roll_up, temperature_buckets  # noqa: E402
from server.db.tables import MachineRow, TemperatureReadingRow  # noqa: E402
from server.db.temperatures import list_readings  # noqa: E402

PG_ADMIN = "host=127.0.0.1 port=5432 user=postgres dbname=postgres connect_timeout=5"
END = dt.datetime(2026, 11, 27, tzinfo=dt.UTC)


def fill(db: Database, hours: float, rate: float, sensors: int) -> tuple[int, int]:
    with db.session() as s:
        machine = MachineRow(name="vmc-01", ip="10.0.0.1", controller="fanuc",
                             description={}, secret="x")
        s.add(machine)
        s.flush()
        mid = machine.id
    n = int(hours * 3600 * rate)
    t0 = END - dt.timedelta(hours=hours)
    chunk = 50_000
    for start in range(0, n, chunk):
        k = np.arange(start, min(n, start + chunk))
        rows = [{"machine_id": mid, "sensor": f"T_s{j}_C", "celsius": 20.0 + 0.001 * (i % 997),
                 "time": t0 + dt.timedelta(seconds=float(i) / rate), "source": "mqtt"}
                for i in k for j in range(sensors)]
        with db.session() as s:
            s.execute(insert(TemperatureReadingRow), rows)
    return mid, n * sensors


def timed(fn: Any, repeat: int = 3) -> tuple[float, Any]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best * 1000.0, out


def naive(db: Database, mid: int, since: dt.datetime, until: dt.datetime, bucket_s: float
          ) -> dict[tuple[str, int], float]:
    """Every reading of the window fetched, bucketed in Python (what a page without a
    downsampling endpoint does with /api/machines/{name}/temperatures)."""
    rows = db.call(list_readings, mid, since=since, until=until, limit=10**9)
    sums: dict[tuple[str, int], list[float]] = {}
    for r in rows:
        key = (r.sensor, int((r.time - since).total_seconds() // bucket_s))
        acc = sums.setdefault(key, [0.0, 0.0])
        acc[0] += r.celsius
        acc[1] += 1
    return {k: v[0] / v[1] for k, v in sums.items()}


def same(buckets: list[Any], means: dict[tuple[str, int], float], since: dt.datetime,
         bucket_s: float) -> None:
    """The database's buckets are the naive ones (means within rounding)."""
    t0 = since.timestamp()
    fast = {(b.series, int((b.t - t0) // bucket_s)): b.mean for b in buckets}
    worst = max(abs(fast[k] - v) for k, v in means.items() if k in fast)
    assert len(fast) == len(means) and worst < 0.01, (len(fast), len(means), worst)


def run(url: str, hours: float, rate: float, sensors: int) -> dict[str, Any]:
    db = Database(make_engine(url))
    db.create_schema()
    t = time.perf_counter()
    mid, rows = fill(db, hours, rate, sensors)
    out: dict[str, Any] = {"backend": db.engine.dialect.name, "rows": rows,
                           "fill_s": round(time.perf_counter() - t, 1)}
    windows = {label: window(END, window_s, 300)
               for label, window_s in (("1h", 3600.0), ("all", hours * 3600.0))}
    found: dict[str, dict[tuple[str, int], float]] = {}
    for label, (since, _, bucket_s) in windows.items():
        fast_ms, buckets = timed(lambda s=since, b=bucket_s: db.call(
            temperature_buckets, [mid], s, END, b))
        slow_ms, means = timed(lambda s=since, b=bucket_s: naive(db, mid, s, END, b), repeat=1)
        found[label] = means
        same(buckets, means, since, bucket_s)
        out[label] = {"points": len(buckets), "bucket_s": bucket_s,
                      "downsampled_ms": round(fast_ms, 1), "naive_ms": round(slow_ms, 1),
                      "naive_over_downsampled": round(slow_ms / fast_ms, 1)}
    t = time.perf_counter()
    while db.call(roll_up, END + dt.timedelta(minutes=2)):
        pass
    out["roll_up_s"] = round(time.perf_counter() - t, 1)
    for label, (since, _, bucket_s) in windows.items():
        minutes_ms, buckets = timed(lambda s=since, b=bucket_s: db.call(
            temperature_buckets, [mid], s, END, b))
        same(buckets, found[label], since, bucket_s)
        out[label]["from_minutes_ms"] = round(minutes_ms, 1)
        out[label]["naive_over_minutes"] = round(out[label]["naive_ms"] / minutes_ms, 1)
    db.engine.dispose()
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--hours", type=float, default=24.0)
    parser.add_argument("--rate", type=float, default=10.0, help="readings/s per sensor")
    parser.add_argument("--sensors", type=int, default=3)
    parser.add_argument("--url", default=None, help="sqlite:///... or postgresql (a fresh "
                        "database of its own is made when it is the word 'postgresql')")
    a = parser.parse_args()
    if a.url == "postgresql":
        name = f"ednc_bench_{uuid.uuid4().hex[:10]}"
        with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
            admin.execute(f'CREATE DATABASE "{name}"')
        try:
            result = run(f"postgresql+psycopg://postgres@127.0.0.1:5432/{name}", a.hours,
                         a.rate, a.sensors)
        finally:
            with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
                admin.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')
    else:
        with tempfile.TemporaryDirectory() as tmp:
            result = run(a.url or f"sqlite:///{tmp}/bench.db", a.hours, a.rate, a.sensors)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
