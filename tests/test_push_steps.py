"""The push's database steps and what a re-push reads: a session keeps its map's bytes
(read once, sent many times, never for another row), the deliveries and events the
push's Core statements write read back as the ORM's did (states, UTC times, event text
made storable), and a delivery of a map row gone meanwhile is refused whole."""

from __future__ import annotations

import asyncio
import datetime as dt
from pathlib import Path
from typing import Any

import pytest

from protocol import Controller, ErrorCode, Hello, MapEncoding
from server.db import error_models as model_repo
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.events import EventKind
from server.links.ednc.session import Verdict
from server.push import scheduler as scheduler_module
from server.push import steps
from tests.support.link import DEADLINE_S, model_body, rig, until


class _Plc:
    """A controller link that applies every map at once and keeps the bytes it got."""

    def __init__(self, name: str) -> None:
        self._name = name
        self.address = "10.0.0.1:502"
        self.closed_because: str | None = None
        self.hello: Hello | None = Hello(
            name=name, ip="10.0.0.1", controller=Controller.FANUC,
            map_formats=MapEncoding.FLOAT32_MM | MapEncoding.INT32_INCREMENTS,
            software_version="plc/test", translational_type=1)
        self.got: list[tuple[int, bytes]] = []

    @property
    def name(self) -> str:
        return self._name

    @property
    def reported_version(self) -> int | None:
        return None

    def adopt(self, version: int, payload: bytes) -> None:
        pass

    async def push_map(self, version: int, payload: bytes, timeout_s: float) -> Verdict:
        self.got.append((version, payload))
        return Verdict(version, True, None, "", 0.001)

    def send(self, msg: object) -> None:
        pass

    def abort(self, code: ErrorCode | None, text: str) -> None:
        self.closed_because = text

    async def wait_closed(self) -> None:
        await asyncio.Event().wait()


def _log_steps(r: Any) -> list[str]:
    """The names of the database steps the center runs from now on, in order (through
    ``Database.run`` or the scheduler's group commit)."""
    ran: list[str] = []
    for owner in (r.db, r.services.push.writes):
        def logged(fn: Any, *args: Any, __run: Any = owner.run, **kwargs: Any) -> Any:
            ran.append(fn.__name__)
            return __run(fn, *args, **kwargs)

        owner.run = logged
    return ran


async def _served(tmp_path: Path, pushes: int, *, new_model_after: int | None = None
                  ) -> tuple[list[tuple[int, bytes]], list[str], dict[int, bytes]]:
    """One machine served over :class:`_Plc`, re-pushed until it got ``pushes`` maps (a
    new model stored after the ``new_model_after``-th); the maps it got, the database
    steps the scheduler ran, every stored map's bytes by version."""
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=600.0) as r:
        mid = await r.register("plc-01", model=model_body("plc-01"))
        row = await r.db.run(machine_repo.get_machine, "plc-01")
        assert row is not None
        run = r.db.run
        ran = _log_steps(r)
        plc = _Plc("plc-01")
        worker = asyncio.create_task(r.services.push.serve(plc, row))
        try:
            for n in range(1, pushes + 1):
                if n > 1:
                    if n - 1 == new_model_after:
                        await run(model_repo.add_model, mid, source="fit",
                                  body=model_body("plc-01", slope=0.02))
                    else:
                        assert r.services.push.request("plc-01", "test", resend=True)
                await until(lambda n=n: len(plc.got) >= n)
                await until(lambda: len(ran) > 0 and ran[-1] == "record_answer")
        finally:
            worker.cancel()
            await asyncio.gather(worker, return_exceptions=True)
        maps = await run(map_repo.list_map_versions, mid)
        stored = {}
        for m in maps:
            full = await run(map_repo.get_map_version, mid, m.version)
            assert full is not None
            stored[m.version] = full.payload
        return plc.got, ran, stored


async def test_a_re_push_reads_the_map_once_per_session(tmp_path: Path) -> None:
    got, ran, stored = await _served(tmp_path, 4)
    assert [v for v, _ in got] == [1, 1, 1, 1]
    assert all(payload == stored[1] for _, payload in got)
    # built at the session's start, then kept: no re-push read it again
    assert ran.count("stored_payload") == 0
    assert ran.count("record_sent") == 3 and ran.count("record_answer") == 4


async def test_a_new_map_is_sent_as_stored_and_then_kept(tmp_path: Path) -> None:
    got, ran, stored = await _served(tmp_path, 4, new_model_after=2)
    assert [v for v, _ in got] == [1, 1, 2, 2]
    assert got[1][1] == stored[1] and got[2][1] == stored[2] and got[3][1] == stored[2]
    assert stored[1] != stored[2]
    assert ran.count("stored_payload") == 0


async def test_a_map_too_large_to_keep_is_read_for_each_push(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(scheduler_module, "KEPT_PAYLOAD_BYTES", 0)
    got, ran, stored = await _served(tmp_path, 3)
    assert all(payload == stored[1] for _, payload in got)
    assert ran.count("stored_payload") == 2  # the two re-pushes


async def test_a_session_reads_a_stored_map_once(tmp_path: Path) -> None:
    """A map stored before the session (not built in it): read at the session's start,
    then kept."""
    async with asyncio.timeout(DEADLINE_S), rig(tmp_path, period_s=600.0) as r:
        mid = await r.register("plc-01", model=model_body("plc-01"))
        row = await r.db.run(machine_repo.get_machine, "plc-01")
        assert row is not None
        first = _Plc("plc-01")
        worker = asyncio.create_task(r.services.push.serve(first, row))
        await until(lambda: len(first.got) == 1)
        worker.cancel()
        await asyncio.gather(worker, return_exceptions=True)
        run = r.db.run
        ran = _log_steps(r)
        plc = _Plc("plc-01")
        worker = asyncio.create_task(r.services.push.serve(plc, row))
        try:
            await until(lambda: len(plc.got) == 1)
            for n in (2, 3):
                await until(lambda: ran[-1] == "record_answer")
                assert r.services.push.request("plc-01", "test", resend=True)
                await until(lambda n=n: len(plc.got) == n)
        finally:
            worker.cancel()
            await asyncio.gather(worker, return_exceptions=True)
        stored = await run(map_repo.get_map_version, mid, 1)
        assert stored is not None
        assert [p for _, p in plc.got] == [stored.payload] * 3
        assert ran.count("stored_payload") == 1


def _machine_with_map(db: Any, name: str = "m-01") -> tuple[int, int]:
    row = db.call(machine_repo.create_machine, name=name, ip=f"10.0.0.{name[-1]}",
                  controller="fanuc", description={"name": name}, secret="s" * 32)
    db.call(model_repo.add_model, row.id, source="upload", body=model_body(name))
    stored = db.call(map_repo.add_map_version, row.id, payload=b"map-bytes",
                     model_version=1)
    return row.id, stored.id


@pytest.fixture
def db(database_url: str) -> Any:
    """An empty database on SQLite and on PostgreSQL (tests/support/db.py)."""
    from server.db import Database
    from server.db.database import make_engine
    database = Database(make_engine(database_url))
    database.create_schema()
    yield database
    database.engine.dispose()


def test_the_push_steps_write_what_the_orm_wrote(db: Any) -> None:
    mid, map_id = _machine_with_map(db)
    before = dt.datetime.now(dt.UTC)
    first = db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: test")
    second = db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: again")
    rows = {r.id: r for r in db.call(map_repo.list_applied, mid)}
    assert map_repo.delivery_state(rows[first]) == "superseded"
    assert map_repo.delivery_state(rows[second]) == "pending"
    sent = rows[second]
    assert sent.map_id == map_id and sent.map_version == 1 and sent.acked is False
    assert sent.applied_at.tzinfo is not None and sent.applied_at >= before
    assert rows[first].answered_at is not None and rows[first].answered_at.tzinfo is not None

    long_reason = "x\x00" + "y" * 3000
    db.call(steps.record_answer, second, "m-01", EventKind.REJECTED, acked=False,
            reason="RANGE: out of range", detail=long_reason)
    answered = db.call(map_repo.list_applied, mid)[0]
    assert (answered.state, answered.acked, answered.reject_reason) == (
        "rejected", False, "RANGE: out of range")
    assert answered.answered_at is not None and answered.answered_at >= before
    third = db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: third")
    db.call(steps.record_failure, third, "m-01", failure="session ended before the answer")
    failed = db.call(map_repo.list_applied, mid)[0]
    assert (failed.state, failed.acked, failed.reject_reason, failed.failure) == (
        "failed", False, None, "session ended before the answer")
    fourth = db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: fourth")
    db.call(steps.record_answer, fourth, "m-01", EventKind.APPLIED, acked=True,
            reason=None, detail="map version 1 applied")
    applied = db.call(map_repo.list_applied, mid)[0]
    assert (applied.state, applied.acked, applied.reject_reason, applied.failure) == (
        "applied", True, None, None)
    # the failed and rejected ones keep their state: only pending ones are superseded
    states = [map_repo.delivery_state(r) for r in db.call(map_repo.list_applied, mid)]
    assert states == ["applied", "failed", "rejected", "superseded"]

    events = db.call(event_repo.list_events, machine="m-01")
    assert [e.kind for e in events] == [
        "applied", "pushed", "error", "pushed", "rejected", "pushed", "pushed"]
    rejected = events[4]
    assert rejected.detail.startswith("x\\0yyy") and rejected.detail.endswith("…")
    assert len(rejected.detail) == event_repo.MAX_DETAIL_CHARS
    assert all(e.time.tzinfo is not None and e.time >= before for e in events)


def test_an_answer_to_no_delivery_changes_nothing(db: Any) -> None:
    mid, _ = _machine_with_map(db)
    assert db.call(map_repo.record_answer, 12345, acked=True) is None
    assert db.call(map_repo.record_failure, 12345, "lost") is None
    assert db.call(map_repo.list_applied, mid) == []


def test_a_delivery_of_a_map_not_the_machines_is_refused_whole(db: Any) -> None:
    mid, map_id = _machine_with_map(db)
    other, other_map = _machine_with_map(db, "m-02")
    db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: first")
    for machine, row_id, version in ((mid, other_map, 1), (other, map_id, 1),
                                     (mid, map_id, 2)):
        with pytest.raises(RuntimeError, match="has no map version"):
            db.call(steps.record_sent, machine, "m-01", version, row_id, "wrong")
    # nothing written by the refused ones: the first delivery still waits for its answer
    assert [map_repo.delivery_state(r) for r in db.call(map_repo.list_applied, mid)] == [
        "pending"]
    db.call(machine_repo.delete_machine, "m-01")
    with pytest.raises(RuntimeError, match="has no map version"):
        db.call(steps.record_sent, mid, "m-01", 1, map_id, "map version 1: late")
    assert db.call(map_repo.list_applied, mid) == []
    assert db.call(map_repo.list_applied, other) == []
    # refused before the event: only the first delivery's is there
    pushed = db.call(event_repo.list_events, machine="m-01", kind="pushed")
    assert [e.detail for e in pushed] == ["map version 1: first"]


def test_load_inputs_reads_what_the_orm_reads(db: Any) -> None:
    mid, _ = _machine_with_map(db)
    db.call(map_repo.add_map_version, mid, payload=b"second", model_version=1,
            temperatures={"T_spindle_C": 21.5})
    inputs = db.call(steps.load_inputs, mid)
    machine = db.call(machine_repo.get_machine, "m-01")
    model = db.call(model_repo.get_model, mid)
    current = db.call(map_repo.get_map_version, mid, with_payload=False)
    assert inputs.machine is not None and inputs.model is not None and inputs.map is not None
    assert (inputs.machine.id, inputs.machine.name, inputs.machine.controller,
            inputs.machine.description, inputs.machine.updated_at) == (
        machine.id, machine.name, machine.controller, machine.description,
        machine.updated_at)
    assert (inputs.model.id, inputs.model.version, inputs.model.body) == (
        model.id, model.version, model.body)
    assert (inputs.map.id, inputs.map.version, inputs.map.model_version, inputs.map.sha256,
            inputs.map.size_bytes, inputs.map.temperatures, inputs.map.created_at) == (
        current.id, 2, 1, current.sha256, 6, {"T_spindle_C": 21.5}, current.created_at)
    assert inputs.machine.updated_at.tzinfo is not None
    assert db.call(steps.load_inputs, 9999) == steps.Inputs(None, None, None)


def test_load_inputs_reads_a_model_body_only_when_it_is_new(db: Any) -> None:
    mid, _ = _machine_with_map(db)
    first = db.call(steps.load_inputs, mid).model
    held = {"held": "by the caller"}
    again = db.call(steps.load_inputs, mid, (first.id, held)).model
    assert again.id == first.id and again.body is held  # not read again
    db.call(model_repo.add_model, mid, source="fit", body=model_body("m-01", slope=0.03))
    newer = db.call(steps.load_inputs, mid, (first.id, held)).model
    assert newer.id != first.id and newer.version == 2
    assert newer.body == model_body("m-01", slope=0.03)
