"""Map push latency at 1,000 machines: from MapBegin sent to MapAck received, p50/p99.

    .venv/bin/python benchmarks/push_latency.py [--machines 1000] [--rounds 2]

Each machine is registered with a model and a stored map (built once with
``build_map`` and re-encoded per machine name), so no build runs during the measurement.
The fake fleet (raw protocol clients, benchmarks/center_connections.py) runs in a
separate process; each fake machine checks every map with ``MapAssembler`` (sizes,
SHA-256, decode) before acking. Round 1 is the push every machine gets at Welcome, all
1,000 connecting at once; further rounds re-push to all at once (``PushScheduler.request``
``resend=True``). Latency is what the center's session
measures (``Verdict.latency_s``): it includes the machine's checks and the center's event
loop being busy with the 999 other pushes. Center CPU per push is this process's CPU
time over the round divided by the maps applied (:func:`measure`, which
``controller_links.py fleet`` runs too, for its ratios against the EDNC link).
"""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from center_connections import (
    Fleet,
    center,
    cpu_of,
    description,
    name_of,
    percentiles,
    register,
)

from protocol import encode_map
from server.mapcodec import grid_to_payload
from server.push import Delivery
from volumetric.compensate.gridmap import build_map
from volumetric.model.machine import parse_machine
from volumetric.model.model import MachineModel

MODEL = {"format": "ednc-model/1", "machine": name_of(0),
         "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 0.01, 1e-5],
                                "origin": 0.0, "scale": 1.0},
                        "EYY": {"type": "polynomial", "coefficients": [0.0, -0.02, 3e-5],
                                "origin": 0.0, "scale": 1.0}},
         "locations": {}, "terms": [], "info": {}}


@dataclasses.dataclass
class Round:
    """One round of pushes as the center saw it.

    Attributes
    ----------
    label : str
    deliveries : list of Delivery
        What the push scheduler told its observers during the round.
    wall_s : float
        From the round's start to the last answer, s.
    cpu_s : float
        This process's CPU time over the round (the center), s.
    fleet_cpu_s : float
        The fleet's process's CPU time over the round, s.
    """

    label: str
    deliveries: list[Delivery]
    wall_s: float
    cpu_s: float
    fleet_cpu_s: float
    starts: list[float] = dataclasses.field(default_factory=list)
    """When each push's first send went out, s after the round's start (sorted; from
    the answer's time less the session's latency)."""
    loop_cpu_s: float = 0.0
    """Of ``cpu_s``, the event loop's thread (the rest: the database's threads), s."""

    @property
    def first_sends(self) -> str:
        """First, median and last push's start, for the printout."""
        s = self.starts
        if not s:
            return "-"
        return f"{s[0]:.1f} / {s[len(s) // 2]:.1f} / {s[-1]:.1f} s"

    @property
    def applied(self) -> int:
        return sum(d.outcome == "applied" for d in self.deliveries)

    @property
    def cpu_per_push_s(self) -> float:
        """Center CPU per map applied, s."""
        return self.cpu_s / max(self.applied, 1)


async def measure(count: int, rounds: int, tolerance_um: float = 0.5, nice: int = 0
                  ) -> tuple[int, list[Round]]:
    """Push a map to ``count`` EDNC machines ``rounds`` times (the first at Welcome), the
    fleet's process at nice ``nice``.

    Returns
    -------
    size : int
        Map payload, bytes.
    rounds : list of Round
    """
    built = build_map(parse_machine(description(0)), MachineModel.from_json(MODEL),
                      tolerance_um=tolerance_um)

    def payload(name: str) -> bytes:
        return encode_map(grid_to_payload(dataclasses.replace(built, machine=name, version=1)))

    size = len(payload(name_of(0)))
    with tempfile.TemporaryDirectory() as tmp:
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000) as (c, services):
            await c.db.run(register, count, MODEL, payload)
            got: list[Delivery] = []
            services.push.observers.append(got.append)
            fleet = Fleet(services.server.port, count, nice=nice)
            pid = fleet.proc.pid
            t0, cpu0, fcpu0 = time.perf_counter(), time.process_time(), cpu_of(pid)
            loop0 = time.thread_time()
            ready = await fleet.ready()
            while len(got) < ready:
                await asyncio.sleep(0.01)
            results = [Round("round 1 (at Welcome, all connecting)", list(got),
                             time.perf_counter() - t0, time.process_time() - cpu0,
                             cpu_of(pid) - fcpu0, loop_cpu_s=time.thread_time() - loop0)]
            answered: list[float] = []
            services.push.observers.append(lambda _d: answered.append(time.perf_counter()))
            for r in range(2, rounds + 1):
                got.clear()
                answered.clear()
                t0, cpu0, fcpu0 = time.perf_counter(), time.process_time(), cpu_of(pid)
                loop0 = time.thread_time()
                for name in list(services.push.connected()):
                    services.push.request(name, "benchmark", resend=True)
                while len(got) < ready:
                    await asyncio.sleep(0.01)
                results.append(Round(f"round {r} (re-push to all at once)", list(got),
                                     time.perf_counter() - t0, time.process_time() - cpu0,
                                     cpu_of(pid) - fcpu0, sorted(
                                         t - t0 - (d.latency_s or 0.0)
                                         for t, d in zip(answered, got, strict=False)),
                                     loop_cpu_s=time.thread_time() - loop0))
            await fleet.finish()
    return size, results


async def main(count: int, rounds: int, tolerance_um: float) -> None:
    size, results = await measure(count, rounds, tolerance_um)
    print(f"machines {count}, map payload {size} bytes, "
          f"center on one event loop, fleet in another process")
    for r in results:
        lat = [d.latency_s for d in r.deliveries if d.latency_s is not None]
        bad = sum(d.outcome != "applied" for d in r.deliveries)
        p50, p99, pmax = percentiles(lat, 50, 99, 100)
        print(f"{r.label}: {len(lat)} acks in {r.wall_s:.2f} s, MapBegin->MapAck "
              f"p50 {1000 * p50:.1f} ms, p99 {1000 * p99:.1f} ms, max {1000 * pmax:.1f} ms; "
              f"center CPU {r.cpu_s:.2f} s ({1000 * r.cpu_per_push_s:.2f} ms per push), "
              f"fleet CPU {r.fleet_cpu_s:.2f} s; pushes started (first / median / last) "
              f"{r.first_sends}"
              f"{f', {bad} not applied' if bad else ''}")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", type=int, default=1000)
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--tolerance-um", type=float, default=0.5)
    a = p.parse_args()
    os.environ.setdefault("EDNC_NODE_ID", "bench")
    asyncio.run(main(a.machines, a.rounds, a.tolerance_um))
