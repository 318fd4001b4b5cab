"""Group commit (server/db/batch.py): steps queued together share a commit, each caller
gets its own result or its own error, a step's failure is that step's alone, a failing
commit fails every step of its batch, leaving writes what is queued, and a step
outside the context runs alone."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from typing import Any

import pytest
from sqlalchemy import event, select
from sqlalchemy.exc import OperationalError
from sqlalchemy.orm import Session

from server.db import Database
from server.db import events as event_repo
from server.db.batch import GroupCommit
from server.db.database import make_engine
from server.db.tables import EventRow


@pytest.fixture
async def db(database_url: str) -> AsyncIterator[Database]:
    """An empty database on SQLite and on PostgreSQL (tests/support/db.py)."""
    database = Database(make_engine(database_url))
    database.create_schema()
    yield database
    database.engine.dispose()


def _note(session: Session, machine: str) -> str:
    event_repo.note_event(session, kind="pushed", machine=machine, detail="d")
    return machine


def _fail(session: Session, machine: str) -> str:
    event_repo.note_event(session, kind="pushed", machine=machine, detail="d")
    raise RuntimeError(f"{machine} refused")


def _stored(db: Database) -> list[str]:
    with db.session() as session:
        return list(session.scalars(select(EventRow.machine).order_by(EventRow.id)))


def _count_commits(db: Database) -> list[int]:
    commits = [0]

    @event.listens_for(db.engine, "commit")
    def _on_commit(_conn: Any) -> None:
        commits[0] += 1

    return commits


async def test_steps_queued_together_share_one_commit(db: Database) -> None:
    commits = _count_commits(db)
    async with GroupCommit(db) as writes:
        names = [f"m-{i:03d}" for i in range(100)]
        got = await asyncio.gather(*(writes.run(_note, n) for n in names))
    assert got == names
    # queued before the first batch left: one transaction for all of them
    assert commits[0] == writes.commits == 1
    assert sorted(_stored(db)) == names


async def test_steps_queued_during_a_commit_go_in_the_next(db: Database) -> None:
    async with GroupCommit(db, max_batch=40) as writes:
        first = asyncio.create_task(writes.run(_note, "first"))
        await asyncio.sleep(0)  # the first batch on its way, alone
        later = [writes.run(_note, f"m-{i:03d}") for i in range(100)]
        got = await asyncio.gather(first, *later)
    assert got == ["first"] + [f"m-{i:03d}" for i in range(100)]
    assert writes.commits == 4  # 1, then 40, 40, 20


async def test_a_failing_step_fails_alone(db: Database) -> None:
    async with GroupCommit(db) as writes:
        results = await asyncio.gather(
            writes.run(_note, "a"), writes.run(_note, "b"), writes.run(_fail, "bad"),
            writes.run(_note, "c"), return_exceptions=True)
    assert list(results[:2]) == ["a", "b"] and results[3] == "c"
    assert isinstance(results[2], RuntimeError) and "bad refused" in str(results[2])
    # the failed step's own write went with it; the others' are there once each
    assert sorted(_stored(db)) == ["a", "b", "c"]


async def test_a_failing_commit_fails_every_step_of_its_batch(db: Database) -> None:
    refuse = [False]

    @event.listens_for(db.engine, "commit")
    def _on_commit(_conn: Any) -> None:
        if refuse[0]:
            raise OperationalError("COMMIT", {}, Exception("disk I/O error"))

    async with GroupCommit(db) as writes:
        assert await writes.run(_note, "before") == "before"
        refuse[0] = True
        results = await asyncio.gather(*(writes.run(_note, f"x{i}") for i in range(5)),
                                       return_exceptions=True)
        refuse[0] = False
        assert await writes.run(_note, "after") == "after"
    assert all(isinstance(r, OperationalError) for r in results)
    assert _stored(db) == ["before", "after"]


async def test_a_cancelled_caller_still_has_its_step_written(db: Database) -> None:
    async with GroupCommit(db) as writes:
        tasks = [asyncio.create_task(writes.run(_note, f"m{i}")) for i in range(20)]
        await asyncio.sleep(0)
        for task in tasks[5:]:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
    # leaving waited for the queue: every step written, the cancelled callers' too
    assert sorted(_stored(db)) == sorted(f"m{i}" for i in range(20))


async def test_outside_its_context_a_step_runs_alone(db: Database) -> None:
    writes = GroupCommit(db)
    assert await writes.run(_note, "before") == "before"
    async with writes:
        assert await writes.run(_note, "inside") == "inside"
    assert await writes.run(_note, "after") == "after"  # an answer late at shutdown
    assert writes.commits == 1  # only the one inside went through the batches
    assert _stored(db) == ["before", "inside", "after"]
