"""Machine leases: the repository on SQLite and PostgreSQL, the plant-wide live links, and
two ``ednc serve`` processes on one PostgreSQL sharing a fleet, one of them killed."""

from __future__ import annotations

import datetime as dt
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor

import pytest

from server.db import Database, leases, live_links, machines, make_engine
from server.plant import PlantView
from server.state import Registry
from tests.test_server_db import database_url, postgres_url  # noqa: F401 - fixtures

T0 = dt.datetime(2026, 1, 1, 12, 0, tzinfo=dt.UTC)


def at(seconds: float) -> dt.datetime:
    return T0 + dt.timedelta(seconds=seconds)


@pytest.fixture
def db(database_url: str) -> Iterator[Database]:  # noqa: F811 - the imported fixture
    database = Database(make_engine(database_url))
    database.create_schema()
    yield database
    database.engine.dispose()


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
