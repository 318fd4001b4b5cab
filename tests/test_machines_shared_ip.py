"""Machines reached through a link may share an ip; an EDNC machine's ip stays its own.

The ip is the key of EDNC logins (the server admits a peer by its address and checks the
Hello's against it), so it is unique among EDNC machines and no link machine may take an
EDNC machine's; controllers behind one gateway are registered at the gateway's address.
On SQLite and on the PostgreSQL on loopback, in the repository, under concurrent
registrations, and in a database made by the schema before (migrated at start).
"""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from sqlalchemy import Engine, create_engine, insert, inspect, select, text
from sqlalchemy.exc import IntegrityError

from server.db import Database, DuplicateError, machines, make_engine
from server.db.tables import Base, MachineRow, ModelRow, utcnow

GATEWAY = "10.20.0.5"


def description(name: str, ip: str, link: str | None = None, unit: int = 1) -> dict[str, Any]:
    """A fanuc machine at ``ip``; with ``link`` (``modbus``) behind a gateway at ``ip``."""
    d: dict[str, Any] = {"name": name, "ip": ip, "controller": "fanuc",
                         "chain": "w X Y b Z t"}
    if link == "modbus":
        d["link"] = {"kind": "modbus", "host": ip, "port": 502, "unit_id": unit}
    elif link is not None:
        d["link"] = {"kind": link}
    return d


def register(db: Database, name: str, ip: str, link: str | None = None,
             unit: int = 1) -> MachineRow:
    return db.call(machines.create_machine, name=name, ip=ip, controller="fanuc",
                   description=description(name, ip, link, unit), secret="s3cret-s3cret")


def test_link_machines_share_an_ip(db: Database) -> None:
    a = register(db, "pmc-1", GATEWAY, "modbus", 1)
    b = register(db, "pmc-2", GATEWAY, "modbus", 2)
    register(db, "sd-3", GATEWAY, "sinumerik_sd")
    rows = {r.name: r for r in db.call(machines.list_machines)}
    assert {r.ip for r in rows.values()} == {GATEWAY} and len(rows) == 3
    assert a.id != b.id and rows["pmc-2"].description["link"]["unit_id"] == 2
    assert (rows["pmc-1"].link, rows["sd-3"].link) == ("modbus", "sinumerik_sd")
    # no EDNC machine logs in from there
    assert db.call(machines.get_machine_by_ip, GATEWAY) is None


@pytest.mark.parametrize(("first", "second"), [(None, None), ("ednc", None), (None, "modbus"),
                                               ("modbus", None), ("opcua", "ednc")])
def test_an_ednc_machines_ip_is_its_own(db: Database, first: str | None,
                                        second: str | None) -> None:
    register(db, "one", GATEWAY, first)
    with pytest.raises(DuplicateError) as info:
        register(db, "two", GATEWAY, second)
    assert info.value.field == "ip" and "EDNC machine" in str(info.value)
    assert [r.name for r in db.call(machines.list_machines)] == ["one"]


def test_an_update_follows_the_same_rule(db: Database) -> None:
    register(db, "pmc-1", GATEWAY, "modbus")
    register(db, "pmc-2", GATEWAY, "modbus", 2)
    register(db, "vmc-9", "10.20.0.9")
    # a link machine turned into an EDNC machine at the shared ip: refused
    with pytest.raises(DuplicateError):
        db.call(machines.update_machine, "pmc-2", description=description("pmc-2", GATEWAY))
    # a link machine moved onto the EDNC machine's ip: refused
    with pytest.raises(DuplicateError):
        db.call(machines.update_machine, "pmc-2",
                description=description("pmc-2", "10.20.0.9", "modbus", 2))
    # the EDNC machine moved to its own new address, then reached through the gateway
    db.call(machines.update_machine, "vmc-9", description=description("vmc-9", "10.20.0.10"))
    row = db.call(machines.update_machine, "vmc-9",
                  description=description("vmc-9", GATEWAY, "modbus", 3))
    assert row is not None and (row.ip, row.link) == (GATEWAY, "modbus")
    # and the last link machine at an ip may become an EDNC machine there
    db.call(machines.update_machine, "pmc-1", description=description("pmc-1", "10.20.0.7",
                                                                      "modbus"))
    row = db.call(machines.update_machine, "pmc-1",
                  description=description("pmc-1", "10.20.0.7"))
    assert row is not None and row.link == "ednc"
    assert db.call(machines.get_machine_by_ip, "10.20.0.7") is not None


def test_the_database_holds_one_ednc_machine_per_ip(db: Database) -> None:
    """The partial unique index, past the repository's check (another process's insert)."""
    register(db, "pmc-1", GATEWAY, "modbus")
    register(db, "vmc-1", "10.20.0.9")
    row = {"ip": GATEWAY, "controller": "fanuc", "description": {}, "secret": "x",
           "created_at": utcnow(), "updated_at": utcnow()}
    with db.session() as s:
        s.execute(insert(MachineRow).values(name="pmc-2", link="modbus", **row))
    with pytest.raises(IntegrityError), db.session() as s:
        s.execute(insert(MachineRow).values(name="vmc-2", link="ednc",
                                            **{**row, "ip": "10.20.0.9"}))
    names = [r.name for r in db.call(machines.list_machines)]
    assert names == ["pmc-1", "pmc-2", "vmc-1"]


@pytest.mark.parametrize("order", ["link first", "ednc first"])
def test_concurrent_registrations_at_one_ip_cannot_both_win(db: Database, order: str) -> None:
    """One registration's transaction is open (checked and inserted, not committed) when
    the other checks: the second waits for it, sees it and is refused, whichever kind
    comes first. Without a lock the second sees nothing and both commit."""
    kinds = ("modbus", None) if order == "link first" else (None, "modbus")
    inserted, release = threading.Event(), threading.Event()
    errors: list[BaseException] = []

    def first() -> None:
        try:
            with db.session() as s:
                machines.create_machine(s, name="first", ip=GATEWAY, controller="fanuc",
                                        description=description("first", GATEWAY, kinds[0]),
                                        secret="s3cret-s3cret")
                inserted.set()
                release.wait(10)
        except BaseException as exc:  # surfaced by the assertion below
            errors.append(exc)
            inserted.set()

    holder = threading.Thread(target=first)
    holder.start()
    assert inserted.wait(10)
    outcome: list[BaseException | None] = []

    def second() -> None:
        try:
            register(db, "second", GATEWAY, kinds[1])
            outcome.append(None)
        except BaseException as exc:
            outcome.append(exc)

    other = threading.Thread(target=second)
    other.start()
    other.join(0.5)  # it waits on the first's lock
    release.set()
    holder.join(15)
    other.join(15)
    assert not errors, errors
    assert len(outcome) == 1 and isinstance(outcome[0], DuplicateError), outcome
    assert [r.name for r in db.call(machines.list_machines)] == ["first"]


# -- a database made by the schema before: machines.ip unique for every machine

OLD_MACHINES = {
    "sqlite": """CREATE TABLE machines (
        id INTEGER NOT NULL, name VARCHAR(64) NOT NULL, ip VARCHAR(45) NOT NULL,
        controller VARCHAR(16) NOT NULL, description JSON NOT NULL,
        secret VARCHAR(512) NOT NULL, created_at DATETIME NOT NULL,
        updated_at DATETIME NOT NULL, PRIMARY KEY (id), UNIQUE (name), UNIQUE (ip))""",
    "postgresql": """CREATE TABLE machines (
        id SERIAL NOT NULL, name VARCHAR(64) NOT NULL, ip VARCHAR(45) NOT NULL,
        controller VARCHAR(16) NOT NULL, description JSON NOT NULL,
        secret VARCHAR(512) NOT NULL, created_at TIMESTAMP WITH TIME ZONE NOT NULL,
        updated_at TIMESTAMP WITH TIME ZONE NOT NULL, PRIMARY KEY (id), UNIQUE (name),
        UNIQUE (ip))""",
}
"""``machines`` as ``create_all`` made it before link machines could share an ip."""


def old_database(engine: Engine) -> dict[str, int]:
    """The old schema with three machines (one behind a gateway, at its own ip as the old
    rule wanted) and a model each; their ids by name."""
    with engine.begin() as conn:
        conn.execute(text(OLD_MACHINES[engine.dialect.name]))
    others = [t for t in Base.metadata.sorted_tables if t.name != "machines"]
    Base.metadata.create_all(engine, tables=others)
    ids: dict[str, int] = {}
    with engine.begin() as conn:
        for name, ip, link in [("vmc-01", "10.0.0.21", None), ("pmc-02", GATEWAY, "modbus"),
                               ("hmc-03", "10.0.0.23", None)]:
            conn.execute(text(
                "INSERT INTO machines (name, ip, controller, description, secret, created_at,"
                " updated_at) VALUES (:name, :ip, 'fanuc', :d, 's3cret-s3cret', :t, :t)"),
                {"name": name, "ip": ip, "t": utcnow(),
                 "d": json.dumps(description(name, ip, link))})
        conn.execute(text("DELETE FROM machines WHERE name = 'vmc-01'"))  # ids have a gap
        for name, mid in conn.execute(text("SELECT name, id FROM machines")):
            ids[name] = mid
            conn.execute(insert(ModelRow).values(machine_id=mid, version=1, source="upload",
                                                 body={"of": name}, created_at=utcnow()))
    return ids


@pytest.fixture
def old_engine(database_url: str) -> Iterator[Engine]:
    engine = create_engine(database_url)
    yield engine
    engine.dispose()


def test_an_old_database_is_migrated_keeping_rows_ids_and_foreign_keys(
        database_url: str, old_engine: Engine) -> None:
    ids = old_database(old_engine)
    db = Database(make_engine(database_url))
    try:
        db.create_schema()
        db.create_schema()  # a second start finds nothing left to do
        rows = {r.name: r for r in db.call(machines.list_machines)}
        assert {n: r.id for n, r in rows.items()} == ids
        assert (rows["pmc-02"].link, rows["hmc-03"].link) == ("modbus", "ednc")
        assert rows["pmc-02"].description["link"]["kind"] == "modbus"
        with db.session() as s:
            bodies = dict(s.execute(select(ModelRow.machine_id, ModelRow.body)).all())
        assert bodies == {ids["pmc-02"]: {"of": "pmc-02"}, ids["hmc-03"]: {"of": "hmc-03"}}
        # the new rule holds: a second controller behind the gateway, the EDNC ip its own
        new = register(db, "pmc-04", GATEWAY, "modbus", 2)
        assert new.id > max(ids.values())
        with pytest.raises(DuplicateError):
            register(db, "vmc-05", GATEWAY)
        with pytest.raises(IntegrityError), db.session() as s:  # and the index under it
            s.execute(insert(MachineRow).values(
                name="vmc-06", ip="10.0.0.23", link="ednc", controller="fanuc",
                description={}, secret="x", created_at=utcnow(), updated_at=utcnow()))
        # foreign keys still point at machines: cascade on delete, refuse an unknown id
        db.call(machines.delete_machine, "hmc-03")
        with db.session() as s:
            assert s.scalars(select(ModelRow.machine_id)).all() == [ids["pmc-02"]]
        with pytest.raises(IntegrityError), db.session() as s:
            s.execute(insert(ModelRow).values(machine_id=9999, version=1, source="upload",
                                              body={}, created_at=utcnow()))
        uniques = inspect(db.engine).get_unique_constraints("machines")
        assert [u["column_names"] for u in uniques] == [["name"]]
    finally:
        db.engine.dispose()
