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

    .venv/bin/python benchmarks/mqtt_to_map.py --mode temperatures [--machines 50]
        [--samples 1000] [--interval 0.02]

``--mode temperatures`` measures the path without any map: the machines' model has no
thermal term (their description lists the sensor ``spindle``, so the intake takes it),
and a sample is the time from the publish to the Temperatures message carrying that value
decoded by the machine (broker, bridge, intake screen, coalesced forwarding, TCP, the
machine's protocol decode; a real controller uses it in its next cycle, 4-8 ms more at
most). Also printed: the center's CPU per temperature (process time of the whole center
process over the publishing phase, database writes of the time series included, divided
by the temperatures published).
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
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
from center_connections import (
    SECRET,
    Fleet,
    center,
    description,
    ip_of,
    name_of,
    percentiles,
    register,
)

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


PLAIN = {**MODEL, "terms": []}


def register_with_sensor(session: Any, count: int) -> None:
    """``count`` machines whose model has no thermal term and whose description lists the
    sensor ``spindle`` (what the intake needs to take its readings)."""
    from server.db import error_models, machines
    for i in range(count):
        row = machines.create_machine(session, name=name_of(i), ip=ip_of(i),
                                      controller="fanuc",
                                      description={**description(i), "sensors": ["spindle"]},
                                      secret=SECRET)
        error_models.add_model(session, row.id, source="upload",
                               body={**PLAIN, "machine": name_of(i)})


async def main_temperatures(count: int, samples: int, interval: float,
                            broker: tuple[str, int], show: bool = False) -> None:
    """Publish → Temperatures on the machine (module docstring)."""
    prefix = f"ednc-bench-{uuid.uuid4().hex[:8]}"
    with tempfile.TemporaryDirectory() as tmp:
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000, mqtt=broker,
                          prefix=prefix) as (c, services):
            await c.db.run(register_with_sensor, count)
            assert services.mqtt is not None and services.intake is not None
            await services.mqtt.connected.wait()
            fleet = Fleet(services.server.port, count)
            await fleet.ready()
            pub = subprocess.Popen(
                [sys.executable, __file__, "--publisher", "--prefix", prefix,
                 "--machines", str(count), "--samples", str(samples),
                 "--interval", str(interval)], stdin=subprocess.PIPE,
                stdout=subprocess.PIPE, text=True)
            assert pub.stdin is not None and pub.stdout is not None
            assert (await asyncio.to_thread(pub.stdout.readline)).strip() == "INIT"
            forwarded = services.intake.forwarder.stats
            while forwarded.readings < count:  # every machine has its first temperature
                await asyncio.sleep(0.05)
            await asyncio.sleep(5.0)  # start-up work settles (status seeding, first flush)
            idle0, idle_wall0 = time.process_time(), time.monotonic()
            await asyncio.sleep(5.0)  # the center's own cost meanwhile: sessions, status
            idle = (time.process_time() - idle0) / (time.monotonic() - idle_wall0)
            cpu0, wall0 = time.process_time(), time.monotonic()
            times0 = os.times()
            pub.stdin.write("GO\n")
            pub.stdin.flush()
            sent = json.loads(await asyncio.to_thread(pub.stdout.readline))
            await asyncio.sleep(1.0)  # the last ones
            await services.intake.flush()
            cpu, wall = time.process_time() - cpu0, time.monotonic() - wall0
            times1 = os.times()
            user, system = times1.user - times0.user, times1.system - times0.system
            refused = services.intake.stats.refused
            report = await fleet.finish()
            pub.wait(10)
    got: dict[str, list[list[float]]] = report.get("temperatures", {})
    latencies, missing = [], 0
    for k, (name, t) in enumerate(sent):
        celsius = 20.0 + 0.5 * (k // count + 1)  # as the publisher steps them
        # that value or a later one (values only rise): coalescing may skip a value that
        # a newer one overtook before it was sent, which is the point of it
        after = [a for value, a in got.get(name, []) if a > t and value >= celsius - 1e-9]
        if after:
            latencies.append(min(after) - t)
        else:
            missing += 1
    if show:
        print(" ".join(f"{1000 * x:.1f}" for x in latencies))
    p50, p99, pmax = percentiles(latencies, 50, 99, 100)
    print(f"machines {count}, {len(sent)} temperature steps of 0.5 K, one every "
          f"{1000 * interval:.0f} ms ({1 / interval:.0f} updates/s)")
    print(f"publish -> Temperatures on the machine: p50 {1000 * p50:.1f} ms, "
          f"p99 {1000 * p99:.1f} ms, max {1000 * pmax:.1f} ms ({len(latencies)} samples, "
          f"{missing} without a Temperatures of that value or a newer one, {refused} refused "
          f"by the intake)")
    extra = max(cpu - idle * wall, 0.0)
    print(f"center CPU {1000 * extra / max(len(sent), 1):.3f} ms per temperature above "
          f"its idle {100 * idle:.1f} % of one core ({1000 * cpu / max(len(sent), 1):.3f} ms "
          f"with it; {100 * cpu / wall:.0f} % of one core over {wall:.1f} s; "
          f"target <= 0.2 ms)")
    n = max(len(sent), 1)
    print(f"  of which user {1000 * user / n:.3f} ms, kernel {1000 * system / n:.3f} ms per "
          f"temperature (the kernel part is mostly the loopback send to each machine)")
    own = await center_path_cost(count, 20_000)
    print(f"  the center's own code (topic and payload parsing, screen, board, series "
          f"buffer, Temperatures frame), in process without MQTT client or sockets: "
          f"{1000 * own:.3f} ms per temperature ({1 / own:,.0f}/s on one core)")


class _NullSession:
    """A session that encodes the frame and drops it (no socket): the center's own code."""

    def __init__(self) -> None:
        from protocol import Connection, Role
        from protocol.state import Channel, State
        self.conn = Connection(Role.CENTER)
        self.conn._state.states[Channel.SESSION] = State.READY  # past the handshake
        self.bytes = 0

    def send(self, msg: Any) -> None:
        self.bytes += len(self.conn.send(msg))


async def center_path_cost(count: int, readings: int) -> float:
    """CPU s per reading of the center's own path, without MQTT client or sockets: the
    bridge's topic and payload parsing, the intake's screen, the board, the time-series
    buffer and the forwarder's encoding into a Temperatures frame."""
    from server.mqtt import MqttBridge
    with tempfile.TemporaryDirectory() as tmp:
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000) as (c, services):
            await c.db.run(register_with_sensor, count)
            intake = services.intake
            for i in range(count):
                await intake.lookup(name_of(i))
            intake.forwarder.sessions = {name_of(i): _NullSession() for i in range(count)}
            intake.forwarder.interval_s = 0.0  # every reading its own frame, as at low rates
            bridge = MqttBridge(c, services.feed, services.temperatures, host="unused")
            topics = [f"ednc/{name_of(i)}/temperature/spindle" for i in range(count)]
            t0 = time.process_time()
            for k in range(readings):
                bridge.handle(topics[k % count], f"{20.0 + 0.001 * (k // count)}".encode())
            cost = (time.process_time() - t0) / readings
            assert intake.forwarder.stats.readings == readings, intake.forwarder.stats
    return float(cost)


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
    p.add_argument("--mode", choices=("map", "temperatures"), default="map",
                   help="measure to the new map applied (map) or to the Temperatures "
                   "message on the machine (temperatures)")
    p.add_argument("--publisher", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--prefix", default="ednc", help=argparse.SUPPRESS)
    a = p.parse_args()
    host, _, port = a.broker.rpartition(":")
    if a.publisher:
        asyncio.run(publisher_main(host, int(port), a.prefix, a.machines, a.samples,
                                   a.interval))
    else:
        os.environ.setdefault("EDNC_NODE_ID", "bench")
        run = main_temperatures if a.mode == "temperatures" else main
        asyncio.run(run(a.machines, a.samples, a.interval, (host, int(port)), a.show))
