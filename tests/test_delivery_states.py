"""Delivery states that say what happened: applied, rejected (the PLC's verdict and code,
nothing else), failed (the transport; the map is sent again), superseded.

Before: a write exception, a lost connection mid-push or a map too large became
deliveries ``rejected`` ("session ended before the answer"), raised the rejects metric and
put the machine in alarm; some deliveries stayed ``pending`` for good; ``applied_at``
held the send time of rejected ones; code 100 (a torn header) was never sent again.
"""

from __future__ import annotations

import asyncio
from contextlib import AsyncExitStack
from pathlib import Path

import pytest

from protocol import Controller
from server.api.routes.maps import applied_public
from server.db import Database
from server.db import history as history_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db.tables import AppliedRow
from server.links.modbus import ModbusMemory
from server.links.window.session import ControllerSession
from tests.support.integration import center, spec, until
from tests.support.pmc import REGISTER, Faults, built_map, linked, payload, pmc

GANTRY = spec("gantry-02")
M = GANTRY.machine


# -- the store

async def _machine_with_maps(db: Database, versions: int) -> int:
    def add(session: object) -> int:
        row = machine_repo.create_machine(session, name="m1", ip="10.0.0.1",  # type: ignore[arg-type]
                                          controller="fanuc", secret="s" * 16,
                                          description={"name": "m1"})
        for _ in range(versions):
            map_repo.add_map_version(session, row.id, payload=b"x" * 16,  # type: ignore[arg-type]
                                     model_version=1)
        return int(row.id)
    return await db.run(add)


async def test_each_outcome_is_its_own_state_and_only_verdicts_count_as_rejects(
        tmp_path: Path) -> None:
    async with Database.open(f"sqlite:///{tmp_path / 'd.db'}") as db:
        mid = await _machine_with_maps(db, 4)
        a = await db.run(map_repo.record_sent, mid, 1)
        await db.run(map_repo.record_answer, a.id, acked=True)
        r = await db.run(map_repo.record_sent, mid, 2)
        await db.run(map_repo.record_answer, r.id, acked=False,
                     reject_reason="CHECKSUM_MISMATCH: PLC code 4: checksum mismatch")
        f = await db.run(map_repo.record_sent, mid, 3)
        await db.run(map_repo.record_failure, f.id, "session ended before the answer: x")
        p = await db.run(map_repo.record_sent, mid, 4)  # never answered...
        last = await db.run(map_repo.record_sent, mid, 4)  # ...the next one goes out
        rows = {row.id: row for row in await db.run(map_repo.list_applied, mid)}
        states = {k: map_repo.delivery_state(rows[k]) for k in rows}
        assert [states[x.id] for x in (a, r, f, p, last)] == [
            "applied", "rejected", "failed", "superseded", "pending"]
        public = {k: applied_public(rows[k], "m1") for k in rows}
        assert public[a.id].applied_at == public[a.id].sent_at
        for k in (r.id, f.id, p.id, last.id):
            assert public[k].applied_at is None, public[k]
        assert public[r.id].reject_reason is not None and public[r.id].failure is None
        assert public[f.id].reject_reason is None
        assert public[f.id].failure is not None and "session ended" in public[f.id].failure
        # the rejects metric's source: the PLC's verdicts only
        assert await db.run(history_repo.rejects_by_machine) == {"m1": 1}
        states_now = await db.run(map_repo.map_states, mid)
        assert states_now[mid].reject_reason is None  # the newest is pending, not rejected


def test_rows_stored_before_the_state_column_read_as_meant() -> None:
    def row(**kw: object) -> AppliedRow:
        return AppliedRow(machine_id=1, map_id=1, map_version=1, state=None, **kw)

    assert map_repo.delivery_state(row(acked=True)) == "applied"
    assert map_repo.delivery_state(row(acked=False, reject_reason=None)) == "pending"
    assert map_repo.delivery_state(row(acked=False, reject_reason="CRC")) == "rejected"
    assert map_repo.delivery_state(row(
        acked=False, reject_reason="no answer to map version 3 within 30 s")) == "failed"


# -- code 100 over a real socket

def _session(port: int) -> ControllerSession:
    return ControllerSession(M.name, "127.0.0.1", Controller.FANUC, M.axis_names,
                             ModbusMemory("127.0.0.1", port, register=REGISTER),
                             link="modbus", chain=M.chain, poll_s=0.01)


@pytest.mark.parametrize("torn", [1, 2])
async def test_a_torn_header_is_written_again_once(torn: int) -> None:
    await asyncio.to_thread(built_map)
    faults = Faults(tear_headers=torn)
    async with asyncio.timeout(60), pmc(GANTRY, faults=faults, cycle_s=0.005) as cnc:
        s = _session(cnc.server.port)  # type: ignore[attr-defined]
        await s.open()
        runner = asyncio.create_task(s.run())
        try:
            verdict = await s.push_map(1, payload(1), 10.0)
            assert s.torn_rewrites == 1 and len(s.push_times) == 2
            if torn == 1:
                assert verdict.applied and cnc.runtime.controller.store.version == 1
            else:  # torn again: the PLC's verdict stands, with its code
                assert not verdict.applied and "PLC code 100" in verdict.text, verdict
                assert cnc.runtime.controller.store.version is None or \
                    cnc.runtime.controller.store.version != 1
        finally:
            s.abort(None, "test over")
            await runner


# -- the center

@pytest.mark.slow
async def test_a_refused_write_is_a_failed_delivery_not_a_rejection(tmp_path: Path) -> None:
    faults = Faults(refuse_buffer_writes=True)
    async with asyncio.timeout(240), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(GANTRY, faults=faults))
        s = linked(GANTRY, cnc.server.port)  # type: ignore[attr-defined]
        await plant.register(s)
        await plant.fit_from_campaign(s.name)

        async def failed() -> bool:
            rows = await plant.deliveries(s.name)
            return bool(rows) and rows[0]["state"] == "failed"

        await until(failed)
        rows = await plant.deliveries(s.name)
        assert rows[0]["reject_reason"] is None and "exception 02" in rows[0]["failure"]
        assert rows[0]["applied_at"] is None
        assert await plant.metric("ednc_machine_map_rejects_total", machine=s.name) == 0.0
        assert await plant.metric("ednc_map_pushes_total", outcome="rejected") == 0.0
        st = await plant.status(s.name)
        assert st["last_reject_reason"] is None, st
        r = await plant.client.get("/api/dashboard")
        card = next(c for c in r.json()["machines"] if c["name"] == s.name)
        assert card["health"] != "alarm", card
        # cleared: applied; no delivery left pending, none rejected
        faults.refuse_buffer_writes = False
        await until(plant.applied(s.name, 1))
        states = [d["state"] for d in await plant.deliveries(s.name)]
        assert states[0] == "applied" and set(states[1:]) <= {"failed", "superseded"}, states


def test_a_database_from_before_gets_the_new_columns(tmp_path: Path) -> None:
    import sqlite3

    from server.db import make_engine

    path = tmp_path / "old.db"
    with sqlite3.connect(path) as conn:  # the table as it shipped before
        conn.execute("CREATE TABLE applied (id INTEGER PRIMARY KEY, machine_id INTEGER, "
                     "map_id INTEGER, map_version INTEGER, applied_at DATETIME, "
                     "acked BOOLEAN, reject_reason TEXT)")
        conn.execute("INSERT INTO applied VALUES (1, 1, 1, 1, '2026-01-01', 0, "
                     "'session ended before the answer to map version 1')")
    db = Database(make_engine(f"sqlite:///{path}"))
    try:
        db.create_schema()
        db.create_schema()  # again: nothing to add
        row = db.call(lambda s: s.get(AppliedRow, 1))
        assert row is not None and row.state is None and row.failure is None
        assert map_repo.delivery_state(row) == "failed"
    finally:
        db.engine.dispose()
