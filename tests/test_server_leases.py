"""Machine leases: the repository on SQLite and PostgreSQL, the plant-wide live links, and
two ``ednc serve`` processes on one PostgreSQL sharing a fleet, one of them killed."""

from __future__ import annotations

import asyncio
import datetime as dt
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import AsyncIterator, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import AsyncExitStack, asynccontextmanager
from pathlib import Path
from typing import Any

import httpx
import psycopg
import pytest
from sqlalchemy import update

from machine_sim.fanuc import FanucConfig
from machine_sim.fleet import FleetSpecError, parse_centers
from machine_sim.link import SimulatedCNC
from machine_sim.runtime import MachineRuntime
from protocol.backoff import Backoff
from server.center import Center
from server.db import Database, leases, live_links, machines, make_engine
from server.db import error_models as model_repo
from server.db import events as event_repo
from server.db.tables import LeaseRow
from server.events import EventKind
from server.leasing import LeaseKeeper
from server.plant import PlantView
from server.settings import load_settings
from server.state import Registry
from tests.support.db import PG_ADMIN, database_url, postgres_url  # noqa: F401
from tests.support.link import SECRET, description, model_body, rig, until
from tests.support.services import reachable, require
from volumetric.model.machine import parse_machine

T0 = dt.datetime(2026, 1, 1, 12, 0, tzinfo=dt.UTC)


def at(seconds: float) -> dt.datetime:
    return T0 + dt.timedelta(seconds=seconds)


def machine(db: Database, name: str = "vmc-01", ip: str = "10.0.0.21") -> int:
    row = db.call(machines.create_machine, name=name, ip=ip, controller="fanuc",
                  description={"name": name, "ip": ip, "controller": "fanuc",
                               "chain": "w X Y b Z t"}, secret="s3cret-s3cret")
    return row.id


# -- the repository

def test_acquire_renew_and_release(db: Database) -> None:
    mid = machine(db)
    first = db.call(leases.acquire, mid, "node-a", 15.0, now=at(0))
    assert (first.owner, first.acquired_at, first.expires_at) == ("node-a", at(0), at(15))
    again = db.call(leases.acquire, mid, "node-a", 15.0, now=at(5))
    assert again.owner == "node-a" and again.expires_at == at(20)
    assert again.acquired_at == at(0), "re-acquiring one's own lease keeps its start"
    assert db.call(leases.renew, [mid], "node-a", 15.0, now=at(10)) == {mid}
    stored = db.call(leases.list_leases)
    assert [(x.owner, x.expires_at) for x in stored] == [("node-a", at(25))]
    assert db.call(leases.release, [mid], "node-b") == 0, "not node-b's to release"
    assert db.call(leases.release, [mid], "node-a") == 1
    assert db.call(leases.list_leases) == []


def test_a_live_lease_is_refused_with_its_owner(db: Database) -> None:
    mid = machine(db)
    db.call(leases.acquire, mid, "node-a", 15.0, now=at(0))
    other = db.call(leases.acquire, mid, "node-b", 15.0, now=at(14.9))
    assert other.owner == "node-a" and other.expires_at == at(15)
    assert db.call(leases.renew, [mid], "node-b", 15.0, now=at(14.9)) == set()
    assert db.call(leases.list_leases)[0].owner == "node-a"


def test_an_expired_lease_is_stolen_and_its_old_owner_cannot_renew_it(db: Database) -> None:
    mid, mid2 = machine(db), machine(db, "vmc-02", "10.0.0.22")
    db.call(leases.acquire, mid, "node-a", 15.0, now=at(0))
    db.call(leases.acquire, mid2, "node-a", 15.0, now=at(0))
    stolen = db.call(leases.acquire, mid, "node-b", 15.0, now=at(15.5))
    assert (stolen.owner, stolen.acquired_at, stolen.expires_at) == ("node-b", at(15.5),
                                                                      at(30.5))
    # node-a comes back: the stolen one is lost to it, the other (expired but untaken)
    # is still its own
    assert db.call(leases.renew, [mid, mid2], "node-a", 15.0, now=at(16)) == {mid2}
    assert db.call(leases.release_all, "node-a") == 1
    assert [(x.machine_id, x.owner) for x in db.call(leases.list_leases)] == [(mid, "node-b")]
    assert db.call(leases.list_leases, live_only=True, now=at(31)) == []


def test_leases_go_with_their_machine(db: Database) -> None:
    mid = machine(db)
    db.call(leases.acquire, mid, "node-a", 15.0, now=at(0))
    assert db.call(machines.delete_machine, "vmc-01")
    assert db.call(leases.list_leases) == []


def test_bad_ttl_is_refused(db: Database) -> None:
    mid = machine(db)
    with pytest.raises(ValueError, match="time to live"):
        db.call(leases.acquire, mid, "node-a", 0.0)


def test_racing_nodes_never_both_win(db: Database) -> None:
    """Eight nodes at once on one free machine, then on the same machine expired."""
    mid = machine(db)
    nodes = [f"node-{i}" for i in range(8)]
    for moment in (at(0), at(100)):
        with ThreadPoolExecutor(len(nodes)) as pool:
            got = list(pool.map(lambda n, m=moment: db.call(leases.acquire, mid, n, 15.0,
                                                            now=m), nodes))
        winners = {g.owner for g in got}
        assert len(winners) == 1, got
        assert sum(g.owner == g_node for g, g_node in zip(got, nodes, strict=True)) == 1
        assert db.call(leases.list_leases)[0].owner in winners


def test_the_database_clock_is_utc(db: Database) -> None:
    now = db.call(leases.clock)
    assert now.tzinfo is not None and now.utcoffset() == dt.timedelta(0)
    assert abs((now - dt.datetime.now(dt.UTC)).total_seconds()) < 60


# -- live links

def link(name: str, connected: bool, seen: float, **extra: object) -> dict[str, object]:
    return {"machine": name, "connected": connected, "address": "127.0.1.1:5000",
            "connected_since": at(0) if connected else None, "last_seen": at(seen),
            "telemetry": {"state": "idle", "axes": {"X": {"position": 1.5}}}, **extra}


def test_a_disconnected_write_does_not_overwrite_the_new_owner(db: Database) -> None:
    mid = machine(db)
    db.call(leases.acquire, mid, "node-b", 15.0, now=at(0))
    db.call(live_links.publish, "node-a", [link("vmc-01", True, 0)])
    db.call(live_links.publish, "node-b", [link("vmc-01", True, 1)])  # took it over
    db.call(live_links.publish, "node-a", [link("vmc-01", False, 2)])  # late news from A
    [row] = db.call(live_links.plant_links, now=at(3))
    assert (row.node, row.connected, row.live) == ("node-b", True, True)
    assert row.telemetry == {"state": "idle", "axes": {"X": {"position": 1.5}}}
    db.call(live_links.publish, "node-b", [link("vmc-01", False, 4)])
    [row] = db.call(live_links.plant_links, now=at(5))
    assert (row.node, row.connected, row.live) == ("node-b", False, False)


def test_a_link_is_live_only_while_its_node_holds_the_lease(db: Database) -> None:
    mid = machine(db)
    db.call(leases.acquire, mid, "node-a", 15.0, now=at(0))
    db.call(live_links.publish, "node-a", [link("vmc-01", True, 1)])
    assert db.call(live_links.plant_links, now=at(14))[0].live
    [dead] = db.call(live_links.plant_links, now=at(16))  # node-a died, its lease expired
    assert dead.connected and not dead.live


def test_the_plant_view_merges_memory_and_table(db: Database) -> None:
    for i, name in enumerate(("here", "there", "dead"), start=1):
        mid = machine(db, name, f"10.0.0.{i}")
        db.call(leases.acquire, mid, "node-b" if name == "there" else "node-c", 15.0,
                now=at(0 if name != "dead" else -20))
    db.call(live_links.publish, "node-b", [link("there", True, 2)])
    db.call(live_links.publish, "node-c", [link("dead", True, 1)])
    local = Registry()
    local.connected("here", "127.0.1.1:4000", at=at(3))
    local.connected("there", "127.0.1.2:4000", at=at(0.5))
    local.disconnected("there")  # it moved from here to node-b
    view = PlantView(local, db.call(live_links.plant_links, now=at(5)), "node-a")
    assert (view.get("here").connected, view.get("here").owner) == (True, "node-a")
    assert (view.get("there").connected, view.get("there").owner) == (True, "node-b")
    assert view.get("there").telemetry["state"] == "idle"
    assert (view.get("dead").connected, view.get("dead").owner) == (False, None)
    assert view.get("dead").last_seen == at(1)
    assert view.get("never").connected is False
    assert view.names() == ["dead", "here", "there"] and view.connected_count() == 2


# -- one center process: refusal, takeover after expiry, loss of the lease

def cnc(name: str, ip: str, centers: list[tuple[str, int]], controller: str = "fanuc",
        seed: int = 1) -> SimulatedCNC:
    m = parse_machine(description(name, controller, ip))
    runtime = MachineRuntime(m, seed=seed, fanuc=FanucConfig(max_step_counts=1000))
    return SimulatedCNC(m, centers, SECRET.encode(), runtime=runtime, cycle_s=0.02,
                        backoff=Backoff(initial_s=0.05, factor=2.0, cap_s=0.3))


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def test_centers_parse_from_text_and_lists() -> None:
    assert parse_centers("127.0.0.1:7878, [::1]:7879") == [("127.0.0.1", 7878), ("::1", 7879)]
    assert parse_centers(["a:1", "b:2"]) == [("a", 1), ("b", 2)]
    for bad in ("a:1,,b:2", "a:1,b", 7878, ["a:1", 2]):
        with pytest.raises(FleetSpecError, match="center"):
            parse_centers(bad)


async def test_a_machine_moves_on_when_a_center_is_down(tmp_path: Path) -> None:
    async with rig(tmp_path) as r:
        await r.register(model=model_body())
        down = ("127.0.0.1", free_port())
        sim = cnc("vmc-01", "127.0.0.1", [down, ("127.0.0.1", r.port)])
        async with asyncio.timeout(20), sim:
            await sim.ready.wait()
            assert sim.connected_to == ("127.0.0.1", r.port)
            assert "Connect" in sim.stats.last_error or "refused" in sim.stats.last_error


async def test_a_machine_owned_by_another_node_is_refused_until_its_lease_expires(
        tmp_path: Path) -> None:
    async with rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        await r.db.run(leases.acquire, mid, "node-x", 1.0)  # node-x "died" just now
        sim = cnc("vmc-01", "127.0.0.1", [("127.0.0.1", r.port)])
        async with asyncio.timeout(20), sim:
            await sim.ready.wait()
            await until(lambda: sim.stats.maps_acked >= 1)
        assert any("owned by node node-x" in text for text in sim.stats.rejects)
        refusals = await r.events()
        assert any(e.kind == "refused" and "owned by node node-x" in e.detail
                   for e in refusals)
        # the session has ended: its lease is given back (in the background)

        async def released() -> bool:
            return await r.db.run(leases.list_leases) == []

        async with asyncio.timeout(20):
            await until(released)


async def test_a_lost_lease_ends_the_session(tmp_path: Path) -> None:
    async with rig(tmp_path) as r:
        mid = await r.register(model=model_body())
        keeper = r.services.leases
        assert keeper is not None
        sim = cnc("vmc-01", "127.0.0.1", [("127.0.0.1", r.port)])
        async with asyncio.timeout(20), sim:
            await sim.ready.wait()
            [mine] = await r.db.run(leases.list_leases)
            assert (mine.machine_id, mine.owner) == (mid, r.center.settings.node_id)
            assert keeper.holds(mid)

            def steal(session: Any) -> None:  # as a node that found it expired would
                session.execute(update(LeaseRow).values(owner="node-y"))

            await r.db.run(steal)
            await keeper.renew_once()
            assert not keeper.holds(mid)
            await until(lambda: any("owned by node node-y" in t for t in sim.stats.rejects))
        assert "vmc-01" not in r.services.server.sessions
        ended = await r.events(EventKind.DISCONNECTED)
        assert any("lease lost" in e.detail for e in ended), [e.detail for e in ended]
        assert (await r.db.run(leases.list_leases))[0].owner == "node-y"


# -- two ednc serve processes on one PostgreSQL

NODES = ("node-a", "node-b")
TTL_S = 2.0
MACHINES = 6


@pytest.fixture
def plant_url() -> Iterator[str]:
    """A PostgreSQL database of its own, with the plant's machines and their models."""
    require("PostgreSQL", reachable("127.0.0.1", 5432),
            "start it with `pg_ctlcluster <version> main start` (trust auth, user postgres)")
    name = f"ednc_plant_{uuid.uuid4().hex[:12]}"
    with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
        admin.execute(f'CREATE DATABASE "{name}"')
    url = f"postgresql+psycopg://postgres@127.0.0.1:5432/{name}"
    db = Database(make_engine(url))
    try:
        db.create_schema()
        for i in range(MACHINES):
            name_i, ip, ctl = plant_machine(i)
            row = db.call(machines.create_machine, name=name_i, ip=ip, controller=ctl,
                          description=description(name_i, ctl, ip), secret=SECRET)
            db.call(model_repo.add_model, row.id, source="upload", body=model_body(name_i))
        db.engine.dispose()
        yield url
    finally:
        db.engine.dispose()
        with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
            admin.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


def plant_machine(i: int) -> tuple[str, str, str]:
    return f"pm-{i + 1:02d}", f"127.0.3.{i + 1}", ("fanuc", "siemens")[i % 2]


class Node:
    """One ``ednc serve`` process."""

    def __init__(self, node_id: str, url: str, log: Path) -> None:
        self.node_id = node_id
        self.http = free_port()
        self.machine_port = free_port()
        env = {k: v for k, v in os.environ.items() if not k.startswith("EDNC_")}
        env.update(EDNC_DATABASE_URL=url, EDNC_NODE_ID=node_id,
                   EDNC_HTTP_PORT=str(self.http), EDNC_MACHINE_HOST="127.0.0.1",
                   EDNC_MACHINE_PORT=str(self.machine_port), EDNC_LEASE_TTL_S=str(TTL_S),
                   EDNC_HEARTBEAT_S="1")
        self.log = log
        with log.open("wb") as out:
            self.proc = subprocess.Popen([str(Path(sys.executable).parent / "ednc"), "serve"],
                                         env=env, stdout=out, stderr=subprocess.STDOUT)

    @property
    def address(self) -> tuple[str, int]:
        return ("127.0.0.1", self.machine_port)

    async def get(self, path: str) -> Any:
        async with httpx.AsyncClient(timeout=5.0) as client:
            r = await client.get(f"http://127.0.0.1:{self.http}{path}")
            r.raise_for_status()
            return r.json()

    async def up(self) -> None:
        while True:
            assert self.proc.poll() is None, f"{self.node_id} exited:\n{self.log.read_text()}"
            try:
                await self.get("/api/status")
                return
            except httpx.TransportError:
                await asyncio.sleep(0.1)

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
        self.proc.wait(timeout=30)


@asynccontextmanager
async def plant(url: str, tmp_path: Path) -> AsyncIterator[dict[str, Node]]:
    nodes = {n: Node(n, url, tmp_path / f"{n}.log") for n in NODES}
    try:
        await asyncio.gather(*(n.up() for n in nodes.values()))
        yield nodes
    finally:
        for n in nodes.values():
            n.stop()


async def owners(db: Database) -> dict[str, str]:
    """Machine name -> owner of its unexpired lease."""
    by_id = {m.id: m.name for m in await db.run(machines.list_machines)}
    return {by_id[x.machine_id]: x.owner
            for x in await db.run(leases.list_leases, live_only=True)}


async def plant_status(node: Node) -> dict[str, tuple[bool, str | None]]:
    status = await node.get("/api/status")
    return {m["name"]: (m["connected"], m["owner"]) for m in status["machine_status"]}


async def dashboard_owners(node: Node) -> dict[str, str | None]:
    snap = await node.get("/api/dashboard")
    return {m["name"]: m["owner"] if m["connected"] else None for m in snap["machines"]}


@pytest.mark.services
@pytest.mark.slow
async def test_two_centers_share_the_plant_and_one_takes_over_when_the_other_dies(
        plant_url: str, tmp_path: Path) -> None:
    db = Database(make_engine(plant_url))
    loop = asyncio.get_running_loop()
    try:
        async with asyncio.timeout(120), plant(plant_url, tmp_path) as nodes, \
                AsyncExitStack() as stack:
            a, b = nodes["node-a"], nodes["node-b"]
            port_of = {a.machine_port: a.node_id, b.machine_port: b.node_id}
            sims = []
            for i in range(MACHINES):
                name, ip, ctl = plant_machine(i)
                order = [a.address, b.address] if i % 2 == 0 else [b.address, a.address]
                sims.append(await stack.enter_async_context(cnc(name, ip, order, ctl, i)))

            # each machine is served by exactly one node, the one holding its lease
            await until(lambda: all(s.ready.is_set() and s.stats.maps_acked >= 1
                                    for s in sims), step_s=0.05)
            held = await owners(db)
            assert sorted(held) == [s.machine.name for s in sims]
            assert set(held.values()) == set(NODES), "both nodes serve part of the plant"
            for s in sims:
                assert s.connected_to is not None
                assert port_of[s.connected_to[1]] == held[s.machine.name]
            # the status and dashboard of either node list every machine with its owner
            want = {name: (True, owner) for name, owner in held.items()}

            async def everyone_sees(expected: dict[str, tuple[bool, str | None]]) -> bool:
                seen = [await plant_status(n) for n in nodes.values()
                        if n.proc.poll() is None]
                return all(s == expected for s in seen)

            await until(lambda: everyone_sees(want), step_s=0.2)
            for n in (a, b):
                assert await dashboard_owners(n) == held

            # kill -9 node-a: its machines go to node-b once node-a's leases expired
            moved = [s for s in sims if held[s.machine.name] == "node-a"]
            acked_before = {s.machine.name: s.stats.maps_acked for s in moved}
            killed_at = loop.time()
            a.proc.send_signal(signal.SIGKILL)
            a.proc.wait(timeout=10)
            await until(lambda: all(s.ready.is_set() and s.connected_to == b.address
                                    for s in sims), step_s=0.02)
            takeover_s = loop.time() - killed_at
            await until(lambda: all(s.stats.maps_acked > acked_before[s.machine.name]
                                    for s in moved), step_s=0.05)
            print(f"\ntakeover of {len(moved)} machines after kill -9: {takeover_s:.2f} s "
                  f"(lease TTL {TTL_S:g} s)")
            assert await owners(db) == {s.machine.name: "node-b" for s in sims}
            for s in moved:
                assert any("owned by node node-a" in t for t in s.stats.rejects), \
                    s.stats.rejects
            events = await db.run(event_repo.list_events, kind="refused", limit=1000)
            assert any("owned by node node-a" in e.detail for e in events)
            everyone_b = {s.machine.name: (True, "node-b") for s in sims}
            await until(lambda: everyone_sees(everyone_b), step_s=0.2)

            # a clean stop gives every lease back at once
            b.stop()
            assert await owners(db) == {}
            assert await db.run(leases.list_leases) == []
    finally:
        db.engine.dispose()


async def test_a_claim_abandoned_mid_statement_gives_its_lease_back(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A handshake that times out while the lease is being taken leaves no lease behind."""
    settings = load_settings(database_url=f"sqlite:///{tmp_path / 'c.db'}", node_id="node-a")
    started, finished = threading.Event(), threading.Event()
    real_acquire = leases.acquire

    def slow_acquire(*args: Any, **kwargs: Any) -> leases.Lease:
        started.set()
        time.sleep(0.3)  # the database is slow: the caller stops waiting meanwhile
        try:
            return real_acquire(*args, **kwargs)
        finally:
            finished.set()

    monkeypatch.setattr(leases, "acquire", slow_acquire)
    async with Database.open(settings.database_url) as db, \
            LeaseKeeper(Center(settings=settings, db=db), ttl_s=60.0) as keeper:
        mid = machine(db)
        lost: list[str] = []
        with pytest.raises(TimeoutError):
            async with asyncio.timeout(0.05):
                await keeper.claim(mid, "vmc-01", object(), lost.append)
        assert started.is_set()

        async def released() -> bool:
            return await db.run(leases.list_leases) == []

        async with asyncio.timeout(20):
            await until(finished.is_set)  # the statement took the lease on its thread
            await until(released)
        assert keeper.held() == {} and lost == []


def test_forgetting_a_machine_drops_its_live_link(db: Database) -> None:
    db.call(live_links.publish, "node-a", [link("vmc-01", True, 0), link("vmc-02", True, 0)])
    db.call(live_links.forget, "vmc-01")
    db.call(live_links.forget, "never-there")
    assert [x.machine for x in db.call(live_links.plant_links, now=at(1))] == ["vmc-02"]
