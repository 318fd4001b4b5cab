"""Group commit: small write steps from many tasks share one transaction and one commit.

Why: each push writes twice (its delivery, then the machine's answer), each a transaction
of its own through :meth:`~server.db.Database.run`. On SQLite in WAL mode with
``synchronous=FULL`` (the default) every commit waits for an fsync of the log: 7 ms on
the development VM, and SQLite takes one writer at a time, so a re-push to 1,000
machines waited about 14 s for its 2,000 commits whatever the CPU did. Here the steps
queued while a commit runs go together into the next transaction: one fsync for all of
them, each step still durable before its caller hears back (no weaker setting; a
caller's result comes after the commit that holds its writes).

A step that raises rolls the shared transaction back; then every step of that batch runs
again in a transaction of its own, so one step's failure is that step's alone, as
without batching (the steps are database writes and nothing else, so running one again
after a rollback is running it once). A failing commit fails every step of the batch:
each caller sees the error its own commit would have given.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Concatenate, Final, ParamSpec, TypeVar

from sqlalchemy.orm import Session

from server.db.database import Database

P = ParamSpec("P")
T = TypeVar("T")

MAX_BATCH: Final = 128
"""Steps in one transaction at most: the write lock is held for their statements (about
0.3 ms of CPU each), so other writers (the API, temperature intake) wait at most tens of
milliseconds for it."""


@dataclass(slots=True)
class _Step:
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    kwargs: dict[str, Any]
    future: asyncio.Future[Any]


class GroupCommit:
    """Runs ``fn(session, ...)`` write steps in shared transactions on one thread of its
    own; an async context manager (leaving it waits for the steps queued).

    Parameters
    ----------
    db : Database
    max_batch : int
        Steps in one transaction at most.
    """

    def __init__(self, db: Database, *, max_batch: int = MAX_BATCH) -> None:
        self.db = db
        self.max_batch = max_batch
        self.commits = 0
        """Transactions committed (a batch that fell back counts each of its own)."""
        self._queue: list[_Step] = []
        self._drainer: asyncio.Task[None] | None = None
        self._pool: ThreadPoolExecutor | None = None

    async def __aenter__(self) -> GroupCommit:
        # a thread of its own: the steps never queue behind the reads in the default pool
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="groupcommit")
        return self

    async def __aexit__(self, *_: object) -> None:
        # the steps queued are answers the center received: written, not dropped (a step
        # queued while this waits makes a drainer of its own: waited for too)
        while self._drainer is not None and not self._drainer.done():
            with contextlib.suppress(Exception):
                await asyncio.shield(self._drainer)
        # no await from here: a step from now on runs alone (run)
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True)

    async def run(self, fn: Callable[Concatenate[Session, P], T], *args: P.args,
                  **kwargs: P.kwargs) -> T:
        """Run ``fn(session, *args, **kwargs)`` in the next shared transaction; its result
        once that transaction is committed. A caller cancelled meanwhile does not take
        its step back: it is written all the same. Outside the context (a shielded
        answer of a session ended at shutdown may come after leaving) the step runs
        alone, as :meth:`~server.db.Database.run` runs it: written, not refused."""
        if self._pool is None:
            return await self.db.run(fn, *args, **kwargs)
        future: asyncio.Future[T] = asyncio.get_running_loop().create_future()
        future.add_done_callback(_retrieved)
        self._queue.append(_Step(fn, args, kwargs, future))
        if self._drainer is None or self._drainer.done():
            self._drainer = asyncio.create_task(self._drain(), name="group commit")
        return await asyncio.shield(future)

    async def _drain(self) -> None:
        loop = asyncio.get_running_loop()
        while self._queue:
            batch, self._queue = (self._queue[:self.max_batch],
                                  self._queue[self.max_batch:])
            assert self._pool is not None
            outcomes = await loop.run_in_executor(self._pool, self._commit, batch)
            for step, (ok, value) in zip(batch, outcomes, strict=True):
                if step.future.done():
                    continue
                if ok:
                    step.future.set_result(value)
                else:
                    step.future.set_exception(value)

    def _commit(self, batch: list[_Step]) -> list[tuple[bool, Any]]:
        """On the writer thread: the batch in one transaction, or each step alone when
        one of them raised."""
        try:
            with self.db.session() as session:
                results: list[tuple[bool, Any]] = []
                for step in batch:
                    try:
                        results.append((True, step.fn(session, *step.args, **step.kwargs)))
                    except Exception as exc:
                        raise _StepFailed from exc
            self.commits += 1
            return results
        except _StepFailed:
            pass  # rolled back by the session: each step again, alone
        except Exception as exc:  # the commit (or the session) failed: so did every step
            return [(False, exc)] * len(batch)
        alone: list[tuple[bool, Any]] = []
        for step in batch:
            try:
                alone.append((True, self.db.call(step.fn, *step.args, **step.kwargs)))
                self.commits += 1
            except Exception as exc:
                alone.append((False, exc))
        return alone


def _retrieved(future: asyncio.Future[Any]) -> None:
    # a caller cancelled meanwhile never reads its step's error: not a loop warning
    if not future.cancelled():
        future.exception()


class _StepFailed(Exception):
    """A step of a shared transaction raised (its exception is the cause)."""


__all__ = ["MAX_BATCH", "GroupCommit"]
