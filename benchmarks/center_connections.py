"""How many machine connections one center process holds, and what each costs.

    .venv/bin/python benchmarks/center_connections.py [--machines 5000] [--hold 20]

The center (push scheduler, machine TCP server, SQLite in a temporary directory) runs in
this process; the machines are lightweight raw protocol clients (handshake with HMAC,
heartbeat replies, Telemetry, map acks through ``MapAssembler``) in a separate process, so
the center's event loop is measured alone. Each machine connects from its own loopback
address (127.1.x.y), which is also its registered ip. Prints: time to connect all, RSS
growth per connection, the center's CPU share while holding them with heartbeats, and
whether any session dropped.

The fake fleet (``--fleet``) is reused by push_latency.py and mqtt_to_map.py.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import gc
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from protocol import (  # noqa: E402
    NEED_DATA,
    AuthResponse,
    Challenge,
    Connection,
    Controller,
    Error,
    Heartbeat,
    HeartbeatReply,
    Hello,
    MapAssembler,
    MapBegin,
    MapChunk,
    MapEncoding,
    MapEnd,
    Message,
    Reject,
    Role,
    Telemetry,
    Temperatures,
    Welcome,
    compute_mac,
)

SECRET = "benchmark-secret-0123456789"


def name_of(i: int) -> str:
    return f"bench-{i:05d}"


def ip_of(i: int) -> str:
    return f"127.1.{i // 250}.{i % 250 + 1}"


def description(i: int) -> dict[str, Any]:
    return {"name": name_of(i), "controller": "fanuc", "ip": ip_of(i),
            "chain": "w X Y b Z t",
            "travel_mm": {"x": [0, 500], "y": [0, 300], "z": [-300, 0]},
            "tool_length_mm": 100.0}


def rss_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def cpu_of(pid: int) -> float:
    """CPU time (user + system) of another process so far, s (Linux ``/proc``)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def percentiles(values: list[float], *qs: float) -> list[float]:
    s = sorted(values)
    if not s:
        return [float("nan")] * len(qs)
    return [s[min(len(s) - 1, int(q / 100.0 * len(s)))] for q in qs]


# -- the fake fleet (child process)

TEMPERATURES: dict[str, list[tuple[float, float]]] = {}
"""Per machine: (°C of the sensor ``spindle``, time.monotonic()) of every Temperatures."""


class FakeMachine:
    """One machine: the protocol, nothing else."""

    def __init__(self, i: int, port: int, acks: dict[str, list[tuple[int, float]]]) -> None:
        self.name, self.ip, self.port = name_of(i), ip_of(i), port
        self.acks = acks
        self.welcomed = asyncio.Event()
        self.applied = 0
        self.error = ""

    async def run(self) -> None:
        """Connect, retrying with jittered backoff (as a PLC does) until welcomed once."""
        rng = random.Random(self.name)
        for attempt in range(30):
            await self._session()
            if self.welcomed.is_set():
                return
            await asyncio.sleep(min(5.0, 0.2 * 2 ** attempt) * (0.5 + 0.5 * rng.random()))

    async def _session(self) -> None:
        try:
            reader, writer = await asyncio.open_connection("127.0.0.1", self.port,
                                                          local_addr=(self.ip, 0))
        except OSError as exc:
            self.error = f"connect: {exc}"
            return
        conn = Connection(Role.MACHINE)
        assembler = MapAssembler(self.name, MapEncoding.INT32_INCREMENTS)
        telemetry: asyncio.Task[None] | None = None

        def send(msg: Message) -> None:
            writer.write(conn.send(msg))

        send(Hello(self.name, self.ip, Controller.FANUC, MapEncoding.INT32_INCREMENTS,
                   "bench-1", "w X Y b Z t"))
        try:
            while True:
                data = await reader.read(65536)
                conn.receive_data(data)
                while (event := conn.next_event()) is not NEED_DATA:
                    match event:
                        case Challenge(nonce=nonce):
                            send(AuthResponse(compute_mac(SECRET.encode(), nonce, self.name)))
                        case Welcome(telemetry_period_ms=period):
                            self.welcomed.set()
                            telemetry = asyncio.create_task(self._telemetry(send, period))
                        case Heartbeat(token=token):
                            send(HeartbeatReply(token))
                        case MapBegin() | MapChunk() | MapEnd():
                            verdict = assembler.feed(event)
                            if verdict is not None:
                                if hasattr(verdict, "ack"):
                                    self.applied = assembler.applied_version = verdict.version
                                    send(verdict.ack())
                                    self.acks.setdefault(self.name, []).append(
                                        (verdict.version, time.monotonic()))
                                else:
                                    send(verdict.message())
                        case Temperatures(readings=readings):
                            now = time.monotonic()
                            for r in readings:
                                if r.name == "spindle":
                                    TEMPERATURES.setdefault(self.name, []).append(
                                        (r.celsius, now))
                        case Reject() | Error():
                            self.error = repr(event)
                            return
                        case _:
                            self.error = "closed"
                            return
        except (OSError, ValueError) as exc:
            self.error = repr(exc)
        finally:
            if telemetry is not None:
                telemetry.cancel()
            writer.close()

    async def _telemetry(self, send: Callable[[Message], None], period_ms: int) -> None:
        await asyncio.sleep(period_ms / 1000.0 * (hash(self.name) % 1000) / 1000.0)
        while True:
            send(Telemetry(int(time.time() * 1000), "idle", self.applied))
            await asyncio.sleep(period_ms / 1000.0)


async def fleet_main(port: int, count: int, ramp_per_s: float) -> None:
    """Connect ``count`` machines, say READY, hold until stdin closes, then report."""
    acks: dict[str, list[tuple[int, float]]] = {}
    machines = [FakeMachine(i, port, acks) for i in range(count)]
    tasks = []
    for m in machines:
        tasks.append(asyncio.create_task(m.run()))
        if ramp_per_s:
            await asyncio.sleep(1.0 / ramp_per_s)
    waits = [asyncio.create_task(m.welcomed.wait()) for m in machines]
    done, _ = await asyncio.wait(waits, timeout=120)
    print(json.dumps({"ready": len(done)}), flush=True)
    loop = asyncio.get_running_loop()
    await loop.run_in_executor(None, sys.stdin.read)  # until the parent closes stdin
    errors = [m.error for m in machines if not m.welcomed.is_set()]
    print(json.dumps({"acks": acks, "temperatures": TEMPERATURES,
                      "errors": errors[:20], "error_count": len(errors),
                      "welcomed": sum(m.welcomed.is_set() for m in machines)}), flush=True)
    for t in tasks:
        t.cancel()


class Fleet:
    """The fake fleet as a child process."""

    def __init__(self, port: int, count: int, ramp_per_s: float = 0.0, nice: int = 0) -> None:
        self.proc = subprocess.Popen(
            [*(["nice", "-n", str(nice)] if nice else []), sys.executable, __file__,
             "--fleet", "--port", str(port), "--machines", str(count),
             "--ramp", str(ramp_per_s)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    async def ready(self) -> int:
        assert self.proc.stdout is not None
        line = await asyncio.to_thread(self.proc.stdout.readline)
        return int(json.loads(line)["ready"])

    async def finish(self) -> dict[str, Any]:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.close()
        line = await asyncio.to_thread(self.proc.stdout.readline)
        await asyncio.to_thread(self.proc.wait, 30)
        return dict(json.loads(line)) if line else {}


# -- the center (this process)

def register(session: Any, count: int, model: dict[str, Any] | None,
             maps: Callable[[str], bytes] | None) -> None:
    from server.db import error_models, machines
    from server.db import maps as map_repo
    for i in range(count):
        row = machines.create_machine(session, name=name_of(i), ip=ip_of(i),
                                      controller="fanuc", description=description(i),
                                      secret=SECRET)
        if model is not None:
            error_models.add_model(session, row.id, source="upload",
                                   body={**model, "machine": name_of(i)})
            if maps is not None:
                map_repo.add_map_version(session, row.id, payload=maps(name_of(i)),
                                         model_version=1)


@asynccontextmanager
async def center(tmp: Path, *, heartbeat_s: float, telemetry_ms: int,
                 mqtt: tuple[str, int] | None = None, prefix: str = "ednc",
                 push: dict[str, Any] | None = None) -> AsyncIterator[Any]:
    from server.center import Center
    from server.db import Database
    from server.links.ednc import LinkTiming
    from server.services import machine_services
    from server.settings import load_settings
    settings = load_settings(database_url=f"sqlite:///{tmp / 'bench.db'}",
                             machine_host="127.0.0.1", machine_port=0,
                             heartbeat_s=heartbeat_s, push_period_s=600.0,
                             mqtt_host=mqtt[0] if mqtt else None,
                             mqtt_port=mqtt[1] if mqtt else 1883, mqtt_topic_prefix=prefix)
    async with Database.open(settings.database_url) as db:
        c = Center(settings=settings, db=db)
        timing = LinkTiming(heartbeat_s=heartbeat_s, telemetry_period_ms=telemetry_ms)
        async with machine_services(c, timing=timing, push_options=push) as services:
            yield c, services


async def main(count: int, hold_s: float, heartbeat_s: float, telemetry_ms: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        async with center(Path(tmp), heartbeat_s=heartbeat_s, telemetry_ms=telemetry_ms) as (
                c, services):
            await c.db.run(register, count, None, None)
            gc.collect()
            rss0 = rss_mb()
            t0 = time.perf_counter()
            fleet = Fleet(services.server.port, count)
            ready = await fleet.ready()
            while c.registry.connected_count() < ready:
                await asyncio.sleep(0.05)
            t_connect = time.perf_counter() - t0
            gc.collect()
            rss1 = rss_mb()
            cpu0, w0 = time.process_time(), time.perf_counter()
            await asyncio.sleep(hold_s)
            cpu = (time.process_time() - cpu0) / (time.perf_counter() - w0)
            held = c.registry.connected_count()
            report = await fleet.finish()
    print(f"machines            {count} (heartbeat {heartbeat_s:g} s, "
          f"telemetry {telemetry_ms} ms)")
    print(f"welcomed            {ready} in {t_connect:.1f} s "
          f"({ready / t_connect:.0f} handshakes/s)")
    print(f"held after {hold_s:g} s    {held}")
    print(f"center RSS          {rss0:.0f} MB -> {rss1:.0f} MB: "
          f"{(rss1 - rss0) * 1024 / max(ready, 1):.1f} KiB per connection")
    print(f"center CPU holding  {100 * cpu:.0f} % of one core "
          f"(~{ready * (1000 / telemetry_ms + 2 / heartbeat_s):.0f} messages/s)")
    print(f"never welcomed      {report.get('error_count')} {report.get('errors', [])[:3]}")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", type=int, default=5000)
    p.add_argument("--hold", type=float, default=20.0, help="seconds to hold them")
    p.add_argument("--heartbeat", type=float, default=5.0)
    p.add_argument("--telemetry-ms", type=int, default=5000)
    p.add_argument("--fleet", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--port", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--ramp", type=float, default=0.0, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.fleet:
        with contextlib.suppress(KeyboardInterrupt):
            asyncio.run(fleet_main(a.port, a.machines, a.ramp))
    else:
        os.environ.setdefault("EDNC_NODE_ID", "bench")
        asyncio.run(main(a.machines, a.hold, a.heartbeat, a.telemetry_ms))
