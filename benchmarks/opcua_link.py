"""100 SINUMERIK-style machines over OPC UA, secured: connect all, push a map to each.

    .venv/bin/python benchmarks/opcua_link.py [--machines 100] [--workers 1] [--cycle-ms 100]
                                              [--peer-first]

The machines (WindowCNC over a SiemensNC, each with its own asyncua OPC UA server,
machine_sim/opcua_server.py, offering Basic256Sha256 Sign and SignAndEncrypt beside None)
run in ``--workers`` separate processes (one holds all 100: the servers share the
standard address space), so the center side is measured alone: this process holds one
:class:`~server.links.opcua.OpcuaMemory` (asyncua client, user with PlcWrite) per
machine, in one event loop, with the link's defaults. Measured:

* connect: all sessions opened at once with **Basic256Sha256 SignAndEncrypt** (the
  default), on a fresh PKI folder: the center's certificate made once, each controller's
  certificate fetched and trusted on first use, login included; wall time and this
  process's CPU;
* push: every machine gets its map at once (its name in the map; a Siemens-style tables
  map of a five-axis machine at 1 µm, 5.4 kB, built once): status read, the writes of
  ``plan_map_write`` in 240-byte blocks (an S7-300-class PLC, the default), the status
  polled every 100 ms (the SINUMERIK's fastest sampling) until the PLC's ack; wall time,
  per-push latency p50/max and CPU of this process per push; every ack must say applied
  with the map's version. The target: connect and push of all 100 within 30 s;
* the same push in 960-byte blocks (an S7-1500), same sessions;
* peer in the same run: new sessions with security None (the password in clear), connect
  and push in 240-byte blocks, so the cost of the encryption is seen side by side; last,
  or first with ``--peer-first`` (the simulator's wall times grow with each step of a
  run, so both orders are needed to compare walls; the center's CPU per push is not
  moved by the order).

The machines' controller cycle is ``--cycle-ms`` (100 ms by default instead of the
SINUMERIK's 4 ms IPO cycle: 100 machines at 4 ms would need 25,000 Python cycles a
second on this 2-core machine; the PLC program handles a switch in its next cycle either
way, so the ack comes up to one cycle later than on a real controller).
"""

from __future__ import annotations

import argparse
import asyncio
import dataclasses
import json
import logging
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from machine_sim.opcua_server import PLC_WRITER, OpcuaUser, sinumerik_server  # noqa: E402
from machine_sim.truth import random_geometry  # noqa: E402
from machine_sim.windowcnc import WindowCNC  # noqa: E402
from protocol.ctrlmem import (  # noqa: E402
    STATUS_AT,
    STATUS_SIZE,
    Layout,
    decode_identity,
    decode_status,
    plan_map_write,
)
from server.links.opcua import OpcuaMemory  # noqa: E402
from server.links.opcuapki import Pki  # noqa: E402
from server.mapcodec import build_for, encode  # noqa: E402
from volumetric.model.machine import Machine, parse_machine  # noqa: E402
from volumetric.model.model import MachineModel  # noqa: E402

PASSWORD_ENV = "EDNC_BENCH_OPCUA_PW"
PASSWORD = "bench-plc-pw"
def name_of(i: int) -> str:
    return f"sie-{i:05d}"


def machine_of(i: int) -> Machine:
    """A five-axis Siemens-style machine (the test fleet's 5ax-04 chain and pivots)."""
    return parse_machine({
        "name": name_of(i), "controller": "siemens", "ip": "127.0.0.1",
        "chain": "w C A X b Y Z t",
        "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0], "a": [-120, 120],
                      "c": [-360, 360]},
        "pivots_mm": {"C": [400.0, 300.0, -200.0], "A": [400.0, 300.0, -150.0]},
        "tool_length_mm": 100.0})


# -- the machines (worker processes)

async def serve(first: int, count: int, cycle_s: float) -> None:
    """Run machines first..first+count-1; print their ports as one JSON line; run until
    stdin closes."""
    users = {"ednc": OpcuaUser(PASSWORD, PLC_WRITER)}
    cncs = [WindowCNC(machine_of(i), sinumerik_server(users), seed=i, cycle_s=cycle_s)
            for i in range(first, first + count)]
    for c in cncs:
        await c.__aenter__()
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"ports": [c.server.port for c in cncs], "rss_mb": rss_mb}),
          flush=True)
    loop = asyncio.get_running_loop()
    await loop.run_in_executor(None, sys.stdin.read)
    for c in cncs:
        await c.__aexit__(None, None, None)


# -- the center side (this process)

def cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


async def push(mem: OpcuaMemory, payload: bytes, version: int) -> float:
    """Deliver ``payload`` as ``version``; returns the latency to the PLC's ack, s."""
    t0 = time.perf_counter()
    ident = decode_identity(await mem.read(0, 64))
    st = decode_status(await mem.read(STATUS_AT, STATUS_SIZE))
    target = 2 if st.active == 1 else 1
    seq = st.ack_seq % 0x3FFF + 1
    for w in plan_map_write(Layout(ident.capacity), target, payload, version, seq,
                            block=mem.block):
        await mem.write(w.offset, w.data)
    while True:
        await asyncio.sleep(0.1)
        st = decode_status(await mem.read(STATUS_AT, STATUS_SIZE))
        if st.ack_seq == seq:
            break
    if st.ack_code != 0 or st.applied_version != version:
        raise RuntimeError(f"{mem.address}: ack {st.ack_code}, version {st.applied_version}")
    return time.perf_counter() - t0


async def push_all(mems: list[OpcuaMemory], payloads: list[bytes], version: int
                   ) -> dict[str, Any]:
    c0, t0 = cpu_s(), time.perf_counter()
    lat = await asyncio.gather(*(push(m, p, version) for m, p in zip(mems, payloads,
                                                                     strict=True)))
    wall, cpu = time.perf_counter() - t0, cpu_s() - c0
    return {"wall_s": wall, "cpu_per_push_ms": 1000 * cpu / len(mems),
            "p50_s": statistics.median(lat), "max_s": max(lat)}


async def center(n: int, workers: int, cycle_ms: float, peer_first: bool = False) -> None:
    m = machine_of(0)
    truth = random_geometry(m, np.random.default_rng(4), scale=2.0, form="table")
    content = build_for(m, MachineModel(m.name, truth), {}, tolerance_um=1.0,
                        controller="siemens")

    def payload(i: int, version: int) -> bytes:
        mach = content.machine
        named = name_of(i) if isinstance(mach, str) else dataclasses.replace(mach,
                                                                             name=name_of(i))
        return encode(dataclasses.replace(content, machine=named,  # type: ignore[arg-type]
                                          version=version))

    print(f"map: {type(content).__name__}, {len(payload(0, 1))} bytes")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    per = -(-n // workers)
    procs = []
    t0 = time.perf_counter()
    for w in range(workers):
        first, count = w * per, min(per, n - w * per)
        if count <= 0:
            break
        procs.append(subprocess.Popen(
            [sys.executable, __file__, "--serve", str(first), str(count),
             "--cycle-ms", str(cycle_ms)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            env=env, text=True))
    ports: list[int] = []
    rss: list[float] = []
    for p in procs:
        assert p.stdout is not None
        got = json.loads(await asyncio.to_thread(p.stdout.readline))
        ports += got["ports"]
        rss.append(got["rss_mb"])
    print(f"{len(ports)} machines serving in {len(procs)} processes after "
          f"{time.perf_counter() - t0:.1f} s, peak RSS {max(rss):.0f} MB per process")
    os.environ[PASSWORD_ENV] = PASSWORD
    pki = Pki(Path(tempfile.mkdtemp(prefix="ednc-bench-pki-")))  # a first start

    def memories(**kw: Any) -> list[OpcuaMemory]:
        return [OpcuaMemory(f"opc.tcp://127.0.0.1:{port}", "ednc", f"env:{PASSWORD_ENV}",
                            timeout_s=30.0, pki=pki, **kw) for port in ports]

    mems: list[OpcuaMemory] = []
    plain: list[OpcuaMemory] = []
    try:
        rows: list[tuple[str, dict[str, Any]]] = []
        steps = [("SignAndEncrypt, 240-byte blocks", mems, 240),
                 ("SignAndEncrypt, 960-byte blocks", mems, 960),
                 ("None (peer), 240-byte blocks", plain, 240)]
        if peer_first:  # the order's own effect on the wall times, seen by swapping it
            steps = steps[2:] + steps[:2]
        for version, (label, group, block) in enumerate(steps, start=1):
            if not group:  # the other set's sessions closed first: 10 per controller
                for other in (mems, plain):
                    await asyncio.gather(*(m.close() for m in other))
                group += memories(security_policy="None", security_mode="None") \
                    if group is plain else memories()
            if not group[0]._client:
                c0, t0 = cpu_s(), time.perf_counter()
                await asyncio.gather(*(m.connect() for m in group))
                wall, cpu = time.perf_counter() - t0, cpu_s() - c0
                print(f"{label.split(',')[0]}: connect all {n}: {wall:.2f} s wall, "
                      f"{1000 * cpu / n:.1f} ms CPU per session")
            else:
                wall = 0.0
            for mem in group:
                mem.block = block
            r = await push_all(group, [payload(i, version) for i in range(n)], version)
            r["connect_s"] = wall
            rows.append((label, r))
            print(f"push all {n}, {label}: {r['wall_s']:.2f} s wall, latency p50 "
                  f"{r['p50_s']:.2f} s max {r['max_s']:.2f} s, "
                  f"{r['cpu_per_push_ms']:.1f} ms CPU per push"
                  + (f"; connect + push {wall + r['wall_s']:.2f} s" if wall else ""))
        got = dict(rows)
        secured, peer = got["SignAndEncrypt, 240-byte blocks"], got[
            "None (peer), 240-byte blocks"]
        total = secured["connect_s"] + secured["wall_s"]
        print(f"target: {n} machines with SignAndEncrypt connected and pushed in "
              f"{total:.2f} s ({'met' if total <= 30.0 else 'MISSED'}: 30 s); "
              f"CPU per push SignAndEncrypt / None: "
              f"{secured['cpu_per_push_ms'] / peer['cpu_per_push_ms']:.2f}; retries "
              f"{sum(m.busy_retries for m in mems + plain)}")
    finally:
        await asyncio.gather(*(m.close() for m in mems + plain))
        for p in procs:  # nothing left to measure: no orderly stop of 100 servers
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def main() -> None:
    # the warnings a plant should see (security None, first-use trust) once per machine
    # would be 100 lines here; counted in the summary instead
    logging.getLogger("server.links").setLevel(logging.ERROR)
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--machines", type=int, default=100)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--cycle-ms", type=float, default=100.0)
    ap.add_argument("--peer-first", action="store_true",
                    help="run the None peer first (to see the order's own effect)")
    ap.add_argument("--serve", type=int, nargs=2, metavar=("FIRST", "COUNT"),
                    help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.serve:
        asyncio.run(serve(a.serve[0], a.serve[1], a.cycle_ms / 1000))
    else:
        asyncio.run(center(a.machines, a.workers, a.cycle_ms, a.peer_first))


if __name__ == "__main__":
    main()
