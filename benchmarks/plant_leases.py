"""What machine leases and plant-wide live links cost a node, per database round.

    .venv/bin/python benchmarks/plant_leases.py [--machines 5000] [--url postgresql://...]

On a fresh PostgreSQL database of its own (loopback, trust auth, dropped after) or the
SQLite file of ``--url sqlite:///...``, with ``--machines`` registered machines, it times
the statements one node runs (server/db/leases.py, server/db/live_links.py):

* acquiring each machine's lease (one call per machine, at handshake), mean and p99;
* renewing every lease of the node (one call every TTL/3);
* publishing every machine's live link (the once-a-second batch when all changed);
* reading the whole plant (what each status/dashboard snapshot reads).

Prints one JSON object (milliseconds).
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import sys
import time
import uuid
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import psycopg  # noqa: E402

from server.db import Database, leases, live_links, make_engine  # noqa: E402
from server.db.tables import MachineRow  # noqa: E402

PG_ADMIN = "host=127.0.0.1 port=5432 user=postgres dbname=postgres connect_timeout=5"


def telemetry(i: int) -> dict[str, Any]:
    return {"timestamp_ms": 1_763_820_000_000 + i, "state": "compensating",
            "map_version": 3,
            "axes": {a: {"position": 100.0 + i % 7, "compensation": 0.0021}
                     for a in "XYZ"},
            "temperatures": {"spindle": 24.5, "bed": 21.2}}


def run(url: str, n: int) -> dict[str, Any]:
    db = Database(make_engine(url))
    db.create_schema()
    try:
        def register(session: Any) -> list[int]:
            rows = [MachineRow(name=f"m-{i:05d}", ip=f"10.{i // 65536}.{i // 256 % 256}."
                               f"{i % 256}", controller="fanuc",
                               description={}, secret="s" * 16) for i in range(n)]
            session.add_all(rows)
            session.flush()
            return [r.id for r in rows]

        ids = db.call(register)
        times = []
        for mid in ids:
            t = time.perf_counter()
            db.call(leases.acquire, mid, "node-a", 15.0)
            times.append(time.perf_counter() - t)
        times.sort()
        t = time.perf_counter()
        kept = db.call(leases.renew, ids, "node-a", 15.0)
        renew_s = time.perf_counter() - t
        assert len(kept) == n
        now = time.time()
        links = [{"machine": f"m-{i:05d}", "connected": True, "address": "10.0.0.1:5000",
                  "connected_since": dt.datetime.fromtimestamp(now, dt.UTC),
                  "last_seen": dt.datetime.fromtimestamp(now, dt.UTC),
                  "telemetry": telemetry(i)} for i in range(n)]
        t = time.perf_counter()
        db.call(live_links.publish, "node-a", links)
        publish_s = time.perf_counter() - t
        t = time.perf_counter()
        db.call(live_links.publish, "node-a", links)
        republish_s = time.perf_counter() - t
        t = time.perf_counter()
        plant = db.call(live_links.plant_links)
        read_s = time.perf_counter() - t
        assert len(plant) == n and all(p.live for p in plant)
        return {
            "backend": db.engine.dialect.name, "machines": n,
            "acquire_mean_ms": 1000 * sum(times) / n,
            "acquire_p99_ms": 1000 * times[int(0.99 * (n - 1))],
            "renew_all_ms": 1000 * renew_s,
            "publish_all_first_ms": 1000 * publish_s,
            "publish_all_again_ms": 1000 * republish_s,
            "read_plant_ms": 1000 * read_s,
        }
    finally:
        db.engine.dispose()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--machines", type=int, default=5000)
    parser.add_argument("--url", default=None, help="database URL (default: a fresh "
                        "PostgreSQL database on 127.0.0.1:5432)")
    args = parser.parse_args()
    if args.url is not None:
        print(json.dumps(run(args.url, args.machines), indent=1))
        return
    name = f"ednc_bench_{uuid.uuid4().hex[:12]}"
    with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
        admin.execute(f'CREATE DATABASE "{name}"')
    try:
        result = run(f"postgresql+psycopg://postgres@127.0.0.1:5432/{name}", args.machines)
        print(json.dumps({k: round(v, 2) if isinstance(v, float) else v
                          for k, v in result.items()}, indent=1))
    finally:
        with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
            admin.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


if __name__ == "__main__":
    main()
