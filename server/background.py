"""Background tasks that live as long as a service's ``async with`` block.

The services (live-link publisher, lease renewer, event retention, MQTT bridge, dashboard
feed) each start a task or two on entry and must stop them on exit, even when a task is
blocked in a library call that swallows one cancel. :class:`Background` is that start /
cancel / await in one place; :func:`every` is the periodic loop most of them run.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any

log = logging.getLogger(__name__)


class Background:
    """A set of tasks started by a service and stopped with it.

    Parameters
    ----------
    grace_s : float or None
        How long :meth:`stop` waits for the cancelled tasks; those still running after it
        are cancelled once more and waited for as long again (aiomqtt, for one, waits for
        a broker's answer inside its own cancellation handling). None waits as long as
        they take.
    """

    def __init__(self, *, grace_s: float | None = None) -> None:
        self.grace_s = grace_s
        self._tasks: list[asyncio.Task[Any]] = []

    def start(self, coro: Coroutine[Any, Any, Any], name: str) -> asyncio.Task[Any]:
        """Run ``coro`` until :meth:`stop`; its exception, if any, is logged there."""
        task = asyncio.create_task(coro, name=name)
        self._tasks.append(task)
        return task

    def __len__(self) -> int:
        return len(self._tasks)

    async def stop(self) -> None:
        """Cancel every task and wait for them (see ``grace_s``)."""
        tasks, self._tasks = self._tasks, []
        if not tasks:
            return
        for task in tasks:
            task.cancel()
        _, pending = await asyncio.wait(tasks, timeout=self.grace_s)
        for task in pending:
            task.cancel()
        if pending:
            log.warning("background tasks %s did not stop within %g s: cancelled again",
                        ", ".join(sorted(t.get_name() for t in pending)), self.grace_s)
            _, pending = await asyncio.wait(pending, timeout=self.grace_s)
        for task in pending:  # left to the loop's shutdown: never hold the service's exit
            log.error("background task %s still running after two cancels", task.get_name())
        for task in tasks:
            if task.done() and not task.cancelled() and task.exception() is not None:
                log.error("background task %s ended with %r", task.get_name(),
                          task.exception())


async def every(period_s: float, step: Callable[[], Awaitable[object]], *,
                errors: tuple[type[BaseException], ...] = (), what: str = "") -> None:
    """Await ``step()`` every ``period_s`` seconds, forever (cancel to stop).

    Exceptions of the types in ``errors`` are logged and the loop goes on (a database
    that is busy now may answer next period); any other ends the loop.
    """
    while True:
        await asyncio.sleep(period_s)
        try:
            await step()
        except errors as exc:
            log.warning("%s failed, trying again in %g s: %s", what or step, period_s,
                        str(exc).splitlines()[0] if str(exc) else type(exc).__name__)


__all__ = ["Background", "every"]
