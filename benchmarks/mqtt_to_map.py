"""MQTT temperature publish → new map applied by the machine: latency p50/p99 (target p99
< 250 ms).

    .venv/bin/python benchmarks/mqtt_to_map.py [--machines 20] [--samples 200]

Needs Mosquitto on 127.0.0.1:1883. Three processes: this one runs the center (push
scheduler, machine TCP server, MQTT bridge, SQLite in a temporary directory); a fake
fleet (benchmarks/center_connections.py) whose machines carry a thermal model term on the
spindle sensor and check every map before acking; a publisher that sets every machine's
spindle temperature once, then steps one machine's temperature by 0.5 K every
``--interval`` seconds. A sample is the time from the publish (``time.monotonic``, which
is system-wide on Linux) to the machine's MapAck of the map built for it: broker, bridge,
trigger, map build on the build pool, database, push and the machine's checks.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from center_connections import Fleet, center, name_of, percentiles, register

MODEL = {"format": "ednc-model/1", "machine": name_of(0),
         "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 0.01, 1e-5],
                                "origin": 0.0, "scale": 1.0}},
         "locations": {},
         "terms": [{"effect": "thermal_drift", "axis": "z", "sensor": "T_spindle_C",
                    "coefficient": 1.5, "t_ref_C": 20.0, "q_min": 0.0}],
         "info": {}}


async def publisher_main(host: str, port: int, prefix: str, count: int, samples: int,
                         interval: float) -> None:
    import aiomqtt
    sent: list[tuple[str, float]] = []
    async with aiomqtt.Client(host, port, identifier=f"bench-pub-{uuid.uuid4().hex[:8]}") as c:
        for i in range(count):
            await c.publish(f"{prefix}/{name_of(i)}/temperature/spindle", "20.0", qos=1)
        print("INIT", flush=True)
        await asyncio.to_thread(sys.stdin.readline)
        for k in range(samples):
            i = k % count
            celsius = 20.0 + 0.5 * (k // count + 1)
            t = time.monotonic()
            await c.publish(f"{prefix}/{name_of(i)}/temperature/spindle",
                            json.dumps({"celsius": celsius}), qos=0)
            sent.append((name_of(i), t))
            await asyncio.sleep(interval)
    print(json.dumps(sent), flush=True)


async def main(count: int, samples: int, interval: float, broker: tuple[str, int],
               show: bool = False) -> None:
    prefix = f"ednc-bench-{uuid.uuid4().hex[:8]}"
    with tempfile.TemporaryDirectory() as tmp:
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000, mqtt=broker,
                          prefix=prefix) as (c, services):
            await c.db.run(register, count, MODEL, None)
            assert services.mqtt is not None
            await services.mqtt.connected.wait()
            builds: list[float] = []
            services.push.observers.append(lambda d: builds.append(time.monotonic()))
            fleet = Fleet(services.server.port, count)
            await fleet.ready()
            pub = subprocess.Popen(
                [sys.executable, __file__, "--publisher", "--prefix", prefix,
                 "--machines", str(count), "--samples", str(samples),
                 "--interval", str(interval)], stdin=subprocess.PIPE,
                stdout=subprocess.PIPE, text=True)
            assert pub.stdin is not None and pub.stdout is not None
            assert (await asyncio.to_thread(pub.stdout.readline)).strip() == "INIT"
            while len(builds) < count:  # every machine has its first thermal map
                await asyncio.sleep(0.05)
            pub.stdin.write("GO\n")
            pub.stdin.flush()
            sent = json.loads(await asyncio.to_thread(pub.stdout.readline))
            await asyncio.sleep(1.0)  # the last maps
            report = await fleet.finish()
            pub.wait(10)
    acks: dict[str, list[list[float]]] = report["acks"]
    latencies, missing = [], 0
    for name, t in sent:
        after = [a for _, a in acks.get(name, []) if a > t]
        if after:
            latencies.append(min(after) - t)
        else:
            missing += 1
    if show:
        print(" ".join(f"{1000 * x:.0f}" for x in latencies))
    p50, p99, pmax = percentiles(latencies, 50, 99, 100)
    print(f"machines {count}, {len(sent)} temperature steps of 0.5 K, one every "
          f"{1000 * interval:.0f} ms")
    print(f"publish -> MapAck: p50 {1000 * p50:.0f} ms, p99 {1000 * p99:.0f} ms, "
          f"max {1000 * pmax:.0f} ms ({len(latencies)} samples, {missing} without a map)")
    print(f"target p99 < 250 ms: {'met' if p99 < 0.25 else 'NOT met'}")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", type=int, default=20)
    p.add_argument("--samples", type=int, default=200)
    p.add_argument("--interval", type=float, default=0.1)
    p.add_argument("--broker", default="127.0.0.1:1883")
    p.add_argument("--show", action="store_true", help="print every sample, ms")
    p.add_argument("--publisher", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--prefix", default="ednc", help=argparse.SUPPRESS)
    a = p.parse_args()
    host, _, port = a.broker.rpartition(":")
    if a.publisher:
        asyncio.run(publisher_main(host, int(port), a.prefix, a.machines, a.samples,
                                   a.interval))
    else:
        os.environ.setdefault("EDNC_NODE_ID", "bench")
        asyncio.run(main(a.machines, a.samples, a.interval, (host, int(port)), a.show))
