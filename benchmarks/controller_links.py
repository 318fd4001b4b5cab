"""Controller links (Modbus/TCP): delivery of a five-axis map, a fleet re-pushed, and a
temperature's way to the applied compensation. Run by hand:

    .venv/bin/python benchmarks/controller_links.py delivery [--delay-ms 2]
    .venv/bin/python benchmarks/controller_links.py fleet [--machines 1000] [--load 2]
        [--failing 100] [--pmc-procs 4] [--pmc-nice 19] [--repushes 3]
        [--profile center.prof]
    .venv/bin/python benchmarks/controller_links.py temperature [--machines 20] [--rate 200]

* ``delivery``: a Fanuc-style five-axis machine (the test fleet's 5ax-09) gets its
  factored map (built from its simulated campaign's fit at 1 µm) through
  :class:`~server.links.window.session.ControllerSession` over Modbus/TCP, its PMC server
  waiting ``delay_ms`` per request (network and scan); the time from the first write to
  the PLC's verdict, against the same push with no delay, and the requests it took.
* ``fleet``: issue 30's fleet targets in one run. First the EDNC link's fleet as
  ``benchmarks/push_latency.py`` measures it (its :func:`measure`: round 1 at Welcome,
  then ``--repushes`` rounds, 3 by default, each a re-push to all); then ``ednc serve``'s
  services (SQLite) with N machines registered with a modbus link and a stored map each,
  the simulated PMCs (WindowCNC + PmcModbusServer, one port each on 127.0.0.1) in child
  processes; then the EDNC link's fleet again. Round 1 is every machine connected and
  given its map; the rounds after it re-push to all at once. The targets compare the
  medians of the re-push rounds, the EDNC link's from before and after the Modbus fleet
  (a shared machine's speed drifts by tens of percent within a minute). Center CPU per
  push is this process's CPU time over the round divided by the maps applied, for both
  links. The table gives the ratios Modbus/EDNC of those medians (targets <= 1.5x).
  ``--load n``: n busy-looping processes hold the machine from 5 s before the first
  EDNC fleet to the end (both links measured under it): failed deliveries (each try)
  and machines without their map in any round (targets 0). ``--failing k``: k of the N
  PMCs (spread over the ports) sit behind :class:`~machine_sim.faultrelay.FaultRelay` s
  failing from the start in four ways in turn (:data:`FAULT_KINDS`): a re-push round's
  wall time is until every healthy machine has its map again (target 10 s, the slowest
  round). After the last, the center's CPU per second over 10 s without pushes (status
  polls and the failing links' retries).
  ``--pmc-procs n`` spreads the PMCs over n child processes: one Python process with
  several hundred of them stalls on a loaded machine (its answers come later than the
  center's 2 s time-out, which a plant's PMCs, each its own device, do not cause).
  ``--pmc-nice n`` runs them, and the EDNC link's fleet alike, at that nice value. The
  default, ``19``, gives the simulated devices only the CPU the center leaves: the
  targets are for an idle machine, and a plant's devices, each with its own CPU, take
  none of the center's (1,000 simulated PMCs take 2-3 s of CPU in a re-push round, the
  EDNC link's fleet 0.5 s; at ``0`` they share the 2 cores with the center as equals,
  which measures the simulator's cost beside the link's); ``-5`` with ``--load`` keeps the busy
  loops off the PMCs (in a plant the load is on the center's computer, each PMC is a device
  of its own); at nice 0, 1,000 simulated PMCs sharing 2 cores with two busy loops answer
  status reads later than the link's time-out twice in a row and the fleet collapses.
* ``temperature``: N machines with a spindle-growth map; temperatures go into the center's
  intake (as MQTT or REST readings do) at ``rate`` per second across the machines; the
  child process stamps when each PLC program took each value from its slots
  (CLOCK_MONOTONIC is one clock for both processes). Latency p50/p99 and the center's CPU
  per temperature.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import cProfile
import itertools
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import AsyncExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from center_connections import center, cpu_of, percentiles  # noqa: E402

BASE_PORT = 21000
POLL_MS = 100
"""The fleet links' status reads while a push waits for its verdict, ms (``--poll-ms``;
the link's default)."""
SWITCH_SCAN_MS = 16.0
"""The simulated PMCs take a new switch word by an extra scan this long after it
arrives, as a PMC whose ladder scans every 16 ms does (``--switch-scan-ms``; 0: at the
next regular scan, up to a PLC cycle later)."""
TEMPS: list[tuple[str, int, float]] = []
"""Child process: (machine, milli-°C taken, monotonic time) per slot value taken."""
SWITCHES: list[float] = []
"""Child process: when each switch word written by the center arrived (monotonic time,
one clock with the parent's perf_counter on Linux)."""


def fleet_description(i: int, port: int) -> dict[str, Any]:
    return {"name": f"mb-{i:04d}", "controller": "fanuc",
            "ip": f"127.3.{i // 250}.{i % 250 + 1}", "chain": "w b Y X Z t",
            "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]},
            "tool_length_mm": 150.0,
            "link": {"kind": "modbus", "host": "127.0.0.1", "port": port,
                     "poll_ms": POLL_MS}}


# -- the child process: the simulated PMCs

def failing_indices(count: int, failing: int) -> list[int]:
    """Which machines fail: ``failing`` of ``count``, spread evenly over the ports."""
    return sorted({int((k + 0.5) * count / failing) for k in range(failing)}) if failing else []


FAULT_KINDS = ("busy-90pct", "writes-02", "drop-after-6", "no-answer")
"""How the failing machines fail, in turn: 90 % of requests answered with exception 06
(busy); writes into the map buffers answered with exception 02; the connection closed
after 6 answers; requests never answered."""


def fault_of(k: int) -> Any:
    """The k-th failing machine's faults (:data:`FAULT_KINDS` in turn)."""
    from machine_sim.faultrelay import Faults
    from machine_sim.windowcnc import DEFAULT_CAPACITY
    from protocol.ctrlmem import BUFFERS_AT, Layout

    kind = FAULT_KINDS[k % len(FAULT_KINDS)]
    if kind == "busy-90pct":
        return Faults(exception_fraction=0.9, exception_code=6)
    if kind == "writes-02":
        return Faults(refuse_writes=((BUFFERS_AT // 2, Layout(DEFAULT_CAPACITY).size // 2),))
    if kind == "drop-after-6":
        return Faults(drop_after=6)
    return Faults(swallow=True)


async def fleet_main(count: int, base_port: int, cycle_s: float, delay_s: float = 0.0,
                     five_axis: bool = False, failing: int = 0, first: int = 0,
                     total: int = 0, profile: Path | None = None) -> None:
    """PMCs ``first`` .. ``first + count - 1`` of a fleet of ``total`` (0: ``count``);
    ``profile``: a cProfile of this process from ready to the end, to that file."""
    from machine_sim.faultrelay import FaultRelay
    from machine_sim.modbus_server import PmcModbusServer
    from machine_sim.plcmap import PlcMapProgram
    from machine_sim.runtime import MachineRuntime
    from machine_sim.windowcnc import WindowCNC
    from protocol.ctrlmem import MAX_SENSORS, NO_TEMPERATURE, TEMPERATURES_AT
    from volumetric.model.machine import parse_machine

    class Stamping(PlcMapProgram):
        def _take_temperatures(self, now_s: float) -> None:
            before = self._temp_seq
            super()._take_temperatures(now_s)
            if self._temp_seq != before:
                import struct
                values = struct.unpack_from(f"<{MAX_SENSORS}i", self.window, TEMPERATURES_AT)
                t = time.monotonic()
                name = self.controller.store.machine
                TEMPS.extend((name, v, t) for v in values[:len(self._slots)]
                             if v != NO_TEMPERATURE)

    bad = failing_indices(total or count, failing)
    async with AsyncExitStack() as stack:
        cncs = []
        relays = []
        for i in range(first, first + count):
            if five_axis:
                from machine_sim.fanuc import FanucConfig
                from tests.support.integration import FANUC_5AX
                m = FANUC_5AX.machine
                fanuc = FanucConfig(max_step_counts=100_000)
            else:
                m = parse_machine(fleet_description(i, base_port + i))
                fanuc = None
            rt = MachineRuntime(m, seed=i, own_sensors=False, fanuc=fanuc)
            # a failing machine's PMC listens on any port, its relay on the machine's
            port = 0 if i in bad else base_port + i
            cnc = WindowCNC(m, lambda c, p=port: PmcModbusServer(
                c, port=p, delay_s=delay_s), runtime=rt, cycle_s=cycle_s,
                switch_scan_s=min(SWITCH_SCAN_MS / 1000, cycle_s) if SWITCH_SCAN_MS else None)
            cnc.program = Stamping(cnc.window, cnc.layout, rt.controller,
                                   formats=cnc.program.formats)
            cncs.append(await stack.enter_async_context(cnc))
            _stamp_switches(cnc.server)
            if i in bad:
                relays.append(await stack.enter_async_context(FaultRelay(
                    ("127.0.0.1", int(cnc.server.port)), port=base_port + i,
                    faults=fault_of(bad.index(i)), seed=i)))
        print(json.dumps({"ready": len(cncs)}), flush=True)
        # CPU time, not wall: on a shared machine a wall-clock profile counts the waits
        prof = cProfile.Profile(time.process_time) if profile is not None else None
        if prof is not None:
            prof.enable()
        await asyncio.get_running_loop().run_in_executor(None, sys.stdin.read)
        if prof is not None and profile is not None:
            prof.disable()
            prof.dump_stats(profile)
        healthy = [c for i, c in enumerate(cncs, start=first) if i not in bad]
        print(json.dumps({"applied": sum(c.program.applied_switches for c in healthy),
                          "machines_applied": sum(c.program.applied_switches > 0
                                                  for c in healthy),
                          "failing_connects": sum(r.connects for r in relays),
                          "failing_requests": len([s for r in relays for s in r.seen]),
                          "temps": TEMPS, "switches": SWITCHES}), flush=True)


def _stamp_switches(server: Any) -> None:
    """Note in :data:`SWITCHES` when a write of the switch word reaches ``server``'s PMC
    memory (its area answers one request at a time)."""
    from protocol.ctrlmem import SWITCH_AT

    area = server.area
    plain = area.answer
    switch = area.register + SWITCH_AT // 2

    def answer(unit: int, pdu: bytes) -> bytes:
        if pdu[:1] == b"\x10" and len(pdu) >= 5:
            first, count = int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")
            if first <= switch < first + count:
                SWITCHES.append(time.monotonic())
        return bytes(plain(unit, pdu))

    area.answer = answer


class ChildFleet:
    def __init__(self, count: int, base_port: int, cycle_s: float, *, delay_ms: float = 0.0,
                 five_axis: bool = False, failing: int = 0, first: int = 0,
                 total: int = 0, nice: int = 0, profile: Path | None = None) -> None:
        self.proc = subprocess.Popen(
            [*(["nice", "-n", str(nice)] if nice else []), sys.executable, __file__,
             "child", "--machines", str(count), "--base-port", str(base_port),
             "--cycle-s", str(cycle_s), "--delay-ms", str(delay_ms),
             "--switch-scan-ms", str(SWITCH_SCAN_MS),
             "--failing", str(failing), "--first", str(first), "--total", str(total),
             *(["--five-axis"] if five_axis else []),
             *(["--pmc-profile", str(profile)] if profile is not None else [])],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    async def ready(self) -> int:
        assert self.proc.stdout is not None
        line = await asyncio.to_thread(self.proc.stdout.readline)
        return int(json.loads(line)["ready"])

    async def finish(self) -> dict[str, Any]:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.close()
        line = await asyncio.to_thread(self.proc.stdout.readline)
        await asyncio.to_thread(self.proc.wait, 60)
        return dict(json.loads(line)) if line else {}


class PmcProcesses:
    """The fleet's simulated PMCs spread over ``procs`` child processes (consecutive
    slices): one Python process stalls with some hundreds of PMCs on a loaded machine
    (its status answers late, the center times them out), which a plant's PMCs, each its
    own device, never do."""

    def __init__(self, count: int, procs: int, cycle_s: float, failing: int,
                 nice: int = 0, profile: Path | None = None) -> None:
        edges = [round(k * count / procs) for k in range(procs + 1)]
        self.children = [ChildFleet(b - a, BASE_PORT, cycle_s, failing=failing, first=a,
                                    total=count, nice=nice,
                                    profile=None if profile is None
                                    else profile / f"pmc-{a:04d}.prof")
                         for a, b in itertools.pairwise(edges) if b > a]

    def cpu_s(self) -> float:
        return sum(cpu_of(c.proc.pid) for c in self.children)

    async def ready(self) -> int:
        return sum(await asyncio.gather(*(c.ready() for c in self.children)))

    async def finish(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for done in await asyncio.gather(*(c.finish() for c in self.children)):
            for k, v in done.items():
                out[k] = out.get(k, 0 if isinstance(v, int) else []) + v
        return out


def register(session: Any, count: int, base_port: int, model: dict[str, Any],
             payload: Any) -> None:
    from server.db import error_models, machines
    from server.db import maps as map_repo
    for i in range(count):
        d = fleet_description(i, base_port + i)
        row = machines.create_machine(session, name=d["name"], ip=d["ip"],
                                      controller="fanuc", description=d,
                                      secret="benchmark-secret-0123456789")
        error_models.add_model(session, row.id, source="upload",
                               body={**model, "machine": d["name"]})
        if payload is not None:
            map_repo.add_map_version(session, row.id, payload=payload(d["name"]),
                                     model_version=1)


def fitted_model() -> dict[str, Any]:
    """A realistic model: the fit of the test fleet's gantry-02 campaign (21 component
    errors of a Fanuc-style gantry of the same chain and travel)."""
    from tests.support.integration import campaign
    from volumetric.identify.fit import fit

    sim, readings, _ = campaign("gantry-02")
    body: dict[str, Any] = fit(sim.machine, readings).model.to_json()
    return body


def _factored(name: str, model: dict[str, Any]) -> Any:
    from protocol import MapEncoding
    from server.mapcodec import build_for, encode, with_version
    from volumetric.model.machine import parse_machine
    from volumetric.model.model import MachineModel

    m = parse_machine(fleet_description(0, BASE_PORT))
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    built = build_for(m, MachineModel.from_json({**model, "machine": m.name}), {},
                      formats=formats,
                      tolerance_um=1.0, controller="fanuc")
    import dataclasses

    def payload(machine: str) -> bytes:
        return encode(with_version(dataclasses.replace(built, machine=machine), 1))
    return payload


MODEL = {"format": "ednc-model/1", "machine": "mb-0000",
         "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 0.01, 1e-5],
                                "origin": 0.0, "scale": 1.0},
                        "EYY": {"type": "polynomial", "coefficients": [0.0, -0.02, 3e-5],
                                "origin": 0.0, "scale": 1.0}},
         "locations": {}, "terms": [], "info": {}}

THERMAL_MODEL = {**MODEL, "terms": [{"effect": "thermal_drift", "axis": "z",
                                     "sensor": "T_spindle_C", "coefficient": -2.5,
                                     "t_ref_C": 20.0, "q_min": 0.0}]}


@dataclass
class ModbusRound:
    """One round of the Modbus fleet (push_latency's :class:`Round` for the EDNC link)."""

    label: str
    deliveries: list[Any]
    wall_s: float
    cpu_s: float
    pmc_cpu_s: float
    """The simulated PMCs' process's CPU over the round, s."""
    healthy: set[str]
    loop_cpu_s: float = 0.0
    """Of ``cpu_s``, the event loop's thread (the rest: the database's threads), s."""
    t0: float = 0.0
    """The round's start (perf_counter, the children's monotonic clock), s."""

    def applied(self) -> set[str]:
        return {d.machine for d in self.deliveries
                if d.outcome == "applied" and d.machine in self.healthy}

    def failed(self) -> int:
        """Deliveries to healthy machines that were not applied (each try counted)."""
        return sum(d.outcome != "applied" for d in self.deliveries if d.machine in self.healthy)

    @property
    def cpu_per_push_s(self) -> float:
        return self.cpu_s / max(len(self.applied()), 1)


async def _modbus_rounds(count: int, cycle_s: float, failing: int, procs: int,
                         timeout_s: float, nice: int = 0, pmc_profile: Path | None = None,
                         repushes: int = 1
                         ) -> tuple[int, list[ModbusRound], dict[str, Any],
                                    tuple[float, float]]:
    """Round 1 (connect and push) and ``repushes`` rounds re-pushing to all, back to back,
    over Modbus; the child's report; center CPU per second over 10 s without pushes after
    the last (all threads, the event loop's)."""
    from server.push import Delivery

    model = fitted_model()
    payload = _factored("mb-0000", model)
    size = len(payload("mb-0000"))
    bad = set(failing_indices(count, failing))
    healthy = {fleet_description(i, 0)["name"] for i in range(count) if i not in bad}

    async def until_applied(got: list[Delivery], t0: float) -> None:
        while not healthy <= {d.machine for d in got if d.outcome == "applied"}:
            await asyncio.sleep(0.02)
            if time.perf_counter() - t0 > timeout_s:
                missing = healthy - {d.machine for d in got if d.outcome == "applied"}
                progress(f"{len(missing)} healthy machines without their map after "
                         f"{timeout_s:g} s: {', '.join(sorted(missing)[:10])}")
                break

    rounds = []
    with tempfile.TemporaryDirectory() as tmp:
        child = PmcProcesses(count, procs, cycle_s, failing, nice, pmc_profile)
        await child.ready()
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000) as (c, services):
            got: list[Delivery] = []
            answered: list[float] = []
            """When each delivery of round 2 was answered (perf_counter, s)."""
            services.push.observers.append(got.append)
            services.push.observers.append(lambda _d: answered.append(time.perf_counter()))
            t0, cpu0, pcpu0 = time.perf_counter(), time.process_time(), child.cpu_s()
            loop0 = time.thread_time()
            await c.db.run(register, count, BASE_PORT, model, payload)
            await until_applied(got, t0)
            progress("Modbus round 1 done")
            rounds.append(ModbusRound("round 1 (connect and push)", list(got),
                                      time.perf_counter() - t0, time.process_time() - cpu0,
                                      child.cpu_s() - pcpu0, healthy,
                                      time.thread_time() - loop0, t0))
            for r in range(2, 2 + repushes):
                got.clear()
                if PROFILE is not None:
                    PROFILE.enable()
                t0, cpu0, pcpu0 = time.perf_counter(), time.process_time(), child.cpu_s()
                loop0 = time.thread_time()
                answered.clear()
                for name in list(services.push.connected()):
                    services.push.request(name, "benchmark", resend=True)
                await until_applied(got, t0)
                if PROFILE is not None:
                    PROFILE.disable()
                progress(f"Modbus round {r} done")
                starts = sorted(t - t0 - (d.latency_s or 0.0)
                                for t, d in zip(answered, got, strict=False))
                if starts:
                    progress(f"round {r}: first writes from {starts[0]:.1f} s, median "
                             f"{starts[len(starts) // 2]:.1f} s, last {starts[-1]:.1f} s "
                             "after the requests")
                rounds.append(ModbusRound(f"round {r} (re-push to all at once)", list(got),
                                          time.perf_counter() - t0,
                                          time.process_time() - cpu0,
                                          child.cpu_s() - pcpu0, healthy,
                                          time.thread_time() - loop0, t0))
            cpu0, loop0 = time.process_time(), time.thread_time()
            await asyncio.sleep(QUIET_S)
            quiet = ((time.process_time() - cpu0) / QUIET_S,
                     (time.thread_time() - loop0) / QUIET_S)
            progress("closing the center")
            watchdog = asyncio.create_task(_tell_stuck(20.0))
        watchdog.cancel()
        progress("closing the PMCs")
        done = await child.finish()
    return size, rounds, done, quiet


QUIET_S = 10.0
PROFILE: cProfile.Profile | None = None
"""``--profile FILE``: the center over the Modbus re-push rounds (their figures are then
slower)."""


async def _tell_stuck(after_s: float) -> None:
    """Print every task's stack if still running after ``after_s`` (a shutdown hanging)."""
    await asyncio.sleep(after_s)
    progress(f"still closing after {after_s:g} s; the tasks:")
    for task in asyncio.all_tasks():
        task.print_stack(limit=6, file=sys.stderr)


def progress(what: str) -> None:
    print(f"{time.strftime('%H:%M:%S')} {what} (load {os.getloadavg()[0]:.2f})",
          file=sys.stderr, flush=True)

TARGET_RATIO = 1.5
TARGET_HEALTHY_S = 10.0


@contextlib.contextmanager
def load_held(n: int) -> Iterator[None]:
    """``n`` child processes busy-looping while the block runs (the machine at load n)."""
    procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]
    try:
        yield
    finally:
        for proc in procs:
            proc.kill()
            proc.wait()


def _median(values: list[float]) -> float:
    return float(statistics.median(values))


async def fleet(count: int, cycle_s: float, load: int, failing: int, timeout_s: float,
                procs: int = 1, nice: int = 0, pmc_profile: Path | None = None,
                repushes: int = 3) -> None:
    from push_latency import measure

    from server.links.window.session import IDLE_POLL_S

    load0 = os.getloadavg()
    with load_held(load):
        if load:
            await asyncio.sleep(5.0)  # the busy loops running before anything is timed
        # the EDNC link's fleet before and after the Modbus fleet: a shared machine's speed
        # drifts by tens of percent within a minute, and a ratio against one neighbour
        # measured 30 s earlier took that drift for the link's cost
        progress("EDNC link's fleet")
        ednc_size, before = await measure(count, 1 + repushes, nice=nice)
        load1 = os.getloadavg()
        progress("Modbus fleet")
        size, rounds, done, quiet = await _modbus_rounds(count, cycle_s, failing, procs,
                                                           timeout_s, nice, pmc_profile,
                                                           repushes)
        progress("EDNC link's fleet again")
        _, after = await measure(count, 1 + repushes, nice=nice)
    load2 = os.getloadavg()
    healthy = count - len(failing_indices(count, failing))
    print(f"machines {count} ({healthy} healthy, {count - healthy} failing: "
          f"{', '.join(FAULT_KINDS)} in turn), busy-looping processes {load}; load average "
          f"(1 min) {load0[0]:.2f} at start, {load1[0]:.2f} after the EDNC link, "
          f"{load2[0]:.2f} at the end")
    print(f"Modbus: simulated Fanuc PMCs in {procs} child process(es) at nice {nice} "
          f"(PLC cycle {cycle_s * 1000:.0f} ms, a switch word taken "
          f"{f'{SWITCH_SCAN_MS:g} ms after it arrives' if SWITCH_SCAN_MS else 'at the next'}; "
          f"status read every {POLL_MS / 1000:g} s "
          f"while a push waits "
          f"for its verdict, every {IDLE_POLL_S:g} s otherwise), factored map {size} bytes, "
          f"{done.get('applied')} "
          f"switches applied by {done.get('machines_applied')} healthy PLCs; EDNC: "
          f"push_latency.py's fleet at nice {nice}, grid map {ednc_size} bytes, measured "
          f"before and after the Modbus fleet; {repushes} re-push rounds each")
    for r in rounds:
        lat = [d.latency_s for d in r.deliveries
               if d.latency_s is not None and d.machine in r.healthy]
        p50, p99 = percentiles(lat, 50, 99)
        print(f"  Modbus {r.label}: {len(r.applied())} of {healthy} applied in "
              f"{r.wall_s:.1f} s; write->verdict p50 {p50 * 1000:.0f} ms, p99 "
              f"{p99 * 1000:.0f} ms; center CPU {r.cpu_s:.1f} s "
              f"({r.cpu_per_push_s * 1000:.2f} ms per push, "
              f"{r.loop_cpu_s / max(len(r.applied()), 1) * 1000:.2f} of it in the event "
              f"loop's thread), PMCs' CPU {r.pmc_cpu_s:.1f} s; "
              f"{r.failed()} failed deliveries "
              f"to healthy machines, "
              f"{sum(d.machine not in r.healthy for d in r.deliveries)} to failing")
    for when, ednc in (("before", before), ("after", after)):
        for e in ednc:
            print(f"  EDNC ({when}) {e.label}: {e.applied} applied in {e.wall_s:.2f} s; "
                  f"center CPU {e.cpu_s:.1f} s ({e.cpu_per_push_s * 1000:.2f} ms per push, "
                  f"{e.loop_cpu_s / max(e.applied, 1) * 1000:.2f} of it in the event "
                  f"loop's thread), fleet's CPU {e.fleet_cpu_s:.1f} s")
    print(f"  after the last round, {QUIET_S:.0f} s without pushes: center CPU "
          f"{quiet[0] * 1000:.0f} ms/s, {quiet[1] * 1000:.0f} ms/s of it in the event loop's "
          f"thread, the rest in the database's (status polls, live links written, failing "
          f"links' retries); the failing "
          f"relays saw {done.get('failing_connects', 0)} connects, "
          f"{done.get('failing_requests', 0)} requests over the run")

    # the targets on the medians of the re-push rounds (the EDNC link's from both sides)
    m_rounds, e_rounds = rounds[1:], before[1:] + after[1:]
    m_wall = _median([r.wall_s for r in m_rounds])
    e_wall = _median([e.wall_s for e in e_rounds])
    m_cpu = _median([r.cpu_per_push_s for r in m_rounds])
    e_cpu = _median([e.cpu_per_push_s for e in e_rounds])
    rows: list[tuple[str, str, str, str, bool | None]] = []
    wall_ratio, cpu_ratio = m_wall / e_wall, m_cpu / e_cpu
    print(f"re-push walls, s: Modbus {' '.join(f'{r.wall_s:.2f}' for r in m_rounds)}; EDNC "
          f"before {' '.join(f'{e.wall_s:.2f}' for e in before[1:])}, after "
          f"{' '.join(f'{e.wall_s:.2f}' for e in after[1:])}")
    rows.append(("re-push to all, wall (median)", f"{m_wall:.2f} s", f"{e_wall:.2f} s",
                 f"{wall_ratio:.2f}x <= {TARGET_RATIO}x", wall_ratio <= TARGET_RATIO))
    parts = []
    for r in m_rounds:
        switched = [t - r.t0 for t in done.get("switches", [])
                    if r.t0 <= t <= r.t0 + r.wall_s]
        if switched:
            parts.append(max(switched))
    if parts:
        # the center's part of a round: every switch word written; the rest is the
        # PLC's scan and the status read that finds its verdict (not the center's CPU)
        part = _median(parts)
        rows.append(("re-push, last switch word written", f"{part:.2f} s",
                     f"{e_wall:.2f} s", f"{part / e_wall:.2f}x (info)", None))
    rows.append(("center CPU per push (median)", f"{m_cpu * 1000:.2f} ms",
                 f"{e_cpu * 1000:.2f} ms", f"{cpu_ratio:.2f}x <= {TARGET_RATIO}x",
                 cpu_ratio <= TARGET_RATIO))
    if load:
        failed = sum(r.failed() for r in rounds)
        every = all(len(r.applied()) == healthy for r in rounds)
        rows.append((f"load {load}: failed pushes", str(failed), "-", "0", failed == 0))
        rows.append((f"load {load}: every map applied",
                     f"{min(len(r.applied()) for r in rounds)} of {healthy}", "-", "all",
                     every))
    if failing:
        worst = max(m_rounds, key=lambda r: r.wall_s)
        rows.append((f"{failing} failing: healthy {healthy} re-pushed (slowest)",
                     f"{worst.wall_s:.2f} s ({len(worst.applied())})", "-",
                     f"<= {TARGET_HEALTHY_S:.0f} s",
                     all(r.wall_s <= TARGET_HEALTHY_S and len(r.applied()) == healthy
                         for r in m_rounds)))
    width = max(len(r[0]) for r in rows)
    head = f"{'target':<{width}}  {'Modbus':>14}  {'EDNC':>10}  {'goal':>14}  met"
    print(head)
    print("-" * len(head))
    for what, mb, ed, goal, met in rows:
        said = "-" if met is None else "yes" if met else "NO"
        print(f"{what:<{width}}  {mb:>14}  {ed:>10}  {goal:>14}  {said}")


async def temperature(count: int, rate: float, seconds: float) -> None:
    payload = _factored("mb-0000", THERMAL_MODEL)
    sent: dict[tuple[str, int], float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        child = ChildFleet(count, BASE_PORT, 0.008)
        await child.ready()
        async with center(Path(tmp), heartbeat_s=10.0, telemetry_ms=5000) as (c, services):
            await c.db.run(register, count, BASE_PORT, THERMAL_MODEL, payload)
            names = [f"mb-{i:04d}" for i in range(count)]
            while sum(1 for n in names if c.registry.get(n).telemetry.get("map_version")
                      == 1) < count:
                await asyncio.sleep(0.1)
            await asyncio.sleep(1.0)
            # the center's own cost with no temperature (status reads, telemetry, pushes'
            # bookkeeping), so that the cost per temperature is told apart from it
            idle_t0, idle_cpu0 = time.perf_counter(), time.process_time()
            await asyncio.sleep(min(seconds, 10.0))
            idle = (time.process_time() - idle_cpu0) / (time.perf_counter() - idle_t0)
            intake = services.intake
            assert intake is not None
            n = int(rate * seconds)
            rng = np.random.default_rng(1)
            t0, cpu0 = time.perf_counter(), time.process_time()
            for k in range(n):
                name = names[k % count]
                milli = 20000 + int(rng.integers(0, 3000)) * 1 + k % 7
                while (name, milli) in sent:
                    milli += 7
                sent[(name, milli)] = time.monotonic()
                intake.take(name, "spindle", milli / 1000.0, source="rest")
                target = t0 + (k + 1) / rate
                await asyncio.sleep(max(0.0, target - time.perf_counter()))
            await asyncio.sleep(1.0)
            cpu = time.process_time() - cpu0
            wall = time.perf_counter() - t0
        done = await child.finish()
    taken: dict[tuple[str, int], float] = {}
    for name, milli, t in done.get("temps", []):
        taken.setdefault((name, int(milli)), float(t))
    lat = [taken[k] - t for k, t in sent.items() if k in taken]
    p50, p99, pmax = percentiles(lat, 50, 99, 100)
    print(f"{count} machines, {len(sent)} temperatures at {rate:g}/s: {len(lat)} taken by "
          f"the PLCs ({len(sent) - len(lat)} superseded by the next one within the "
          f"forwarder's 20 ms before being written); intake->PLC took it p50 "
          f"{p50 * 1000:.1f} ms, p99 {p99 * 1000:.1f} ms, max {pmax * 1000:.1f} ms; center "
          f"CPU {cpu / len(sent) * 1000:.2f} ms per temperature, of which "
          f"{(cpu - idle * wall) / len(sent) * 1000:.2f} ms beyond its idle "
          f"{idle * 1000:.1f} ms/s")


async def delivery(delay_ms: float, repeats: int) -> None:
    from protocol import Controller, MapEncoding
    from server.links.modbus import ModbusMemory
    from server.links.window.session import ControllerSession
    from server.mapcodec import encode, with_version
    from server.push.adapter import build_for
    from tests.support.integration import FANUC_5AX, campaign
    from volumetric.identify.fit import fit

    s = FANUC_5AX
    sim, readings, _ = campaign(s.name)
    formats = MapEncoding.INT32_INCREMENTS | MapEncoding.THERMAL | MapEncoding.FACTORED
    built = build_for(s.description, "fanuc", fit(sim.machine, readings).model.to_json(), {},
                      1.0, formats)
    rows = []
    for delay in (0.0, delay_ms / 1000.0):
        times, requests = [], []
        # the PMC in a process of its own: its ladder scans (8 ms) must not share this
        # event loop with the center's client
        child = ChildFleet(1, BASE_PORT, 0.008, delay_ms=delay * 1000, five_axis=True)
        await child.ready()
        try:
            mem = ModbusMemory("127.0.0.1", BASE_PORT)
            session = ControllerSession(s.name, "127.0.0.1", Controller.FANUC,
                                        s.machine.axis_names, mem, link="modbus",
                                        chain=s.machine.chain, poll_s=0.01)
            await session.open()
            runner = asyncio.create_task(session.run())
            for v in range(1, repeats + 1):
                payload = encode(with_version(built, v))
                r0 = mem.requests
                t0 = time.perf_counter()
                verdict = await session.push_map(v, payload, 30.0)
                times.append(time.perf_counter() - t0)
                requests.append(mem.requests - r0)
                assert verdict.applied, verdict
            session.abort(None, "done")
            await runner
        finally:
            await child.finish()
        rows.append((delay, len(payload), times, requests))
    for delay, size, times, requests in rows:
        print(f"5-axis factored map {size} bytes over Modbus/TCP, {delay * 1000:g} ms per "
              f"request: first write to verdict median {np.median(times) * 1000:.0f} ms, "
              f"max {max(times) * 1000:.0f} ms over {len(times)} pushes "
              f"({int(np.median(requests))} requests each, status polls included)")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("what", choices=["delivery", "fleet", "temperature", "child"])
    p.add_argument("--machines", type=int, default=None)
    p.add_argument("--delay-ms", type=float, default=2.0)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--rate", type=float, default=200.0)
    p.add_argument("--seconds", type=float, default=20.0)
    p.add_argument("--base-port", type=int, default=BASE_PORT)
    p.add_argument("--cycle-s", type=float, default=1.0)
    p.add_argument("--poll-ms", type=int, default=POLL_MS,
                   help="fleet: the links' status reads while a push waits, ms")
    p.add_argument("--switch-scan-ms", type=float, default=SWITCH_SCAN_MS,
                   help="the PMCs take a switch word this long after it arrives (0: at "
                        "their next regular scan)")
    p.add_argument("--five-axis", action="store_true")
    p.add_argument("--load", type=int, default=0,
                   help="fleet: busy-looping processes holding the machine meanwhile")
    p.add_argument("--failing", type=int, default=0,
                   help="fleet: machines behind fault relays, failing in mixed ways")
    p.add_argument("--profile", type=Path, default=None,
                   help="fleet: cProfile of the center over the Modbus re-push rounds, to this "
                        "file")
    p.add_argument("--pmc-procs", type=int, default=1,
                   help="fleet: child processes the simulated PMCs are spread over")
    p.add_argument("--pmc-nice", type=int, default=19,
                   help="fleet: the nice value of the PMC processes and of the EDNC "
                        "link's fleet (a plant's devices do not take the center's CPU)")
    p.add_argument("--pmc-profile", type=Path, default=None,
                   help="fleet: cProfile (CPU time) of each PMC process from ready to its "
                        "end, to DIR/pmc-<first>.prof")
    p.add_argument("--first", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--total", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--repushes", type=int, default=3,
                   help="fleet: re-push rounds per fleet (the targets on their medians)")
    p.add_argument("--round-timeout", type=float, default=300.0,
                   help="fleet: longest wait for a round's maps, s")
    a = p.parse_args()
    if a.repushes < 1:
        p.error(f"--repushes must be at least 1 (the targets take their median), got {a.repushes}")
    if not -20 <= a.pmc_nice <= 19:
        p.error(f"--pmc-nice must be a nice value, -20..19, got {a.pmc_nice}")
    os.environ.setdefault("EDNC_NODE_ID", "bench")
    BASE_PORT = a.base_port  # the PMCs' first port (two runs at once need two ranges)
    POLL_MS = a.poll_ms
    SWITCH_SCAN_MS = a.switch_scan_ms
    if a.what == "child":
        asyncio.run(fleet_main(a.machines, a.base_port, a.cycle_s, a.delay_ms / 1000,
                               a.five_axis, a.failing, a.first, a.total, a.pmc_profile))
    elif a.what == "delivery":
        asyncio.run(delivery(a.delay_ms, a.repeats))
    elif a.what == "fleet":
        if a.profile is not None:
            PROFILE = cProfile.Profile()
            try:
                asyncio.run(fleet(a.machines or 1000, a.cycle_s, a.load, a.failing,
                                  a.round_timeout, a.pmc_procs, a.pmc_nice, a.pmc_profile,
                                  a.repushes))
            finally:
                PROFILE.dump_stats(a.profile)
            sys.exit(0)
        asyncio.run(fleet(a.machines or 1000, a.cycle_s, a.load, a.failing,
                          a.round_timeout, a.pmc_procs, a.pmc_nice, a.pmc_profile,
                          a.repushes))
    else:
        asyncio.run(temperature(a.machines or 20, a.rate, a.seconds))
