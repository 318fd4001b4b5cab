"""The model-change hook: SQLAlchemy session events that wake the push scheduler.

Every path that stores a model (upload, fit, diagnosis) or changes a machine commits
through a session; watching commits covers them all without each path remembering to
tell the scheduler.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Callable
from typing import Any, Final

from sqlalchemy import event
from sqlalchemy.orm import Session

from server.db import Database
from server.db.tables import MachineRow, ModelRow


class CommitWatcher:
    """Calls ``callback(machine_ids)`` in the event loop after a transaction on ``db``
    commits new ``models`` rows or changed ``machines`` rows."""

    _KEY: Final = "ednc.push.changed"

    def __init__(self, db: Database, loop: asyncio.AbstractEventLoop,
                 callback: Callable[[set[int]], None]) -> None:
        self.engine = db.engine
        self.loop = loop
        self.callback = callback

    def _after_flush(self, session: Session, _context: Any) -> None:
        if session.bind is not self.engine:
            return
        ids: set[int] = session.info.setdefault(self._KEY, set())
        ids.update(o.machine_id for o in session.new if isinstance(o, ModelRow))
        ids.update(o.id for o in session.dirty if isinstance(o, MachineRow))

    def _after_commit(self, session: Session) -> None:
        ids = session.info.pop(self._KEY, None)
        if ids:
            with contextlib.suppress(RuntimeError):  # loop closed: nobody to tell
                self.loop.call_soon_threadsafe(self.callback, set(ids))

    def _after_rollback(self, session: Session) -> None:
        session.info.pop(self._KEY, None)

    def __enter__(self) -> CommitWatcher:
        event.listen(Session, "after_flush", self._after_flush)
        event.listen(Session, "after_commit", self._after_commit)
        event.listen(Session, "after_rollback", self._after_rollback)
        return self

    def __exit__(self, *_: object) -> None:
        event.remove(Session, "after_flush", self._after_flush)
        event.remove(Session, "after_commit", self._after_commit)
        event.remove(Session, "after_rollback", self._after_rollback)


__all__ = ["CommitWatcher"]
