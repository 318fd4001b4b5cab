"""The demo's live part: the control center and the fleet over real TCP (and MQTT).

The center runs in this process under uvicorn (REST API, dashboard, machine TCP server,
push scheduler, MQTT bridge when a broker answers on 127.0.0.1:1883), with an embedded
SQLite database. Each prepared machine is registered through the REST API with its own
loopback address and secret, its measurements, diagnosis and model are uploaded, and a
simulated CNC connects, authenticates and takes its map, except two machines that are
reached the way plants reach controllers without an EDNC client (:data:`LINKS`): the
Fanuc-style gantry-02 serves its PMC window through Modbus/TCP and the Siemens-style
5ax-04 its PLC data block through OPC UA, and the center connects to them and writes the
map into controller memory (protocol/README.md §13). The ISO 230-6 diagonals are then
measured with the map the machine actually received and applies, and the machine with a
thermal model warms up from cold (an hour of machine time per minute): its tables map
carries the thermal terms, so its compensation follows its own temperature readings each
cycle while the map version stays the same (no rebuild).
"""

from __future__ import annotations

import asyncio
import contextlib
import io
import logging
import os
import secrets
import socket
import tempfile
from collections.abc import AsyncIterator
from pathlib import Path

import httpx
import numpy as np
import uvicorn
from rich.console import Console
from rich.table import Table

from ednc.demo import DIAGONALS, Prepared
from machine_sim.campaign import map_compensation, run_campaign
from machine_sim.link import MqttTarget, SimulatedCNC
from machine_sim.lookup import ActiveMap, FactoredLadder, TablesMap
from machine_sim.modbus_server import PmcModbusServer
from machine_sim.opcua_server import PLC_WRITER, OpcuaUser, sinumerik_server
from machine_sim.runtime import MachineRuntime
from machine_sim.testprograms import diagonal_test
from machine_sim.thermal import default_thermal
from machine_sim.windowcnc import WindowCNC
from server.app import create_app
from server.services import machine_services
from server.settings import Settings
from volumetric.measure.measurement import Measurements, write_measurements
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import ThermalTerm
from volumetric.verify.iso230_6 import diagonal_ranges

THERMAL_SPEEDUP = 60.0
LINKS = {"gantry-02": "modbus", "5ax-04": "opcua"}
"""Demo machines the center reaches through their controller's own server."""
OPCUA_PASSWORD_ENV = "EDNC_DEMO_OPCUA_PASSWORD"


class Served:
    """A demo machine behind its controller's server, shaped like a SimulatedCNC for the
    demo's loops (``machine``, ``runtime``, ``ip``, ``now``)."""

    def __init__(self, cnc: WindowCNC, ip: str) -> None:
        self.cnc = cnc
        self.machine = cnc.machine
        self.runtime = cnc.runtime
        self.ip = ip

    def now(self) -> float:
        return self.cnc.now()

    async def __aenter__(self) -> Served:
        await self.cnc.__aenter__()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.cnc.__aexit__(None, None, None)


def _served(m: Machine, runtime: MachineRuntime, ip: str, kind: str
            ) -> tuple[Served, dict[str, object]]:
    """The machine behind a Modbus/TCP or OPC UA server on a free port at its address,
    and the link its registration takes."""
    port = _free_port(ip)
    if kind == "modbus":
        cnc = WindowCNC(m, lambda c: PmcModbusServer(c, host=ip, port=port), runtime=runtime,
                        cycle_s=0.02)
        return Served(cnc, ip), {"kind": "modbus", "host": ip, "port": port, "poll_ms": 100}
    password = os.environ.setdefault(OPCUA_PASSWORD_ENV, secrets.token_hex(12))
    users = {"ednc": OpcuaUser(password, PLC_WRITER)}
    cnc = WindowCNC(m, sinumerik_server(users, host=ip, port=port), runtime=runtime,
                    cycle_s=0.02)
    return Served(cnc, ip), {"kind": "opcua", "endpoint": f"opc.tcp://{ip}:{port}",
                             "user": "ednc", "password_ref": f"env:{OPCUA_PASSWORD_ENV}"}


def _reachable(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, port), timeout=0.5):
            return True
    except OSError:
        return False


def _free_port(host: str = "127.0.0.1") -> int:
    with socket.socket() as s:
        s.bind((host, 0))
        port: int = s.getsockname()[1]
        return port


def _csv(m: Measurements) -> str:
    buf = io.StringIO()
    write_measurements(buf, m)
    return buf.getvalue()


@contextlib.asynccontextmanager
async def running_center(settings: Settings) -> AsyncIterator[None]:
    """The center under uvicorn in this event loop, until the block ends."""
    app = create_app(settings, services=[machine_services])
    server = uvicorn.Server(uvicorn.Config(app, host=settings.http_host,
                                           port=settings.http_port, log_level="warning",
                                           timeout_graceful_shutdown=3))
    task = asyncio.create_task(server.serve(), name="uvicorn")
    try:
        async with asyncio.timeout(30):
            while not server.started:
                if task.done():
                    task.result()
                await asyncio.sleep(0.05)
        yield
    finally:
        server.should_exit = True
        await task


async def _register(client: httpx.AsyncClient, p: Prepared, ip: str, secret: str,
                    link: dict[str, object] | None = None) -> None:
    name = p.machine.name
    # the sensors it publishes: the center stores their readings (re-identification) and
    # refuses names it was not told of
    sensors = [f"T_{s.name}_C" for s in default_thermal(p.machine).sensors]
    description = {**p.fleet.description, "ip": ip, "sensors": sensors}
    if link is not None:
        description["link"] = link
    r = await client.post("/api/machines", json={**description, "secret": secret})
    r.raise_for_status()
    r = await client.post(f"/api/machines/{name}/measurements", params={"set_name": "campaign"},
                          content=_csv(p.readings), headers={"Content-Type": "text/csv"})
    r.raise_for_status()
    d = p.diagnosis.to_json()
    r = await client.post(f"/api/machines/{name}/diagnoses",
                          json={k: d[k] for k in ("effect", "axis", "sensor", "estimate",
                                                  "rms_before_um", "rms_after_um",
                                                  "candidates")})
    r.raise_for_status()
    # the model: the center builds this machine's map from it and pushes it
    r = await client.post(f"/api/machines/{name}/models",
                          json={"source": "diagnose", "body": p.model.to_json()})
    r.raise_for_status()


async def _verify(client: httpx.AsyncClient, p: Prepared, grid: ActiveMap) -> tuple[float, float]:
    """Diagonals before and with the map the machine received; stored as a report."""
    m, sim = p.machine, p.sim
    programs = [diagonal_test(m, g, points=20, runs=2) for g in DIAGONALS]
    before = run_campaign(sim, programs).measurements
    inc = 0.001 if m.controller == "fanuc" else None
    after = run_campaign(sim, programs,
                         compensation=map_compensation(m, grid, increment_mm=inc)).measurements
    for label, data in (("diagonals-before", before), ("diagonals-after", after)):
        r = await client.post(f"/api/machines/{m.name}/measurements",
                              params={"set_name": label}, content=_csv(data),
                              headers={"Content-Type": "text/csv"})
        r.raise_for_status()
    r = await client.post(f"/api/machines/{m.name}/verifications",
                          json={"before": "diagonals-before", "after": "diagonals-after"})
    r.raise_for_status()
    pre, post = diagonal_ranges(before), diagonal_ranges(after)
    return max(pre.values()), max(post.values())


async def run_live(console: Console, prepared: list[Prepared], *, http_port: int,
                   exit_after: bool, workdir: Path | None = None) -> None:
    # asyncua warns on every login without an encrypting policy (the demo's loopback
    # servers offer None) and on every close: the demo's output says what matters
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    mqtt_up = _reachable("127.0.0.1", 1883)
    api_key = secrets.token_hex(16)
    tmp = tempfile.TemporaryDirectory(prefix="ednc-demo-") if workdir is None else None
    root = Path(tmp.name) if tmp is not None else workdir
    assert root is not None
    machine_port = _free_port()
    prefix = f"ednc-demo-{secrets.token_hex(3)}"
    settings = Settings(database_url=f"sqlite:///{root / 'ednc.db'}", api_key=api_key,
                        http_host="127.0.0.1", http_port=http_port,
                        machine_host="127.0.0.1", machine_port=machine_port,
                        mqtt_host="127.0.0.1" if mqtt_up else None, mqtt_topic_prefix=prefix,
                        push_period_s=30.0, heartbeat_s=5.0)
    base = f"http://127.0.0.1:{http_port}"
    console.rule("the control center")
    console.print(f"center: REST and dashboard on {base}, machines on 127.0.0.1:"
                  f"{machine_port}, database {root / 'ednc.db'}, MQTT "
                  + (f"via the broker on 127.0.0.1:1883 (topics {prefix}/...)" if mqtt_up
                     else "off (no broker on 127.0.0.1:1883; Siemens-style machines send "
                          "temperatures over their link)"))
    async with running_center(settings), httpx.AsyncClient(
            base_url=base, headers={"X-API-Key": api_key}, timeout=60) as client:
        cncs: list[SimulatedCNC | Served] = []
        links: dict[str, str] = {}
        for i, p in enumerate(prepared):
            ip, secret = f"127.0.2.{i + 1}", f"{p.machine.name}-{secrets.token_hex(12)}"
            m = parse_machine({**p.fleet.description, "ip": ip})
            runtime = MachineRuntime(m, seed=p.fleet.seed, thermal_speedup=THERMAL_SPEEDUP,
                                     warmup=bool(p.model.sensors))
            kind = LINKS.get(m.name, "ednc")
            links[m.name] = kind
            if kind == "ednc":
                await _register(client, p, ip, secret)
                mqtt = MqttTarget("127.0.0.1", 1883, prefix) if mqtt_up else None
                cncs.append(SimulatedCNC(m, ("127.0.0.1", machine_port), secret.encode(),
                                         runtime=runtime, ip=ip, mqtt=mqtt,
                                         seed=p.fleet.seed, cycle_s=0.02))
            else:
                served, link = _served(m, runtime, ip, kind)
                await _register(client, p, ip, secret, link)
                cncs.append(served)
        console.print(f"registered {len(cncs)} machines through the REST API; "
                      + ", ".join(f"{n} over {k}" for n, k in links.items() if k != "ednc")
                      + " (the center connects to their controllers), the others connect")
        async with contextlib.AsyncExitStack() as stack:
            for c in cncs:
                await stack.enter_async_context(c)
            grids = await _wait_for_maps(console, cncs)
            table = Table(title="ISO 230-6 with the map each machine received over its link")
            for col in ("machine", "controller", "link", "map", "bytes",
                        "worst range before µm", "after µm", "better"):
                table.add_column(col)
            for p, c in zip(prepared, cncs, strict=True):
                grid = grids[c.machine.name]
                r = await client.get(f"/api/machines/{p.machine.name}/maps/{grid.version}")
                size = f"{r.json()['size_bytes']:,d}" if r.status_code == 200 else "?"
                kind = f"v{grid.version} {_kind(grid)}"
                if all(a in p.machine.axis_names for a in "XYZ"):
                    pre, post = await _verify(client, p, grid)
                    table.add_row(p.machine.name, p.machine.controller, links[p.machine.name],
                                  kind, size, f"{pre:.1f}", f"{post:.2f}",
                                  f"{100 * (1 - post / pre):.0f} %")
                else:
                    table.add_row(p.machine.name, p.machine.controller, links[p.machine.name],
                                  kind, size, "two spindles", "shared axes", "see above")
            console.print(table)
            hot = next(((p, c) for p, c in zip(prepared, cncs, strict=True)
                        if p.model.sensors), None)
            if hot is not None:
                await _follow_heat(console, hot[0], hot[1], warm_s=20.0 if exit_after else 60.0)
            console.rule()
            console.print(f"dashboard: [bold]{base}/[/]   REST API: {base}/docs")
            # the demo's key is made for this run: say it, so that a machine can be
            # registered into the running demo from another terminal
            console.print(f"API key of this demo: {api_key}\nregister a machine into it: "
                          f"ednc machine register --machine M.json --secret SECRET "
                          f"--api {base} --api-key {api_key}", soft_wrap=True, markup=False)
            if exit_after:
                return
            console.print("running until Ctrl-C")
            await asyncio.Event().wait()
    if tmp is not None:
        tmp.cleanup()


def _kind(active: ActiveMap) -> str:
    if isinstance(active, FactoredLadder):
        return "factored"
    return "tables" if isinstance(active, TablesMap) else "grid"


async def _wait_for_maps(console: Console, cncs: list[SimulatedCNC | Served]
                         ) -> dict[str, ActiveMap]:
    grids: dict[str, ActiveMap] = {}
    # a five-axis map over five dimensions takes the center tens of seconds to build
    async with asyncio.timeout(300):
        while len(grids) < len(cncs):
            for c in cncs:
                active = c.runtime.controller.store.active
                if active is not None and c.machine.name not in grids:
                    grids[c.machine.name] = active
                    how = ("received, checked and applied" if isinstance(c, SimulatedCNC)
                           else "written into controller memory, checked and applied")
                    console.print(f"  {c.machine.name} ({c.ip}): {_kind(active)} map version "
                                  f"{active.version} {how} by its "
                                  f"{'PMC ladder' if c.machine.controller == 'fanuc' else 'NC'}")
            await asyncio.sleep(0.1)
    return grids


async def _follow_heat(console: Console, p: Prepared, cnc: SimulatedCNC | Served,
                       warm_s: float) -> None:
    """The thermal map follows the machine's temperature (module docstring)."""
    term = next(t for t in p.model.terms if isinstance(t, ThermalTerm))
    sensor, coefficient = term.sensor, term.coefficient
    key = sensor[2:-2]  # T_spindle_C -> spindle
    m = p.machine
    zi = m.axis_names.index("Z")
    ref = np.array([[0.5 * (a.travel[0] + a.travel[1]) for a in m.axes]])
    console.rule(f"{m.name}: thermal compensation, live")
    carried = isinstance(cnc.runtime.controller.store.active, TablesMap)
    how = ("its tables map carries the thermal terms: the machine applies its own latest "
           "temperature every cycle, the map is not rebuilt" if carried else
           "the center rebuilds and pushes its grid map as the temperature moves")
    console.print(f"the diagnosis found {term.kind} along {term.axis} with {sensor} "
                  f"({coefficient:+.2f} µm/K); the machine warms up from cold "
                  f"({THERMAL_SPEEDUP:.0f}x machine time); {how}:")
    start_t: float | None = None
    start_z: float | None = None
    seen = -1
    loop = asyncio.get_running_loop()
    t_end = loop.time() + warm_s
    while loop.time() < t_end:
        await asyncio.sleep(2.0)
        grid = cnc.runtime.controller.store.active
        if grid is None:
            continue
        temp = cnc.runtime.temperatures(cnc.now())[key]
        z = float(grid.lookup(ref[:, [m.axis_names.index(g) for g in grid.inputs]])[0, zi] * 1e3)
        if start_t is None or start_z is None:
            start_t, start_z = temp, z
        drift = coefficient * (temp - start_t)
        fresh = "new" if grid.version != seen and seen >= 0 else "   "
        seen = grid.version
        console.print(f"  {temp:6.2f} °C  drift {drift:+7.2f} µm   map v{grid.version:<3d}{fresh} "
                      f"z correction {z - start_z:+7.2f} µm   left {drift + z - start_z:+6.2f} µm")
