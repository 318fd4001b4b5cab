"""Start-up and shut-down of a simulated controller: its clock, first scan, server, loop.

Every simulated controller that serves its memory to the center (the Python PLC program's
:class:`~machine_sim.windowcnc.WindowCNC`, the compiled ST program's
:class:`~machine_sim.stplc.StWindowCNC`, the native SINUMERIK's
:class:`~machine_sim.sinumerik_native.NativeSinumerik`) starts and stops the same way, as
an async context manager (style habit 5): its clock starts, a first scan writes what a
client reads first (the window's identity), the server listens, and a task scans every
cycle until the context ends, when the task is cancelled before the server stops (a scan
never runs against a stopped server).
"""

from __future__ import annotations

import asyncio
from types import TracebackType
from typing import Any, Self

__all__ = ["ScannedController"]


class ScannedController:
    """A base for a simulated controller with a ``server`` and a scan every ``cycle_s``.

    A subclass sets ``machine`` (for the task's name), ``server`` (``start()`` and
    ``stop()`` coroutines), ``cycle_s`` (s) and :attr:`task_name`, and defines
    :meth:`cycle`; :meth:`boot` and :meth:`_loop` are there to override.
    """

    machine: Any
    server: Any
    cycle_s: float
    task_name = "plc"
    """The scan task's name after the machine's (``<machine>:<task_name>``)."""
    _t0 = 0.0
    _task: asyncio.Task[None] | None = None

    def now(self) -> float:
        """Machine time since start, s."""
        return asyncio.get_running_loop().time() - self._t0

    def boot(self) -> None:
        """The first scan, before the server listens (default: none)."""

    def cycle(self) -> None:
        """One scan (what the loop runs)."""
        raise NotImplementedError

    async def _loop(self) -> None:
        while True:
            self.cycle()
            await asyncio.sleep(self.cycle_s)

    async def __aenter__(self) -> Self:
        self._t0 = asyncio.get_running_loop().time()
        self.boot()
        await self.server.start()
        self._task = asyncio.create_task(self._loop(),
                                         name=f"{self.machine.name}:{self.task_name}")
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
        await self.server.stop()
